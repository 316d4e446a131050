//! Tests of the collision world (broad-phase tests live in `broad_phase`).
//!
//! `pairs`: contact conventions shape pair by shape pair; `ellipsoid`: the ellipsoid against
//! every convex shape, a mesh and a plane, checked against analytic support points; `scenes`: filtering, errors and
//! determinism of `CollisionWorld::detect`.

use super::*;
use crate::material::ContactMaterial;
use crate::math::{Isometry3, Vector3};
use crate::shape::Shape;

mod ellipsoid;
mod grid;
mod pairs;
mod removal;
mod scenes;

pub(super) fn at(x: f64, y: f64, z: f64) -> Isometry3<f64> {
    Isometry3::translation(x, y, z)
}

pub(super) fn mat() -> ContactMaterial {
    ContactMaterial::default()
}

pub(super) fn plane() -> Shape {
    Shape::HalfSpace {
        normal: Vector3::z(),
    }
}

pub(super) fn unit_box() -> Shape {
    Shape::Box {
        half_extents: Vector3::new(0.5, 0.5, 0.5),
    }
}

/// A world with one collider per owner; owner 0 fixed, the others active.
pub(super) fn world(envelope: f64, shapes: &[Shape]) -> CollisionWorld {
    let mut w = CollisionWorld::new(envelope).unwrap();
    for (i, s) in shapes.iter().enumerate() {
        w.add_collider(i as u32, s, Isometry3::identity(), mat())
            .unwrap();
    }
    w
}

pub(super) fn detect(w: &mut CollisionWorld, poses: &[Isometry3<f64>]) -> Vec<ContactPoint> {
    let active: Vec<bool> = (0..poses.len()).map(|i| i != 0).collect();
    let mut out = Vec::new();
    w.detect(poses, &active, &mut out).unwrap();
    out
}

pub(super) fn check_invariants(cs: &[ContactPoint]) {
    for c in cs {
        assert!((c.normal.norm() - 1.0).abs() < 1e-9, "{c:?}");
        assert!(
            ((c.point_b - c.point_a) - c.normal * c.distance).norm() < 1e-12,
            "{c:?}"
        );
        assert!(c.collider_a < c.collider_b);
        assert_eq!(
            (c.key.collider_a, c.key.collider_b),
            (c.collider_a.0, c.collider_b.0)
        );
    }
    // No contact twice (the same points and normal): a repeated contact is a repeated row
    // of the CCP (a singular problem, and work for nothing).
    for (i, a) in cs.iter().enumerate() {
        for b in &cs[i + 1..] {
            assert!(
                !a.coincides(b, 1e-6),
                "the same contact twice: {a:?} and {b:?}"
            );
        }
    }
}
