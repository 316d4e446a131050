//! Distributed runs: the ranks' collectives ([`Transport`]: threads of one process,
//! [`LocalTransport`], or MPI processes, `MpiTransport` with the cargo feature `mpi`) and
//! slab decompositions along one axis ([`Slabs`]). The domain crates build their
//! decompositions on these: chrono-sph's particles (`chrono_sph::distributed`) and the
//! SMC granular material here ([`granular`]).

pub mod granular;
mod local;
#[cfg(feature = "mpi")]
mod mpi;

pub use local::LocalTransport;
#[cfg(feature = "mpi")]
pub use mpi::MpiTransport;

use crate::error::{ChronoError, Result};

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
                return Err(ChronoError::Rank {
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
        Some(n) => Err(ChronoError::invalid(
            "ranks",
            n,
            format!(
                "{program} was started as one of {n} MPI ranks but runs whole scenes in one process (no MPI support here: the examples `mpi_dam_break` of chrono-sph and `mpi_granular_settle` of chrono-core, built with `--features mpi`, run over ranks)"
            ),
        )),
        None => Ok(()),
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
            return Err(ChronoError::invalid(
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
            return Err(ChronoError::invalid(
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
