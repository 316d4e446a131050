//! Filtering, errors and determinism of `CollisionWorld::detect`.

use super::*;
use crate::error::ChronoError;

#[test]
fn envelope_must_be_non_negative() {
    let e = CollisionWorld::new(-0.1).unwrap_err().to_string();
    assert!(
        e.contains("collision.envelope") && e.contains("-0.1"),
        "{e}"
    );
    let mut w = CollisionWorld::new(0.0).unwrap();
    assert!(w.set_envelope(f64::NAN).is_err());
    let e = w
        .add_collider(
            0,
            &Shape::Sphere { radius: 0.0 },
            Isometry3::identity(),
            mat(),
        )
        .unwrap_err();
    assert!(e.to_string().contains("collider.shape.radius"), "{e}");
    assert!(
        w.add_collider(
            0,
            &unit_box(),
            Isometry3::identity(),
            ContactMaterial::with_friction(-1.0)
        )
        .is_err()
    );
    assert!(w.is_empty());
}

#[test]
fn excluded_same_owner_and_inactive_pairs_are_skipped() {
    let s = Shape::Sphere { radius: 0.5 };
    let b = unit_box();
    let mut w = CollisionWorld::new(0.01).unwrap();
    // Owners 0 and 1 overlap with spheres and boxes; owner 2 overlaps both.
    w.add_collider(0, &s, Isometry3::identity(), mat()).unwrap();
    w.add_collider(0, &b, Isometry3::identity(), mat()).unwrap(); // same owner as 0
    w.add_collider(1, &b, at(0.5, 0.0, 0.0), mat()).unwrap();
    w.add_collider(2, &s, at(0.0, 0.6, 0.0), mat()).unwrap();
    let poses = [at(0.0, 0.0, 0.0); 3];
    let mut out = Vec::new();
    w.detect(&poses, &[true, true, true], &mut out).unwrap();
    let owners = |out: &[ContactPoint]| {
        let mut v: Vec<_> = out.iter().map(|c| (c.owner_a, c.owner_b)).collect();
        v.sort();
        v.dedup();
        v
    };
    assert_eq!(owners(&out), vec![(0, 1), (0, 2), (1, 2)]);
    w.exclude_pair(1, 0);
    assert!(w.is_pair_excluded(0, 1));
    w.detect(&poses, &[true, true, true], &mut out).unwrap();
    assert_eq!(owners(&out), vec![(0, 2), (1, 2)]);
    // Owners 0 and 2 inactive: only pairs with owner 1 are left, and (0, 1) is excluded.
    w.detect(&poses, &[false, true, false], &mut out).unwrap();
    assert_eq!(owners(&out), vec![(1, 2)]);
    w.detect(&poses, &[false, false, false], &mut out).unwrap();
    assert!(out.is_empty());
}

#[test]
fn bad_owner_inputs_are_errors() {
    let mut w = world(0.0, &[unit_box(), unit_box()]);
    let mut out = Vec::new();
    let e = w
        .detect(&[at(0.0, 0.0, 0.0)], &[true, true], &mut out)
        .unwrap_err();
    assert!(
        matches!(e, ChronoError::UnknownHandle { index: 1, .. }),
        "{e}"
    );
    let e = w
        .detect(&[at(0.0, 0.0, 0.0); 2], &[true], &mut out)
        .unwrap_err();
    assert!(e.to_string().contains("owner_active"), "{e}");
    let e = w
        .detect(
            &[at(0.0, 0.0, 0.0), at(f64::NAN, 0.0, 0.0)],
            &[true, true],
            &mut out,
        )
        .unwrap_err();
    assert!(e.to_string().contains("owner_poses[1]"), "{e}");
}

#[test]
fn unsupported_pair_is_a_collision_error() {
    let mut w = world(
        0.0,
        &[
            plane(),
            Shape::HalfSpace {
                normal: -Vector3::z(),
            },
        ],
    );
    let mut out = Vec::new();
    let e = w
        .detect(
            &[at(0.0, 0.0, 0.0), at(0.0, 0.0, -1.0)],
            &[true, true],
            &mut out,
        )
        .unwrap_err();
    let s = e.to_string();
    assert!(matches!(e, ChronoError::Collision { .. }), "{s}");
    assert!(
        s.contains("collider 0 (half-space, owner 0)")
            && s.contains("collider 1 (half-space, owner 1)"),
        "{s}"
    );
}

/// 200 random spheres and a few boxes in a 1.5 m cube over a ground plane.
fn random_scene(seed: u64) -> (CollisionWorld, Vec<Isometry3<f64>>, Vec<bool>) {
    let mut rng = crate::rng::Rng::new(seed);
    let mut rnd = move || rng.uniform();
    let mut w = CollisionWorld::new(0.01).unwrap();
    let mut poses = vec![Isometry3::identity()];
    w.add_collider(0, &plane(), Isometry3::identity(), mat())
        .unwrap();
    for i in 1..=220u32 {
        let shape = if i % 20 == 0 {
            Shape::Box {
                half_extents: Vector3::new(0.1 + 0.1 * rnd(), 0.1, 0.15),
            }
        } else {
            Shape::Sphere {
                radius: 0.05 + 0.1 * rnd(),
            }
        };
        w.add_collider(i, &shape, Isometry3::identity(), mat())
            .unwrap();
        let angles = Vector3::new(rnd(), rnd(), rnd()) * 3.0;
        poses.push(Isometry3::new(
            Vector3::new(1.5 * rnd(), 1.5 * rnd(), 1.5 * rnd() - 0.05),
            angles,
        ));
    }
    let active = (0..poses.len()).map(|i| i != 0).collect();
    (w, poses, active)
}

#[test]
fn detection_is_deterministic_across_runs_and_threads() {
    let (mut w1, poses, active) = random_scene(7);
    let (mut w2, _, _) = random_scene(7);
    let mut a = Vec::new();
    w1.detect(&poses, &active, &mut a).unwrap();
    assert!(
        w1.num_pairs() >= 2 * crate::collision::world::PARALLEL_MIN_PAIRS,
        "the scene must take the parallel path"
    );
    assert!(a.len() > 200, "{}", a.len());
    check_invariants(&a);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let mut b = Vec::new();
    pool.install(|| w2.detect(&poses, &active, &mut b)).unwrap();
    assert_eq!(a, b);
    let mut c = Vec::new();
    w1.detect(&poses, &active, &mut c).unwrap();
    assert_eq!(a, c);
    // Pairs come out sorted.
    assert!(
        a.windows(2)
            .all(|p| (p[0].collider_a, p[0].collider_b) <= (p[1].collider_a, p[1].collider_b))
    );
}
