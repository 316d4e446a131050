//! The output of collision detection: contact points and their persistence keys.

use serde::{Deserialize, Serialize};

use crate::material::ContactMaterial;
use crate::math::Vector3;

/// Handle of a collider in a [`CollisionWorld`](super::CollisionWorld): its index, in
/// insertion order.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ColliderId(pub u32);

/// Persistence key of a contact point: the two colliders and the touching features.
///
/// It is stable from one step to the next as long as the same pair of features (vertex,
/// edge or face of each shape, as numbered by parry) stays in touch, so solvers can
/// warm-start NSC impulses and keep SMC tangential displacement history by looking the
/// key up in the previous step's contacts. Within one step the keys of one pair are
/// distinct (except in the rare case of two contacts on the same feature pair of a mesh).
///
/// - `collider_a < collider_b` always (the order of [`ContactPoint`]).
/// - For convex shapes `feature_*` is parry's packed feature id (2-bit kind vertex / edge /
///   face, 30-bit index).
/// - For triangle meshes and height fields the triangle index is folded in:
///   `triangle << 4 | kind << 2 | feature-in-triangle` (wraps past 2^28 triangles).
/// - Analytic sphere / half-space contacts use the face feature 0 (`0xC000_0000`) on both.
/// - A pair that parry's manifolds do not support (or a height field against a mesh, whose
///   manifolds parry 0.31 leaves empty) falls back to one closest-point contact with the
///   unknown feature `0` (and the triangle index folded in for meshes and height fields).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ContactKey {
    /// Index of the first collider (the smaller one).
    pub collider_a: u32,
    /// Index of the second collider.
    pub collider_b: u32,
    /// Feature of the first collider.
    pub feature_a: u32,
    /// Feature of the second collider.
    pub feature_b: u32,
}

impl ContactKey {
    /// The key after the colliders were renumbered by `map` (old id -> new id, `None` for
    /// a removed collider, from [`CollisionWorld::remove_owner`](super::CollisionWorld::remove_owner)).
    /// `None` if a collider is gone or the two swap order (the key of such a contact is the
    /// other way round, with the impulses' sign convention, so it is dropped, not reused).
    pub fn remap(&self, map: &[Option<u32>]) -> Option<Self> {
        let a = (*map.get(self.collider_a as usize)?)?;
        let b = (*map.get(self.collider_b as usize)?)?;
        (a < b).then_some(Self {
            collider_a: a,
            collider_b: b,
            ..*self
        })
    }
}

/// A contact point between two colliders.
///
/// Convention: `normal` is the world unit normal pointing **from A towards B** (outward
/// from A). `distance` is the signed gap along it, negative when the shapes penetrate, and
/// `point_b - point_a == distance * normal` (to round-off: the two points lie on a common
/// normal line, so equal and opposite forces there form no couple). So A is pushed along
/// `-normal` and B along `+normal` to separate them. A contact is reported when
/// `distance < envelope`.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct ContactPoint {
    /// The first collider (`collider_a < collider_b`).
    pub collider_a: ColliderId,
    /// The second collider.
    pub collider_b: ColliderId,
    /// The owner (rigid body) of collider A.
    pub owner_a: u32,
    /// The owner (rigid body) of collider B.
    pub owner_b: u32,
    /// Contact point on the surface of A (world frame, m).
    pub point_a: Vector3<f64>,
    /// Contact point on the surface of B (world frame, m).
    pub point_b: Vector3<f64>,
    /// World unit normal from A towards B.
    pub normal: Vector3<f64>,
    /// Signed gap (m), negative = penetration.
    pub distance: f64,
    /// Persistence key, see [`ContactKey`].
    pub key: ContactKey,
    /// The combined material of the two colliders ([`ContactMaterial::combine`]).
    pub material: ContactMaterial,
    /// Effective curvature radius of the contact `R = 1/(1/R_a + 1/R_b)` (m) from
    /// [`Shape::curvature_radius`](crate::shape::Shape::curvature_radius):
    /// `f64::INFINITY` when both surfaces are flat.
    pub radius: f64,
}

impl ContactPoint {
    /// True if `other` is the same contact: the same two colliders, both points and the
    /// normal within `tol` (m; unitless for the normal). A collision step reports no contact
    /// twice (a repeated contact would be a repeated row of the contact problem).
    pub fn coincides(&self, other: &ContactPoint, tol: f64) -> bool {
        self.collider_a == other.collider_a
            && self.collider_b == other.collider_b
            && (self.point_a - other.point_a).norm() <= tol
            && (self.point_b - other.point_b).norm() <= tol
            && (self.normal - other.normal).norm() <= tol
    }
}

/// Effective radius `1/(1/a + 1/b)` of two curvature radii (m); infinite radii are flat.
#[inline]
pub fn effective_radius(a: f64, b: f64) -> f64 {
    1.0 / (1.0 / a + 1.0 / b)
}
