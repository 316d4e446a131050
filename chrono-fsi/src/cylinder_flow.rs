//! Flow past a cylinder in a channel: the benchmark of Schäfer and Turek (1996, case 2D-1)
//! with a velocity inlet and a pressure outlet ([`chrono_sph::OpenChannel`]), the scene of
//! `fsi-cylinder-flow`.
//!
//! # Reference
//!
//! Schäfer, M. and Turek, S. (1996), "Benchmark computations of laminar flow around a
//! cylinder", in: Flow Simulation with High-Performance Computers II, Notes on Numerical
//! Fluid Mechanics 52, Vieweg, 547-566. Case 2D-1: a channel of height `H = 0.41 m` and
//! length `L = 2.2 m`, a cylinder of diameter `D = 0.1 m` centred at `(0.2, 0.2) m` (slightly
//! below the mid-height, so the flow has a small lift), fluid density `1 kg/m^3`,
//! kinematic viscosity `1e-3 m^2/s`; parabolic inflow `U(z) = 4 U_m z (H - z) / H^2` with
//! `U_m = 0.3 m/s` (mean `U = 2 U_m / 3 = 0.2 m/s`, `Re = U D / nu = 20`), no-slip walls and
//! cylinder, a "do-nothing" outflow. The flow is steady; its drag and lift coefficients
//! `C_D = 2 F_D / (rho U^2 D)`, `C_L = 2 F_L / (rho U^2 D)` (forces per unit length) lie in
//! the benchmark's bounds `C_D` 5.57-5.59 and `C_L` 0.0104-0.0110 ([`DRAG_RANGE`],
//! [`LIFT_RANGE`]); the participants' best results, e.g. 5.5795 and 0.0106.
//!
//! # The scene
//!
//! A quasi-2-D slab ([`slab_layers`] spacings thick, periodic along the cylinder's axis,
//! y); walls (marker layers) at `z = 0` and `z = H`; the channel's x-axis is open: an
//! inlet buffer before `x = 0` fed with the parabolic profile, a pressure outlet (gauge 0)
//! after `x = L` (buffers of [`buffer_layers`] spacings, [`chrono_sph::open`]). The
//! cylinder is a fixed rigid body with BCE markers, and the fluid, at rest at the start,
//! is carved around it. The inflow is ramped up over `ramp_time` (C1), longer than the
//! channel's acoustic round trip `4 L / c_s` so the start launches no strong pressure
//! wave; the coefficients are averaged over a window at the end of the run.
//!
//! WCSPH with the settings of the other resolved viscous flows (Morris viscosity, no
//! artificial viscosity or XSPH, delta-SPH density diffusion); the sound speed keeps the
//! density variation near 1 % for `1.5 U_m` (the flow speeds up beside the cylinder).
//! Particle shifting is off by default: the shift moves particles without their density
//! (the continuity equation has no term for it), and in an open channel the fluid then
//! drains through the outlet with its density unchanged (measured at `D/5`: 2 % of the
//! particles in 2 s with delta-plus shifting, none without; docs/validation-fsi.md).

use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::{slab_layers, wall_layers};
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_sph::{Inflow, OpenChannel, Outflow, ShiftForm, Shifting, SphSettings, sound_speed_for};

use crate::builder::FsiBuilder;
use crate::error::{FsiError, Result, check_positive};
use crate::fluid::SphFluid;

/// Schäfer and Turek's (1996) bounds of the drag coefficient of case 2D-1.
pub const DRAG_RANGE: (f64, f64) = (5.57, 5.59);
/// Schäfer and Turek's (1996) bounds of the lift coefficient of case 2D-1.
pub const LIFT_RANGE: (f64, f64) = (0.0104, 0.0110);

/// Buffer depth of the open ends in spacings for `h / dp`: the kernel support `2 h`
/// rounded up, plus one spacing (a row's rear waits up to a list rebuild to be fed).
pub fn buffer_layers(h_over_dp: f64) -> usize {
    wall_layers(h_over_dp) + 1
}

/// The channel, its fluid and the run's start (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderFlowParams {
    /// Channel length from the inlet to the outlet, m.
    pub length: f64,
    /// Channel height (between the wall surfaces), m.
    pub height: f64,
    /// Cylinder diameter, m.
    pub diameter: f64,
    /// Cylinder centre along the channel, m.
    pub centre_x: f64,
    /// Cylinder centre across the channel (height above the lower wall), m.
    pub centre_z: f64,
    /// Mean inflow speed `U` (the parabola's peak is `1.5 U`), m/s.
    pub u_mean: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Smoothing length over spacing.
    pub h_over_dp: f64,
    /// The inflow's ramp time from rest, s.
    pub ramp_time: f64,
    /// Particle shifting coefficient (delta-plus form, [`ShiftForm::DeltaPlus`]); 0: none.
    pub shifting: f64,
    /// The outlet lets the channel's plane acoustic mode out ([`Outflow::Absorbing`]);
    /// `false`: a plain pressure outlet ([`Outflow::Pressure`]), which reflects it.
    pub absorbing_outlet: bool,
}

impl Default for CylinderFlowParams {
    /// Case 2D-1 at `dp = D / 10`, `h = 1.3 dp`, a 2 s ramp, no particle shifting (it
    /// drains an open channel: see the module docs), an absorbing outlet.
    fn default() -> Self {
        Self {
            length: 2.2,
            height: 0.41,
            diameter: 0.1,
            centre_x: 0.2,
            centre_z: 0.2,
            u_mean: 0.2,
            rho: 1.0,
            viscosity: 1e-3,
            spacing: 0.01,
            h_over_dp: 1.3,
            ramp_time: 2.0,
            shifting: 0.0,
            absorbing_outlet: true,
        }
    }
}

impl CylinderFlowParams {
    /// `Re = rho U D / mu`.
    pub fn reynolds(&self) -> f64 {
        self.rho * self.u_mean * self.diameter / self.viscosity
    }

    /// The inflow's peak speed `U_m = 1.5 U`, m/s.
    pub fn u_max(&self) -> f64 {
        1.5 * self.u_mean
    }

    /// The slab's thickness along the cylinder's axis, m.
    pub fn width(&self) -> f64 {
        slab_layers(self.h_over_dp) as f64 * self.spacing
    }

    /// The buffers' depth, m.
    pub fn buffer(&self) -> f64 {
        buffer_layers(self.h_over_dp) as f64 * self.spacing
    }

    /// `C = 2 F / (rho U^2 D W)` of a force `F` (N) on the slab's width `W`.
    pub fn coefficient(&self, force: f64) -> f64 {
        2.0 * force / (self.rho * self.u_mean * self.u_mean * self.diameter * self.width())
    }

    /// Checks every field; the error names it.
    pub fn validate(&self) -> Result<()> {
        for (f, v) in [
            ("length", self.length),
            ("height", self.height),
            ("diameter", self.diameter),
            ("u_mean", self.u_mean),
            ("rho", self.rho),
            ("viscosity", self.viscosity),
            ("spacing", self.spacing),
            ("h_over_dp", self.h_over_dp),
        ] {
            check_positive(f, v)?;
        }
        if !(self.ramp_time.is_finite() && self.ramp_time >= 0.0) {
            return Err(FsiError::invalid(
                "ramp_time",
                self.ramp_time,
                "must be finite and >= 0",
            ));
        }
        if !(self.shifting.is_finite() && self.shifting >= 0.0) {
            return Err(FsiError::invalid(
                "shifting",
                self.shifting,
                "must be finite and >= 0",
            ));
        }
        let r = 0.5 * self.diameter;
        // the cylinder inside the channel with a kernel support of fluid all round
        let support = 2.0 * self.h_over_dp * self.spacing;
        if !(self.centre_z - r >= support && self.centre_z + r <= self.height - support) {
            return Err(FsiError::invalid(
                "centre_z",
                self.centre_z,
                format!(
                    "the cylinder must clear both walls by a kernel support ({support} m): its radius is {r} m, the channel {} m high",
                    self.height
                ),
            ));
        }
        if !(self.centre_x - r >= support && self.centre_x + r <= self.length - support) {
            return Err(FsiError::invalid(
                "centre_x",
                self.centre_x,
                format!(
                    "the cylinder must lie inside the channel (0 to {} m) a kernel support ({support} m) from its ends",
                    self.length
                ),
            ));
        }
        let rows = self.height / self.spacing;
        if (rows - rows.round()).abs() > 1e-6 {
            return Err(FsiError::invalid(
                "spacing",
                self.spacing,
                format!(
                    "must divide the height {} m (the lattice fills it exactly)",
                    self.height
                ),
            ));
        }
        Ok(())
    }

    /// The fluid's settings: the open channel along x, periodic along y, no gravity.
    pub fn fluid_settings(&self) -> Result<SphSettings> {
        let nu = self.viscosity / self.rho;
        let cs = sound_speed_for(1.5 * self.u_max(), self.diameter, 0.0, nu, 0.01)?;
        let b = self.buffer();
        Ok(SphSettings {
            spacing: self.spacing,
            h_over_dp: self.h_over_dp,
            rho0: self.rho,
            viscosity: self.viscosity,
            sound_speed: cs,
            artificial_viscosity: 0.0,
            xsph: 0.0,
            gravity: [0.0; 3],
            domain_lower: [-b, 0.0, 0.0],
            domain_upper: [self.length + b, self.width(), self.height],
            periodic: [false, true, false],
            // no free surface: the gauge pressure is negative behind the cylinder
            clamp_wall_pressure: false,
            shifting: (self.shifting > 0.0).then_some(Shifting {
                coefficient: self.shifting,
                form: ShiftForm::DeltaPlus,
            }),
            open_channel: Some(OpenChannel {
                axis: 0,
                buffer: b,
                inflow: Inflow::PlanePoiseuille {
                    u_max: self.u_max(),
                    across: 2,
                    lower: 0.0,
                    upper: self.height,
                },
                ramp_time: self.ramp_time,
                outflow: if self.absorbing_outlet {
                    Outflow::Absorbing { p: 0.0 }
                } else {
                    Outflow::Pressure { p: 0.0 }
                },
            }),
            ..SphSettings::default()
        })
    }
}

/// The scene: the system with the fixed cylinder and the fluid item.
pub struct CylinderFlow {
    /// The multibody system (no gravity).
    pub system: System,
    /// The fluid item.
    pub fluid: ItemHandle,
    /// The fixed cylinder.
    pub cylinder: BodyHandle,
    /// The parameters it was built from.
    pub params: CylinderFlowParams,
}

impl CylinderFlow {
    /// The fluid item.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid item")
    }

    /// The fluid's mean force on the cylinder over the last system step (world, N): drag
    /// along x, lift along z.
    pub fn force(&self) -> Vector3<f64> {
        self.fluid()
            .body_load(self.cylinder)
            .map_or(Vector3::zeros(), |l| l[0])
    }

    /// The drag coefficient of the last system step.
    pub fn drag_coefficient(&self) -> f64 {
        self.params.coefficient(self.force().x)
    }

    /// The lift coefficient of the last system step (positive upwards, +z).
    pub fn lift_coefficient(&self) -> f64 {
        self.params.coefficient(self.force().z)
    }
}

/// Builds the scene of `p` (see the [module docs](self)) with the multibody `solver`.
/// Errors name the parameter ([`CylinderFlowParams::validate`]) or the body (a cylinder not
/// resolved by the spacing, [`FsiBuilder::add_body`]).
pub fn cylinder_flow(p: &CylinderFlowParams, solver: Box<dyn CcpSolver>) -> Result<CylinderFlow> {
    p.validate()?;
    let settings = p.fluid_settings()?;
    let (lo, hi) = (settings.domain_lower, settings.domain_upper);
    let layers = wall_layers(settings.h_over_dp);
    let mut system = System::new(
        SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        },
        solver,
    )?;
    let w = p.width();
    let cylinder = system.add_body(
        RigidBodyBuilder::fixed()
            .name("cylinder")
            .position(Vector3::new(p.centre_x, 0.5 * w, p.centre_z))
            .collider(
                Shape::Cylinder {
                    half_length: 0.5 * w,
                    radius: 0.5 * p.diameter,
                },
                Isometry3::identity(),
                Default::default(),
            ),
    )?;
    let mut fsi = FsiBuilder::new(settings)?;
    fsi.add_fluid_box(lo, hi, None)?;
    fsi.sph()
        .add_tank(lo, hi, layers, [false, false, false, false, true, true], 0)?;
    fsi.add_body(&system, cylinder)?;
    let fluid = system.add_item(Box::new(fsi.build("fluid", 10)?));
    Ok(CylinderFlow {
        system,
        fluid,
        cylinder,
        params: p.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_is_case_2d1() {
        let p = CylinderFlowParams::default();
        assert!((p.reynolds() - 20.0).abs() < 1e-12);
        assert!((p.u_max() - 0.3).abs() < 1e-15);
        p.validate().unwrap();
        // C = 2 F / (rho U^2 D W)
        let f = 0.5 * p.rho * p.u_mean * p.u_mean * p.diameter * p.width();
        assert!((p.coefficient(f) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_named() {
        let base = CylinderFlowParams::default();
        for (field, p) in [
            (
                "viscosity",
                CylinderFlowParams {
                    viscosity: 0.0,
                    ..base.clone()
                },
            ),
            (
                "centre_z",
                CylinderFlowParams {
                    centre_z: 0.36,
                    ..base.clone()
                },
            ),
            (
                "centre_x",
                CylinderFlowParams {
                    centre_x: 2.19,
                    ..base.clone()
                },
            ),
            (
                "spacing",
                CylinderFlowParams {
                    spacing: 0.0123,
                    ..base.clone()
                },
            ),
            (
                "ramp_time",
                CylinderFlowParams {
                    ramp_time: -1.0,
                    ..base.clone()
                },
            ),
            (
                "shifting",
                CylinderFlowParams {
                    shifting: f64::NAN,
                    ..base.clone()
                },
            ),
        ] {
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{field}: {e}");
        }
    }
}
