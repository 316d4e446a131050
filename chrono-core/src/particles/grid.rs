//! The uniform cell grid: particles binned by a counting sort on the cell index, queried
//! for all neighbours within a radius.
//!
//! One grid serves the sphere broad phase (DEM), SPH and constraint-fluid neighbour
//! lists, and MPM particle binning. The cells are at least `cutoff` wide, so every
//! neighbour within `cutoff` of a particle lies in the 3 x 3 x 3 block of cells around
//! it. A build costs `O(N + cells)`:
//!
//! 1. the cell of every particle is computed (in parallel, rayon);
//! 2. a counting sort (histogram, exclusive prefix sum, stable scatter) gives the
//!    permutation [`order`](CellGrid::order) (`order[k]` is the particle in sorted slot
//!    `k`) and the cell ranges [`cell_start`](CellGrid::cell_start)
//!    (`cell_start[c]..cell_start[c + 1]` are the slots of cell `c`). This pass is
//!    serial: it streams memory once and the scatter is nearly in order when the caller
//!    keeps its arrays sorted, so threads do not pay here (measured in `docs/performance.md`).
//!
//! Callers that want memory locality reorder their structure-of-arrays data by
//! [`order`](CellGrid::order) every few builds ([`permute`]) and then call
//! [`CellGrid::reordered`], after which particle `k` is slot `k`.
//!
//! Domain: fixed bounds (particles outside are clamped into the edge cells on
//! non-periodic axes, which keeps every query exact, only slower if many are outside) or
//! automatic bounds (the bounding box of the particles at each build). The number of
//! cells is capped at [`MAX_CELLS`]; a spread-out cloud in auto mode is an error rather
//! than a huge allocation (a spatial hash would lift this; not implemented).
//!
//! Periodic directions are handled **in the grid**: cell indices wrap and distances use
//! the minimum-image convention `d -= L round(d / L)`, which requires `radius <= L / 2`
//! (checked). Positions need not be wrapped into the box, though callers usually do.
//!
//! Output order is deterministic (independent of the thread count): neighbour lists
//! follow the stencil order (z, then y, then x cells ascending) and the sorted slot order
//! within a cell. After a warm-up build, no call allocates unless the particle count,
//! cell count or a neighbour count grows past its previous maximum.

use std::ops::Range;

use rayon::prelude::*;

use crate::error::{ChronoError, Result};

/// Positions in structure-of-arrays form: `[x, y, z]`, each of length `n`, m.
pub type Positions<'a> = [&'a [f64]; 3];

/// The largest number of cells a grid may allocate.
pub const MAX_CELLS: usize = 1 << 27;

/// Particles per task when neighbour lists and pairs are built in parallel.
const BLOCK: usize = 1024;

/// Bounds and periodicity of a [`CellGrid`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridConfig {
    /// The largest query radius, m (`> 0`). Cells are at least this wide.
    pub cutoff: f64,
    /// `Some((lower, upper))`: a fixed box, m. `None`: the bounding box of the particles
    /// at each build (no periodic axis allowed).
    pub bounds: Option<([f64; 3], [f64; 3])>,
    /// Periodic axes (x, y, z); a periodic axis needs fixed bounds, its period is
    /// `upper - lower`, which must be at least `2 cutoff`.
    pub periodic: [bool; 3],
}

impl GridConfig {
    /// A fixed box `[lower, upper]`, not periodic.
    pub fn bounded(cutoff: f64, lower: [f64; 3], upper: [f64; 3]) -> Self {
        Self {
            cutoff,
            bounds: Some((lower, upper)),
            periodic: [false; 3],
        }
    }

    /// Bounds taken from the particles at each build (for unbounded scenes).
    pub fn auto(cutoff: f64) -> Self {
        Self {
            cutoff,
            bounds: None,
            periodic: [false; 3],
        }
    }

    /// The same configuration with the given periodic axes.
    pub fn with_periodic(mut self, periodic: [bool; 3]) -> Self {
        self.periodic = periodic;
        self
    }
}

/// A neighbour list in compressed-row (CSR) form: the neighbours of particle `i` are
/// `indices[offsets[i]..offsets[i + 1]]` (particle `i` itself excluded), in the grid's
/// deterministic order. Reuse one list across builds: its buffers are kept.
#[derive(Debug, Clone, Default)]
pub struct NeighborList {
    /// Row offsets, length `n + 1`.
    pub offsets: Vec<usize>,
    /// Neighbour indices, length `offsets[n]`.
    pub indices: Vec<u32>,
    blocks: Vec<Vec<u32>>,
}

impl NeighborList {
    /// An empty list.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of rows (particles).
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The neighbours of particle `i`.
    #[inline]
    pub fn neighbors(&self, i: usize) -> &[u32] {
        &self.indices[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Total number of (directed) entries, `sum_i |N(i)|`.
    pub fn total(&self) -> usize {
        self.indices.len()
    }
}

/// Scratch buffers of [`CellGrid::unique_pairs`], reused across calls.
#[derive(Debug, Clone, Default)]
pub struct PairScratch {
    blocks: Vec<Vec<[u32; 2]>>,
}

/// The uniform cell grid (see the [module documentation](self)).
#[derive(Debug, Clone)]
pub struct CellGrid {
    config: GridConfig,
    lower: [f64; 3],
    dims: [usize; 3],
    inv_cell: [f64; 3],
    period: [f64; 3],
    /// Whether some axis is periodic (else displacements are plain differences).
    any_periodic: bool,
    cell_of: Vec<u32>,
    order: Vec<u32>,
    cell_start: Vec<u32>,
    scratch: Vec<u32>,
}

impl CellGrid {
    /// A grid for `config`, empty until [`build`](Self::build).
    ///
    /// Errors: `cutoff` not finite and positive, bounds not finite or `upper <= lower`
    /// on an axis, a periodic axis without bounds or shorter than `2 cutoff`, or more
    /// than [`MAX_CELLS`] cells.
    pub fn new(config: GridConfig) -> Result<Self> {
        crate::error::check_positive("grid.cutoff", config.cutoff)?;
        let mut grid = Self {
            config,
            lower: [0.0; 3],
            dims: [1; 3],
            inv_cell: [1.0 / config.cutoff; 3],
            period: [0.0; 3],
            any_periodic: config.periodic.iter().any(|&p| p),
            cell_of: Vec::new(),
            order: Vec::new(),
            cell_start: vec![0, 0],
            scratch: Vec::new(),
        };
        match config.bounds {
            Some((lo, hi)) => {
                for a in 0..3 {
                    crate::error::check_finite(&format!("grid.lower[{a}]"), lo[a])?;
                    crate::error::check_finite(&format!("grid.upper[{a}]"), hi[a])?;
                    if hi[a] <= lo[a] {
                        return Err(ChronoError::invalid(
                            format!("grid.upper[{a}]"),
                            hi[a],
                            format!("must exceed grid.lower[{a}] = {}", lo[a]),
                        ));
                    }
                }
                grid.set_box(lo, hi)?;
            }
            None => {
                if let Some(a) = config.periodic.iter().position(|&p| p) {
                    return Err(ChronoError::invalid(
                        format!("grid.periodic[{a}]"),
                        true,
                        "a periodic axis needs fixed bounds",
                    ));
                }
            }
        }
        Ok(grid)
    }

    fn set_box(&mut self, lo: [f64; 3], hi: [f64; 3]) -> Result<()> {
        let c = self.config.cutoff;
        let mut total = 1usize;
        for a in 0..3 {
            let len = hi[a] - lo[a];
            if self.config.periodic[a] {
                if len < 2.0 * c {
                    return Err(ChronoError::invalid(
                        format!("grid period along axis {a}"),
                        len,
                        format!("must be at least 2 cutoff = {}", 2.0 * c),
                    ));
                }
                let n = ((len / c).floor() as usize).max(1);
                self.dims[a] = n;
                self.inv_cell[a] = n as f64 / len;
                self.period[a] = len;
            } else {
                let n = ((len / c).ceil() as usize).max(1);
                self.dims[a] = n;
                self.inv_cell[a] = 1.0 / c;
                self.period[a] = 0.0;
            }
            total = total.saturating_mul(self.dims[a]);
        }
        if total > MAX_CELLS {
            return Err(ChronoError::invalid(
                "grid cell count",
                total,
                format!("exceeds {MAX_CELLS}: the box is too large for the cutoff"),
            ));
        }
        self.lower = lo;
        Ok(())
    }

    /// The configuration.
    pub fn config(&self) -> &GridConfig {
        &self.config
    }

    /// Cells along x, y, z (of the last build for automatic bounds).
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Number of particles of the last build.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Whether the last build had no particle.
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// The sorted permutation: `order()[k]` is the particle in sorted slot `k`.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Cell ranges: the slots of cell `c` are `cell_start()[c]..cell_start()[c + 1]`.
    pub fn cell_start(&self) -> &[u32] {
        &self.cell_start
    }

    /// The cell (linear index `ix + nx (iy + ny iz)`) of particle `i` at the last build.
    pub fn cell_of(&self, i: usize) -> usize {
        self.cell_of[i] as usize
    }

    /// The sorted slots of cell `c`.
    pub fn cell_range(&self, c: usize) -> Range<usize> {
        self.cell_start[c] as usize..self.cell_start[c + 1] as usize
    }

    /// Integer cell coordinates of a point (clamped or wrapped as the axes say).
    #[inline]
    pub fn cell_coords(&self, p: [f64; 3]) -> [usize; 3] {
        let mut c = [0usize; 3];
        for a in 0..3 {
            let t = ((p[a] - self.lower[a]) * self.inv_cell[a]).floor();
            let n = self.dims[a] as i64;
            // `as i64` saturates (NaN -> 0); positions are checked in `build`.
            let i = t as i64;
            c[a] = if self.config.periodic[a] {
                i.rem_euclid(n) as usize
            } else {
                i.clamp(0, n - 1) as usize
            };
        }
        c
    }

    #[inline]
    fn linear(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    #[inline]
    fn unlinear(&self, c: usize) -> [usize; 3] {
        let x = c % self.dims[0];
        let r = c / self.dims[0];
        [x, r % self.dims[1], r / self.dims[1]]
    }

    /// Bins `n` particles. Errors when the slices differ in length, a position is not
    /// finite (naming the particle), there are `u32::MAX` particles or more, or (auto
    /// bounds) the cloud needs more than [`MAX_CELLS`] cells.
    pub fn build(&mut self, pos: Positions<'_>) -> Result<()> {
        let n = pos[0].len();
        if pos[1].len() != n || pos[2].len() != n {
            return Err(ChronoError::invalid(
                "positions",
                format!("[{}, {}, {}]", n, pos[1].len(), pos[2].len()),
                "x, y and z must have the same length",
            ));
        }
        if n >= u32::MAX as usize {
            return Err(ChronoError::invalid(
                "positions.len()",
                n,
                "must be < 2^32 - 1",
            ));
        }
        for (a, coord) in pos.iter().enumerate() {
            if let Some(i) = coord.par_iter().position_first(|v| !v.is_finite()) {
                return Err(ChronoError::invalid(
                    format!("position[{i}][{a}]"),
                    coord[i],
                    "particle position must be finite",
                ));
            }
        }
        if self.config.bounds.is_none() {
            let mut lo = [0.0; 3];
            let mut hi = [0.0; 3];
            for a in 0..3 {
                let (mn, mx) = pos[a]
                    .par_iter()
                    .fold(
                        || (f64::INFINITY, f64::NEG_INFINITY),
                        |(mn, mx), &v| (mn.min(v), mx.max(v)),
                    )
                    .reduce(
                        || (f64::INFINITY, f64::NEG_INFINITY),
                        |(a0, b0), (a1, b1)| (a0.min(a1), b0.max(b1)),
                    );
                lo[a] = if n == 0 { 0.0 } else { mn };
                // One cell of margin so that the upper point is strictly inside.
                hi[a] = if n == 0 {
                    self.config.cutoff
                } else {
                    mx + self.config.cutoff
                };
            }
            self.set_box(lo, hi)?;
        }
        let ncells = self.num_cells();
        self.cell_of.resize(n, 0);
        let mut cell_of = std::mem::take(&mut self.cell_of);
        {
            let this = &*self;
            cell_of.par_iter_mut().enumerate().for_each(|(i, c)| {
                *c = this.linear(this.cell_coords([pos[0][i], pos[1][i], pos[2][i]])) as u32;
            });
        }
        self.cell_of = cell_of;
        // Counting sort: histogram, exclusive prefix sum, stable scatter.
        self.cell_start.clear();
        self.cell_start.resize(ncells + 1, 0);
        for &c in &self.cell_of {
            self.cell_start[c as usize + 1] += 1;
        }
        for c in 0..ncells {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        self.scratch.clear();
        self.scratch.extend_from_slice(&self.cell_start[..ncells]);
        self.order.resize(n, 0);
        for (i, &c) in self.cell_of.iter().enumerate() {
            let slot = &mut self.scratch[c as usize];
            self.order[*slot as usize] = i as u32;
            *slot += 1;
        }
        Ok(())
    }

    /// Tells the grid that the caller has reordered its particle arrays by
    /// [`order`](Self::order) (particle `order[k]` is now particle `k`, see [`permute`]):
    /// the grid's per-particle data follows, and `order` becomes the identity.
    pub fn reordered(&mut self) {
        self.scratch.clear();
        self.scratch
            .extend(self.order.iter().map(|&i| self.cell_of[i as usize]));
        std::mem::swap(&mut self.scratch, &mut self.cell_of);
        self.order
            .par_iter_mut()
            .enumerate()
            .for_each(|(k, o)| *o = k as u32);
    }

    /// Checks that `radius` is usable: finite, `> 0`, `<= cutoff`, and `<= L / 2` on
    /// periodic axes.
    pub fn check_radius(&self, radius: f64) -> Result<()> {
        crate::error::check_positive("radius", radius)?;
        if radius > self.config.cutoff * (1.0 + 1e-12) {
            return Err(ChronoError::invalid(
                "radius",
                radius,
                format!("must not exceed the grid cutoff {}", self.config.cutoff),
            ));
        }
        Ok(())
    }

    /// The up to three distinct neighbour cells of `c` along axis `a`, ascending.
    #[inline]
    fn axis_stencil(&self, a: usize, c: usize) -> ([usize; 3], usize) {
        let n = self.dims[a];
        let mut out = [0usize; 3];
        if self.config.periodic[a] {
            match n {
                1 => (out, 1),
                2 => ([0, 1, 0], 2),
                _ => {
                    let mut v = [(c + n - 1) % n, c, (c + 1) % n];
                    v.sort_unstable();
                    (v, 3)
                }
            }
        } else {
            let mut k = 0;
            for d in [c.wrapping_sub(1), c, c + 1] {
                if d < n {
                    out[k] = d;
                    k += 1;
                }
            }
            (out, k)
        }
    }

    /// The period of each axis, m (0 where the axis is not periodic): the minimum image
    /// of [`displacement`](Self::displacement) wraps by it.
    pub fn periods(&self) -> [f64; 3] {
        self.period
    }

    /// Minimum-image displacement `p - q` (periodic axes wrapped).
    #[inline]
    pub fn displacement(&self, p: [f64; 3], q: [f64; 3]) -> [f64; 3] {
        let mut d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        if !self.any_periodic {
            return d;
        }
        for a in 0..3 {
            let l = self.period[a];
            if l > 0.0 {
                // one compare for the usual case (wrapped positions); `round` (a libm
                // call without SSE4.1) only for points more than 1.5 periods apart
                let half = 0.5 * l;
                if d[a] > half {
                    d[a] -= l;
                } else if d[a] < -half {
                    d[a] += l;
                }
                if d[a].abs() > half {
                    d[a] -= l * (d[a] / l).round();
                }
            }
        }
        d
    }

    /// Calls `f(j, p - x_j, |p - x_j|^2)` for every particle `j` with `keep(j)` and
    /// `|p - x_j| <= radius`, around the point `p` in the cell `cell` (`keep` is asked
    /// before the distance is computed). `radius` must
    /// satisfy [`check_radius`](Self::check_radius) (the public callers check it).
    #[inline]
    fn visit<F: FnMut(usize, [f64; 3], f64)>(
        &self,
        pos: Positions<'_>,
        p: [f64; 3],
        cell: [usize; 3],
        radius: f64,
        keep: impl Fn(usize) -> bool,
        mut f: F,
    ) {
        let r2max = radius * radius;
        let (zs, nz) = self.axis_stencil(2, cell[2]);
        let (ys, ny) = self.axis_stencil(1, cell[1]);
        let (xs, nx) = self.axis_stencil(0, cell[0]);
        let [px, py, pz] = pos;
        for &cz in &zs[..nz] {
            for &cy in &ys[..ny] {
                let row = self.dims[0] * (cy + self.dims[1] * cz);
                // Merge runs of consecutive x cells into one slot range.
                let mut k = 0;
                while k < nx {
                    let first = xs[k];
                    let mut last = first;
                    while k + 1 < nx && xs[k + 1] == last + 1 {
                        k += 1;
                        last = xs[k];
                    }
                    k += 1;
                    let s = self.cell_start[row + first] as usize;
                    let e = self.cell_start[row + last + 1] as usize;
                    for &j in &self.order[s..e] {
                        let j = j as usize;
                        if !keep(j) {
                            continue;
                        }
                        let d = self.displacement(p, [px[j], py[j], pz[j]]);
                        let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        if r2 <= r2max {
                            f(j, d, r2);
                        }
                    }
                }
            }
        }
    }

    /// Calls `f(j, x_i - x_j, r^2)` for every neighbour `j != i` of particle `i` within
    /// `radius` (positions as passed to the last [`build`](Self::build)).
    pub fn for_each_neighbor<F: FnMut(usize, [f64; 3], f64)>(
        &self,
        pos: Positions<'_>,
        i: usize,
        radius: f64,
        f: F,
    ) -> Result<()> {
        self.check_radius(radius)?;
        let p = [pos[0][i], pos[1][i], pos[2][i]];
        self.visit(
            pos,
            p,
            self.unlinear(self.cell_of[i] as usize),
            radius,
            |j| j != i,
            f,
        );
        Ok(())
    }

    /// Calls `f(j, p - x_j, r^2)` for every particle `j` within `radius` of the point
    /// `p` (a probe or sensor).
    pub fn for_each_in_radius<F: FnMut(usize, [f64; 3], f64)>(
        &self,
        pos: Positions<'_>,
        p: [f64; 3],
        radius: f64,
        f: F,
    ) -> Result<()> {
        self.check_radius(radius)?;
        for (a, v) in p.iter().enumerate() {
            crate::error::check_finite(&format!("point[{a}]"), *v)?;
        }
        self.visit(pos, p, self.cell_coords(p), radius, |_| true, f);
        Ok(())
    }

    /// Builds the CSR neighbour list of every particle (itself excluded) within
    /// `radius`, in parallel over blocks of particles; deterministic.
    pub fn neighbor_list(
        &self,
        pos: Positions<'_>,
        radius: f64,
        list: &mut NeighborList,
    ) -> Result<()> {
        self.neighbor_list_filtered(pos, radius, list, |_, _| true)
    }

    /// [`neighbor_list`](Self::neighbor_list) keeping only the entries `j` of row `i`
    /// with `keep(i, j)` (e.g. SPH wall markers, which need only their fluid
    /// neighbours); the order of the kept entries is unchanged. `keep` is called from
    /// several threads.
    pub fn neighbor_list_filtered<K: Fn(usize, usize) -> bool + Sync>(
        &self,
        pos: Positions<'_>,
        radius: f64,
        list: &mut NeighborList,
        keep: K,
    ) -> Result<()> {
        self.neighbor_list_rows(pos, radius, list, |_| true, keep)
    }

    /// [`neighbor_list_filtered`](Self::neighbor_list_filtered) for the rows `i` with
    /// `row(i)` only: the other rows are left empty without visiting their cells (e.g.
    /// the frozen particles of an SPH active domain, which no pass evaluates). `row` and
    /// `keep` are called from several threads.
    pub fn neighbor_list_rows<R, K>(
        &self,
        pos: Positions<'_>,
        radius: f64,
        list: &mut NeighborList,
        row: R,
        keep: K,
    ) -> Result<()>
    where
        R: Fn(usize) -> bool + Sync,
        K: Fn(usize, usize) -> bool + Sync,
    {
        self.check_radius(radius)?;
        let n = self.len();
        if pos[0].len() != n {
            return Err(ChronoError::invalid(
                "positions.len()",
                pos[0].len(),
                format!("must equal the particle count of the last build ({n})"),
            ));
        }
        let nblocks = n.div_ceil(BLOCK);
        if list.blocks.len() < nblocks {
            list.blocks.resize_with(nblocks, Vec::new);
        }
        list.offsets.resize(n + 1, 0);
        list.offsets[0] = 0;
        list.blocks[..nblocks]
            .par_iter_mut()
            .zip(list.offsets[1..].par_chunks_mut(BLOCK))
            .enumerate()
            .for_each(|(b, (buf, counts))| {
                buf.clear();
                for (k, count) in counts.iter_mut().enumerate() {
                    let i = b * BLOCK + k;
                    let before = buf.len();
                    if !row(i) {
                        *count = 0;
                        continue;
                    }
                    let p = [pos[0][i], pos[1][i], pos[2][i]];
                    let cell = self.unlinear(self.cell_of[i] as usize);
                    self.visit(
                        pos,
                        p,
                        cell,
                        radius,
                        |j| j != i,
                        |j, _, _| {
                            if keep(i, j) {
                                buf.push(j as u32)
                            }
                        },
                    );
                    *count = buf.len() - before;
                }
            });
        for i in 0..n {
            list.offsets[i + 1] += list.offsets[i];
        }
        list.indices.resize(list.offsets[n], 0);
        copy_blocks(&list.blocks[..nblocks], &mut list.indices);
        Ok(())
    }

    /// Calls `f(i, j, x_i - x_j, r^2)` once for every unordered pair with `i < j` and
    /// `r <= radius` (serial; ordered by `i`, then the stencil order).
    pub fn for_each_pair<F: FnMut(usize, usize, [f64; 3], f64)>(
        &self,
        pos: Positions<'_>,
        radius: f64,
        mut f: F,
    ) -> Result<()> {
        self.check_radius(radius)?;
        for i in 0..self.len() {
            let p = [pos[0][i], pos[1][i], pos[2][i]];
            let cell = self.unlinear(self.cell_of[i] as usize);
            // Only `j > i` (the pairs reported) has its distance computed.
            self.visit(pos, p, cell, radius, |j| j > i, |j, d, r2| f(i, j, d, r2));
        }
        Ok(())
    }

    /// Collects every unordered pair `[i, j]` with `i < j` and `r <= radius` into `out`
    /// (cleared first), in parallel; the order is that of
    /// [`for_each_pair`](Self::for_each_pair) (deterministic). The DEM broad phase.
    pub fn unique_pairs(
        &self,
        pos: Positions<'_>,
        radius: f64,
        scratch: &mut PairScratch,
        out: &mut Vec<[u32; 2]>,
    ) -> Result<()> {
        self.check_radius(radius)?;
        let n = self.len();
        let nblocks = n.div_ceil(BLOCK);
        if scratch.blocks.len() < nblocks {
            scratch.blocks.resize_with(nblocks, Vec::new);
        }
        scratch.blocks[..nblocks]
            .par_iter_mut()
            .enumerate()
            .for_each(|(b, buf)| {
                buf.clear();
                for i in b * BLOCK..((b + 1) * BLOCK).min(n) {
                    let p = [pos[0][i], pos[1][i], pos[2][i]];
                    let cell = self.unlinear(self.cell_of[i] as usize);
                    // Only `j > i` (the pairs reported) has its distance computed.
                    self.visit(
                        pos,
                        p,
                        cell,
                        radius,
                        |j| j > i,
                        |j, _, _| {
                            buf.push([i as u32, j as u32]);
                        },
                    );
                }
            });
        out.clear();
        for b in &scratch.blocks[..nblocks] {
            out.extend_from_slice(b);
        }
        Ok(())
    }
}

/// Copies the blocks back to back into `dst` (whose length is their total), in parallel.
fn copy_blocks(blocks: &[Vec<u32>], dst: &mut [u32]) {
    if blocks.len() <= 8 {
        let mut o = 0;
        for b in blocks {
            dst[o..o + b.len()].copy_from_slice(b);
            o += b.len();
        }
        return;
    }
    let mid = blocks.len() / 2;
    let left: usize = blocks[..mid].iter().map(Vec::len).sum();
    let (dl, dr) = dst.split_at_mut(left);
    rayon::join(
        || copy_blocks(&blocks[..mid], dl),
        || copy_blocks(&blocks[mid..], dr),
    );
}

/// Reorders `data` by `order` (`data[k] <- data[order[k]]`), through `scratch` (whose
/// buffer is swapped in, so both keep their capacity). Use it on every array of a
/// structure of arrays with [`CellGrid::order`], then call [`CellGrid::reordered`].
pub fn permute<T: Copy + Send + Sync>(order: &[u32], data: &mut Vec<T>, scratch: &mut Vec<T>) {
    assert_eq!(
        order.len(),
        data.len(),
        "permute: order and data lengths differ"
    );
    scratch.clear();
    scratch.reserve(data.len());
    // Parallel gather into the spare capacity would need unsafe; extend is serial but
    // streams (the data are nearly sorted already).
    scratch.extend(order.iter().map(|&i| data[i as usize]));
    std::mem::swap(data, scratch);
}

#[cfg(test)]
mod tests;
