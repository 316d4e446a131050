//! Tests of the position-level CCP density projection
//! ([`CfluidSettings::density_projection`]): it removes a compression, its rows are the
//! exact gradients (the residual left by one linearized projection is second order in
//! the compression, also with gradient-corrected step rows), bad settings are rejected by
//! name, and it is off by default.

use chrono_core::descriptor::SolverSettings;
use chrono_core::math::Vector3;
use chrono_core::rng::Rng;
use chrono_core::{System, SystemSettings};

use crate::{CfluidSettings, ConstraintFluid, ProjectionReport, lattice_box};

fn apgd(tolerance: f64) -> Box<chrono_ccp::Apgd> {
    Box::new(chrono_ccp::Apgd::new(SolverSettings {
        tolerance,
        max_iterations: 5000,
        record_history: false,
    }))
}

/// A free block of 8^3 particles on a lattice of spacing `(1 - squeeze) dp`, jittered by
/// `0.05 dp` (a disordered packing), no gravity, the velocity-level stabilization
/// nearly off (so the step's rows barely move it); one step of 1 ms with the
/// settings `f(defaults)`. Returns the largest `C_i` after the step (recomputed at the
/// final positions) and the step's projection report.
fn squeezed_block(
    squeeze: f64,
    f: impl Fn(CfluidSettings) -> CfluidSettings,
    solver: bool,
) -> (f64, ProjectionReport) {
    let dp = 0.01;
    let settings = f(CfluidSettings {
        spacing: dp,
        compressibility: 0.0,
        max_recovery_rate: 1e-9,
        xsph: 0.0,
        domain_lower: [-0.05; 3],
        domain_upper: [0.15; 3],
        ..CfluidSettings::default()
    });
    let q = (1.0 - squeeze) * dp;
    let mut rng = Rng::new(11);
    let fluid: Vec<[f64; 3]> = lattice_box([0.0; 3], [8.0 * q; 3], q)
        .unwrap()
        .into_iter()
        .map(|p| p.map(|x| x + 0.05 * dp * (2.0 * rng.uniform() - 1.0)))
        .collect();
    assert_eq!(fluid.len(), 512);
    let mut item = ConstraintFluid::new("block", settings, &fluid, &[]).unwrap();
    if solver {
        item.set_projection_solver(apgd(1e-13));
    }
    let mut sys = System::new(SystemSettings::default(), apgd(1e-10)).unwrap();
    let mut st = sys.settings().clone();
    st.gravity = Vector3::zeros();
    sys.set_settings(st).unwrap();
    let id = sys.add_item(Box::new(item));
    sys.step(1e-3).unwrap();
    let fluid = sys.item_mut::<ConstraintFluid>(id).unwrap();
    let report = fluid.last_density_projection();
    let r0 = fluid.settings().rest_density;
    let worst = fluid
        .compute_densities()
        .unwrap()
        .iter()
        .map(|r| r / r0 - 1.0)
        .fold(f64::NEG_INFINITY, f64::max);
    (worst, report)
}

fn projected(s: CfluidSettings) -> CfluidSettings {
    CfluidSettings {
        density_projection: 2000,
        density_projection_tolerance: 1e-13,
        ..s
    }
}

#[test]
fn the_density_projection_removes_a_compression() {
    let (off, _) = squeezed_block(0.01, |s| s, false);
    let (on, report) = squeezed_block(0.01, projected, true);
    assert!(off > 0.03, "the squeezed block is compressed: {off}");
    assert!(
        (report.max_compression_before - off).abs() < 0.01 * off,
        "the projection saw the compression: {report:?} against {off}"
    );
    assert!(report.iterations > 0 && report.max_displacement > 0.0);
    // one linearized projection: what is left is second order (`~ C^2`)
    assert!(
        on < 0.1 * off && on < off * off,
        "after the projection the compression is {on} (without it {off})"
    );
}

/// One linearized projection leaves `C(x + dx) - (C - D' dx)`, second order in `dx` when
/// `D` is the exact gradient: halving the squeeze divides the compression left by about
/// 4 (a first-order error, as corrected rows would leave on a jittered packing, by 2).
/// With the step's rows corrected (`gradient_correction`) the projection's stay exact.
#[test]
fn the_projection_rows_are_the_exact_gradients() {
    for correction in [0.0, 0.8] {
        let with = |s: CfluidSettings| {
            projected(CfluidSettings {
                gradient_correction: correction,
                ..s
            })
        };
        let (big, _) = squeezed_block(0.02, with, true);
        let (small, _) = squeezed_block(0.01, with, true);
        let (before_big, _) = squeezed_block(0.02, |s| s, false);
        let (before_small, _) = squeezed_block(0.01, |s| s, false);
        let order = (big / small).log2() / (before_big / before_small).log2();
        assert!(
            big > 0.0 && small > 0.0 && order > 1.7,
            "correction {correction}: left {big} and {small} from {before_big} and \
             {before_small}: order {order}"
        );
    }
}

#[test]
fn bad_projection_settings_are_rejected_by_name() {
    for (bad, field) in [
        (
            CfluidSettings {
                density_projection_tolerance: 0.0,
                ..CfluidSettings::default()
            },
            "cfluid.density_projection_tolerance",
        ),
        (
            CfluidSettings {
                density_projection_tolerance: f64::NAN,
                ..CfluidSettings::default()
            },
            "cfluid.density_projection_tolerance",
        ),
        (
            CfluidSettings {
                density_projection: 10,
                position_iterations: 3,
                ..CfluidSettings::default()
            },
            "cfluid.density_projection",
        ),
    ] {
        let err = bad.validate().unwrap_err().to_string();
        assert!(err.contains(field), "{err}");
        let err = ConstraintFluid::new("w", bad, &[[0.5; 3]], &[])
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains(field), "{err}");
    }
}

#[test]
fn the_projection_without_a_solver_is_an_error_naming_the_setting() {
    let settings = CfluidSettings {
        density_projection: 10,
        ..CfluidSettings::default()
    };
    let item = ConstraintFluid::new("w", settings, &[[0.5; 3]], &[]).unwrap();
    let mut sys = System::new(SystemSettings::default(), apgd(1e-8)).unwrap();
    sys.add_item(Box::new(item));
    let err = sys.step(1e-3).unwrap_err().to_string();
    assert!(err.contains("cfluid.density_projection"), "{err}");
}

#[test]
fn the_projection_is_off_by_default() {
    assert_eq!(CfluidSettings::default().density_projection, 0);
    let (_, report) = squeezed_block(0.02, |s| s, false);
    assert_eq!(report, ProjectionReport::default());
}
