//! The ellipsoid as a parry shape: parry 0.31 has none, so ours is a custom shape that
//! parry's generic algorithms accept.
//!
//! The solid is `sum_i (x_i / e_i)^2 <= 1` with semi-axes `e = (a, b, c)` along the local
//! X, Y, Z axes. What parry needs from it, and how each is computed:
//!
//! - **Support map** (GJK / EPA, and so every convex–convex pair): the point of the surface
//!   furthest along `d` is `x_i = e_i^2 d_i / |(e_1 d_1, e_2 d_2, e_3 d_3)|` (the surface
//!   normal `x_i / e_i^2` is parallel to `d` there). Exact.
//! - **Polygonal feature map** (parry's manifold generators for half-spaces, boxes, hulls,
//!   cylinders, triangles of meshes and height fields): a smooth convex surface touches
//!   anything at one point, so the "feature" is the single support vertex; parry adds the
//!   GJK / EPA closest pair. One contact point per pair.
//! - **Point projection** (a ball against the ellipsoid): the closest surface point of
//!   `y` is `x_i = e_i^2 y_i / (t + e_i^2)` with `t` the root of
//!   `F(t) = sum_i (e_i y_i / (t + e_i^2))^2 - 1` on `t > -min_i e_i^2`, found by bisection
//!   in the first octant with the axes sorted, the degenerate cases (a zero coordinate)
//!   treated apart. Method: D. Eberly, "Distance from a point to an ellipse, an ellipsoid,
//!   or a hyperellipsoid" (Geometric Tools, 2013). Inside and outside points alike.
//! - **Ray cast**: the ray scaled by `1/e` against the unit sphere. Exact.
//! - **Mass properties**: volume `4/3 pi a b c`, principal inertia `m/5 (b^2 + c^2)` etc.

use parry3d_f64::bounding_volume::{Aabb, BoundingSphere};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::math::{Real, Vector};
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d_f64::shape::{
    FeatureId, PackedFeatureId, PolygonalFeature, PolygonalFeatureMap, Shape, ShapeType,
    SupportMap, TypedShape,
};

/// A solid ellipsoid centered at the local origin, semi-axes along local X, Y, Z (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ellipsoid {
    /// Semi-axes `(a, b, c)` (m), each finite and > 0 (checked by `Shape::validate`).
    pub semi_axes: Vector,
}

impl Ellipsoid {
    pub(crate) fn new(semi_axes: Vector) -> Self {
        Self { semi_axes }
    }

    /// Outward unit normal at a surface point `x` (the gradient `x_i / e_i^2`).
    fn normal_at(&self, x: Vector) -> Vector {
        let e = self.semi_axes;
        (x / (e * e)).try_normalize().unwrap_or(Vector::Z)
    }

    /// The closest surface point to `y` (inside or outside), see the module doc.
    pub(crate) fn closest_surface_point(&self, y: Vector) -> Vector {
        let e = self.semi_axes.to_array();
        let yv = y.to_array();
        // Sort the axes by decreasing length; work with |y| (first octant).
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| e[j].total_cmp(&e[i]));
        let es = order.map(|i| e[i]);
        let ys = order.map(|i| yv[i].abs());
        let xs = closest_first_octant(es, ys);
        let mut out = [0.0; 3];
        for k in 0..3 {
            let i = order[k];
            out[i] = xs[k].copysign(if yv[i] == 0.0 { 1.0 } else { yv[i] });
        }
        Vector::from_array(out)
    }
}

/// Closest point of the ellipsoid `e0 >= e1 >= e2` to `y` with `y_i >= 0`.
fn closest_first_octant(e: [f64; 3], y: [f64; 3]) -> [f64; 3] {
    let [e0, e1, e2] = e;
    let [y0, y1, y2] = y;
    if y2 > 0.0 {
        if y1 > 0.0 {
            if y0 > 0.0 {
                return generic_root(&e, &y);
            }
            let [x1, x2] = closest_ellipse([e1, e2], [y1, y2]);
            return [0.0, x1, x2];
        }
        if y0 > 0.0 {
            let [x0, x2] = closest_ellipse([e0, e2], [y0, y2]);
            return [x0, 0.0, x2];
        }
        return [0.0, 0.0, e2];
    }
    // y2 == 0: the closest point leaves the plane z = 0 only if y is deep inside.
    let (d0, d1) = (e0 * e0 - e2 * e2, e1 * e1 - e2 * e2);
    let (n0, n1) = (e0 * y0, e1 * y1);
    if n0 < d0 && n1 < d1 {
        let (q0, q1) = (n0 / d0, n1 / d1);
        let disc = 1.0 - q0 * q0 - q1 * q1;
        if disc > 0.0 {
            return [e0 * q0, e1 * q1, e2 * disc.sqrt()];
        }
    }
    let [x0, x1] = closest_ellipse([e0, e1], [y0, y1]);
    [x0, x1, 0.0]
}

/// Closest point of the ellipse `e0 >= e1` to `y` with `y_i >= 0`.
fn closest_ellipse(e: [f64; 2], y: [f64; 2]) -> [f64; 2] {
    let [e0, e1] = e;
    let [y0, y1] = y;
    if y1 > 0.0 {
        if y0 > 0.0 {
            return generic_root(&e, &y);
        }
        return [0.0, e1];
    }
    let d0 = e0 * e0 - e1 * e1;
    if e0 * y0 < d0 {
        let x0 = e0 * e0 * y0 / d0;
        let q = x0 / e0;
        return [x0, e1 * (1.0 - q * q).max(0.0).sqrt()];
    }
    [e0, 0.0]
}

/// All `y_i > 0`, `e` sorted decreasing: root `s` of
/// `G(s) = sum_i (r_i z_i / (s + r_i))^2 - 1` with `z_i = y_i / e_i`,
/// `r_i = (e_i / e_min)^2`, by bisection; `x_i = r_i y_i / (s + r_i)`.
fn generic_root<const N: usize>(e: &[f64; N], y: &[f64; N]) -> [f64; N] {
    let emin = e[N - 1];
    let z: [f64; N] = std::array::from_fn(|i| y[i] / e[i]);
    let r: [f64; N] = std::array::from_fn(|i| (e[i] / emin).powi(2));
    let g = |s: f64| -> f64 {
        z.iter()
            .zip(&r)
            .map(|(zi, ri)| (ri * zi / (s + ri)).powi(2))
            .sum::<f64>()
            - 1.0
    };
    let g0 = g(0.0);
    if g0 == 0.0 {
        return *y;
    }
    // Bracket: G(z_min - 1) >= 0 and G(|r z| - 1) <= 0 (outside), G(0) < 0 (inside).
    let mut s0 = z[N - 1] - 1.0;
    let mut s1 = if g0 < 0.0 {
        0.0
    } else {
        z.iter()
            .zip(&r)
            .map(|(zi, ri)| (ri * zi).powi(2))
            .sum::<f64>()
            .sqrt()
            - 1.0
    };
    let mut s = 0.5 * (s0 + s1);
    // Down to round-off relative to r_i >= 1 (about 60 halvings; not to the ulp of s,
    // which near s = 0 would take a thousand).
    for _ in 0..200 {
        s = 0.5 * (s0 + s1);
        if s1 - s0 <= f64::EPSILON * (1.0 + s.abs()) {
            break;
        }
        let v = g(s);
        if v > 0.0 {
            s0 = s;
        } else if v < 0.0 {
            s1 = s;
        } else {
            break;
        }
    }
    std::array::from_fn(|i| r[i] * y[i] / (s + r[i]))
}

impl SupportMap for Ellipsoid {
    fn local_support_point(&self, dir: Vector) -> Vector {
        let e = self.semi_axes;
        let ed = e * dir;
        let len = ed.length();
        if len > 0.0 {
            e * ed / len
        } else {
            Vector::new(e.x, 0.0, 0.0)
        }
    }
}

impl PolygonalFeatureMap for Ellipsoid {
    fn local_support_feature(&self, dir: Vector, out: &mut PolygonalFeature) {
        // A smooth surface: the support "feature" is one vertex.
        out.vertices[0] = self.local_support_point(dir);
        out.vids[0] = PackedFeatureId::vertex(0);
        out.eids[0] = PackedFeatureId::UNKNOWN;
        out.fid = PackedFeatureId::vertex(0);
        out.num_vertices = 1;
    }
}

impl PointQuery for Ellipsoid {
    fn project_local_point(&self, pt: Vector, solid: bool) -> PointProjection {
        let e = self.semi_axes;
        let inside = (pt / e).length_squared() <= 1.0;
        if inside && solid {
            PointProjection::new(true, pt)
        } else {
            PointProjection::new(inside, self.closest_surface_point(pt))
        }
    }

    fn project_local_point_and_get_feature(&self, pt: Vector) -> (PointProjection, FeatureId) {
        (self.project_local_point(pt, false), FeatureId::Face(0))
    }
}

impl RayCast for Ellipsoid {
    fn cast_local_ray_and_get_normal(
        &self,
        ray: &Ray,
        max_time_of_impact: Real,
        solid: bool,
    ) -> Option<RayIntersection> {
        // Scaled by 1/e the ellipsoid is the unit sphere and the ray stays a ray with the
        // same parameter t.
        let e = self.semi_axes;
        let (o, d) = (ray.origin / e, ray.dir / e);
        let a = d.length_squared();
        let b = o.dot(d);
        let c = o.length_squared() - 1.0;
        if c <= 0.0 && solid {
            return Some(RayIntersection::new(0.0, Vector::ZERO, FeatureId::Face(0)));
        }
        if a == 0.0 {
            return None;
        }
        let disc = b * b - a * c;
        if disc < 0.0 {
            return None;
        }
        let t = if c <= 0.0 {
            (-b + disc.sqrt()) / a
        } else if b < 0.0 {
            (-b - disc.sqrt()) / a
        } else {
            return None;
        };
        if t > max_time_of_impact {
            return None;
        }
        let n = self.normal_at(ray.origin + ray.dir * t);
        Some(RayIntersection::new(t, n, FeatureId::Face(0)))
    }
}

impl Shape for Ellipsoid {
    fn compute_local_aabb(&self) -> Aabb {
        Aabb::new(-self.semi_axes, self.semi_axes)
    }

    fn compute_local_bounding_sphere(&self) -> BoundingSphere {
        BoundingSphere::new(Vector::ZERO, self.semi_axes.max_element())
    }

    fn clone_dyn(&self) -> Box<dyn Shape> {
        Box::new(*self)
    }

    fn scale_dyn(&self, scale: Vector, _num_subdivisions: u32) -> Option<Box<dyn Shape>> {
        let e = self.semi_axes * scale.abs();
        (e.min_element() > 0.0).then(|| Box::new(Ellipsoid::new(e)) as Box<dyn Shape>)
    }

    fn mass_properties(&self, density: Real) -> MassProperties {
        let e = self.semi_axes;
        let m = density * 4.0 / 3.0 * std::f64::consts::PI * e.x * e.y * e.z;
        let e2 = e * e;
        let i = Vector::new(e2.y + e2.z, e2.x + e2.z, e2.x + e2.y) * (m / 5.0);
        MassProperties::new(Vector::ZERO, m, i)
    }

    fn shape_type(&self) -> ShapeType {
        ShapeType::Custom
    }

    fn as_typed_shape(&self) -> TypedShape<'_> {
        TypedShape::Custom(self)
    }

    fn ccd_thickness(&self) -> Real {
        self.semi_axes.min_element()
    }

    fn ccd_angular_thickness(&self) -> Real {
        std::f64::consts::FRAC_PI_2
    }

    fn is_convex(&self) -> bool {
        true
    }

    fn as_support_map(&self) -> Option<&dyn SupportMap> {
        Some(self as &dyn SupportMap)
    }

    fn as_polygonal_feature_map(&self) -> Option<(&dyn PolygonalFeatureMap, Real)> {
        Some((self as &dyn PolygonalFeatureMap, 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> [Vector; 3] {
        [
            Vector::new(0.3, 0.2, 0.1),
            Vector::new(0.1, 0.5, 0.25),
            Vector::new(0.2, 0.2, 0.2),
        ]
    }

    /// The projection is on the surface and `y - x` is along the normal (the optimality
    /// condition), for points inside, outside and on symmetry planes.
    #[test]
    fn projection_is_on_surface_and_normal() {
        let pts = [
            Vector::new(0.5, 0.4, 0.3),
            Vector::new(0.01, -0.02, 0.015),
            Vector::new(-0.05, 0.0, 0.0),
            Vector::new(0.0, 0.0, 0.03),
            Vector::new(0.02, 0.01, 0.0),
            Vector::new(0.0, -0.7, 0.2),
            Vector::new(1.0, 0.0, 0.0),
            Vector::new(0.0, 0.0, -1.0),
        ];
        for e in axes() {
            let s = Ellipsoid::new(e);
            for &y in &pts {
                let x = s.closest_surface_point(y);
                let on = (x / e).length_squared();
                assert!((on - 1.0).abs() < 1e-12, "{e:?} {y:?}: |x/e|^2 = {on}");
                let n = s.normal_at(x);
                let d = y - x;
                assert!(d.cross(n).length() < 1e-10, "{e:?} {y:?}: {d:?} x {n:?}");
                // No surface point sampled nearby is closer.
                let best = (y - x).length();
                for k in 0..2000 {
                    let (u, v) = (k as f64 * 0.7771, k as f64 * 0.3181);
                    let p = e * Vector::new(u.cos() * v.sin(), u.sin() * v.sin(), v.cos());
                    assert!((y - p).length() >= best - 1e-12, "{e:?} {y:?}: {p:?}");
                }
            }
        }
    }

    #[test]
    fn support_point_is_furthest() {
        for e in axes() {
            let s = Ellipsoid::new(e);
            for d in [
                Vector::X,
                Vector::new(1.0, -2.0, 0.5),
                Vector::new(-0.3, 0.1, -1.0),
            ] {
                let p = s.local_support_point(d);
                assert!(((p / e).length_squared() - 1.0).abs() < 1e-12);
                assert!(s.normal_at(p).cross(d.normalize()).length() < 1e-12);
            }
        }
    }

    #[test]
    fn ray_hits_surface() {
        let s = Ellipsoid::new(Vector::new(0.3, 0.2, 0.1));
        let ray = Ray::new(Vector::new(-1.0, 0.0, 0.0), Vector::X);
        let hit = s.cast_local_ray_and_get_normal(&ray, 10.0, true).unwrap();
        assert!((hit.time_of_impact - 0.7).abs() < 1e-12);
        assert!((hit.normal + Vector::X).length() < 1e-12);
        let inside = Ray::new(Vector::ZERO, Vector::Z);
        let t = s.cast_local_ray(&inside, 10.0, false).unwrap();
        assert!((t - 0.1).abs() < 1e-12);
        assert!(s.cast_local_ray(&ray, 0.5, true).is_none());
        let miss = Ray::new(Vector::new(-1.0, 0.25, 0.0), Vector::X);
        assert!(s.cast_local_ray(&miss, 10.0, true).is_none());
    }
}
