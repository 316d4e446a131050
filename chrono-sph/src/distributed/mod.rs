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
//! particle turned non-finite reports it, the others stop with [`SphError::Rank`](crate::SphError::Rank)
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

mod record;

#[cfg(feature = "mpi")]
pub use chrono_core::distributed::MpiTransport;
pub use chrono_core::distributed::{
    LocalTransport, Slabs, Transport, launched_ranks, require_single_process,
};
pub(crate) use record::{MIGRATE_LEN, Refresh, compact, compact_data, pack_state, push_state};

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
