//! A triply periodic cell of resolved viscous flow (the set-up of
//! [`beam_flow`](crate::beam_flow) and [`cylinder_array`](crate::cylinder_array)): WCSPH
//! without artificial viscosity or XSPH (Morris et al. 1997, J. Comput. Phys. 136:214),
//! driven along x by a body force on the fluid, in a system without gravity.

use chrono_core::descriptor::CcpSolver;
use chrono_core::math::Vector3;
use chrono_core::{System, SystemSettings};
use chrono_sph::{SphSettings, sound_speed_for};

use crate::error::Result;

/// The cell and its flow (SI units).
pub(crate) struct DrivenCell {
    /// Cell size (x, y, z), m.
    pub cell: [f64; 3],
    /// Particle spacing, m.
    pub spacing: f64,
    /// Smoothing length over spacing.
    pub h_over_dp: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Body force along x, m/s^2.
    pub body_force: f64,
    /// Largest expected fluid speed, m/s.
    pub v_max: f64,
    /// The obstacle's diameter `D` (the length scale of the flow), m.
    pub diameter: f64,
    /// Particle shifting ([`chrono_sph::Shifting`]); `None`: none.
    pub shifting: Option<chrono_sph::Shifting>,
}

impl DrivenCell {
    /// The fluid's settings and the system. The sound speed keeps the density variation
    /// near 1 % ([`sound_speed_for`]) for `v_max`, the viscosity at length `D` and the
    /// pressure difference across the obstacle, `~ rho f P_x^2 / D` (the cell's driving
    /// force per length on the diameter): the force term at length `D`.
    pub fn build(&self, solver: Box<dyn CcpSolver>) -> Result<(SphSettings, System)> {
        let nu = self.viscosity / self.rho;
        let force_scale =
            self.body_force.abs() * self.cell[0] * self.cell[0] / (self.diameter * self.diameter);
        let cs = sound_speed_for(self.v_max, self.diameter, force_scale, nu, 0.01)?;
        let settings = SphSettings {
            spacing: self.spacing,
            h_over_dp: self.h_over_dp,
            rho0: self.rho,
            viscosity: self.viscosity,
            sound_speed: cs,
            artificial_viscosity: 0.0,
            xsph: 0.0,
            gravity: [0.0; 3],
            body_force: [self.body_force, 0.0, 0.0],
            domain_lower: [0.0; 3],
            domain_upper: self.cell,
            periodic: [true; 3],
            // no free surface: the gauge pressure is negative downstream of a body
            clamp_wall_pressure: false,
            shifting: self.shifting,
            ..SphSettings::default()
        };
        let sys_settings = SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        };
        Ok((settings, System::new(sys_settings, solver)?))
    }
}

/// A periodic array's drag factor `K(c)` from a published table `t` of `(c, K)` pairs
/// (increasing `c`): interpolated linearly in `(c, ln K)` (K grows about exponentially
/// with `c`) inside the table, `dilute(c)` (the table's own low-concentration expansion)
/// for `0 < c` below its first entry, `None` above it or for a `c` that is not positive.
pub(crate) fn drag_factor_from_table(
    t: &[(f64, f64)],
    c: f64,
    dilute: impl Fn(f64) -> f64,
) -> Option<f64> {
    if c > 0.0 && c < t[0].0 {
        return Some(dilute(c));
    }
    if !(c >= t[0].0 && c <= t[t.len() - 1].0) {
        return None;
    }
    let k = t.windows(2).position(|w| c <= w[1].0)?;
    let ((c0, k0), (c1, k1)) = (t[k], t[k + 1]);
    let s = (c - c0) / (c1 - c0);
    Some((k0.ln() + s * (k1.ln() - k0.ln())).exp())
}
