//! The scene the HMMWV cases share: a system with the Schur solver (joints by a direct
//! factorization, contacts by APGD on their Schur complement), flat rigid ground, and the
//! vehicle resting just above it.

use std::sync::Arc;

use chrono_core::math::Isometry3;
use chrono_core::{ContactMaterial, System, SystemSettings};
use chrono_vehicle::hmmwv::{TireKind, hmmwv_data_with};
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
    /// Build the scene with `solver` (tolerance `tol`, at most `max_iterations`).
    pub fn flat(
        tire: &str,
        mu: f64,
        solver: &str,
        tol: f64,
        max_iterations: usize,
    ) -> anyhow::Result<Self> {
        let data = hmmwv_data_with(tire_kind(tire)?)?;
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
