//! The scene the HMMWV cases share: a system with the Schur solver (joints by a direct
//! factorization, contacts by APGD on their Schur complement), flat rigid ground, and the
//! vehicle resting just above it.

use std::sync::Arc;

use chrono_core::math::Isometry3;
use chrono_core::{ContactMaterial, System, SystemSettings};
use chrono_vehicle::hmmwv::{PowertrainKind, TireKind, hmmwv_data_variant};
use chrono_vehicle::terrain::{FlatTerrain, Terrain};
use chrono_vehicle::{VehicleData, WheeledVehicle};

use crate::cases::rigid::make_solver;

/// Parse a tire kind parameter (`rigid` | `handling`).
pub fn tire_kind(name: &str) -> anyhow::Result<TireKind> {
    match name {
        "rigid" => Ok(TireKind::Rigid),
        "handling" => Ok(TireKind::Handling),
        other => anyhow::bail!("parameter `tire` must be rigid or handling, got `{other}`"),
    }
}

/// Parse a powertrain parameter (`chrono` | `m998`).
pub fn powertrain_kind(name: &str) -> anyhow::Result<PowertrainKind> {
    match name {
        "chrono" => Ok(PowertrainKind::Chrono),
        "m998" => Ok(PowertrainKind::M998),
        other => anyhow::bail!("parameter `powertrain` must be chrono or m998, got `{other}`"),
    }
}

/// A HMMWV on flat rigid ground (friction `mu`), its wheels `gap` m above it.
pub struct VehicleScene {
    /// The system.
    pub sys: System,
    /// The vehicle.
    pub vehicle: WheeledVehicle,
    /// Its description.
    pub data: VehicleData,
}

impl VehicleScene {
    /// Build the scene with `solver` (tolerance `tol`, at most `max_iterations`) and
    /// Chrono's powertrain.
    pub fn flat(
        tire: &str,
        mu: f64,
        solver: &str,
        tol: f64,
        max_iterations: usize,
    ) -> anyhow::Result<Self> {
        Self::flat_with(tire, "chrono", mu, solver, tol, max_iterations)
    }

    /// [`flat`](Self::flat) with the named powertrain (`chrono` | `m998`).
    pub fn flat_with(
        tire: &str,
        powertrain: &str,
        mu: f64,
        solver: &str,
        tol: f64,
        max_iterations: usize,
    ) -> anyhow::Result<Self> {
        let data = hmmwv_data_variant(tire_kind(tire)?, powertrain_kind(powertrain)?)?;
        let mut sys = System::new(
            SystemSettings::default(),
            make_solver(solver, tol, max_iterations)?,
        )?;
        let terrain = Arc::new(FlatTerrain::new(0.0, mu)?);
        terrain.add_to_system(&mut sys, ContactMaterial::with_friction(mu))?;
        // Wheel centres sit 1.035 in below the chassis reference (the data's spindle
        // points); start the tires 5 mm above the ground.
        let spindle_z = data.axles[0].suspension.points.spindle[2];
        let z0 = data.wheel.tire.radius() - spindle_z + 0.005;
        let vehicle = WheeledVehicle::build(
            &mut sys,
            &data,
            &Isometry3::translation(0.0, 0.0, z0),
            terrain,
        )?;
        Ok(Self { sys, vehicle, data })
    }
}

impl VehicleScene {
    /// Steer angle of each wheel about the chassis' Z axis, rad (positive: turned left),
    /// from the spindles' spin axes in the chassis frame.
    pub fn steer_angles(&self) -> anyhow::Result<Vec<f64>> {
        let chassis = self.sys.body(self.vehicle.chassis())?.rotation();
        self.vehicle
            .wheels()
            .iter()
            .map(|w| {
                let axis = chassis.inverse()
                    * (self.sys.body(w.spindle)?.rotation() * chrono_core::math::Vector3::y());
                Ok((-axis.x).atan2(axis.y))
            })
            .collect()
    }

    /// The mean front-wheel steer angle at full left input (rad), measured on a separate
    /// scene at rest: the steering linkage's ratio, which a path follower needs to turn a
    /// wanted wheel angle into a steering input.
    pub fn max_front_steer(tire: &str, mu: f64, solver: &str) -> anyhow::Result<f64> {
        let mut s = Self::flat(tire, mu, solver, 1e-8, 500)?;
        let h = 1e-3;
        for k in 0..60 {
            let steering = if k < 40 { 0.0 } else { 1.0 };
            s.vehicle.synchronize(
                &mut s.sys,
                chrono_vehicle::DriverInputs {
                    steering,
                    brake: 1.0,
                    ..Default::default()
                },
            )?;
            s.sys.step(h)?;
        }
        let a = s.steer_angles()?;
        Ok(0.5 * (a[0] + a[1]))
    }
}
