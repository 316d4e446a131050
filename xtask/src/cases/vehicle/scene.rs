//! The scene the HMMWV cases share, from their parameters: `chrono_vehicle::scene::FlatScene`
//! (flat rigid ground, the vehicle resting just above it) with the named CCP solver (the
//! Schur solver by default: joints by a direct factorization, contacts by APGD on their
//! Schur complement).

use chrono_vehicle::hmmwv::{PowertrainKind, TireKind, hmmwv_data_variant};
use chrono_vehicle::scene::FlatScene;

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
    Ok(FlatScene::new(data, mu, make_solver(solver, 1e-8, 500)?)?)
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
