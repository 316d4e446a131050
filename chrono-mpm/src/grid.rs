//! The background grid: its geometry ([`GridSpec`]), the walls of its box ([`Wall`]) and
//! the sparse block storage ([`SparseGrid`]) that keeps only the nodes markers touch.
//!
//! Nodes sit at `origin + i dx`, `i` in `[-GHOST, cells + GHOST]` per axis: the box
//! `[origin, origin + cells dx]` plus [`GHOST`] layers of nodes outside it, so that a marker
//! on or slightly past a wall still has its whole B-spline stencil. Nodes on a face of the
//! box carry that face's wall condition, the ghost nodes beyond it its mirror image.
//!
//! Storage: nodes are grouped in blocks of `BLOCK^3` = 64 nodes, keyed by block
//! coordinate; each step the markers are sorted by (block, base node) and the *active*
//! blocks (those some marker's stencil touches) are listed in a sorted vector of keys with
//! their node data stored block by block. Empty space costs nothing, and all vectors keep
//! their capacity, so after the first steps a step does not allocate.

use rayon::prelude::*;

use crate::error::{Result, invalid, positive};

/// Nodes per block edge.
pub const BLOCK: usize = 4;
/// Nodes per block.
pub const BLOCK3: usize = BLOCK * BLOCK * BLOCK;
/// Node layers outside the box on each side.
pub const GHOST: i64 = 2;

/// The velocity condition of a face of the grid's box: applied to the nodes on the face;
/// the ghost nodes beyond it take the mirror image of the nodes inside (see
/// [`MpmBody`](crate::MpmBody)'s grid update).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wall {
    /// No condition: material may leave the box (and is an error once it leaves the grid).
    Open,
    /// No-slip: the node velocity is zero.
    Sticky,
    /// Frictionless and bilateral: the normal velocity component is zero.
    Slip,
    /// Frictionless and unilateral: a normal velocity into the wall is removed, one away
    /// from it kept (material can lift off).
    #[default]
    Separating,
}

/// The geometry of the background grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    /// Lower corner of the box, m.
    pub origin: [f64; 3],
    /// Cells of the box per axis.
    pub cells: [usize; 3],
    /// Node spacing, m.
    pub dx: f64,
    /// `walls[a][0]` on the lower face of axis `a`, `walls[a][1]` on the upper one.
    pub walls: [[Wall; 2]; 3],
}

impl GridSpec {
    /// A box from `origin` with `cells` cells of size `dx` per axis, all walls separating.
    pub fn new(origin: [f64; 3], cells: [usize; 3], dx: f64) -> Result<Self> {
        positive("grid.dx", dx)?;
        for a in 0..3 {
            if !origin[a].is_finite() {
                return Err(invalid(
                    &format!("grid.origin[{a}]"),
                    origin[a],
                    "must be finite",
                ));
            }
            if cells[a] == 0 || cells[a] > 1 << 20 {
                return Err(invalid(
                    &format!("grid.cells[{a}]"),
                    cells[a],
                    "must lie in [1, 2^20]",
                ));
            }
        }
        Ok(Self {
            origin,
            cells,
            dx,
            walls: [[Wall::Separating; 2]; 3],
        })
    }

    /// The same grid with the walls of axis `axis` (lower, upper) set.
    pub fn with_walls(mut self, axis: usize, lower: Wall, upper: Wall) -> Self {
        self.walls[axis] = [lower, upper];
        self
    }

    /// The region markers may occupy: their stencil stays inside the grid's nodes,
    /// `[origin - 1.5 dx, origin + (cells + 1.5) dx)` per axis, m.
    pub fn admissible(&self) -> ([f64; 3], [f64; 3]) {
        let h = (GHOST as f64 - 0.5) * self.dx;
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for a in 0..3 {
            lo[a] = self.origin[a] - h;
            hi[a] = self.origin[a] + self.cells[a] as f64 * self.dx + h;
        }
        (lo, hi)
    }

    /// Blocks per axis.
    pub(crate) fn blocks(&self) -> [usize; 3] {
        let mut nb = [0; 3];
        for a in 0..3 {
            nb[a] = (self.cells[a] + 2 * GHOST as usize + 1).div_ceil(BLOCK);
        }
        nb
    }
}

/// A marker-block run: markers `start..end` of the sorted order have their base node in
/// block `key`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Run {
    pub key: u64,
    pub start: u32,
    pub end: u32,
}

/// The sparse grid of active blocks and its per-step marker sort.
#[derive(Clone, Debug, Default)]
pub struct SparseGrid {
    /// Markers sorted by `(block key * BLOCK3 + base node in block, marker index)`.
    pub(crate) sorted: Vec<(u64, u32)>,
    /// Runs of `sorted` sharing a block, in key order.
    pub(crate) runs: Vec<Run>,
    /// Keys of the active blocks, sorted.
    pub(crate) active: Vec<u64>,
    /// Node mass per active block, `BLOCK3` per block, kg.
    pub(crate) mass: Vec<f64>,
    /// Node momentum after P2G, then node velocity after the grid update.
    pub(crate) mom: Vec<[f64; 3]>,
    /// Node velocities before the ghost images (scratch of the grid update).
    pub(crate) prev: Vec<[f64; 3]>,
    /// Node momentum of the transfer alone, without the stress impulse (the FLIP blend's
    /// old grid velocity, [`MpmBody::set_flip`](crate::MpmBody::set_flip)).
    pub(crate) mom0: Vec<[f64; 3]>,
    /// Impulse (N s) and angular impulse about the body's centre (N m s) per active block
    /// and rigid body (scratch of the grid update).
    pub(crate) impulse: Vec<[f64; 6]>,
    /// Node masses with the ghosts' folded in (the box nodes; [`crate::fold`]), kg.
    pub(crate) fmass: Vec<f64>,
    /// The sticky bodies' ghost links of the step (scratch of the grid update).
    pub(crate) links: Vec<crate::fold::Link>,
    /// The links' folded mass and momentum per node: (node, link order, mass, momentum,
    /// body) (scratch of the grid update).
    pub(crate) folds: Vec<(usize, usize, f64, [f64; 3], usize)>,
    /// The folded nodes' momentum change (N s) and its moment about the body's centre
    /// (N m s) per rigid body (scratch of the grid update).
    pub(crate) fold_impulse: Vec<[f64; 6]>,
    /// Whether the step has mirrored markers ([`crate::rigid::RigidBody::mirrored_markers`]).
    pub(crate) mirror_on: bool,
    /// The mirrored markers' node masses (kg) and momenta (N s, their stress and gravity
    /// impulses included) per active block (empty when `mirror_on` is false); in the grid
    /// update, the masses with the real markers' added.
    pub(crate) mirror_mass: Vec<f64>,
    pub(crate) mirror_mom: Vec<[f64; 3]>,
    /// The real markers' folded node masses (kg) and velocities under the walls (m/s)
    /// alone, when `mirror_on` (the mirrored bodies' impulse).
    pub(crate) real_mass: Vec<f64>,
    pub(crate) real_vel: Vec<[f64; 3]>,
}

impl SparseGrid {
    /// Number of active blocks.
    pub fn active_blocks(&self) -> usize {
        self.active.len()
    }

    /// Number of active nodes (with mass).
    pub fn nodes_with_mass(&self) -> usize {
        self.mass.iter().filter(|&&m| m > 0.0).count()
    }

    /// Sorts the markers and lists the active blocks. `base` gives each marker's base node
    /// shifted by [`GHOST`] (all components in range; checked by the caller).
    pub(crate) fn rebuild(
        &mut self,
        spec: &GridSpec,
        base: impl Fn(usize) -> [usize; 3] + Sync,
        n: usize,
    ) {
        let nb = spec.blocks();
        let key_of = |g: [usize; 3]| -> u64 {
            let b = [g[0] / BLOCK, g[1] / BLOCK, g[2] / BLOCK];
            let l = [g[0] % BLOCK, g[1] % BLOCK, g[2] % BLOCK];
            let bk = ((b[0] * nb[1] + b[1]) * nb[2] + b[2]) as u64;
            bk * BLOCK3 as u64 + ((l[0] * BLOCK + l[1]) * BLOCK + l[2]) as u64
        };
        self.sorted.clear();
        self.sorted.resize(n, (0, 0));
        self.sorted
            .par_iter_mut()
            .with_min_len(256)
            .enumerate()
            .for_each(|(p, s)| *s = (key_of(base(p)), p as u32));
        // Unique keys (the marker index breaks ties): the sorted order is the same for any
        // thread count.
        self.sorted.par_sort_unstable();

        self.runs.clear();
        let mut p = 0;
        while p < n {
            let key = self.sorted[p].0 / BLOCK3 as u64;
            let start = p;
            while p < n && self.sorted[p].0 / BLOCK3 as u64 == key {
                p += 1;
            }
            self.runs.push(Run {
                key,
                start: start as u32,
                end: p as u32,
            });
        }

        // Active blocks: those the stencils (base .. base + 2) of each run reach.
        self.active.clear();
        for r in &self.runs {
            let b = unkey(r.key, nb);
            let mut hi_l = [0usize; 3];
            for &(k, _) in &self.sorted[r.start as usize..r.end as usize] {
                let l = (k % BLOCK3 as u64) as usize;
                let l = [l / (BLOCK * BLOCK), (l / BLOCK) % BLOCK, l % BLOCK];
                for a in 0..3 {
                    hi_l[a] = hi_l[a].max(l[a]);
                }
            }
            let reach = |a: usize| if hi_l[a] + 2 >= BLOCK { 2 } else { 1 };
            for dx in 0..reach(0) {
                for dy in 0..reach(1) {
                    for dz in 0..reach(2) {
                        let c = [b[0] + dx, b[1] + dy, b[2] + dz];
                        if c[0] < nb[0] && c[1] < nb[1] && c[2] < nb[2] {
                            self.active
                                .push(((c[0] * nb[1] + c[1]) * nb[2] + c[2]) as u64);
                        }
                    }
                }
            }
        }
        self.active.sort_unstable();
        self.active.dedup();
        let nodes = self.active.len() * BLOCK3;
        self.mass.clear();
        self.mass.resize(nodes, 0.0);
        self.mom.clear();
        self.mom.resize(nodes, [0.0; 3]);
    }

    /// Index of the active block `key`, if active.
    #[inline]
    pub(crate) fn block_index(&self, key: u64) -> Option<usize> {
        self.active.binary_search(&key).ok()
    }

    /// The run of block `key`, if it holds markers.
    #[inline]
    pub(crate) fn run(&self, key: u64) -> Option<Run> {
        self.runs
            .binary_search_by_key(&key, |r| r.key)
            .ok()
            .map(|i| self.runs[i])
    }

    /// The sorted-marker index ranges of the markers whose stencils can reach block `b`
    /// (block coordinates; `nb` blocks per axis): the runs of the 2 x 2 x 2 blocks at
    /// `b - 1 .. b` per axis (a quadratic stencil starts at most one block below), in that
    /// order (x slowest), the ones that hold markers.
    pub(crate) fn runs_reaching(
        &self,
        b: [usize; 3],
        nb: [usize; 3],
    ) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        (0..8usize).filter_map(move |i| {
            let d = [i >> 2, (i >> 1) & 1, i & 1];
            if (0..3).any(|a| b[a] + d[a] < 1) {
                return None;
            }
            let k = key([b[0] + d[0] - 1, b[1] + d[1] - 1, b[2] + d[2] - 1], nb);
            self.run(k).map(|r| r.start as usize..r.end as usize)
        })
    }
}

/// Block coordinates of a block key.
#[inline]
pub(crate) fn unkey(key: u64, nb: [usize; 3]) -> [usize; 3] {
    let k = key as usize;
    [k / (nb[1] * nb[2]), (k / nb[2]) % nb[1], k % nb[2]]
}

/// Block key of block coordinates.
#[inline]
pub(crate) fn key(b: [usize; 3], nb: [usize; 3]) -> u64 {
    ((b[0] * nb[1] + b[1]) * nb[2] + b[2]) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_grid_names_the_field() {
        let e = GridSpec::new([0.0; 3], [4, 4, 4], -0.1).unwrap_err();
        assert!(e.to_string().contains("grid.dx"), "{e}");
        let e = GridSpec::new([0.0; 3], [4, 0, 4], 0.1).unwrap_err();
        assert!(e.to_string().contains("grid.cells[1]"), "{e}");
        let e = GridSpec::new([0.0, f64::NAN, 0.0], [4, 4, 4], 0.1).unwrap_err();
        assert!(e.to_string().contains("grid.origin[1]"), "{e}");
    }

    #[test]
    fn keys_round_trip() {
        let nb = [3, 5, 7];
        for b in [[0, 0, 0], [2, 4, 6], [1, 3, 2]] {
            assert_eq!(unkey(key(b, nb), nb), b);
        }
    }
}
