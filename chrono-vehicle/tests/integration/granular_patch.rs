//! The moving granular patch keeps its grain count, moves its walls by one slab per
//! relocation, and refills the front with the settled template.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::{System, SystemSettings};
use chrono_vehicle::terrain::{GranularPatch, GranularPatchParams};

fn params() -> GranularPatchParams {
    GranularPatchParams {
        length: 1.2,
        width: 0.4,
        depth: 0.16,
        grain_radius: 0.04,
        density: 2500.0,
        friction: 0.5,
        young_modulus: 2e7,
        restitution: 0.3,
        rolling_friction: 0.0,
        compliance: 0.0,
        slab: 0.2,
        seed: 3,
        lanes: Vec::new(),
    }
}

#[test]
fn relocation_keeps_the_count_and_refills_the_front() {
    let s = SolverSettings {
        tolerance: 1e-4,
        max_iterations: 200,
        record_history: false,
    };
    let mut sys = System::new(SystemSettings::default(), Box::new(Apgd::new(s))).unwrap();
    let mut patch = GranularPatch::build(&mut sys, &params(), -0.6).unwrap();
    let n = patch.grains().len();
    assert!(n > 20, "{n} grains");
    assert!(
        patch.advance(&mut sys, 10.0).is_err(),
        "advance before capture must fail"
    );
    for _ in 0..300 {
        sys.step(2e-3).unwrap();
    }
    patch.capture_settled(&sys).unwrap();
    assert!(patch.surface() > 0.0 && patch.surface() < params().depth + 0.01);
    // A vehicle at x = 0.35 is past the middle by more than a slab once: one relocation
    // (0.35 > -0.6 + 0.6 + 0.2), not two (0.35 < -0.4 + 0.6 + 0.2).
    assert_eq!(patch.advance(&mut sys, 0.35).unwrap(), 1);
    assert!((patch.rear() + 0.4).abs() < 1e-12);
    assert_eq!(patch.grains().len(), n);
    let r = params().grain_radius;
    for &g in patch.grains() {
        let x = sys.body(g).unwrap().position().x;
        assert!(
            x > patch.rear() + r - 1e-9,
            "grain at {x} behind the rear wall {}",
            patch.rear()
        );
        assert!(
            x < patch.front() - r + 1e-9,
            "grain at {x} beyond the front wall"
        );
    }
    // The moved grains sit in the new front slab, at rest.
    let in_front = patch
        .grains()
        .iter()
        .filter(|&&g| sys.body(g).unwrap().position().x > patch.front() - params().slab)
        .count();
    assert!(in_front > 0);
    for _ in 0..50 {
        sys.step(2e-3).unwrap();
    }
    assert_eq!(patch.advance(&mut sys, 0.35).unwrap(), 0);
}

#[test]
fn bad_patch_parameters_name_the_field() {
    let mut p = params();
    p.slab = 0.01;
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("granular_patch.slab"), "{e}");
    p = params();
    p.grain_radius = -1.0;
    assert!(
        p.validate()
            .unwrap_err()
            .to_string()
            .contains("grain_radius")
    );
}

/// Two lanes: grains only inside the lanes (between their side walls) after settling and
/// after a relocation, nothing between them, the count kept.
#[test]
fn lanes_hold_their_grains_and_relocate() {
    let s = SolverSettings {
        tolerance: 1e-4,
        max_iterations: 200,
        record_history: false,
    };
    let mut sys = System::new(SystemSettings::default(), Box::new(Apgd::new(s))).unwrap();
    let p = GranularPatchParams {
        width: 0.24,
        // A tall, slippery bed: without its side walls it spreads.
        depth: 0.4,
        friction: 0.1,
        lanes: vec![-0.3, 0.3],
        ..params()
    };
    let mut patch = GranularPatch::build(&mut sys, &p, -0.6).unwrap();
    let n = patch.grains().len();
    let inside = |sys: &System, patch: &GranularPatch| -> (usize, usize) {
        let mut count = [0usize; 2];
        for &g in patch.grains() {
            let y = sys.body(g).unwrap().position().y;
            let k = usize::from(y > 0.0);
            let c = p.lanes[k];
            assert!(
                (y - c).abs() <= 0.5 * p.width - p.grain_radius + 1e-6,
                "grain at y = {y} outside lane {c}"
            );
            count[k] += 1;
        }
        (count[0], count[1])
    };
    let (a, b) = inside(&sys, &patch);
    assert!(a > 10 && a == b, "lanes hold {a} and {b} grains");
    for _ in 0..300 {
        sys.step(2e-3).unwrap();
    }
    inside(&sys, &patch);
    patch.capture_settled(&sys).unwrap();
    assert!(patch.surface() > 0.0 && patch.surface() < p.depth + 0.01);
    assert_eq!(patch.advance(&mut sys, 0.35).unwrap(), 1);
    for _ in 0..100 {
        sys.step(2e-3).unwrap();
    }
    let (a, b) = inside(&sys, &patch);
    assert_eq!(a + b, n);
    assert!(a > 10 && b > 10, "after the relocation {a} and {b}");
}

#[test]
fn overlapping_or_bad_lanes_are_refused() {
    let mut p = params();
    p.lanes = vec![0.0, 0.3];
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("granular_patch.lanes"), "{e}");
    p.lanes = vec![0.0, f64::NAN];
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("granular_patch.lanes[1]"), "{e}");
}
