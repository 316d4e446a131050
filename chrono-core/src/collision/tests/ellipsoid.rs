//! The ellipsoid (a custom parry support-map shape) against the other shapes: contact
//! distance, normal and points against analytic support points.
//!
//! The construction used throughout: for a world direction `n`, the support point of a
//! convex body along `n` is where its surface normal is `n`. Placing body B so that its
//! support point along `-n` sits at `s_A(n) + gap n` makes the plane through `s_A(n)` with
//! normal `n` separate them: their distance is exactly `gap`, realized by those two points,
//! and the contact normal (A to B) is `n`. With a small penetration (`gap < 0`) the depth
//! along `n` is `gap`; the true penetration depth can only be smaller in magnitude, by
//! `O(gap^2 / R)` for curvature radius `R`.

use super::*;
use crate::math::{Translation3, UnitQuaternion};

fn ellipsoid(a: f64, b: f64, c: f64) -> Shape {
    Shape::Ellipsoid {
        semi_axes: Vector3::new(a, b, c),
    }
}

/// World support point along `d` of an ellipsoid with semi-axes `e` at `pose`.
fn support(e: &Vector3<f64>, pose: &Isometry3<f64>, d: &Vector3<f64>) -> Vector3<f64> {
    let dl = pose.rotation.inverse() * d;
    let ed = e.component_mul(&dl);
    let local = e.component_mul(&ed) / ed.norm();
    (pose * nalgebra::Point3::from(local)).coords
}

fn orientations() -> Vec<UnitQuaternion<f64>> {
    vec![
        UnitQuaternion::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.7),
        UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0),
        UnitQuaternion::from_euler_angles(1.4, 0.2, -0.5),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
    ]
}

fn pose_with(rot: UnitQuaternion<f64>, p: Vector3<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(Translation3::from(p), rot)
}

/// One contact (the ellipsoid is smooth) with the expected distance and normal and its
/// points on the two surfaces; tolerances as the callers state.
fn check_one(
    cs: &[ContactPoint],
    gap: f64,
    n: &Vector3<f64>,
    pa: &Vector3<f64>,
    tol_d: f64,
    tol_p: f64,
) {
    check_invariants(cs);
    assert_eq!(cs.len(), 1, "{cs:?}");
    let c = &cs[0];
    assert!(
        (c.distance - gap).abs() < tol_d,
        "distance {} vs {gap}",
        c.distance
    );
    assert!(
        (c.normal - n).norm() < tol_p.max(1e-9),
        "normal {} vs {n}",
        c.normal
    );
    assert!(
        (c.point_a - pa).norm() < tol_p,
        "point_a {} vs {pa}",
        c.point_a
    );
}

#[test]
fn ellipsoid_rests_on_a_plane_at_its_support_height() {
    // Ground is collider 0 (A), the ellipsoid B: the normal is +Z, the ellipsoid's lowest
    // point is its support point along -Z, at height z_c - sqrt(sum (e_i R_zi)^2).
    let e = Vector3::new(0.3, 0.2, 0.1);
    for rot in orientations() {
        for gap in [-0.004, 0.0, 0.003] {
            let mut w = world(0.01, &[plane(), ellipsoid(e.x, e.y, e.z)]);
            let probe = pose_with(rot, Vector3::zeros());
            let low = support(&e, &probe, &-Vector3::z());
            let center = Vector3::new(0.4, -0.2, gap - low.z);
            let pose = pose_with(rot, center);
            let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), pose]);
            let on_e = support(&e, &pose, &-Vector3::z());
            assert!((on_e.z - gap).abs() < 1e-12);
            let on_plane = Vector3::new(on_e.x, on_e.y, 0.0);
            check_one(&cs, gap, &Vector3::z(), &on_plane, 1e-12, 1e-9);
            assert!(
                (cs[0].point_b - on_e).norm() < 1e-9,
                "{:?} vs {on_e}",
                cs[0]
            );
        }
    }
}

#[test]
fn ellipsoid_on_a_box_face_and_a_mesh() {
    // A wide box and a two-triangle mesh as floors (A), the ellipsoid (B) above.
    let e = Vector3::new(0.25, 0.15, 0.1);
    let slab = Shape::Box {
        half_extents: Vector3::new(2.0, 2.0, 0.5),
    };
    let floor = Shape::TriMesh {
        vertices: vec![
            Vector3::new(-2.0, -2.0, 0.5),
            Vector3::new(2.0, -2.0, 0.5),
            Vector3::new(2.0, 2.0, 0.5),
            Vector3::new(-2.0, 2.0, 0.5),
        ],
        indices: vec![[0, 1, 2], [0, 2, 3]],
    };
    for base in [slab, floor] {
        for rot in orientations() {
            for gap in [-0.002, 0.004] {
                let mut w = world(0.01, &[base.clone(), ellipsoid(e.x, e.y, e.z)]);
                let low = support(&e, &pose_with(rot, Vector3::zeros()), &-Vector3::z());
                let pose = pose_with(rot, Vector3::new(0.3, 0.1, 0.5 + gap - low.z));
                let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), pose]);
                let on_e = support(&e, &pose, &-Vector3::z());
                let on_floor = Vector3::new(on_e.x, on_e.y, 0.5);
                // The box: GJK / EPA (one point), measured normal within 1.2e-5 rad and
                // distance within 1e-10 m; the mesh: parry's triangle manifold reduced to
                // its deepest point, exact.
                check_one(&cs, gap, &Vector3::z(), &on_floor, 1e-8, 1e-4);
            }
        }
    }
}

#[test]
fn two_ellipsoids_touching_along_an_axis() {
    // Along X: the gap is x_B - a_B - a_A, whatever the other axes.
    let (ea, eb) = (Vector3::new(0.3, 0.2, 0.1), Vector3::new(0.15, 0.25, 0.05));
    // Exactly touching (gap 0) is where GJK's direction is undefined: the normal comes
    // from the ellipsoid's gradient at the contact point.
    for gap in [-0.003, -1e-4, 0.0, 1e-4, 0.005] {
        let mut w = world(
            0.01,
            &[ellipsoid(ea.x, ea.y, ea.z), ellipsoid(eb.x, eb.y, eb.z)],
        );
        let x = ea.x + eb.x + gap;
        let cs = detect(&mut w, &[at(0.0, 0.0, 0.0), at(x, 0.0, 0.0)]);
        // Touching along a symmetry axis the depth is exactly along X. Two curved
        // surfaces: GJK / EPA stop at parry's tolerance, the normal within ~2e-5 rad
        // (measured 1.5e-5), the points within R * that, R <= max^2/min = 0.9 m.
        check_one(
            &cs,
            gap,
            &Vector3::x(),
            &Vector3::new(ea.x, 0.0, 0.0),
            1e-8,
            1e-4,
        );
        assert!((cs[0].point_b - Vector3::new(x - eb.x, 0.0, 0.0)).norm() < 1e-4);
    }
}

#[test]
fn ellipsoid_against_convex_shapes_in_general_position() {
    // A: the ellipsoid, rotated; B: each convex shape, rotated, placed by its support point
    // along -n at s_A(n) + gap n (see the module doc). B's support point along -n is found
    // by parry's support map of B (boxes have a face there only at special angles, fine).
    use crate::collision::convert::{pose_to_glam, to_parry, vec_from_glam, vec_to_glam};
    let e = Vector3::new(0.3, 0.2, 0.12);
    let others = [
        Shape::Sphere { radius: 0.1 },
        ellipsoid(0.1, 0.22, 0.15),
        Shape::Box {
            half_extents: Vector3::new(0.1, 0.2, 0.15),
        },
        Shape::Cylinder {
            half_length: 0.15,
            radius: 0.08,
        },
        Shape::Capsule {
            half_length: 0.1,
            radius: 0.05,
        },
    ];
    let dirs = [
        Vector3::new(1.0, 0.4, 0.3).normalize(),
        Vector3::new(-0.2, 1.0, -0.5).normalize(),
        Vector3::new(0.1, -0.3, -1.0).normalize(),
    ];
    let rot_a = UnitQuaternion::from_euler_angles(0.4, -0.3, 1.2);
    let rot_b = UnitQuaternion::from_euler_angles(-0.9, 0.5, 0.25);
    for other in &others {
        let pb = to_parry(other, "b").unwrap().shape;
        let sm = pb.as_support_map().unwrap();
        for n in &dirs {
            // The gap is positive (the exact case) and inside the envelope.
            let gap = 0.004;
            let pose_a = pose_with(rot_a, Vector3::new(0.1, -0.2, 0.3));
            let s_a = support(&e, &pose_a, n);
            let probe = pose_with(rot_b, Vector3::zeros());
            let s_b0 = vec_from_glam(sm.support_point(&pose_to_glam(&probe), vec_to_glam(&-n)));
            let pose_b = pose_with(rot_b, s_a + n * gap - s_b0);
            let mut w = world(0.01, &[ellipsoid(e.x, e.y, e.z), other.clone()]);
            let cs = detect(&mut w, &[pose_a, pose_b]);
            // Boxes and cylinders give parry's clipped manifold when their feature is a
            // face: every point must then lie at or beyond the analytic distance.
            assert!(!cs.is_empty(), "{other:?} {n}: no contact");
            check_invariants(&cs);
            let best = cs
                .iter()
                .min_by(|a, b| a.distance.total_cmp(&b.distance))
                .unwrap();
            // GJK on a curved pair stops at parry's tolerance; the points within R * the
            // normal's error.
            assert!(
                (best.distance - gap).abs() < 1e-7,
                "{other:?} {n}: {} vs {gap}",
                best.distance
            );
            assert!(
                (best.normal - n).norm() < 1e-4,
                "{other:?} {n}: {}",
                best.normal
            );
            assert!(
                (best.point_a - s_a).norm() < 1e-4,
                "{other:?} {n}: {best:?} vs {s_a}"
            );
        }
    }
}

#[test]
fn ellipsoid_shapes_validate_and_report_their_field() {
    for (bad, needle) in [
        (ellipsoid(0.1, -0.2, 0.3), "-0.2"),
        (ellipsoid(0.1, 0.2, f64::NAN), "NaN"),
        (ellipsoid(0.0, 0.2, 0.3), "[0, 0.2, 0.3]"),
        (ellipsoid(f64::INFINITY, 0.2, 0.3), "inf"),
    ] {
        let err = CollisionWorld::new(0.01)
            .unwrap()
            .add_collider(0, &bad, Isometry3::identity(), mat())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("collider.shape.semi_axes") && err.contains(needle),
            "{err}"
        );
    }
}
