//! Contact conventions, shape pair by shape pair.

use super::*;
use crate::math::{Translation3, UnitQuaternion};

#[test]
fn sphere_on_halfspace_both_orders() {
    for sphere_first in [true, false] {
        let shapes = if sphere_first {
            [Shape::Sphere { radius: 0.5 }, plane()]
        } else {
            [plane(), Shape::Sphere { radius: 0.5 }]
        };
        let mut w = world(0.01, &shapes);
        let sphere_pose = at(1.0, 2.0, 0.49);
        let poses = if sphere_first {
            [sphere_pose, at(0.0, 0.0, 0.0)]
        } else {
            [at(0.0, 0.0, 0.0), sphere_pose]
        };
        let active = if sphere_first {
            [true, false]
        } else {
            [false, true]
        };
        let mut cs = Vec::new();
        w.detect(&poses, &active, &mut cs).unwrap();
        assert_eq!(cs.len(), 1);
        let c = cs[0];
        check_invariants(&cs);
        assert!((c.distance + 0.01).abs() < 1e-12, "{c:?}");
        let (on_sphere, on_plane, n_expected) = if sphere_first {
            (c.point_a, c.point_b, -Vector3::z())
        } else {
            (c.point_b, c.point_a, Vector3::z())
        };
        assert!((c.normal - n_expected).norm() < 1e-12, "{c:?}");
        assert!((on_sphere - Vector3::new(1.0, 2.0, -0.01)).norm() < 1e-12);
        assert!((on_plane - Vector3::new(1.0, 2.0, 0.0)).norm() < 1e-12);
    }
}

#[test]
fn sphere_on_tilted_halfspace_through_parry_matches_fast_path() {
    // A capsule of zero-ish length behaves like a sphere but takes parry's path (which
    // reports both ends of its tiny segment: two coincident points).
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3);
    let ground = Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.2), tilt);
    let n = tilt * Vector3::z();
    let center = Vector3::new(0.0, 0.0, 0.2) + tilt * Vector3::new(0.1, 0.2, 0.0) + n * 0.45;
    let mut fast = world(0.01, &[plane(), Shape::Sphere { radius: 0.5 }]);
    let mut slow = world(
        0.01,
        &[
            plane(),
            Shape::Capsule {
                half_length: 1e-9,
                radius: 0.5,
            },
        ],
    );
    let poses = [ground, Isometry3::translation(center.x, center.y, center.z)];
    let (a, b) = (detect(&mut fast, &poses), detect(&mut slow, &poses));
    check_invariants(&a);
    check_invariants(&b);
    assert_eq!(a.len(), 1);
    assert!(!b.is_empty() && b.len() <= 2, "{b:?}");
    assert!(
        (a[0].distance + 0.05).abs() < 1e-9 && (a[0].normal - n).norm() < 1e-12,
        "{a:?}"
    );
    for b in &b {
        assert!(
            (b.distance + 0.05).abs() < 1e-6 && (b.normal - n).norm() < 1e-6,
            "{b:?}"
        );
        assert!(
            (a[0].point_b - b.point_b).norm() < 1e-6 && (a[0].point_a - b.point_a).norm() < 1e-6
        );
    }
}

#[test]
fn sphere_sphere() {
    let mut w = world(
        0.0,
        &[
            Shape::Sphere { radius: 0.5 },
            Shape::Sphere { radius: 0.25 },
        ],
    );
    let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.0, 0.7, 0.0)]);
    check_invariants(&cs);
    assert_eq!(cs.len(), 1);
    assert!((cs[0].distance + 0.05).abs() < 1e-12);
    assert!((cs[0].normal - Vector3::y()).norm() < 1e-12);
    assert!((cs[0].point_a - Vector3::new(0.0, 0.5, 0.0)).norm() < 1e-12);
    assert!((cs[0].point_b - Vector3::new(0.0, 0.45, 0.0)).norm() < 1e-12);
    assert!(detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.0, 0.76, 0.0)]).is_empty());
}

#[test]
fn envelope_reports_near_contacts_only() {
    let env = 0.02;
    for shape in [Shape::Sphere { radius: 0.5 }, unit_box()] {
        let mut w = world(env, &[plane(), shape]);
        let near = detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.0, 0.0, 0.5 + 0.5 * env)]);
        assert!(!near.is_empty(), "{near:?}");
        assert!(near.iter().all(|c| (c.distance - 0.5 * env).abs() < 1e-12));
        let far = detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.0, 0.0, 0.5 + 2.0 * env)]);
        assert!(far.is_empty(), "{far:?}");
    }
}

fn assert_four_corners(cs: &[ContactPoint], depth: f64, normal: Vector3<f64>, half: f64) {
    check_invariants(cs);
    assert_eq!(cs.len(), 4, "{cs:#?}");
    for c in cs {
        assert!((c.distance - depth).abs() < 1e-9, "{c:?}");
        assert!((c.normal - normal).norm() < 1e-9, "{c:?}");
        let p = c.point_a;
        assert!(
            (p.x.abs() - half).abs() < 1e-9 && (p.y.abs() - half).abs() < 1e-9,
            "{c:?}"
        );
    }
    let mut keys: Vec<_> = cs.iter().map(|c| c.key).collect();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), 4, "keys must be distinct");
}

#[test]
fn box_resting_on_halfspace_has_four_contacts() {
    let box_pose = at(0.0, 0.0, 0.5 - 0.001);
    let mut w = world(0.005, &[plane(), unit_box()]);
    assert_four_corners(
        &detect(&mut w, &[at(0.0, 0.0, 0.0), box_pose]),
        -0.001,
        Vector3::z(),
        0.5,
    );
    let mut w = world(0.005, &[unit_box(), plane()]);
    let cs = detect(&mut w, &[box_pose, at(0.0, 0.0, 0.0)]);
    assert_four_corners(&cs, -0.001, -Vector3::z(), 0.5);
    assert!(
        cs.iter()
            .all(|c| (c.point_a.z + 0.001).abs() < 1e-9 && c.point_b.z.abs() < 1e-9)
    );
}

#[test]
fn box_resting_on_box_has_four_contacts() {
    // Lower box 4 x 4 x 1 (top face at z = 0), upper unit box sinking 1 mm.
    let big = Shape::Box {
        half_extents: Vector3::new(2.0, 2.0, 0.5),
    };
    let mut w = world(0.005, &[big.clone(), unit_box()]);
    let poses = [at(0.0, 0.0, -0.5), at(0.0, 0.0, 0.5 - 0.001)];
    let cs = detect(&mut w, &poses);
    check_invariants(&cs);
    assert_eq!(cs.len(), 4, "{cs:#?}");
    for c in &cs {
        assert!(
            (c.distance + 0.001).abs() < 1e-9 && (c.normal - Vector3::z()).norm() < 1e-9,
            "{c:?}"
        );
        assert!(
            (c.point_b.x.abs() - 0.5).abs() < 1e-9 && (c.point_b.y.abs() - 0.5).abs() < 1e-9,
            "{c:?}"
        );
    }
    // Same-size boxes, upper on top of lower, reversed ids (unit box is A): normal -Z.
    let mut w = world(0.005, &[unit_box(), unit_box()]);
    let cs = detect(&mut w, &[at(0.0, 0.0, 1.0 - 0.001), at(0.0, 0.0, 0.0)]);
    check_invariants(&cs);
    assert_eq!(cs.len(), 4, "{cs:#?}");
    assert!(
        cs.iter()
            .all(|c| (c.distance + 0.001).abs() < 1e-9 && (c.normal + Vector3::z()).norm() < 1e-9)
    );
}

#[test]
fn contact_keys_persist_under_small_motion() {
    for lower in [
        plane(),
        Shape::Box {
            half_extents: Vector3::new(2.0, 2.0, 0.5),
        },
    ] {
        let lower_pose = if matches!(lower, Shape::HalfSpace { .. }) {
            at(0.0, 0.0, 0.0)
        } else {
            at(0.0, 0.0, -0.5)
        };
        let mut w = world(0.005, &[lower, unit_box()]);
        let k1: Vec<_> = detect(&mut w, &[lower_pose, at(0.0, 0.0, 0.499)])
            .iter()
            .map(|c| c.key)
            .collect();
        let moved = Isometry3::from_parts(
            Translation3::new(1e-4, -2e-4, 0.4991),
            UnitQuaternion::from_euler_angles(1e-5, -1e-5, 1e-3),
        );
        let c2 = detect(&mut w, &[lower_pose, moved]);
        let k2: Vec<_> = c2.iter().map(|c| c.key).collect();
        assert_eq!(k1.len(), 4);
        let (mut s1, mut s2) = (k1.clone(), k2.clone());
        s1.sort();
        s2.sort();
        assert_eq!(s1, s2);
        check_invariants(&c2);
    }
}

#[test]
fn halfspace_against_every_shape() {
    let tri = Shape::TriMesh {
        vertices: vec![
            Vector3::new(-1.0, -1.0, 0.0),
            Vector3::new(1.0, -1.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
        ],
        indices: vec![[0, 1, 2]],
    };
    let hull: Vec<_> = (0..8)
        .map(|k| Vector3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64))
        .collect();
    let hf = Shape::HeightField {
        heights: vec![0.0; 9],
        nrows: 3,
        ncols: 3,
        scale: Vector3::new(2.0, 2.0, 1.0),
    };
    let cases: [(Shape, f64, usize); 6] = [
        (
            Shape::Capsule {
                half_length: 0.5,
                radius: 0.2,
            },
            0.2,
            1,
        ),
        (
            Shape::Cylinder {
                half_length: 0.5,
                radius: 0.2,
            },
            0.2,
            2,
        ),
        (Shape::ConvexHull { points: hull }, 0.0, 4),
        (tri, 0.0, 3),
        (hf, 0.0, 9),
        (unit_box(), 0.5, 4),
    ];
    // Capsule and cylinder lie flat (axis Y horizontal): a line contact, 1 or 2 points.
    for (shape, bottom, min_points) in cases {
        let mut w = world(0.01, &[plane(), shape.clone()]);
        let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.0, 0.0, bottom - 0.002)]);
        check_invariants(&cs);
        assert!(cs.len() >= min_points, "{}: {cs:#?}", shape.kind_name());
        for c in &cs {
            assert!(
                (c.distance + 0.002).abs() < 1e-9 && (c.normal - Vector3::z()).norm() < 1e-9,
                "{}: {c:?}",
                shape.kind_name()
            );
        }
    }
}

#[test]
fn heightfield_is_z_up_with_documented_layout() {
    // Heights rise with the row index (along +Y): node (i, j) height = i.
    let hf = Shape::HeightField {
        heights: vec![0.0, 0.0, 1.0, 1.0],
        nrows: 2,
        ncols: 2,
        scale: Vector3::new(2.0, 2.0, 1.0),
    };
    let s = Shape::Sphere { radius: 0.1 };
    let mut w = world(0.01, &[hf, s]);
    // The surface is the plane z = (y + 1) / 2: at (0.3, 0.5) it is z = 0.75.
    let n = Vector3::new(0.0, -0.5, 1.0).normalize();
    let on = Vector3::new(0.3, 0.5, 0.75) + n * 0.095;
    let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), at(on.x, on.y, on.z)]);
    check_invariants(&cs);
    assert!(!cs.is_empty());
    assert!(
        cs.iter()
            .all(|c| (c.distance + 0.005).abs() < 1e-9 && (c.normal - n).norm() < 1e-9),
        "{cs:#?}"
    );
}

#[test]
fn trimesh_against_box() {
    let ground = Shape::TriMesh {
        vertices: vec![
            Vector3::new(-5.0, -5.0, 0.0),
            Vector3::new(5.0, -5.0, 0.0),
            Vector3::new(5.0, 5.0, 0.0),
            Vector3::new(-5.0, 5.0, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
    };
    let mut w = world(0.01, &[ground, unit_box()]);
    let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.3, 0.2, 0.499)]);
    check_invariants(&cs);
    assert!(cs.len() >= 4, "{cs:#?}");
    assert!(
        cs.iter()
            .all(|c| (c.distance + 0.001).abs() < 1e-9 && (c.normal - Vector3::z()).norm() < 1e-9)
    );
}

#[test]
fn convex_pairs_satisfy_the_contact_conventions() {
    let hull: Vec<_> = (0..8)
        .map(|k| {
            Vector3::new(
                (k & 1) as f64,
                ((k >> 1) & 1) as f64,
                0.7 * ((k >> 2) & 1) as f64,
            )
        })
        .collect();
    let shapes = [
        Shape::Box {
            half_extents: Vector3::new(0.5, 0.3, 0.2),
        },
        Shape::Capsule {
            half_length: 0.4,
            radius: 0.2,
        },
        Shape::Cylinder {
            half_length: 0.4,
            radius: 0.3,
        },
        Shape::ConvexHull { points: hull },
        Shape::Sphere { radius: 0.3 },
    ];
    let env = 0.05;
    let mut total = 0;
    for a in &shapes {
        for b in &shapes {
            let mut w = world(env, &[a.clone(), b.clone()]);
            for k in 0..100 {
                let t = k as f64 * 0.37;
                let pa = Isometry3::new(
                    Vector3::zeros(),
                    Vector3::new(t.sin(), 0.3 * t, t.cos()) * 0.5,
                );
                let pb = Isometry3::new(
                    Vector3::new(0.1 * t.cos(), 0.1, 0.55 + 0.1 * (1.3 * t).sin()),
                    Vector3::new(0.2 * t, t.cos(), 0.1),
                );
                let cs = detect(&mut w, &[pa, pb]);
                check_invariants(&cs);
                total += cs.len();
                for c in &cs {
                    assert!(
                        c.distance < env && c.distance > -1.0,
                        "{} {}: {c:?}",
                        a.kind_name(),
                        b.kind_name()
                    );
                }
                let mut keys: Vec<_> = cs.iter().map(|c| c.key).collect();
                keys.sort();
                keys.dedup();
                assert_eq!(
                    keys.len(),
                    cs.len(),
                    "{} {}: duplicate keys {cs:#?}",
                    a.kind_name(),
                    b.kind_name()
                );
            }
        }
    }
    assert!(total > 1000, "{total}");
}

#[test]
fn composite_shapes_against_each_other() {
    let ground_mesh = Shape::TriMesh {
        vertices: vec![
            Vector3::new(-5.0, -5.0, 0.0),
            Vector3::new(5.0, -5.0, 0.0),
            Vector3::new(5.0, 5.0, 0.0),
            Vector3::new(-5.0, 5.0, 0.0),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
    };
    let field = Shape::HeightField {
        heights: vec![0.0; 16],
        nrows: 4,
        ncols: 4,
        scale: Vector3::new(10.0, 10.0, 1.0),
    };
    // A closed tetrahedron mesh with its base at z = 0 in its frame.
    let tetra = Shape::TriMesh {
        vertices: vec![
            Vector3::new(-0.5, -0.5, 0.0),
            Vector3::new(0.5, -0.5, 0.0),
            Vector3::new(0.0, 0.5, 0.0),
            Vector3::new(0.0, 0.0, 0.5),
        ],
        indices: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
    };
    let cases = [
        (field.clone(), unit_box(), 0.5),
        (ground_mesh.clone(), tetra.clone(), 0.0),
        (field.clone(), tetra.clone(), 0.0),
        (ground_mesh, field, 0.0),
    ];
    for (lower, upper, bottom) in cases {
        let name = format!("{} / {}", lower.kind_name(), upper.kind_name());
        let mut w = world(0.01, &[lower, upper]);
        let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), at(0.1, 0.2, bottom - 0.002)]);
        check_invariants(&cs);
        assert!(!cs.is_empty(), "{name}");
        for c in &cs {
            assert!(c.distance < 0.01 && c.distance > -0.01, "{name}: {c:?}");
            assert!(c.normal.z.abs() > 0.99, "{name}: {c:?}");
        }
    }
}
