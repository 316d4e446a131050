//! Collision proxies of physics items against the colliders of rigid bodies.
//!
//! A [`PhysicsItem`](crate::item::PhysicsItem) (fluid particles, an FE mesh, MPM markers)
//! has no rigid colliders; it exposes simple *proxies* instead: spheres (a particle, a beam
//! node) and thick triangles (a shell or tet face). [`CollisionWorld::detect_proxies`]
//! finds their contacts with the body colliders; the contact rows then take the body's
//! Jacobian from the body and the proxy's from the item (its
//! [`proxy_jacobian`](crate::item::PhysicsItem::proxy_jacobian), e.g. the shape-function
//! weights of a triangle's nodes). Contacts among an item's own proxies are the item's
//! business (it has its own neighbour search); item–item contacts come with chrono-fsi.
//!
//! Broad phase: the proxies are sorted by the x of their centers once per call; each
//! collider's box selects the x range `[min - e, max + e]` (`e` the largest proxy half
//! extent) by binary search and tests the rest of the box; a half-space tests every proxy
//! against its plane. The narrow phase is analytic for a sphere proxy against a sphere or
//! half-space collider and parry's `query::contact` otherwise.

use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::PackedFeatureId;
use parry3d_f64::shape::{Ball, Triangle};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::broad_phase::Bound;
use super::contact::ColliderId;
use super::convert::{vec_from_glam, vec_to_glam};
use super::narrow_phase::{describe, feature_key};
use super::world::{ColliderKind, CollisionWorld};
use crate::error::{ChronoError, Result};
use crate::material::ContactMaterial;
use crate::math::Vector3;

/// Candidate pairs per rayon task.
const CHUNK: usize = 256;

/// The geometry of a collision proxy (world frame, m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ProxyShape {
    /// A sphere: a particle, a beam node.
    Sphere {
        /// Center (m).
        center: Vector3<f64>,
        /// Radius (m, >= 0).
        radius: f64,
    },
    /// A triangle swept by a sphere of radius `thickness`: a shell or tet face.
    Triangle {
        /// The three corners (m).
        vertices: [Vector3<f64>; 3],
        /// Radius of the sweeping sphere (m, >= 0): half the shell thickness.
        thickness: f64,
    },
}

impl ProxyShape {
    /// Center of the bounding box and its half extents (m).
    fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        match *self {
            ProxyShape::Sphere { center, radius } => (center, Vector3::repeat(radius)),
            ProxyShape::Triangle {
                vertices: [a, b, c],
                thickness,
            } => {
                let lo = a.inf(&b).inf(&c);
                let hi = a.sup(&b).sup(&c);
                (
                    (lo + hi) * 0.5,
                    (hi - lo) * 0.5 + Vector3::repeat(thickness),
                )
            }
        }
    }

    /// Check that the proxy is finite with a non-negative radius.
    fn validate(&self, field: &str) -> Result<()> {
        let (pts, r): (&[Vector3<f64>], f64) = match self {
            ProxyShape::Sphere { center, radius } => (std::slice::from_ref(center), *radius),
            ProxyShape::Triangle {
                vertices,
                thickness,
            } => (vertices.as_slice(), *thickness),
        };
        if let Some(p) = pts.iter().find(|p| !p.iter().all(|x| x.is_finite())) {
            return Err(ChronoError::invalid(
                field,
                p,
                "proxy positions must be finite",
            ));
        }
        if !(r.is_finite() && r >= 0.0) {
            return Err(ChronoError::invalid(
                field,
                r,
                "proxy radius / thickness must be finite and >= 0",
            ));
        }
        Ok(())
    }
}

/// A collision proxy exposed by a physics item.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CollisionProxy {
    /// Its geometry at the start of the step.
    pub shape: ProxyShape,
    /// Its surface material.
    pub material: ContactMaterial,
    /// The item's own id of the proxy (a particle or face index): handed back to
    /// [`PhysicsItem::proxy_jacobian`](crate::item::PhysicsItem::proxy_jacobian) and part of
    /// the persistence key, so keep it stable across steps.
    pub id: u32,
}

/// Persistence key of a proxy contact: the collider, the item, the proxy and the
/// collider's feature (a triangle index for meshes and height fields, else 0).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ProxyKey {
    /// The body collider.
    pub collider: u32,
    /// Index of the item in the system.
    pub item: u32,
    /// The proxy's id.
    pub proxy: u32,
    /// Feature on the collider.
    pub feature: u32,
}

/// A contact between a body collider (side A) and an item's proxy (side B).
///
/// Same conventions as [`ContactPoint`](super::ContactPoint): `normal` points from the
/// collider towards the proxy, `distance` is the signed gap (negative = penetration) and
/// `point_b - point_a = distance * normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProxyContact {
    /// The body collider.
    pub collider: ColliderId,
    /// The collider's owner (rigid body index).
    pub owner: u32,
    /// Index of the item in the system.
    pub item: u32,
    /// The proxy's id.
    pub proxy: u32,
    /// Point on the collider's surface (world, m).
    pub point_a: Vector3<f64>,
    /// Point on the proxy's surface (world, m).
    pub point_b: Vector3<f64>,
    /// World unit normal from the collider towards the proxy.
    pub normal: Vector3<f64>,
    /// Signed gap, m.
    pub distance: f64,
    /// Persistence key.
    pub key: ProxyKey,
    /// Combined material.
    pub material: ContactMaterial,
}

/// One chunk's output buffer and error slot.
type ChunkOut<'a> = (&'a mut Vec<ProxyContact>, &'a mut Option<ChronoError>);

/// Reused buffers of [`CollisionWorld::detect_proxies`].
#[derive(Debug, Default)]
pub(crate) struct ProxyScratch {
    /// `(center x, proxy index)` sorted.
    order: Vec<(f64, u32)>,
    /// Candidate `(collider, proxy index)` pairs.
    candidates: Vec<(u32, u32)>,
    /// One output buffer per chunk of candidates.
    chunks: Vec<Vec<ProxyContact>>,
    /// One error slot per chunk.
    errors: Vec<Option<ChronoError>>,
}

impl CollisionWorld {
    /// Contacts between the colliders and the proxies of item `item`, appended to `out`.
    ///
    /// Uses the collider poses of the last [`detect`](Self::detect) (call it first, in the
    /// same step). A contact is reported while its gap is below the envelope. Output order
    /// is deterministic (by collider, then by proxy center x and index) whatever the thread
    /// count. Errors: a non-finite proxy or negative radius (naming the item and the proxy)
    /// or a pair parry cannot handle.
    pub fn detect_proxies(
        &mut self,
        item: u32,
        proxies: &[CollisionProxy],
        out: &mut Vec<ProxyContact>,
    ) -> Result<()> {
        if proxies.is_empty() || self.colliders.is_empty() {
            return Ok(());
        }
        let mut s = std::mem::take(&mut self.proxy_scratch);
        let result = self.detect_proxies_with(item, proxies, &mut s, out);
        self.proxy_scratch = s;
        result
    }

    fn detect_proxies_with(
        &self,
        item: u32,
        proxies: &[CollisionProxy],
        s: &mut ProxyScratch,
        out: &mut Vec<ProxyContact>,
    ) -> Result<()> {
        let envelope = self.envelope;
        let half = 0.5 * envelope;
        // Sort by center x; the widest proxy bounds the x search window.
        s.order.clear();
        let mut reach = 0.0_f64;
        for (i, p) in proxies.iter().enumerate() {
            p.shape
                .validate(&format!("item {item} proxy {i} (id {})", p.id))?;
            let (c, e) = p.shape.bounds();
            reach = reach.max(e.x);
            s.order.push((c.x, i as u32));
        }
        s.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));

        s.candidates.clear();
        for (ci, bound) in self.bounds.iter().enumerate() {
            match bound {
                Bound::Box(aabb) => {
                    let (lo, hi) = (vec_from_glam(aabb.mins), vec_from_glam(aabb.maxs));
                    let from = s.order.partition_point(|o| o.0 < lo.x - reach - half);
                    let to = s.order.partition_point(|o| o.0 <= hi.x + reach + half);
                    for &(_, pi) in &s.order[from..to] {
                        let (c, e) = proxies[pi as usize].shape.bounds();
                        let e = e.add_scalar(half);
                        if (0..3).all(|d| c[d] + e[d] >= lo[d] && c[d] - e[d] <= hi[d]) {
                            s.candidates.push((ci as u32, pi));
                        }
                    }
                }
                Bound::HalfSpace { origin, normal } => {
                    let (o, n) = (vec_from_glam(*origin), vec_from_glam(*normal));
                    for &(_, pi) in &s.order {
                        let (c, e) = proxies[pi as usize].shape.bounds();
                        // Support of the box along -n.
                        let depth = (c - o).dot(&n) - e.dot(&n.abs());
                        if depth <= half {
                            s.candidates.push((ci as u32, pi));
                        }
                    }
                }
            }
        }

        let n_chunks = s.candidates.len().div_ceil(CHUNK);
        s.chunks.resize_with(n_chunks.max(s.chunks.len()), Vec::new);
        s.errors.clear();
        s.errors.resize_with(n_chunks, || None);
        let chunks = &mut s.chunks[..n_chunks];
        let run = |(pairs, (buf, err)): (&[(u32, u32)], ChunkOut<'_>)| {
            buf.clear();
            for &(ci, pi) in pairs {
                if let Err(e) = self.proxy_pair(item, ci, &proxies[pi as usize], envelope, buf) {
                    *err = Some(e);
                    return;
                }
            }
        };
        if s.candidates.len() > CHUNK {
            s.candidates
                .par_chunks(CHUNK)
                .zip(chunks.par_iter_mut().zip(s.errors.par_iter_mut()))
                .for_each(run);
        } else {
            s.candidates
                .chunks(CHUNK)
                .zip(chunks.iter_mut().zip(s.errors.iter_mut()))
                .for_each(run);
        }
        if let Some(e) = s.errors.iter_mut().find_map(Option::take) {
            return Err(e);
        }
        for buf in chunks.iter() {
            out.extend_from_slice(buf);
        }
        Ok(())
    }

    /// The contact (if any) of collider `ci` with one proxy.
    fn proxy_pair(
        &self,
        item: u32,
        ci: u32,
        proxy: &CollisionProxy,
        envelope: f64,
        out: &mut Vec<ProxyContact>,
    ) -> Result<()> {
        let c = &self.colliders[ci as usize];
        let pose = &self.poses[ci as usize];
        // (point on collider, point on proxy core, normal, feature); the core is the
        // sphere's center or the bare triangle, `radius` is added afterwards.
        let (p1, p2, n, feature, radius) = match (&proxy.shape, &c.kind) {
            (ProxyShape::Sphere { center, radius }, ColliderKind::Sphere { radius: rc }) => {
                let x = vec_to_glam(center);
                let d = x - pose.translation;
                let len = d.length();
                let n = if len > 0.0 { d / len } else { Vector::Z };
                (pose.translation + n * *rc, x, n, 0, *radius)
            }
            (ProxyShape::Sphere { center, radius }, ColliderKind::HalfSpace { normal }) => {
                let x = vec_to_glam(center);
                let n = pose.rotation * *normal;
                let height = (x - pose.translation).dot(n);
                (x - n * height, x, n, 0, *radius)
            }
            (shape, _) => {
                let (contact, radius) = match shape {
                    ProxyShape::Sphere { center, radius } => {
                        let p = Pose::from_translation(vec_to_glam(center));
                        let ball = Ball::new(*radius);
                        (
                            query::contact(pose, c.parry.as_ref(), &p, &ball, envelope),
                            0.0,
                        )
                    }
                    ProxyShape::Triangle {
                        vertices: [a, b, cc],
                        thickness,
                    } => {
                        let tri = Triangle::new(vec_to_glam(a), vec_to_glam(b), vec_to_glam(cc));
                        let pred = envelope + thickness;
                        let k = query::contact(pose, c.parry.as_ref(), &Pose::IDENTITY, &tri, pred);
                        (k, *thickness)
                    }
                };
                match contact {
                    Ok(Some(k)) => {
                        let f = feature_key(PackedFeatureId::UNKNOWN, k.subshape1, c.composite);
                        (k.point1, k.point2, k.normal1, f, radius)
                    }
                    Ok(None) => return Ok(()),
                    Err(e) => {
                        return Err(ChronoError::Collision {
                            a: describe(ci, c),
                            b: format!("item {item} proxy {}", proxy.id),
                            reason: format!("{e} (parry has no contact query for this pair)"),
                        });
                    }
                }
            }
        };
        // For the parry sphere query the ball is the proxy itself (radius 0 here); for the
        // analytic paths and triangles the proxy surface is `radius` from the core.
        let p2 = p2 - n * radius;
        let gap = p2 - p1;
        let distance = gap.dot(n);
        if distance.is_nan() || distance >= envelope {
            return Ok(());
        }
        // Put both points on one normal line (no spurious couple), as for body pairs.
        let half_offset = (gap - n * distance) * 0.5;
        out.push(ProxyContact {
            collider: ColliderId(ci),
            owner: c.owner(),
            item,
            proxy: proxy.id,
            point_a: vec_from_glam(p1 + half_offset),
            point_b: vec_from_glam(p2 - half_offset),
            normal: vec_from_glam(n),
            distance,
            key: ProxyKey {
                collider: ci,
                item,
                proxy: proxy.id,
                feature,
            },
            material: c.material().combine(&proxy.material),
        });
        Ok(())
    }
}
