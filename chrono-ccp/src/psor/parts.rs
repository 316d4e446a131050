//! Partitioned parallel sweeps of [`Psor`](super::Psor): the variable blocks are cut into
//! contiguous ranges (one per part), each part sweeps the units that touch only its own
//! blocks in Gauss–Seidel order on its own thread, then the units that straddle two parts
//! (the interface) are swept on one thread. Inside a part the order is the storage order,
//! as in the sequential sweep, so each part is plain Gauss–Seidel; only the interface
//! units move to the end of the sweep (the backward sweep visits the interface first).
//! This is the block (domain-decomposition) ordering of Gauss–Seidel, not the coloured one:
//! every unit reads the velocities its predecessors in its part just changed, where a
//! coloured sweep updates a whole colour from the same velocities (Jacobi within the
//! colour), which converged 3x slower on the granular pour (docs/performance.md).
//!
//! Each part owns the window `dof[k]..dof[k + 1]` of `w = M^-1 D g` (blocks are contiguous
//! in dof) and writes only its own units' rows of `g`, which are held as bits in
//! `AtomicU64`s so that the parts can share the vector without `unsafe` (relaxed loads and
//! stores: plain moves; no two parts touch the same row). The partition depends on the
//! number of parts only, so results are bit-reproducible for a given number of parts
//! (the solver takes the rayon thread count).

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use chrono_core::descriptor::{BlockId, CcpProblem};
use rayon::prelude::*;

use super::unit::{as_triplet, triplet};
use super::{SweepData, Unit, Vel, apply_update, unit_update};
use crate::dense::MAX_BLOCK;

/// Fewest units per part: below this, a part is too small to pay for its thread.
pub(super) const MIN_UNITS_PER_PART: usize = 2048;

/// The units of each part and of the interface, and each part's dof window (rebuilt every
/// solve into the same buffers: no allocation once they have grown).
#[derive(Debug, Clone, Default)]
pub(super) struct Partition {
    /// Part `k` owns the dof `dof[k]..dof[k + 1]` and the pure spheres
    /// `sph[k]..sph[k + 1]` (matrix-free sweeps).
    dof: Vec<usize>,
    sph: Vec<usize>,
    /// Units (indices into the solver's units) of part `k`: `order[ptr[k]..ptr[k + 1]]`,
    /// storage order; the interface units are `order[ptr[parts]..]`.
    order: Vec<u32>,
    ptr: Vec<usize>,
    /// Scratch: each unit's lowest and highest block, units per block, the cuts, each
    /// unit's part.
    spans: Vec<(u32, u32)>,
    count: Vec<usize>,
    cut: Vec<usize>,
    part: Vec<u32>,
}

impl Partition {
    /// Cut the blocks into `parts` contiguous ranges holding about equal numbers of units
    /// (each unit counted half at its lowest and half at its highest block). False (and no
    /// parts) if fewer than two parts would have [`MIN_UNITS_PER_PART`] units each.
    pub(super) fn rebuild(&mut self, problem: &CcpProblem, units: &[Unit], parts: usize) -> bool {
        let parts = parts.min(units.len() / MIN_UNITS_PER_PART);
        if parts < 2 {
            return false;
        }
        let vars = problem.variables();
        let nb = vars.len();
        // each unit's lowest and highest block
        let span = |u: &Unit| {
            let (start, len) = u.rows();
            let (mut lo, mut hi) = (u32::MAX, 0u32);
            for i in start..start + len {
                for b in problem.row_blocks(i) {
                    lo = lo.min(b.0);
                    hi = hi.max(b.0);
                }
            }
            (lo, hi)
        };
        self.spans.clear();
        (self.spans).par_extend(units.par_iter().with_min_len(MIN_UNITS_PER_PART).map(span));
        // each unit counted half at its lowest and half at its highest block, so the
        // units that straddle a cut weigh on both sides (counted at the lowest only, the
        // upper part of the 10 000-grain pour got 15.6k units against 13.1k)
        self.count.clear();
        self.count.resize(nb + 1, 0);
        for &(lo, hi) in &self.spans {
            if lo != u32::MAX {
                self.count[lo as usize] += 1;
                self.count[hi as usize] += 1;
            }
        }
        // cut[k]: the first block of part k
        let total: usize = self.count.iter().sum();
        let cut = &mut self.cut;
        cut.clear();
        cut.push(0);
        let mut acc = 0;
        for (b, c) in self.count.iter().enumerate().take(nb) {
            // part k starts at the first block after k / parts of the units
            if cut.len() < parts && b > cut[cut.len() - 1] && acc * parts >= cut.len() * total {
                cut.push(b);
            }
            acc += c;
        }
        if cut.len() < 2 {
            return false;
        }
        cut.push(nb);
        let n_parts = cut.len() - 1;
        let part_of = |b: u32| cut.partition_point(|&c| c <= b as usize) - 1;
        // each unit's part (the interface is part n_parts), then a counting sort that keeps
        // the storage order within a part
        self.part.clear();
        self.part.extend(self.spans.iter().map(|&(lo, hi)| {
            if lo == u32::MAX {
                // a unit without blocks (a row on fixed bodies only) touches no window
                0
            } else if part_of(lo) == part_of(hi) {
                part_of(lo) as u32
            } else {
                n_parts as u32
            }
        }));
        self.ptr.clear();
        self.ptr.resize(n_parts + 2, 0);
        for &k in &self.part {
            self.ptr[k as usize + 1] += 1;
        }
        for k in 0..=n_parts {
            self.ptr[k + 1] += self.ptr[k];
        }
        self.order.clear();
        self.order.resize(units.len(), 0);
        // (`count` is done with: the next free slot of each part)
        let next = &mut self.count;
        next.clear();
        next.extend_from_slice(&self.ptr);
        for (u, &k) in self.part.iter().enumerate() {
            self.order[next[k as usize]] = u as u32;
            next[k as usize] += 1;
        }
        self.ptr.pop();
        let offset = |b: usize| {
            if b < nb {
                vars.offset(BlockId(b as u32))
            } else {
                problem.ndof()
            }
        };
        self.dof.clear();
        self.dof.extend(cut.iter().map(|&b| offset(b)));
        self.sph.clear();
        self.sph
            .extend(cut.iter().map(|&b| problem.mf_spheres_before(b)));
        true
    }

    /// The number of parts.
    pub(super) fn parts(&self) -> usize {
        self.dof.len() - 1
    }

    /// One sweep, forwards (parts in parallel, then the interface) or backwards (the
    /// interface reversed, then the parts in parallel, each reversed).
    pub(super) fn sweep(
        &self,
        data: &SweepData,
        units: &[Unit],
        g: &[AtomicU64],
        w: &mut [f64],
        ws: &mut [f64],
        forward: bool,
    ) {
        self.run(w, ws, !forward, |list, vel| {
            if forward {
                sweep_units(data, units, list.iter(), g, vel);
            } else {
                sweep_units(data, units, list.iter().rev(), g, vel);
            }
        });
    }

    /// `f(units, window)` for every part in parallel (each with its window of `w` and
    /// `ws`), and for the interface units with the whole vectors, before the parts if
    /// `interface_first`, else after.
    fn run(
        &self,
        w: &mut [f64],
        ws: &mut [f64],
        interface_first: bool,
        f: impl Fn(&[u32], &mut Vel) + Sync,
    ) {
        let n = self.parts();
        let interface = &self.order[self.ptr[n]..];
        if interface_first {
            f(interface, &mut Vel::whole(w, ws));
        }
        // split w and ws into the parts' windows (no sphere windows without matrix-free
        // sweeps)
        let no_spheres = ws.is_empty();
        let sph = |k: usize| if no_spheres { 0 } else { self.sph[k] };
        let mut windows = Vec::with_capacity(n);
        let (mut rest, mut srest) = (&mut w[..], &mut ws[..]);
        let (mut at, mut sat) = (0, 0);
        for k in 0..n {
            let (mine, tail) = rest.split_at_mut(self.dof[k + 1] - at);
            let (smine, stail) = srest.split_at_mut(6 * (sph(k + 1) - sat));
            windows.push((
                k,
                Vel {
                    w: mine,
                    base: self.dof[k],
                    ws: smine,
                    sbase: sph(k),
                },
            ));
            (rest, srest) = (tail, stail);
            (at, sat) = (self.dof[k + 1], sph(k + 1));
        }
        windows
            .into_par_iter()
            .for_each(|(k, mut vel)| f(&self.order[self.ptr[k]..self.ptr[k + 1]], &mut vel));
        if !interface_first {
            f(interface, &mut Vel::whole(w, ws));
        }
    }
}

/// Gauss–Seidel over `list` with `w` the window from dof `base`.
fn sweep_units<'a>(
    data: &SweepData,
    units: &[Unit],
    list: impl Iterator<Item = &'a u32>,
    g: &[AtomicU64],
    vel: &mut Vel,
) {
    for &u in list {
        let unit = units[u as usize];
        if let Some((t, k)) = as_triplet(data, unit) {
            let cur = [0, 1, 2].map(|j| f64::from_bits(g[t + j].load(Relaxed)));
            let new = triplet(data, t, k, cur, vel);
            for j in 0..3 {
                if new[j] != cur[j] {
                    g[t + j].store(new[j].to_bits(), Relaxed);
                }
            }
            continue;
        }
        let (start, len) = unit.rows();
        let mut cur = [0.0; MAX_BLOCK];
        for j in 0..len {
            cur[j] = f64::from_bits(g[start + j].load(Relaxed));
        }
        let d = unit_update(data, unit, &cur, &vel.read());
        apply_update(data, unit, &d, &cur, vel);
        for j in 0..len {
            if d.new[j] != cur[j] {
                g[start + j].store(d.new[j].to_bits(), Relaxed);
            }
        }
    }
}

/// `g` shared by the parts of a sweep, each row's bits in an `AtomicU64`. Scratch of one
/// solve: a clone starts empty.
#[derive(Debug, Default)]
pub(super) struct Shared(Vec<AtomicU64>);

impl Clone for Shared {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Shared {
    /// `g` into the shared copy (in parallel).
    pub(super) fn store(&mut self, g: &[f64]) {
        self.0.resize_with(g.len(), || AtomicU64::new(0));
        self.0
            .par_iter_mut()
            .zip(g.par_iter())
            .with_min_len(4096)
            .for_each(|(a, &x)| *a.get_mut() = x.to_bits());
    }

    /// The shared copy back into `g` (in parallel).
    pub(super) fn load(&mut self, g: &mut [f64]) {
        g.par_iter_mut()
            .zip(self.0.par_iter_mut())
            .with_min_len(4096)
            .for_each(|(x, a)| *x = f64::from_bits(*a.get_mut()));
    }

    /// The rows.
    pub(super) fn rows(&self) -> &[AtomicU64] {
        &self.0
    }
}
