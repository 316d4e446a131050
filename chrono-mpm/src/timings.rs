//! Wall time of the parts of an MPM step, accumulated over steps
//! ([`MpmBody::timings`](crate::MpmBody::timings)), for benches: where a step's time goes.
//! Each part is timed by one `Instant` pair per step (tens of nanoseconds against the
//! milliseconds of a step); nothing here changes the results.

use std::time::Instant;

/// Seconds spent in each part of the steps since the last
/// [`reset_timings`](crate::MpmBody::reset_timings).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepTimings {
    /// Particle to grid: the marker sort, the per-marker stress and the block gather, s.
    pub p2g: f64,
    /// Grid update: gravity, the walls' folding and images, rigid bodies, s.
    pub grid_update: f64,
    /// Grid to particle: the markers' velocity, affine matrix and `dF`, s.
    pub g2p: f64,
    /// The split's rows, neighbour search: the cell grid of the markers and wall markers
    /// and the neighbour list, s.
    pub rows_neighbours: f64,
    /// The split's rows, assembly: densities, row coefficients, the variables and the
    /// CCP's assembly, the warm start, s.
    pub rows_assembly: f64,
    /// The split's rows, solve: APGD, s.
    pub rows_solve: f64,
    /// The split's rows, after the solve: velocities back to the markers, the walls'
    /// friction, the pressure and its kernel average, the strain increment `dF` from the
    /// final velocities ([`crate::StrainFrom`]), s.
    pub rows_post: f64,
    /// The constitutive update: F-bar (when set) and the return mapping, s.
    pub constitutive: f64,
    /// The positions and the finiteness check, s.
    pub advect: f64,
}

impl StepTimings {
    /// The sum of the parts, s.
    pub fn total(&self) -> f64 {
        self.p2g
            + self.grid_update
            + self.g2p
            + self.rows_neighbours
            + self.rows_assembly
            + self.rows_solve
            + self.rows_post
            + self.constitutive
            + self.advect
    }
}

/// Adds the time since `*t` to `slot` and restarts `*t`.
#[inline]
pub(crate) fn lap(t: &mut Instant, slot: &mut f64) {
    let now = Instant::now();
    *slot += (now - *t).as_secs_f64();
    *t = now;
}
