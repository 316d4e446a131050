//! The [`ConstraintFluid`]'s read access: counts, particle state, densities, impulses,
//! pressure and energy (diagnostics and output; the step does not use them).

use chrono_core::body::BodyHandle;
use chrono_core::density_rows::RowBuf;
use chrono_core::descriptor::RowId;
use chrono_core::error::{ChronoError, Result};
use chrono_core::particles::Kernel;

use super::{ConstraintFluid, check_points};
use crate::settings::CfluidSettings;

impl ConstraintFluid {
    /// Number of body markers (all attached bodies).
    pub fn n_body_markers(&self) -> usize {
        self.marker_local.len()
    }

    /// The settings.
    pub fn settings(&self) -> &CfluidSettings {
        &self.settings
    }

    /// Sets a velocity relaxation rate `k` (1/s; 0, the default, turns it off): after
    /// each solve (and the XSPH smoothing) every fluid velocity is scaled by `exp(-k h)`
    /// before `x += h v`, a drag towards rest that leaves a static equilibrium unchanged
    /// (the same relaxation as chrono-sph's `SphSettings::damping`). For settling a scene
    /// to its static state (a floating body's draft), not for a dynamic run. Error: a
    /// negative or non-finite rate, naming `damping`.
    pub fn set_damping(&mut self, rate: f64) -> Result<()> {
        if !(rate.is_finite() && rate >= 0.0) {
            return Err(ChronoError::invalid(
                "damping",
                rate,
                "must be finite and >= 0 (1/s)",
            ));
        }
        self.damping = rate;
        Ok(())
    }

    /// The velocity relaxation rate ([`set_damping`](Self::set_damping)), 1/s.
    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// Set the XSPH epsilon of the following steps (e.g. a settling phase that smooths
    /// more than the run, see [`CfluidSettings::xsph`]); the error names `cfluid.xsph`
    /// when `eps` is outside `[0, 1]`. It replaces [`CfluidSettings::xsph_viscosity`]
    /// (set to 0) so that `eps` is the smoothing used.
    pub fn set_xsph(&mut self, eps: f64) -> Result<()> {
        if !(0.0..=1.0).contains(&eps) {
            return Err(ChronoError::invalid(
                "cfluid.xsph",
                eps,
                "must be in [0, 1]",
            ));
        }
        self.settings.xsph = eps;
        self.settings.xsph_viscosity = 0.0;
        Ok(())
    }

    /// The kernel.
    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }

    /// Inertial and gravitational mass of every fluid particle, `rho_0 dp^3`, kg: a
    /// particle stands for one lattice cell of fluid at the rest density.
    pub fn particle_mass(&self) -> f64 {
        self.mass
    }

    /// The mass in the SPH density sums (fluid, wall and body markers),
    /// `m_k = rho_0 / sum_lattice W` ([`lattice_mass`](crate::geometry::lattice_mass)), kg: the cubic lattice of spacing
    /// `dp` sums to exactly `rho_0`. It differs from [`particle_mass`](Self::particle_mass)
    /// by the kernel's lattice-sum error (`m_k = 0.983 rho_0 dp^3` for Wendland C2 at
    /// `h_k = 1.2 dp`).
    pub fn kernel_mass(&self) -> f64 {
        self.kernel_mass
    }

    /// Number of fluid particles.
    pub fn n_fluid(&self) -> usize {
        self.n_fluid
    }

    /// Number of wall markers.
    pub fn n_walls(&self) -> usize {
        self.n_static - self.n_fluid
    }

    /// Position of fluid particle `i`, m.
    pub fn position(&self, i: usize) -> [f64; 3] {
        [self.pos[0][i], self.pos[1][i], self.pos[2][i]]
    }

    /// Velocities of the fluid particles, m/s.
    pub fn velocities(&self) -> &[[f64; 3]] {
        &self.vel
    }

    /// Set the velocity of every fluid particle (e.g. an initial condition), m/s; the
    /// error names the first non-finite entry.
    pub fn set_velocities(&mut self, v: &[[f64; 3]]) -> Result<()> {
        if v.len() != self.n_fluid {
            return Err(ChronoError::invalid(
                "velocities.len()",
                v.len(),
                format!("must equal the fluid particle count {}", self.n_fluid),
            ));
        }
        check_points("velocities", v)?;
        self.vel.copy_from_slice(v);
        Ok(())
    }

    /// Densities of the fluid particles, kg/m^3, at the positions of the start of the
    /// last step (or of the last [`compute_densities`](Self::compute_densities)).
    pub fn densities(&self) -> &[f64] {
        &self.rho
    }

    /// Recompute the neighbours and densities at the current positions (diagnostics:
    /// the density after the last step), of the fluid particles (returned), of the body
    /// markers ([`marker_densities`](Self::marker_densities); markers stay where the last
    /// step started, or where [`attach_body`](Self::attach_body) put them) and of the wall
    /// markers ([`wall_densities`](Self::wall_densities)).
    pub fn compute_densities(&mut self) -> Result<&[f64]> {
        self.refresh_neighbors()?;
        let mut rho = std::mem::take(&mut self.rho);
        let mut mrho = std::mem::take(&mut self.marker_rho);
        let mut wrho = std::mem::take(&mut self.wall_rho);
        {
            let field = self.field();
            field.densities(&mut rho);
            for (k, r) in mrho.iter_mut().enumerate() {
                *r = field.density(self.n_static + k);
            }
            for (k, r) in wrho.iter_mut().enumerate() {
                *r = field.density(self.n_fluid + k);
            }
        }
        self.rho = rho;
        self.marker_rho = mrho;
        self.wall_rho = wrho;
        Ok(&self.rho)
    }

    /// Densities of the wall markers, kg/m^3, as of the last step with
    /// [`CfluidSettings::wall_marker_rows`] or the last
    /// [`compute_densities`](Self::compute_densities).
    pub fn wall_densities(&self) -> &[f64] {
        &self.wall_rho
    }

    /// The wall-marker rows of the last step: `(wall marker index, row)` for every wall
    /// marker that had fluid neighbours ([`CfluidSettings::wall_marker_rows`]).
    pub fn wall_row_ids(&self) -> &[(u32, RowId)] {
        &self.wall_row_ids
    }

    /// Densities of the body markers (all attached bodies, in attachment order), kg/m^3,
    /// as of the last step or [`compute_densities`](Self::compute_densities).
    pub fn marker_densities(&self) -> &[f64] {
        &self.marker_rho
    }

    /// The body-marker rows of the last step: `(marker index, row)` for every marker that
    /// had fluid neighbours ([`CfluidSettings::body_marker_rows`]).
    pub fn marker_row_ids(&self) -> &[(u32, RowId)] {
        &self.marker_row_ids
    }

    /// The density-row impulses of the last step, N m s (one per fluid particle, `>= 0`
    /// where it pushes).
    pub fn impulses(&self) -> &[f64] {
        &self.gamma
    }

    /// The impulses of the body-marker rows of the last step, N m s (one per body marker,
    /// in attachment order; 0 for a marker without a row), `>= 0` (the rows are unilateral).
    pub fn marker_impulses(&self) -> &[f64] {
        &self.marker_gamma
    }

    /// Position of body marker `k` (all attached bodies, attachment order) at the start of
    /// the last step (or where [`attach_body`](Self::attach_body) put it), m.
    pub fn marker_position(&self, k: usize) -> [f64; 3] {
        let j = self.n_static + k;
        [self.pos[0][j], self.pos[1][j], self.pos[2][j]]
    }

    /// Pressure of body marker `k`'s own row in the last step, `p_k = g_k rho_0 / (h m_k)`,
    /// Pa (0 without a row).
    pub fn marker_pressure(&self, k: usize) -> f64 {
        self.impulse_to_pressure(self.marker_gamma[k])
    }

    /// The linear impulse (N s, world frame) that each density row of the last step gave
    /// the attached body `body`: `D_b g` of every row with a block on it, `D_b` the row's
    /// linear body coefficients (`sum_k c_k` over the body's markers in the row, see
    /// [`ConstraintFluid`]) and `g` its impulse. `fluid[i]` is fluid particle `i`'s row,
    /// `markers[k]` body marker `k`'s own row (all attached bodies' markers, attachment
    /// order; zero where a row has no block on `body`). The sum over both is the impulse
    /// the density rows gave the body (the contact rows' share is not included);
    /// `- g / h` of `(0, 0, 1)` summed is the buoyancy, N. Empty when `body` is not
    /// attached.
    pub fn row_impulses_on(&self, body: BodyHandle) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let Some(slot) = self.bodies.iter().position(|b| b.0 == body) else {
            return (Vec::new(), Vec::new());
        };
        let on = |buf: &RowBuf, g: f64| -> [f64; 3] {
            buf.bodies
                .iter()
                .find(|b| b.0 as usize == slot)
                .map_or([0.0; 3], |(_, c)| [c[0] * g, c[1] * g, c[2] * g])
        };
        let fluid = (self.rows.iter().zip(&self.gamma))
            .map(|(b, g)| on(b, *g))
            .collect();
        let markers = (self.marker_rows.iter().zip(&self.marker_gamma))
            .map(|(b, g)| on(b, *g))
            .collect();
        (fluid, markers)
    }

    /// The density rows of the last step, one per fluid particle (map them to global rows
    /// with [`CcpProblem::row_index`](chrono_core::descriptor::CcpProblem::row_index)).
    pub fn row_ids(&self) -> &[RowId] {
        &self.row_ids
    }

    /// Pressure of fluid particle `i` from the last step, `p_i = g_i rho_0 / (h m_k)`, Pa.
    pub fn pressure(&self, i: usize) -> f64 {
        self.impulse_to_pressure(self.gamma[i])
    }

    /// The largest compression `max_i (rho_i / rho_0 - 1)` over the current densities
    /// (`<= 0` when nothing is compressed).
    pub fn max_compression(&self) -> f64 {
        let r0 = self.settings.rest_density;
        self.rho
            .iter()
            .map(|r| r / r0 - 1.0)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Kinetic energy of the fluid, J.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass
            * self
                .vel
                .iter()
                .map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
                .sum::<f64>()
    }
}
