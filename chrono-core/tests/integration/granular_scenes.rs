//! The library's granular scenes end to end on small setups: a steel ball dropped into a bed of
//! ~200 grains ([`ImpactBed`], [`BallDrop`]) and the sizing of a shear test
//! ([`ShearTest::build`]).

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::{BallDrop, ImpactBed, ShearTest};
use chrono_core::{ContactMaterial, System, SystemSettings};

fn nsc_system(d: f64) -> System {
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-4,
        max_iterations: 60,
        record_history: false,
    });
    let settings = SystemSettings {
        envelope: 0.05 * d,
        ..SystemSettings::default()
    };
    System::new(settings, Box::new(solver)).unwrap()
}

#[test]
fn a_ball_dropped_into_a_small_bed_penetrates_and_stops() {
    let d = 0.005;
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
    let bed = ImpactBed {
        settle_ke: 1e-3,
        ..ImpactBed::new(4.0 * d, 3.0 * d, d, 2500.0, mat)
    };
    let settled = bed.settle(&mut nsc_system(d)).unwrap();
    assert!(settled.grains.len() > 150, "{}", settled.grains.len());
    let ball = BallDrop {
        diameter: 3.0 * d,
        density: 7800.0,
        height: 10.0 * d,
        offset: [0.0, 0.0],
        t_drop: 0.1,
        record_dt: 1e-3,
    };
    let mut last = 0.0;
    let hit = ball
        .run(&mut nsc_system(d), &bed, &settled, |f| last = f)
        .unwrap();
    assert!(hit.depth > 0.0 && hit.depth < 3.0 * d, "{}", hit.depth);
    assert!(hit.max_depth >= hit.depth);
    assert!(
        hit.surface > 1.5 * d && hit.surface < 4.0 * d,
        "{}",
        hit.surface
    );
    assert_eq!(hit.series.len(), 100);
    assert!(last > 0.0 && last <= 1.0);
    // Rebuilding is deterministic: the same drop again gives the same depth.
    let again = ball
        .run(&mut nsc_system(d), &bed, &settled, |_| {})
        .unwrap();
    assert_eq!(again.depth, hit.depth);
}

#[test]
fn a_shear_test_sizes_its_sample_to_twice_the_lower_half() {
    let d = 0.006;
    let mat = ContactMaterial::smc(4e7, 0.22, 0.87, 0.18);
    let test = ShearTest {
        length: 8.0 * d,
        half_height: 2.0 * d,
        h: 1e-3,
        ..ShearTest::new(d, mat)
    };
    let mut sys = nsc_system(d);
    let scene = test.build(&mut sys).unwrap();
    // 0.6 of the volume 4 d x (8 d)^2 in spheres of d: 0.6 * 256 / (pi / 6) = 293.
    assert_eq!(scene.bed().len(), 293);
    // 400 + 100 steps, then 30 bins of 0.05 d / (0.005 m/s) / 1 ms = 60 steps.
    assert_eq!(scene.total_steps(), 500 + 30 * 60);
    let bad = ShearTest { gap: d, ..test };
    let e = bad.build(&mut nsc_system(d)).unwrap_err().to_string();
    assert!(e.contains("shear_test.gap"), "{e}");
}

#[test]
fn a_bed_of_spheres_steps_without_building_its_explicit_rows() {
    // Every contact of a bed of spheres is a frame-only triplet applied matrix-free: with
    // APGD and with the accelerated PSOR a step never needs the explicit coefficients
    // (`CcpProblem::coefficients_deferred`), and they are still there on demand.
    let d = 0.005;
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
    let bed = ImpactBed {
        settle_ke: 1e-3,
        ..ImpactBed::new(4.0 * d, 3.0 * d, d, 2500.0, mat)
    };
    let apsor = chrono_ccp::Psor::accelerated(SolverSettings {
        tolerance: 1e-4,
        max_iterations: 30,
        record_history: false,
    });
    for solver in [
        None,
        Some(Box::new(apsor) as Box<dyn chrono_core::descriptor::CcpSolver>),
    ] {
        let mut sys = nsc_system(d);
        if let Some(s) = solver {
            sys.set_solver(s);
        }
        bed.settle(&mut sys).unwrap();
        let p = sys.last_problem();
        assert!(p.n_rows() > 300, "{}", p.n_rows());
        assert_eq!(p.coefficients_deferred(), (true, false));
        assert_eq!(p.row_entries(0).count(), p.row_blocks(0).count());
        assert_eq!(p.coefficients_deferred(), (true, true));
    }
}
