//! The granular column collapse ([`GranularColumn`]) end to end on small columns: a
//! frictional low column keeps its height, a slippery one spreads; the grains stay in,
//! come to rest, and a seed repeats the run.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::{ColumnRun, GranularColumn};
use chrono_core::{ChronoError, ContactMaterial, ContactMethod, System, SystemSettings};

fn nsc(d: f64) -> System {
    let settings = SystemSettings {
        envelope: 0.1 * d,
        contact_method: ContactMethod::Nsc,
        ..SystemSettings::default()
    };
    System::new(
        settings,
        Box::new(Apgd::new(SolverSettings {
            tolerance: 1e-5,
            max_iterations: 100,
            record_history: false,
        })),
    )
    .unwrap()
}

fn small(a: f64, across: f64, mu: f64, mu_r: f64) -> GranularColumn {
    GranularColumn::new(
        a,
        0.01 * across,
        across,
        ContactMaterial::with_friction(mu).with_rolling_friction(mu_r),
    )
}

fn collapse(c: &GranularColumn) -> ColumnRun {
    let mut sys = nsc(c.grain_diameter());
    let mut scene = c.build(&mut sys, |_, _| Ok::<(), ChronoError>(())).unwrap();
    scene
        .run(&mut sys, |_, _| Ok::<(), ChronoError>(()))
        .unwrap()
}

#[test]
fn frictional_low_column_keeps_its_height_and_a_slippery_one_spreads() {
    // a = 0.5: with high sliding and rolling friction the column sheds its corner and
    // keeps most of its height; with little friction it spreads at least 1.25 times as
    // far (measured: 0.45 and 0.63).
    let rough = collapse(&small(0.5, 10.0, 0.9, 0.2));
    let slippery = collapse(&small(0.5, 10.0, 0.1, 0.0));
    eprintln!(
        "a = 0.5: rough runout {:.3} height {:.3}; slippery runout {:.3} height {:.3}",
        rough.runout_ratio,
        rough.final_height_ratio,
        slippery.runout_ratio,
        slippery.final_height_ratio
    );
    for r in [&rough, &slippery] {
        assert!(r.at_rest, "{r:?}");
        assert_eq!(r.escaped, 0);
    }
    assert!(
        rough.final_height_ratio > 0.8,
        "rough column lost its height: {}",
        rough.final_height_ratio
    );
    assert!(rough.runout_ratio < 0.6, "{}", rough.runout_ratio);
    assert!(
        slippery.runout_ratio > 1.25 * rough.runout_ratio.max(0.1),
        "slippery {} rough {}",
        slippery.runout_ratio,
        rough.runout_ratio
    );
}

#[test]
fn column_keeps_its_grains_comes_to_rest_and_repeats() {
    let c = small(1.0, 6.0, 0.5, 0.0);
    let a = collapse(&c);
    let b = collapse(&c);
    assert_eq!(
        a,
        ColumnRun {
            wall_s: a.wall_s,
            ..b
        }
    );
    assert!(a.at_rest);
    assert_eq!(a.escaped, 0);
    assert!((a.mass_ratio - 1.0).abs() < 1e-12, "{}", a.mass_ratio);
    assert!(a.momentum < 1e-2, "{}", a.momentum);
    assert!(a.runout_ratio > 0.0 && a.final_height_ratio < 1.0, "{a:?}");
    assert!((a.aspect_ratio - 1.0).abs() < 0.25, "{}", a.aspect_ratio);
    assert!(
        (0.45..0.7).contains(&a.solid_fraction),
        "{}",
        a.solid_fraction
    );
}
