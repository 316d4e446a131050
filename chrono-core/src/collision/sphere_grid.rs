//! Broad and narrow phase for many spheres: the uniform cell grid of
//! [`crate::particles::grid`].
//!
//! When a world holds at least [`GRID_MIN_SPHERES`] sphere colliders (grains, and clumps
//! of spheres: each sphere of a clump is a collider of the same owner), the spheres are
//! binned into a [`CellGrid`] with cells `2 r_max + delta` wide (`delta` the envelope), so
//! every sphere pair closer than the envelope is in neighbouring cells. Sphere–sphere
//! pairs from the grid's unique-pairs pass get their analytic contact directly, in
//! parallel blocks, without per-pair state (a sphere contact has no manifold to keep).
//!
//! The other colliders (walls, meshes, boxes, big bodies) keep the sort-and-sweep among
//! themselves; a sphere meets one of them when their bounds overlap: a finite box queries
//! the grid's cells under it, a half-space or a box covering more cells than there are
//! spheres tests every sphere's bound. Those pairs go through the persistent pair states of
//! the narrow phase like any other pair.
//!
//! Order of the sphere contacts: the grid's pair order (by sorted slot, then the stencil),
//! deterministic for given positions and independent of the thread count.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose, Vector};
use rayon::prelude::*;

use super::broad_phase::{Bound, SweepAndPrune, bounds_overlap};
use super::contact::{ColliderId, ContactKey, ContactPoint};
use super::convert::vec_from_glam;
use super::world::{Collider, ColliderKind};
use crate::error::Result;
use crate::particles::grid::{CellGrid, GridConfig, PairScratch};

/// A world with at least this many sphere colliders uses the grid.
pub const GRID_MIN_SPHERES: usize = 256;

/// Sphere pairs per parallel narrow-phase block.
const PAIR_BLOCK: usize = 4096;

/// Feature id of the analytic contacts (parry's `face(0)`), as in the narrow phase.
const FACE0: u32 = 0xC000_0000;

/// State of the sphere grid; buffers are reused between calls.
#[derive(Debug, Default)]
pub(crate) struct SphereGrid {
    grid: Option<CellGrid>,
    cutoff: f64,
    /// Collider count the id lists were built for.
    built_for: usize,
    /// Sphere collider ids, ascending.
    ids: Vec<u32>,
    radius: Vec<f64>,
    r_max: f64,
    /// Sphere centers of this step.
    pos: [Vec<f64>; 3],
    /// Sphere centers when the grid and the pair list were last built.
    built_pos: [Vec<f64>; 3],
    /// Lower corner of the grid at its last build (the minimum of the binned centers).
    lower: [f64; 3],
    /// Largest displacement of a center since the last build, m.
    moved: f64,
    /// Verlet skin as a fraction of `r_max`: the pair list holds the pairs within
    /// `cutoff + skin` and is rebuilt once a center has moved more than `skin / 2`.
    skin: f64,
    /// Whether the pair list must be rebuilt on the next step.
    stale: bool,
    /// Number of rebuilds (grid binning and pair search), for tests and benches.
    rebuilds: u64,
    /// Non-sphere collider ids, ascending, and their bounds.
    other_ids: Vec<u32>,
    other_bounds: Vec<Bound>,
    sap: SweepAndPrune,
    other_pairs: Vec<(u32, u32)>,
    hits: Vec<Vec<u32>>,
    pairs: Vec<[u32; 2]>,
    pair_scratch: PairScratch,
    blocks: Vec<Vec<ContactPoint>>,
}

impl SphereGrid {
    /// Forget the sphere index (colliders were removed or renumbered): the next
    /// [`candidates`](Self::candidates) rebuilds it, one pass over the colliders.
    pub(crate) fn forget_index(&mut self) {
        self.built_for = usize::MAX;
        self.stale = true;
    }

    /// Set the Verlet skin as a fraction of the largest sphere radius (>= 0; 0 rebuilds
    /// every step). The contacts found do not depend on it.
    pub(crate) fn set_skin(&mut self, skin: f64) {
        if skin != self.skin {
            self.skin = skin;
            self.stale = true;
        }
    }

    /// The Verlet skin, as a fraction of the largest sphere radius.
    pub(crate) fn skin(&self) -> f64 {
        self.skin
    }

    /// Number of pair-list rebuilds so far.
    pub(crate) fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Number of sphere colliders among `colliders` (recounted when colliders are added).
    fn index(&mut self, colliders: &[Collider]) {
        if self.built_for == colliders.len() {
            return;
        }
        self.ids.clear();
        self.radius.clear();
        self.other_ids.clear();
        self.r_max = 0.0;
        for (i, c) in colliders.iter().enumerate() {
            match c.kind {
                ColliderKind::Sphere { radius } => {
                    self.ids.push(i as u32);
                    self.radius.push(radius);
                    self.r_max = self.r_max.max(radius);
                }
                _ => self.other_ids.push(i as u32),
            }
        }
        self.built_for = colliders.len();
        self.stale = true;
    }

    /// Candidate pairs that involve a non-sphere collider (with each other, by
    /// sort-and-sweep, and with spheres, by the grid), sorted, into `out` (cleared); then
    /// bins the spheres for [`sphere_contacts`](Self::sphere_contacts).
    pub(crate) fn candidates(
        &mut self,
        colliders: &[Collider],
        poses: &[Pose],
        bounds: &[Bound],
        envelope: f64,
        out: &mut Vec<(u32, u32)>,
    ) -> Result<()> {
        self.index(colliders);
        out.clear();
        // Rebind the spheres only when the pair list is stale: a center moved more than
        // half the skin since the last build (two centers then approached by more than
        // the skin), or the spheres, their largest radius or the envelope changed.
        let cutoff = 2.0 * self.r_max + envelope;
        let skin = self.skin * self.r_max;
        let compare =
            !(self.stale || self.cutoff != cutoff || self.built_pos[0].len() != self.ids.len());
        // The centers, and their largest displacement since the last build in the same
        // pass.
        let moved = gather_centers(
            &self.ids,
            poses,
            &mut self.pos,
            compare.then_some(&self.built_pos),
        );
        self.moved = if compare { moved } else { f64::INFINITY };
        if self.moved > 0.5 * skin {
            let binned = cutoff + skin;
            if self
                .grid
                .as_ref()
                .is_none_or(|g| g.config().cutoff != binned)
            {
                self.grid = Some(CellGrid::new(GridConfig::auto(binned))?);
            }
            self.cutoff = cutoff;
            let grid = self.grid.as_mut().expect("grid built above");
            grid.build([&self.pos[0], &self.pos[1], &self.pos[2]])?;
            for a in 0..3 {
                // The grid's automatic lower corner is the minimum center (exact).
                self.lower[a] = self.pos[a].iter().copied().fold(f64::INFINITY, f64::min);
                self.built_pos[a].clone_from(&self.pos[a]);
            }
            let pos = [&self.pos[0][..], &self.pos[1][..], &self.pos[2][..]];
            grid.unique_pairs(pos, binned, &mut self.pair_scratch, &mut self.pairs)?;
            // The grid lists each sphere's pairs in stencil order; sorted by `(i, j)` the
            // list (and so the contact order) depends neither on the skin nor on when it
            // was built.
            (self.pairs.par_chunk_by_mut(|x, y| x[0] == y[0])).for_each(|run| run.sort_unstable());
            self.moved = 0.0;
            self.stale = false;
            self.rebuilds += 1;
        }

        // Others among themselves.
        self.other_bounds.clear();
        self.other_bounds
            .extend(self.other_ids.iter().map(|&i| bounds[i as usize]));
        self.sap
            .find_pairs(&self.other_bounds, &mut self.other_pairs);
        out.extend(
            self.other_pairs
                .iter()
                .map(|&(a, b)| (self.other_ids[a as usize], self.other_ids[b as usize])),
        );

        // Others against spheres.
        let nothers = self.other_ids.len();
        if self.hits.len() < nothers {
            self.hits.resize_with(nothers, Vec::new);
        }
        let grid = self.grid.as_ref().expect("grid built above");
        // Spheres sit within `moved` of the cell they were binned in.
        let pad = self.r_max + envelope + self.moved;
        let cells = Cells {
            grid,
            lower: self.lower,
            cell: grid.config().cutoff,
        };
        let (ids, other_ids) = (&self.ids, &self.other_ids);
        self.hits[..nothers]
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, hits)| {
                hits.clear();
                let o = other_ids[k] as usize;
                let ob = &bounds[o];
                let mut hit = |s: usize| {
                    if bounds_overlap(ob, &bounds[ids[s] as usize]) {
                        hits.push(ids[s]);
                    }
                };
                let found = match ob {
                    Bound::Box(b) if b.mins.is_finite() && b.maxs.is_finite() => {
                        query_box(grid, b, pad, ids.len(), &mut hit)
                    }
                    Bound::HalfSpace { origin, normal } => {
                        cells.query_halfspace(*origin, *normal, pad, ids.len(), &mut hit)
                    }
                    _ => false,
                };
                if !found {
                    brute(ids, bounds, ob, hits);
                }
                hits.sort_unstable();
            });
        for (k, hits) in self.hits[..nothers].iter().enumerate() {
            let o = self.other_ids[k];
            out.extend(hits.iter().map(|&s| (s.min(o), s.max(o))));
        }
        out.sort_unstable();
        Ok(())
    }

    /// Contacts of the pairs of the Verlet list closer than the envelope, appended to
    /// `out` (call after [`candidates`](Self::candidates) in the same step). Skips two
    /// spheres of the same owner, two inactive owners, and excluded owner pairs (`excluded`
    /// sorted).
    pub(crate) fn sphere_contacts(
        &mut self,
        colliders: &[Collider],
        owner_active: &[bool],
        excluded: &[(u32, u32)],
        envelope: f64,
        out: &mut Vec<ContactPoint>,
    ) -> Result<()> {
        let pos = [&self.pos[0][..], &self.pos[1][..], &self.pos[2][..]];
        let nblocks = self.pairs.len().div_ceil(PAIR_BLOCK);
        if self.blocks.len() < nblocks {
            self.blocks.resize_with(nblocks, Vec::new);
        }
        let (ids, radius, pairs) = (&self.ids, &self.radius, &self.pairs);
        self.blocks[..nblocks]
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, block)| {
                block.clear();
                let end = ((k + 1) * PAIR_BLOCK).min(pairs.len());
                for &[i, j] in &pairs[k * PAIR_BLOCK..end] {
                    let (i, j) = (i as usize, j as usize);
                    // Most pairs of the Verlet list are apart: reject them on the squared
                    // distance (with a margin, so the exact test below decides the rest).
                    let reach = radius[i] + radius[j] + envelope;
                    let d = [
                        pos[0][j] - pos[0][i],
                        pos[1][j] - pos[1][i],
                        pos[2][j] - pos[2][i],
                    ];
                    if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > reach * reach * (1.0 + 1e-9) {
                        continue;
                    }
                    let (a, b) = (ids[i], ids[j]);
                    let (ca, cb) = (&colliders[a as usize], &colliders[b as usize]);
                    let (oa, ob) = (ca.owner(), cb.owner());
                    if oa == ob || !(owner_active[oa as usize] || owner_active[ob as usize]) {
                        continue;
                    }
                    if !excluded.is_empty()
                        && excluded.binary_search(&(oa.min(ob), oa.max(ob))).is_ok()
                    {
                        continue;
                    }
                    let pa = Vector::new(pos[0][i], pos[1][i], pos[2][i]);
                    let pb = Vector::new(pos[0][j], pos[1][j], pos[2][j]);
                    let d = pb - pa;
                    let len = d.length();
                    let distance = len - radius[i] - radius[j];
                    if distance.is_nan() || distance >= envelope {
                        continue;
                    }
                    let n = if len > 0.0 { d / len } else { Vector::Z };
                    block.push(ContactPoint {
                        collider_a: ColliderId(a),
                        collider_b: ColliderId(b),
                        owner_a: oa,
                        owner_b: ob,
                        point_a: vec_from_glam(pa + n * radius[i]),
                        point_b: vec_from_glam(pb - n * radius[j]),
                        normal: vec_from_glam(n),
                        distance,
                        key: ContactKey {
                            collider_a: a,
                            collider_b: b,
                            feature_a: FACE0,
                            feature_b: FACE0,
                        },
                        material: ca.material().combine(&cb.material()),
                        radius: super::contact::effective_radius(radius[i], radius[j]),
                    });
                }
            });
        crate::parallel::append_parts(out, &self.blocks[..nblocks]);
        Ok(())
    }
}

/// The sphere centers `poses[ids]` into `pos` (SoA), in parallel, and the largest
/// distance between them and `old` when given (exact max: deterministic; 0 otherwise).
fn gather_centers(
    ids: &[u32],
    poses: &[Pose],
    pos: &mut [Vec<f64>; 3],
    old: Option<&[Vec<f64>; 3]>,
) -> f64 {
    let n = ids.len();
    for p in pos.iter_mut() {
        p.resize(n, 0.0);
    }
    let [px, py, pz] = pos;
    let d2 = (px
        .par_iter_mut()
        .zip(py.par_iter_mut())
        .zip(pz.par_iter_mut()))
    .zip(ids.par_iter())
    .enumerate()
    .with_min_len(4096)
    .map(|(k, (((x, y), z), &i))| {
        let t = poses[i as usize].translation;
        (*x, *y, *z) = (t.x, t.y, t.z);
        match old {
            Some(o) => {
                let d = [t.x - o[0][k], t.y - o[1][k], t.z - o[2][k]];
                d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
            }
            None => 0.0,
        }
    })
    // `max` that keeps a NaN (f64::max drops it): a NaN center must rebind.
    .reduce(
        || 0.0,
        |a, b| {
            if a.is_nan() || b.is_nan() {
                f64::NAN
            } else {
                a.max(b)
            }
        },
    );
    // A NaN center rebinds (and `build` reports it).
    if d2.is_nan() {
        f64::INFINITY
    } else {
        d2.sqrt()
    }
}

/// The grid's cells in world coordinates (axis-aligned, `cell` wide from `lower`).
struct Cells<'a> {
    grid: &'a CellGrid,
    lower: [f64; 3],
    cell: f64,
}

impl Cells<'_> {
    /// Cell index along `axis` of the coordinate `x`, clamped to the grid.
    fn index(&self, axis: usize, x: f64) -> usize {
        let n = self.grid.dims()[axis];
        let t = ((x - self.lower[axis]) / self.cell).floor();
        t.clamp(0.0, (n - 1) as f64) as usize
    }

    /// Calls `f(sphere)` for every sphere binned in a cell that may hold a center within
    /// `pad` (times the normal's 1-norm, the box bound's reach) of the half-space
    /// `{x : (x - origin) . normal <= 0}`: per column of cells along the normal's dominant
    /// axis, the cells up to where the plane leaves the column (the grid's boundary layer
    /// facing the wall). Returns false (without calling `f`) when that covers more cells
    /// than `limit`.
    fn query_halfspace(
        &self,
        origin: Vector,
        normal: Vector,
        pad: f64,
        limit: usize,
        mut f: impl FnMut(usize),
    ) -> bool {
        let n = normal.to_array();
        let k = if n[0].abs() >= n[1].abs() && n[0].abs() >= n[2].abs() {
            0
        } else if n[1].abs() >= n[2].abs() {
            1
        } else {
            2
        };
        let (a, b) = ((k + 1) % 3, (k + 2) % 3);
        if n[k] == 0.0 || !n.iter().all(|x| x.is_finite()) {
            return false;
        }
        let dims = self.grid.dims();
        // Reach of a center: the bound's corner offset, plus a rounding margin.
        let reach = pad * (n[0].abs() + n[1].abs() + n[2].abs()) + 1e-9 * self.cell;
        let on = origin.dot(normal) + reach;
        // Cells [lo, hi] along k of the column (ia, ib) that may hold a center.
        let span = |ia: usize, ib: usize| -> (usize, usize) {
            let side = |axis: usize, i: usize| {
                let lo = self.lower[axis] + i as f64 * self.cell - 1e-9 * self.cell;
                let hi = self.lower[axis] + (i + 1) as f64 * self.cell + 1e-9 * self.cell;
                (n[axis] * lo).min(n[axis] * hi)
            };
            let rest = on - side(a, ia) - side(b, ib);
            // One cell more: the grid bins with `* (1 / cell)`, rounding differently.
            let i = self.index(k, rest / n[k]);
            if n[k] > 0.0 {
                (0, (i + 1).min(dims[k] - 1))
            } else {
                (i.saturating_sub(1), dims[k] - 1)
            }
        };
        let mut count = 0usize;
        for ib in 0..dims[b] {
            for ia in 0..dims[a] {
                let (lo, hi) = span(ia, ib);
                count += hi + 1 - lo;
            }
        }
        if count > limit.max(1) {
            return false;
        }
        let order = self.grid.order();
        for ib in 0..dims[b] {
            for ia in 0..dims[a] {
                let (lo, hi) = span(ia, ib);
                for ik in lo..=hi {
                    let mut c = [0usize; 3];
                    (c[k], c[a], c[b]) = (ik, ia, ib);
                    let cell = c[0] + dims[0] * (c[1] + dims[1] * c[2]);
                    for slot in self.grid.cell_range(cell) {
                        f(order[slot] as usize);
                    }
                }
            }
        }
        true
    }
}

/// Every sphere whose bound overlaps `ob`, ascending.
fn brute(ids: &[u32], bounds: &[Bound], ob: &Bound, hits: &mut Vec<u32>) {
    hits.extend(
        ids.iter()
            .copied()
            .filter(|&s| bounds_overlap(ob, &bounds[s as usize])),
    );
}

/// Calls `f(sphere)` for every sphere binned in the cells under the box `b` grown by
/// `pad`. Returns false (without calling `f`) when the box covers more cells than
/// `limit`: testing every sphere is cheaper then.
fn query_box(grid: &CellGrid, b: &Aabb, pad: f64, limit: usize, mut f: impl FnMut(usize)) -> bool {
    let lo = grid.cell_coords([b.mins.x - pad, b.mins.y - pad, b.mins.z - pad]);
    let hi = grid.cell_coords([b.maxs.x + pad, b.maxs.y + pad, b.maxs.z + pad]);
    let count: usize = (0..3).map(|a| hi[a] + 1 - lo[a]).product();
    if count > limit.max(1) {
        return false;
    }
    let dims = grid.dims();
    let order = grid.order();
    for iz in lo[2]..=hi[2] {
        for iy in lo[1]..=hi[1] {
            for ix in lo[0]..=hi[0] {
                let c = ix + dims[0] * (iy + dims[1] * iz);
                for slot in grid.cell_range(c) {
                    f(order[slot] as usize);
                }
            }
        }
    }
    true
}
