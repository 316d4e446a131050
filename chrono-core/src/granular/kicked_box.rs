//! A box of grains given random horizontal velocities: a granular scene that has
//! contacts from the first steps and settles under gravity (the distributed SMC run's
//! test and example, `mpi_granular_settle`).

use nalgebra::Vector3;

use super::{GrainBed, Kick, Region, add_box_container};
use crate::contact::smc::RollingModel;
use crate::descriptor::CcpSolver;
use crate::error::{ChronoError, Result};
use crate::material::ContactMaterial;
use crate::system::{ContactMethod, SmcSettings, System, SystemSettings};

/// A lattice of grains (radii uniform in `[0.8 r, r]`, clearance `0.1 r`) filling a box
/// `length x width x height` lattice pitches (`2.1 r`) from the bottom, each grain kicked
/// with a horizontal velocity uniform in `[-kick, kick]` per axis, falling under gravity
/// `g` (m/s^2) along `-z`; SMC Hertz contact (or NSC with `method`).
#[derive(Debug, Clone, PartialEq)]
pub struct KickedBox {
    /// Grains (filled bottom layer first).
    pub grains: usize,
    /// Largest grain radius `r`, m.
    pub radius: f64,
    /// The box in lattice pitches: along x, y, z.
    pub pitches: [usize; 3],
    /// Largest horizontal speed of the kick per axis, m/s.
    pub kick: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Grains' and walls' material (Young's modulus, Poisson ratio, restitution,
    /// friction).
    pub material: ContactMaterial,
    /// Gravity, m/s^2.
    pub gravity: f64,
    /// Seed of the radii, jitter and kick.
    pub seed: u64,
    /// Contact method.
    pub method: ContactMethod,
    /// Rolling resistance model (with the material's rolling friction).
    pub rolling_model: RollingModel,
}

impl Default for KickedBox {
    fn default() -> Self {
        Self {
            grains: 2000,
            radius: 0.01,
            pitches: [40, 6, 14],
            kick: 1.0,
            density: 2500.0,
            material: ContactMaterial::smc(1e7, 0.3, 0.5, 0.5),
            gravity: 9.81,
            seed: 7,
            method: ContactMethod::Smc,
            rolling_model: RollingModel::Relative,
        }
    }
}

impl KickedBox {
    /// The scene in a new system stepped by `solver` (used by NSC; SMC without joints
    /// never calls it), and the step: half the SMC stability limit of the scene
    /// ([`System::smc_max_step`]), or `1e-3` s for NSC. The container is one fixed body
    /// added first, then the grains.
    pub fn build(&self, solver: Box<dyn CcpSolver>) -> Result<(System, f64)> {
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(ChronoError::invalid(
                "radius",
                self.radius,
                "must be finite and > 0",
            ));
        }
        if let Some(a) = (0..3).find(|&a| self.pitches[a] == 0) {
            return Err(ChronoError::invalid(
                format!("pitches[{a}]"),
                0,
                "must be >= 1",
            ));
        }
        if !(self.gravity.is_finite() && self.gravity >= 0.0) {
            return Err(ChronoError::invalid(
                "gravity",
                self.gravity,
                "must be finite and >= 0",
            ));
        }
        let settings = SystemSettings {
            gravity: Vector3::new(0.0, 0.0, -self.gravity),
            envelope: 0.1 * self.radius,
            contact_method: self.method,
            rolling_model: self.rolling_model,
            smc: SmcSettings::default(),
            ..SystemSettings::default()
        };
        let mut sys = System::new(settings, solver)?;
        let pitch = 2.1 * self.radius;
        let p = self.pitches;
        let upper = Vector3::new(p[0] as f64, p[1] as f64, p[2] as f64) * pitch;
        add_box_container(&mut sys, "box", Vector3::zeros(), upper, self.material)?;
        let bed = GrainBed {
            gap: 0.1 * self.radius,
            count: Some(self.grains),
            kick: Some(Kick::new(self.kick)),
            seed: self.seed,
            ..GrainBed::new(
                Region::Box {
                    lower: Vector3::zeros(),
                    upper,
                },
                0.8 * self.radius,
                self.radius,
                self.density,
                self.material,
            )
        };
        bed.pour(&mut sys)?;
        let h = match self.method {
            ContactMethod::Smc => {
                0.5 * sys.smc_max_step().map(|(h, _)| h).ok_or_else(|| {
                    ChronoError::invalid("grains", self.grains, "no SMC contact to limit the step")
                })?
            }
            _ => 1e-3,
        };
        Ok((sys, h))
    }
}
