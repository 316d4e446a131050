//! The read accessors of [`SphSystem`] (settings, kernel, particle arrays, grid, lists,
//! time, statistics and timings) and the buffer fingerprint of the no-allocation test.

use chrono_core::particles::{CellGrid, Kernel, NeighborList};

use super::{SphStats, SphSystem, Timings};
use crate::data::ParticleData;
use crate::eos::Tait;
use crate::motion::WallMotion;
use crate::settings::SphSettings;

impl SphSystem {
    /// The settings.
    pub fn settings(&self) -> &SphSettings {
        &self.settings
    }
    /// The smoothing kernel.
    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }
    /// The equation of state.
    pub fn eos(&self) -> &Tait {
        &self.eos
    }
    /// The wall motion.
    pub fn motion(&self) -> &WallMotion {
        &self.motion
    }
    /// The particle arrays (slot order changes when they are re-sorted; use `id`).
    pub fn data(&self) -> &ParticleData {
        &self.data
    }
    /// The cell grid of the last step.
    pub fn grid(&self) -> &CellGrid {
        &self.grid
    }
    /// The neighbour list of the last step.
    pub fn neighbor_list(&self) -> &NeighborList {
        &self.list
    }
    /// Simulation time, s.
    pub fn time(&self) -> f64 {
        self.time
    }
    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }
    /// The time step the next step will take, s (0 before the first step).
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Number of fluid particles.
    pub fn num_fluid(&self) -> usize {
        self.n_fluid
    }
    /// Number of particles (fluid and wall markers).
    pub fn len(&self) -> usize {
        self.data.len()
    }
    /// Whether there is no particle.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
    /// Statistics of the last step.
    pub fn stats(&self) -> &SphStats {
        &self.stats
    }
    /// Accumulated phase timings.
    pub fn timings(&self) -> &Timings {
        &self.timings
    }
    /// The capacities and addresses of every buffer the step uses; equal before and after
    /// a step when nothing was (re)allocated (used by the no-allocation test).
    #[doc(hidden)]
    pub fn buffer_fingerprint(&self) -> Vec<(usize, usize)> {
        let d = &self.data;
        let mut v: Vec<(usize, usize)> = [
            &d.x,
            &d.y,
            &d.z,
            &d.vx,
            &d.vy,
            &d.vz,
            &d.rho,
            &d.p,
            &d.mass,
            &d.rho_half,
        ]
        .iter()
        .map(|a| (a.capacity(), a.as_ptr() as usize))
        .collect();
        v.push((d.deriv.capacity(), d.deriv.as_ptr() as usize));
        v.push((self.bc.capacity(), self.bc.as_ptr() as usize));
        v.push((self.packed.capacity(), self.packed.as_ptr() as usize));
        v.push((self.x_ref.capacity(), self.x_ref.as_ptr() as usize));
        v.extend(self.support.fingerprint());
        v.push((
            self.list.indices.capacity(),
            self.list.indices.as_ptr() as usize,
        ));
        v.push((
            self.list.offsets.capacity(),
            self.list.offsets.as_ptr() as usize,
        ));
        v.push((self.grid.order().len(), self.grid.cell_start().len()));
        v
    }

    /// Sets the velocity of every fluid particle from the field `velocity(x)` (m/s, `x`
    /// the particle's position, m), e.g. a developed laminar profile at the start. An
    /// error names the particle and the value when the field is not finite there.
    pub fn set_fluid_velocity(
        &mut self,
        velocity: impl Fn([f64; 3]) -> [f64; 3],
    ) -> crate::error::Result<()> {
        let d = &mut self.data;
        for i in 0..d.len() {
            if d.kind[i] != crate::data::FLUID {
                continue;
            }
            let v = velocity([d.x[i], d.y[i], d.z[i]]);
            if !v.iter().all(|c| c.is_finite()) {
                return Err(crate::error::SphError::invalid(
                    format!("fluid velocity of particle {}", d.id[i]),
                    format!("{v:?}"),
                    "must be finite",
                ));
            }
            (d.vx[i], d.vy[i], d.vz[i]) = (v[0], v[1], v[2]);
        }
        Ok(())
    }

    /// Resets the phase timings to zero.
    pub fn reset_timings(&mut self) {
        self.timings = Timings::default();
    }
}
