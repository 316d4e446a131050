//! The scene the HMMWV cases share, from their parameters: `chrono_vehicle::scene::FlatScene`
//! (flat rigid ground, the vehicle resting just above it) with the named CCP solver (the
//! Schur solver by default: joints by a direct factorization, contacts by APGD on their
//! Schur complement).

use chrono_vehicle::VehicleData;
use chrono_vehicle::hmmwv::{PowertrainKind, TireKind, hmmwv_data_variant};
use chrono_vehicle::scene::FlatScene;
use chrono_vehicle::tire::Tire;

use crate::cases::rigid::make_solver;

/// The HMMWV with `tire` and `powertrain` on flat ground of friction `mu`, solved by
/// `solver` (tolerance 1e-8, at most 500 iterations).
pub fn hmmwv_flat(
    tire: TireKind,
    powertrain: PowertrainKind,
    mu: f64,
    solver: &str,
) -> anyhow::Result<FlatScene> {
    let data = hmmwv_data_variant(tire, powertrain)?;
    hmmwv_flat_with(data, mu, solver)
}

/// [`hmmwv_flat`] for a description already edited.
pub fn hmmwv_flat_with(data: VehicleData, mu: f64, solver: &str) -> anyhow::Result<FlatScene> {
    Ok(FlatScene::new(data, mu, make_solver(solver, 1e-8, 500)?)?)
}

/// The parameter `tire_damping` (s): the ANCF carcass' stiffness damping `beta` when `>= 0`
/// (negative: the data's); an error naming it for another tire.
pub fn set_tire_damping(data: &mut VehicleData, beta: f64) -> anyhow::Result<()> {
    if beta < 0.0 {
        return Ok(());
    }
    anyhow::ensure!(
        beta.is_finite(),
        "parameter `tire_damping` must be finite, got {beta}"
    );
    match &mut data.wheel.tire {
        Tire::Ancf(t) => t.damping = beta,
        other => anyhow::bail!(
            "parameter `tire_damping` = {beta} applies to the ANCF tire, got a {} tire",
            match other {
                Tire::Rigid(_) => "rigid",
                _ => "handling",
            }
        ),
    }
    Ok(())
}

/// The mean front-wheel steer angle at full left input of that HMMWV (rad), for a path
/// follower (`chrono_vehicle::scene::max_front_steer`).
pub fn hmmwv_max_front_steer(tire: TireKind, mu: f64, solver: &str) -> anyhow::Result<f64> {
    let data = hmmwv_data_variant(tire, PowertrainKind::Chrono)?;
    Ok(chrono_vehicle::scene::max_front_steer(
        data,
        mu,
        make_solver(solver, 1e-8, 500)?,
    )?)
}
