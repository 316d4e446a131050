//! Narrow phase: contact points of one candidate pair.
//!
//! Sphere–sphere and sphere–half-space are analytic. An ellipsoid against a convex shape
//! or a plane is one `query::contact` point (see [`PairKind::Smooth`]). Every other pair
//! goes through parry's persistent `contact_manifolds` (the manifolds and workspace live in
//! the [`PairState`] and are handed back to parry on the next step so it can reuse them). If parry's manifolds do
//! not support a pair, or return no point for a height field against a triangle mesh or
//! height field (parry 0.31 does that), one closest-point contact from `query::contact` is
//! used instead; if that is unsupported too, the pair is an error
//! ([`ChronoError::Collision`]).
//!
//! Contacts of one pair that coincide (within 1 micrometer on both shapes, the same normal)
//! are merged, keeping the first: parry reports a corner twice when the edges of two
//! touching faces coincide (two equal boxes stacked exactly), a cylinder's line-contact end
//! up to three times, and a mesh vertex once per triangle that shares it. Each copy would
//! be a repeated row of the contact problem (a singular problem, and work for nothing: a
//! quarter of the M113's rows were such copies).

use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::{
    self, ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher,
    PersistentQueryDispatcher,
};
use parry3d_f64::shape::PackedFeatureId;

use super::contact::{ColliderId, ContactKey, ContactPoint};
use super::convert::{vec_from_glam, vec_to_glam};
use super::world::{Collider, ColliderKind};
use crate::error::ChronoError;
use crate::shape::Shape;

/// Feature id used by the analytic contacts (parry's `face(0)`).
const FACE0: u32 = 0xC000_0000;

/// Contacts of one pair closer than this (m, squared) on both shapes, with normals closer
/// than its square root, are merged.
const MERGE_DISTANCE_SQ: f64 = 1e-12;

/// How a pair is computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PairKind {
    /// Two spheres, analytic.
    SphereSphere,
    /// A sphere and a half-space, analytic; `sphere_is_a` tells which is which.
    SphereHalfSpace {
        /// True if collider A is the sphere.
        sphere_is_a: bool,
    },
    /// An ellipsoid against a convex shape or a half-space: one contact point from
    /// `query::contact` (GJK / EPA on the support maps, analytic against a half-space, the
    /// exact point projection against a ball), its normal the ellipsoid's surface normal
    /// at its contact point (GJK's direction is undefined when the two just touch).
    /// Parry's manifold path for the same pair goes through the feature map with the other
    /// shape's rounding as a border, 100x less accurate on curved pairs (measured: normal
    /// 2e-4 rad against 2e-6 for an ellipsoid on a capsule).
    Smooth,
    /// Parry's persistent contact manifolds. With `closest_fallback`, a step where the
    /// manifolds hold no point asks `query::contact` for the closest pair instead: parry
    /// 0.31 returns empty manifolds for a height field against a triangle mesh.
    Manifolds {
        /// Use the closest-point query when the manifolds are empty.
        closest_fallback: bool,
        /// Keep one point per manifold, the deepest: a smooth strictly convex shape (the
        /// ellipsoid, against the triangles of a mesh or height field) touches a convex
        /// piece at one point, but parry adds its GJK / EPA
        /// point to the clipped feature point, the same point twice within GJK's tolerance
        /// (micrometers), which would double an SMC contact force.
        one_point: bool,
    },
}

impl PairKind {
    pub(crate) fn of(a: &Collider, b: &Collider) -> PairKind {
        match (&a.kind, &b.kind) {
            (ColliderKind::Sphere { .. }, ColliderKind::Sphere { .. }) => PairKind::SphereSphere,
            (ColliderKind::Sphere { .. }, ColliderKind::HalfSpace { .. }) => {
                PairKind::SphereHalfSpace { sphere_is_a: true }
            }
            (ColliderKind::HalfSpace { .. }, ColliderKind::Sphere { .. }) => {
                PairKind::SphereHalfSpace { sphere_is_a: false }
            }
            _ if !a.composite
                && !b.composite
                && (matches!(a.shape(), Shape::Ellipsoid { .. })
                    || matches!(b.shape(), Shape::Ellipsoid { .. })) =>
            {
                PairKind::Smooth
            }
            _ => PairKind::Manifolds {
                closest_fallback: a.composite
                    && b.composite
                    && (matches!(a.shape(), Shape::HeightField { .. })
                        || matches!(b.shape(), Shape::HeightField { .. })),
                one_point: matches!(a.shape(), Shape::Ellipsoid { .. })
                    || matches!(b.shape(), Shape::Ellipsoid { .. }),
            },
        }
    }
}

/// Everything kept per candidate pair across steps.
pub(crate) struct PairState {
    /// Collider A (`a < b`).
    pub a: u32,
    /// Collider B.
    pub b: u32,
    /// How the pair is computed.
    pub kind: PairKind,
    /// Parry's persistent manifolds.
    manifolds: Vec<ContactManifold<(), ()>>,
    /// Parry's persistent workspace (composite shapes).
    workspace: Option<ContactManifoldsWorkspace>,
    /// This step's contacts of the pair.
    pub contacts: Vec<ContactPoint>,
    /// This step's error, if any (boxed: keeps the state small to move).
    pub error: Option<Box<ChronoError>>,
}

impl PairState {
    /// A fresh state for the pair `(a, b)`.
    pub(crate) fn new(a: u32, b: u32, kind: PairKind) -> Self {
        Self {
            a,
            b,
            kind,
            manifolds: Vec::new(),
            workspace: None,
            contacts: Vec::new(),
            error: None,
        }
    }

    /// Forget the pair (keeps the buffers' capacity for reuse by another pair).
    pub(crate) fn reset(&mut self, a: u32, b: u32, kind: PairKind) {
        self.a = a;
        self.b = b;
        self.kind = kind;
        self.manifolds.clear();
        self.workspace = None;
        self.contacts.clear();
        self.error = None;
    }

    /// Compute this step's contacts. `poses[i]` is the world pose of collider `i`'s parry
    /// shape. Errors are stored in `self.error` (so parallel runs stay deterministic).
    pub(crate) fn update(&mut self, colliders: &[Collider], poses: &[Pose], envelope: f64) {
        self.contacts.clear();
        self.error = None;
        let (ca, cb) = (&colliders[self.a as usize], &colliders[self.b as usize]);
        let (pa, pb) = (&poses[self.a as usize], &poses[self.b as usize]);
        let out = Output {
            a: self.a,
            b: self.b,
            ca,
            cb,
            envelope,
            material: ca.material().combine(&cb.material()),
            radius: super::contact::effective_radius(
                ca.shape().curvature_radius(),
                cb.shape().curvature_radius(),
            ),
        };
        match self.kind {
            PairKind::SphereSphere => {
                let (ColliderKind::Sphere { radius: ra }, ColliderKind::Sphere { radius: rb }) =
                    (&ca.kind, &cb.kind)
                else {
                    unreachable!("pair kind matches collider kinds")
                };
                let delta = pb.translation - pa.translation;
                let len = delta.length();
                let n = if len > 0.0 { delta / len } else { Vector::Z };
                let p1 = pa.translation + n * *ra;
                let p2 = pb.translation - n * *rb;
                out.push(&mut self.contacts, p1, p2, n, FACE0, FACE0);
            }
            PairKind::SphereHalfSpace { sphere_is_a } => {
                let (sphere, plane, ps, ph) = if sphere_is_a {
                    (ca, cb, pa, pb)
                } else {
                    (cb, ca, pb, pa)
                };
                let (ColliderKind::Sphere { radius }, ColliderKind::HalfSpace { normal }) =
                    (&sphere.kind, &plane.kind)
                else {
                    unreachable!("pair kind matches collider kinds")
                };
                let n = ph.rotation * *normal;
                let c = ps.translation;
                let height = (c - ph.translation).dot(n);
                let on_sphere = c - n * *radius;
                let on_plane = c - n * height;
                if sphere_is_a {
                    out.push(&mut self.contacts, on_sphere, on_plane, -n, FACE0, FACE0);
                } else {
                    out.push(&mut self.contacts, on_plane, on_sphere, n, FACE0, FACE0);
                }
            }
            PairKind::Smooth => self.closest_contact(&out, pa, pb),
            PairKind::Manifolds {
                closest_fallback,
                one_point,
            } => {
                let pos12 = pa.inv_mul(pb);
                let (sa, sb) = (ca.parry.as_ref(), cb.parry.as_ref());
                let res = DefaultQueryDispatcher.contact_manifolds(
                    &pos12,
                    sa,
                    sb,
                    envelope,
                    &mut self.manifolds,
                    &mut self.workspace,
                );
                let empty = self.manifolds.iter().all(|m| m.points.is_empty());
                if res.is_err() || (closest_fallback && empty) {
                    self.closest_contact(&out, pa, pb);
                } else {
                    self.manifold_contacts(&out, pa, pb, one_point);
                }
            }
        }
    }

    /// The points of parry's manifolds (with `one_point`, the deepest of each manifold).
    fn manifold_contacts(&mut self, out: &Output<'_>, pa: &Pose, pb: &Pose, one_point: bool) {
        for m in &self.manifolds {
            let wa = m.subshape_pos1().map_or(*pa, |p| *pa * *p);
            let wb = m.subshape_pos2().map_or(*pb, |p| *pb * *p);
            let n = wa.rotation * m.local_n1;
            let first = self.contacts.len();
            for c in &m.points {
                let (p1, p2) = (wa * c.local_p1, wb * c.local_p2);
                // A smooth surface's normal at the contact point is the contact normal;
                // GJK's direction is undefined when the two just touch.
                let n = if one_point {
                    smooth_normal(out.ca, &wa, p1)
                        .or_else(|| smooth_normal(out.cb, &wb, p2).map(|v| -v))
                        .unwrap_or(n)
                } else {
                    n
                };
                // Parry reports a point more than once: a corner twice (vertex-face and
                // face-vertex) when edges of two faces coincide (equal boxes stacked), a
                // cylinder's line contact end up to three times (its clipping, offset
                // tangentially), a vertex shared by the triangles of a mesh once per
                // triangle. The same points (as stored: on the common normal line) with
                // the same normal are one contact: keep the first.
                let (q1, q2) = on_normal_line(p1, p2, n);
                let dup = self.contacts.iter().any(|k| {
                    (vec_to_glam(&k.point_a) - q1).length_squared() <= MERGE_DISTANCE_SQ
                        && (vec_to_glam(&k.point_b) - q2).length_squared() <= MERGE_DISTANCE_SQ
                        && (vec_to_glam(&k.normal) - n).length_squared() <= MERGE_DISTANCE_SQ
                });
                if !dup {
                    let fa = feature_key(c.fid1, m.subshape1, out.ca.composite);
                    let fb = feature_key(c.fid2, m.subshape2, out.cb.composite);
                    out.push(&mut self.contacts, p1, p2, n, fa, fb);
                }
            }
            if one_point && self.contacts.len() > first + 1 {
                let deepest = (first..self.contacts.len())
                    .min_by(|&i, &j| {
                        self.contacts[i]
                            .distance
                            .total_cmp(&self.contacts[j].distance)
                    })
                    .unwrap_or(first);
                self.contacts.swap(first, deepest);
                self.contacts.truncate(first + 1);
            }
            if one_point && let Some(c) = self.contacts.get_mut(first) {
                // Which of the two copies is deeper may change from step to step: the key
                // names the manifold's sub-shapes only, so it stays the same.
                let unknown = PackedFeatureId::UNKNOWN;
                c.key.feature_a = feature_key(unknown, m.subshape1, out.ca.composite);
                c.key.feature_b = feature_key(unknown, m.subshape2, out.cb.composite);
            }
        }
    }

    /// One closest-point contact from `query::contact`, or the pair's error.
    fn closest_contact(&mut self, out: &Output<'_>, pa: &Pose, pb: &Pose) {
        let (ca, cb) = (out.ca, out.cb);
        match query::contact(pa, ca.parry.as_ref(), pb, cb.parry.as_ref(), out.envelope) {
            Ok(Some(c)) => {
                let fa = feature_key(PackedFeatureId::UNKNOWN, c.subshape1, ca.composite);
                let fb = feature_key(PackedFeatureId::UNKNOWN, c.subshape2, cb.composite);
                let n = if self.kind == PairKind::Smooth {
                    smooth_normal(ca, pa, c.point1)
                        .or_else(|| smooth_normal(cb, pb, c.point2).map(|v| -v))
                        .unwrap_or(c.normal1)
                } else {
                    c.normal1
                };
                out.push(&mut self.contacts, c.point1, c.point2, n, fa, fb);
            }
            Ok(None) => {}
            Err(e) => {
                self.error = Some(Box::new(ChronoError::Collision {
                    a: describe(self.a, ca),
                    b: describe(self.b, cb),
                    reason: format!("{e} (parry has no contact query for this pair)"),
                }));
            }
        }
    }
}

/// The outward unit normal of an ellipsoid collider at its surface point `p` (world), its
/// parry shape at `pose`: the gradient `x_i / e_i^2` of the local point; `None` for other
/// shapes.
fn smooth_normal(c: &Collider, pose: &Pose, p: Vector) -> Option<Vector> {
    let Shape::Ellipsoid { semi_axes } = c.shape() else {
        return None;
    };
    let e = vec_to_glam(semi_axes);
    let x = pose.inverse_transform_point(p);
    (pose.rotation * (x / (e * e))).try_normalize()
}

/// Persistence feature of a contact (see [`ContactKey`]).
#[inline]
pub(crate) fn feature_key(fid: PackedFeatureId, subshape: u32, composite: bool) -> u32 {
    if composite {
        (subshape << 4) | ((fid.0 >> 30) << 2) | (fid.0 & 3)
    } else {
        fid.0
    }
}

/// `collider 3 (box, owner 1)`.
pub(crate) fn describe(id: u32, c: &Collider) -> String {
    format!(
        "collider {id} ({}, owner {})",
        c.shape().kind_name(),
        c.owner()
    )
}

/// What a pair's contacts share.
struct Output<'a> {
    a: u32,
    b: u32,
    ca: &'a Collider,
    cb: &'a Collider,
    envelope: f64,
    material: crate::material::ContactMaterial,
    radius: f64,
}

/// The pair `(p1, p2)` moved onto a common line along `n`: each point by half the
/// tangential part of `p2 - p1` (the distance along `n` unchanged).
#[inline]
fn on_normal_line(p1: Vector, p2: Vector, n: Vector) -> (Vector, Vector) {
    let gap = p2 - p1;
    let half_offset = (gap - n * gap.dot(n)) * 0.5;
    (p1 + half_offset, p2 - half_offset)
}

impl Output<'_> {
    /// Convert one contact to our types, if closer than the envelope.
    ///
    /// The two points are put on a common normal line: parry's pair may be offset
    /// tangentially (pfm-pfm clipping with cylinders and capsules, by centimeters), which
    /// would make equal and opposite contact forces form a spurious couple. Each point moves
    /// by half the tangential offset; the distance along the normal is unchanged.
    #[inline]
    fn push(
        &self,
        out: &mut Vec<ContactPoint>,
        p1: Vector,
        p2: Vector,
        n: Vector,
        fa: u32,
        fb: u32,
    ) {
        let gap = p2 - p1;
        let distance = gap.dot(n);
        if distance.is_nan() || distance >= self.envelope {
            return;
        }
        let (q1, q2) = on_normal_line(p1, p2, n);
        let (point_a, point_b) = (vec_from_glam(q1), vec_from_glam(q2));
        let normal = vec_from_glam(n);
        out.push(ContactPoint {
            collider_a: ColliderId(self.a),
            collider_b: ColliderId(self.b),
            owner_a: self.ca.owner(),
            owner_b: self.cb.owner(),
            point_a,
            point_b,
            normal,
            distance,
            key: ContactKey {
                collider_a: self.a,
                collider_b: self.b,
                feature_a: fa,
                feature_b: fb,
            },
            material: self.material,
            radius: self.radius,
        });
    }
}
