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
            ..SphSettings::default()
        };
        let sys_settings = SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        };
        Ok((settings, System::new(sys_settings, solver)?))
    }
}
