//! Domain decomposition of an [`SphSystem`](crate::SphSystem) over several processes
//! (ranks): slabs along one axis, halo (ghost) layers, migration, global reductions.
//!
//! **Decomposition.** The domain is cut along one non-periodic axis into `R` slabs
//! `[b_r, b_{r+1})` (`b_0 = -inf`, `b_R = +inf`), chosen so each rank has about the
//! same work (a fluid particle weighs 1, a wall marker
//! [`DistributedSettings::wall_weight`]): the initial cut points are the `k W / R`
//! weighted quantiles of the particles' coordinates along the axis,
//! placed half-way between two distinct coordinates ([`Slabs::balanced`]); every
//! [`DistributedSettings::rebalance_every`] neighbour-list builds the cuts move to the
//! quantiles of the current positions (a histogram summed over the ranks). No slab is
//! narrower than the halo width (balanced cuts closer than that are moved apart); a
//! scene too short for that many slabs is an error naming the rank count. From the
//! first rebuild on, the weight of a particle is its work in the last step, one plus
//! its neighbour entries (times the wall weight for a wall marker; one far from the
//! fluid has no entry), so the first
//! rebuild after the start and every `rebalance_every`-th one balance the measured work.
//!
//! **Ownership, ghosts and migration.** A rank steps only the particles it owns; copies
//! of the other ranks' particles within the halo width `w` of its slab (`w` = the
//! neighbour list radius `2 h (1 + skin)`) are its *ghosts*: neighbours of its own
//! particles, never stepped nor evaluated (they carry the frozen flags of the active
//! domain, [`crate::system::active`]). Ghosts and migration are rebuilt with the
//! neighbour list: when some particle of any rank moved more than half the Verlet skin,
//! every rank drops its ghosts, sends each owned particle that left its slab to its new
//! owner with its whole state, then sends every owned particle within `w` of another
//! slab to that rank as a ghost. Between builds the list holds every pair within the
//! kernel support (each particle moved less than half the skin), so the halo width `w`
//! is enough: a pair within the support at any time of the interval was within `w` at
//! the build.
//!
//! **Refreshing the ghosts within a step** (the leapfrog of [`crate::system`]): after
//! the drift, positions and velocities; after the density increment (and the Shepard
//! filter), densities (every rank then computes the ghosts' pressure from them, the same
//! function of the same value); after the wall extrapolation, the wall markers'
//! extrapolated density, pressure, mass and no-slip velocity. The send and receive lists are
//! both ordered by particle id, so no index list travels.
//!
//! **Global decisions** are reductions: the Verlet criterion (any rank), the time step
//! (the fastest speed and the largest acceleration over the ranks, so every rank takes
//! the same `dt`, the one a single process would take), and a failure: a rank whose
//! particle turned non-finite reports it, the others stop with [`SphError::Rank`]
//! naming that rank; no rank waits for one that left.
//!
//! **What equals a single process.** Every particle sees the same neighbours with the
//! same states, so the physics is the same; the order of the neighbour sums follows each
//! rank's own storage order, so results agree with a single process to round-off (the
//! tests compare within 1e-9 relative over 200 steps), and they are bit-reproducible for
//! a given rank count and thread count.
//!
//! **Transports.** [`Transport`] is the two collectives the decomposition needs (an
//! all-to-all of `f64` buffers, element-wise max and sum). [`LocalTransport`] runs the
//! ranks as threads of one process (the test double, and for checking a decomposition
//! without MPI); with the cargo feature `mpi`, `MpiTransport` runs them as MPI processes
//! (rsmpi over the system's MPI library, e.g. OpenMPI): `mpirun -n 4 ...`.

mod local;
#[cfg(feature = "mpi")]
mod mpi;
mod record;

pub use local::LocalTransport;
#[cfg(feature = "mpi")]
pub use mpi::MpiTransport;
pub(crate) use record::{MIGRATE_LEN, Refresh, compact, compact_data, pack_state, push_state};

use crate::error::{Result, SphError};

/// The collectives of a decomposition. Every rank calls each method in the same order
/// (a collective); an error ends the run on that rank.
pub trait Transport: std::fmt::Debug {
    /// This rank, `0..size`.
    fn rank(&self) -> usize;
    /// The number of ranks.
    fn size(&self) -> usize;
    /// Sends `send[q]` to every rank `q` and fills `recv[q]` with what rank `q` sent to
    /// this one (`send.len() == recv.len() == size`; the own entry travels too).
    fn all_to_all(&mut self, send: &[Vec<f64>], recv: &mut [Vec<f64>]) -> Result<()>;
    /// [`all_to_all`](Self::all_to_all) when this rank knows how many values each rank
    /// sends it (`counts[q]`): a transport may then skip exchanging the counts. A rank
    /// that sends another count is an error (default: the plain exchange, then the
    /// check).
    fn all_to_all_sized(
        &mut self,
        send: &[Vec<f64>],
        recv: &mut [Vec<f64>],
        counts: &[usize],
    ) -> Result<()> {
        self.all_to_all(send, recv)?;
        for (q, (r, &c)) in recv.iter().zip(counts).enumerate() {
            if r.len() != c {
                return Err(SphError::Rank {
                    rank: q,
                    reason: format!(
                        "sent {} values where {c} were expected: the halo lists disagree",
                        r.len()
                    ),
                });
            }
        }
        Ok(())
    }
    /// Element-wise maximum over the ranks, in place.
    fn all_max(&mut self, v: &mut [f64]) -> Result<()>;
    /// Element-wise sum over the ranks, in place, added in rank order (so the result
    /// is the same on every rank and for a given rank count).
    fn all_sum(&mut self, v: &mut [f64]) -> Result<()>;
}

/// The rank count a process launcher (`mpirun`, `srun`) set for this process, from the
/// environment (`OMPI_COMM_WORLD_SIZE` of Open MPI, `PMI_SIZE` of MPICH and Slurm);
/// `None` when not launched as one of several ranks.
pub fn launched_ranks() -> Option<usize> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .filter_map(|k| std::env::var(k).ok()?.parse::<usize>().ok())
        .find(|&n| n > 1)
}

/// An error when this process was started as one of several MPI ranks but `program`
/// does not step over ranks (built without the `mpi` feature, or a program that has no
/// distributed mode): every rank would run the whole scene on its own. Call it first in
/// such a program.
pub fn require_single_process(program: &str) -> Result<()> {
    match launched_ranks() {
        Some(n) => Err(SphError::invalid(
            "ranks",
            n,
            format!(
                "{program} was started as one of {n} MPI ranks but runs whole scenes in one process (no MPI support here: build chrono-sph's example `mpi_dam_break` with `--features mpi` to run over ranks)"
            ),
        )),
        None => Ok(()),
    }
}

/// Settings of a decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DistributedSettings {
    /// The axis cut into slabs (0 = x, 1 = y, 2 = z); must not be periodic.
    pub axis: usize,
    /// Move the cuts to the current quantiles every this many neighbour-list builds
    /// (0 = never).
    pub rebalance_every: u32,
    /// Bins of the histogram the rebalancing reads (per slab axis extent).
    pub histogram_bins: usize,
    /// The work of a wall marker against a fluid particle's, for the balance: a wall
    /// marker is in the grid and extrapolates its pressure once per step; a fluid
    /// particle does the continuity and force passes.
    pub wall_weight: f64,
}

impl Default for DistributedSettings {
    fn default() -> Self {
        Self {
            axis: 0,
            rebalance_every: 8,
            histogram_bins: 4096,
            wall_weight: 0.25,
        }
    }
}

/// Slab cut points along one axis: rank `r` owns `[cuts[r-1], cuts[r])` (the first and
/// last slabs are open).
#[derive(Debug, Clone, PartialEq)]
pub struct Slabs {
    /// The `R - 1` interior cut points, increasing, m.
    pub cuts: Vec<f64>,
}

impl Slabs {
    /// Cuts at the `k W / R` quantiles of the weights `weights` of the particles at
    /// `coords` (`W` the total weight), half-way between two distinct coordinates; errors
    /// when a slab would be narrower than `width` (m) or when there are fewer particles
    /// than ranks.
    pub fn balanced(coords: &[f64], weights: &[f64], ranks: usize, width: f64) -> Result<Self> {
        let n = coords.len();
        if ranks == 0 || n < ranks {
            return Err(SphError::invalid(
                "ranks",
                ranks,
                format!("must be between 1 and the particle count {n}"),
            ));
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| coords[a].total_cmp(&coords[b]));
        let s: Vec<f64> = order.iter().map(|&i| coords[i]).collect();
        let total: f64 = weights.iter().sum();
        let mut cuts = Vec::with_capacity(ranks - 1);
        let (mut run, mut j) = (0.0, 0);
        for k in 1..ranks {
            let target = total * k as f64 / ranks as f64;
            while j < n && run + weights[order[j]] <= target {
                run += weights[order[j]];
                j += 1;
            }
            // the next distinct value: a lattice plane is not cut
            let mut m = j.max(1);
            while m < n && s[m] == s[m - 1] {
                m += 1;
            }
            cuts.push(if m < n {
                0.5 * (s[m - 1] + s[m])
            } else {
                s[n - 1]
            });
        }
        let mut slabs = Self { cuts };
        slabs.check(ranks, width, s[0], s[n - 1])?;
        Ok(slabs)
    }

    /// Cuts at the quantiles of a histogram `counts` of `bins` equal bins over
    /// `[lo, hi]` (bin edges: the cut is the upper edge of the bin where the running
    /// count passes `k N / R`).
    pub fn from_histogram(
        counts: &[f64],
        lo: f64,
        hi: f64,
        ranks: usize,
        width: f64,
    ) -> Result<Self> {
        let total: f64 = counts.iter().sum();
        let db = (hi - lo) / counts.len() as f64;
        let mut cuts = Vec::with_capacity(ranks.saturating_sub(1));
        let mut run = 0.0;
        let mut k = 1;
        for (b, &c) in counts.iter().enumerate() {
            run += c;
            while k < ranks && run >= total * k as f64 / ranks as f64 {
                cuts.push(lo + db * (b + 1) as f64);
                k += 1;
            }
        }
        while cuts.len() < ranks.saturating_sub(1) {
            cuts.push(hi);
        }
        let mut slabs = Self { cuts };
        slabs.check(ranks, width, lo, hi)?;
        Ok(slabs)
    }

    /// Every slab at least `width` wide over the particles' extent `[lo, hi]`: cuts that
    /// balance the work but leave a thinner slab are moved apart (forward, then back from
    /// `hi`); an error when the extent holds fewer than `ranks` slabs of that width.
    fn check(&mut self, ranks: usize, width: f64, lo: f64, hi: f64) -> Result<()> {
        let fits = hi - lo >= ranks as f64 * width;
        if !fits {
            return Err(SphError::invalid(
                "ranks",
                ranks,
                format!(
                    "more ranks than slabs: the particles span {:.4e} m along the axis, {} slabs of the halo width {width:.4e} m do not fit",
                    hi - lo,
                    ranks
                ),
            ));
        }
        let n = self.cuts.len();
        let mut prev = lo;
        for c in self.cuts.iter_mut() {
            *c = c.max(prev + width);
            prev = *c;
        }
        let mut next = hi;
        for k in (0..n).rev() {
            self.cuts[k] = self.cuts[k].min(next - width);
            next = self.cuts[k];
        }
        Ok(())
    }

    /// The rank that owns coordinate `c`.
    #[inline]
    pub fn owner(&self, c: f64) -> usize {
        self.cuts.partition_point(|&b| b <= c)
    }

    /// Whether coordinate `c` is within `w` of rank `q`'s slab (inside it or in its
    /// halo).
    #[inline]
    pub fn near(&self, q: usize, c: f64, w: f64) -> bool {
        let lo = if q == 0 {
            f64::NEG_INFINITY
        } else {
            self.cuts[q - 1]
        };
        let hi = self.cuts.get(q).copied().unwrap_or(f64::INFINITY);
        c >= lo - w && c < hi + w
    }
}

#[cfg(test)]
mod tests;
