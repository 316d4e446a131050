//! Our public description of collision and visualization shapes.
//!
//! A [`Shape`] is plain data (serde-friendly, comparable). The collision world converts it
//! once into a parry shape ([`crate::collision`]); the VTK writer triangulates it
//! ([`Shape::to_trimesh`]). Every size is in meters and every vector is in the local frame of
//! the collider (which is placed on its owner body by the collider's local pose).
//!
//! Axis conventions (the engine is Z up, parry is not always):
//! - [`Shape::Capsule`] and [`Shape::Cylinder`] have their axis along local **Y** (parry's
//!   convention). Rotate the collider's local pose to stand them up along Z.
//! - [`Shape::HeightField`] is Z up: heights are along local Z over a grid in the local XY
//!   plane. The conversion to parry's Y-up heightfield applies a fixed local rotation.

use serde::{Deserialize, Serialize};

use crate::error::{ChronoError, Result, check_finite3, check_positive};
use crate::math::Vector3;

/// A triangle mesh as `(vertices, triangles)`: positions (m) and counter-clockwise
/// vertex index triples.
pub type TriangleMesh = (Vec<Vector3<f64>>, Vec<[u32; 3]>);

/// A collision / visualization shape, in its local frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// A ball centered at the local origin.
    Sphere {
        /// Radius (m), > 0.
        radius: f64,
    },
    /// A box centered at the local origin, aligned with the local axes.
    Box {
        /// Half side lengths along local X, Y, Z (m), each > 0.
        half_extents: Vector3<f64>,
    },
    /// A capsule (cylinder with hemispherical caps) centered at the local origin, with its
    /// axis along local **Y**: the segment from `(0, -half_length, 0)` to
    /// `(0, half_length, 0)` swept by a ball of `radius`. Total length
    /// `2 (half_length + radius)`.
    Capsule {
        /// Half length of the inner segment (m), > 0.
        half_length: f64,
        /// Radius (m), > 0.
        radius: f64,
    },
    /// A solid circular cylinder centered at the local origin, axis along local **Y**,
    /// spanning `y` in `[-half_length, half_length]`.
    Cylinder {
        /// Half length along the axis (m), > 0.
        half_length: f64,
        /// Radius (m), > 0.
        radius: f64,
    },
    /// A solid ellipsoid centered at the local origin, `(x/a)^2 + (y/b)^2 + (z/c)^2 <= 1`
    /// with the semi-axes `(a, b, c)` along local X, Y, Z. Parry has no ellipsoid: the
    /// collision world gives parry a support-map shape (GJK / EPA, one contact point per
    /// pair), see the `collision::ellipsoid` module.
    Ellipsoid {
        /// Semi-axes `(a, b, c)` along local X, Y, Z (m), each finite and > 0.
        semi_axes: Vector3<f64>,
    },
    /// The convex hull of a point cloud (at least 4 points, not all coplanar).
    ConvexHull {
        /// The points (m, local frame); interior points are allowed and ignored.
        points: Vec<Vector3<f64>>,
    },
    /// A triangle mesh (possibly open). Triangles are oriented counter-clockwise seen from
    /// outside (the outward normal is `(b - a) x (c - a)`).
    TriMesh {
        /// Vertex positions (m, local frame).
        vertices: Vec<Vector3<f64>>,
        /// Vertex indices of each triangle.
        indices: Vec<[u32; 3]>,
    },
    /// A height field, **Z up**, over a regular grid centered at the local origin.
    ///
    /// Layout: row-major, `heights[i * ncols + j]` is the height of grid node `(i, j)`,
    /// row `i` in `0..nrows` along local +Y and column `j` in `0..ncols` along local +X.
    /// Node `(i, j)` is at
    /// `x = scale.x * (j / (ncols - 1) - 1/2)`, `y = scale.y * (i / (nrows - 1) - 1/2)`,
    /// `z = scale.z * heights[i * ncols + j]`.
    /// So the field covers `scale.x` by `scale.y` meters, and `scale.z` scales the heights.
    /// Each grid cell is split into two triangles. Everything below the surface is not
    /// solid: contacts are with the surface, their normal is the upward triangle normal.
    HeightField {
        /// `nrows * ncols` heights (multiplied by `scale.z`).
        heights: Vec<f64>,
        /// Number of grid rows (along local Y), >= 2.
        nrows: usize,
        /// Number of grid columns (along local X), >= 2.
        ncols: usize,
        /// Extent along X, extent along Y, height scale along Z (m), each > 0.
        scale: Vector3<f64>,
    },
    /// A half-space: the solid below the plane through the local origin with outward
    /// normal `normal` (local frame; need not be unit length, must be non-zero).
    HalfSpace {
        /// Outward normal (local frame).
        normal: Vector3<f64>,
    },
}

impl Shape {
    /// Curvature radius of the surface (m), used for the effective radius of a contact
    /// (Hertz's `R`, the rolling-friction lever arm): spheres, capsules and cylinders their
    /// radius; flat or unknown shapes (boxes, hulls, meshes, height fields, planes)
    /// `f64::INFINITY`. An ellipsoid's curvature varies over its surface (principal radii
    /// from `min^2/max` to `max^2/min` of its semi-axes): it is given the radius of the
    /// sphere of equal volume, `(a b c)^(1/3)`, exact when `a = b = c`.
    pub fn curvature_radius(&self) -> f64 {
        match self {
            Shape::Sphere { radius } | Shape::Capsule { radius, .. } => *radius,
            Shape::Cylinder { radius, .. } => *radius,
            Shape::Ellipsoid { semi_axes: e } => (e.x * e.y * e.z).cbrt(),
            _ => f64::INFINITY,
        }
    }

    /// A short name of the variant (`sphere`, `box`, ...), for messages.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Box { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Ellipsoid { .. } => "ellipsoid",
            Shape::ConvexHull { .. } => "convex hull",
            Shape::TriMesh { .. } => "trimesh",
            Shape::HeightField { .. } => "heightfield",
            Shape::HalfSpace { .. } => "half-space",
        }
    }

    /// Check the shape. `field` is the name of the shape in the caller's terms (e.g.
    /// `collider.shape`); errors name the offending sub-field (e.g.
    /// `collider.shape.radius`) and its value.
    ///
    /// Rejected: non-finite or non-positive sizes; convex hulls with fewer than 4 points,
    /// non-finite or (nearly) coplanar points; meshes with no triangles, non-finite
    /// vertices, out-of-range indices or zero-area triangles; height fields with fewer
    /// than 2 rows or columns, a size mismatch, non-finite heights or a non-positive
    /// scale; a zero or non-finite half-space normal.
    pub fn validate(&self, field: &str) -> Result<()> {
        match self {
            Shape::Sphere { radius } => {
                check_positive(&format!("{field}.radius"), *radius)?;
            }
            Shape::Box { half_extents } => {
                check_positive_vec(&format!("{field}.half_extents"), half_extents)?;
            }
            Shape::Ellipsoid { semi_axes } => {
                check_positive_vec(&format!("{field}.semi_axes"), semi_axes)?;
            }
            Shape::Capsule {
                half_length,
                radius,
            }
            | Shape::Cylinder {
                half_length,
                radius,
            } => {
                check_positive(&format!("{field}.half_length"), *half_length)?;
                check_positive(&format!("{field}.radius"), *radius)?;
            }
            Shape::ConvexHull { points } => validate_hull(field, points)?,
            Shape::TriMesh { vertices, indices } => validate_mesh(field, vertices, indices)?,
            Shape::HeightField {
                heights,
                nrows,
                ncols,
                scale,
            } => {
                if *nrows < 2 {
                    return Err(ChronoError::invalid(
                        format!("{field}.nrows"),
                        nrows,
                        "must be >= 2",
                    ));
                }
                if *ncols < 2 {
                    return Err(ChronoError::invalid(
                        format!("{field}.ncols"),
                        ncols,
                        "must be >= 2",
                    ));
                }
                if heights.len() != nrows * ncols {
                    return Err(ChronoError::invalid(
                        format!("{field}.heights.len()"),
                        heights.len(),
                        format!(
                            "must be nrows * ncols = {nrows} * {ncols} = {}",
                            nrows * ncols
                        ),
                    ));
                }
                if let Some(k) = heights.iter().position(|h| !h.is_finite()) {
                    return Err(ChronoError::invalid(
                        format!("{field}.heights[{k}]"),
                        heights[k],
                        "must be finite",
                    ));
                }
                check_positive_vec(&format!("{field}.scale"), scale)?;
            }
            Shape::HalfSpace { normal } => {
                let f = format!("{field}.normal");
                check_finite3(&f, normal)?;
                if normal.norm() <= f64::MIN_POSITIVE {
                    return Err(ChronoError::invalid(f, fmt_vec(normal), "must be non-zero"));
                }
            }
        }
        Ok(())
    }

    /// The volume (m^3) of a closed solid: `Some` for sphere, box, capsule, cylinder,
    /// ellipsoid (`4/3 pi a b c`) and convex hull; `None` for meshes (possibly open), height fields and half-spaces.
    /// The shape is assumed valid ([`Shape::validate`]); an invalid hull gives `None`.
    pub fn volume(&self) -> Option<f64> {
        use std::f64::consts::PI;
        match self {
            Shape::Sphere { radius: r } => Some(4.0 / 3.0 * PI * r.powi(3)),
            Shape::Box { half_extents: e } => Some(8.0 * e.x * e.y * e.z),
            Shape::Ellipsoid { semi_axes: e } => Some(4.0 / 3.0 * PI * e.x * e.y * e.z),
            Shape::Capsule {
                half_length: h,
                radius: r,
            } => Some(PI * r * r * (2.0 * h) + 4.0 / 3.0 * PI * r.powi(3)),
            Shape::Cylinder {
                half_length: h,
                radius: r,
            } => Some(PI * r * r * 2.0 * h),
            Shape::ConvexHull { .. } => crate::collision::convert::convex_hull_volume(self),
            Shape::TriMesh { .. } | Shape::HeightField { .. } | Shape::HalfSpace { .. } => None,
        }
    }

    /// Principal moments of inertia per unit mass (m^2), about the centroid (the local
    /// origin), in the local frame: `(Ixx, Iyy, Izz) / m` for a homogeneous solid.
    /// Multiply by the mass (`density * volume`) to get the body inertia.
    ///
    /// `Some` for sphere, box, capsule, cylinder and ellipsoid (their local axes are
    /// principal; ellipsoid: `((b^2 + c^2), (a^2 + c^2), (a^2 + b^2)) / 5`);
    /// `None` for the other shapes (their centroid is not the local origin in general).
    pub fn unit_inertia(&self) -> Option<Vector3<f64>> {
        match self {
            Shape::Sphere { radius: r } => Some(Vector3::repeat(0.4 * r * r)),
            Shape::Box { half_extents: e } => {
                let (x2, y2, z2) = (e.x * e.x, e.y * e.y, e.z * e.z);
                Some(Vector3::new(y2 + z2, x2 + z2, x2 + y2) / 3.0)
            }
            Shape::Ellipsoid { semi_axes: e } => {
                let (x2, y2, z2) = (e.x * e.x, e.y * e.y, e.z * e.z);
                Some(Vector3::new(y2 + z2, x2 + z2, x2 + y2) / 5.0)
            }
            Shape::Cylinder {
                half_length: h,
                radius: r,
            } => {
                let t = r * r / 4.0 + h * h / 3.0;
                Some(Vector3::new(t, r * r / 2.0, t))
            }
            Shape::Capsule {
                half_length: h,
                radius: r,
            } => {
                // Mass fractions of the cylinder and of the two hemispheres (one ball).
                let vc = 2.0 * h;
                let vs = 4.0 / 3.0 * r;
                let (mc, ms) = (vc / (vc + vs), vs / (vc + vs));
                let axial = mc * r * r / 2.0 + ms * 0.4 * r * r;
                // Hemispheres: 2/5 r^2 about their flat face, centroid 3r/8 from it,
                // face at distance h from the center (parallel-axis theorem).
                let transverse =
                    mc * (r * r / 4.0 + h * h / 3.0) + ms * (0.4 * r * r + h * h + 0.75 * h * r);
                Some(Vector3::new(transverse, axial, transverse))
            }
            _ => None,
        }
    }

    /// A triangle mesh of the boundary, in the local frame (for visualization).
    ///
    /// `subdivisions` (>= 3) sets the angular resolution of spheres, ellipsoids, capsules
    /// and cylinders (parry's `to_trimesh`). A half-space becomes a square of side
    /// `half_space_size` (m) centered at the local origin, in its plane, facing along the
    /// normal. Triangle meshes are returned as they are; height fields are split into two
    /// triangles per cell.
    pub fn to_trimesh(&self, subdivisions: u32, half_space_size: f64) -> Result<TriangleMesh> {
        crate::collision::mesh::triangulate(self, subdivisions, half_space_size)
    }
}

/// The point of the surface of the ellipsoid `(x/a)^2 + (y/b)^2 + (z/c)^2 = 1`
/// (`semi_axes = (a, b, c)`, m, each > 0) closest to the point `p` of its local frame, for
/// `p` inside or outside (on the medial set, one of the closest points). The root of
/// `sum_i (e_i p_i / (t + e_i^2))^2 = 1` by bisection, the points on a symmetry plane
/// apart (D. Eberly, "Distance from a point to an ellipse, an ellipsoid, or a
/// hyperellipsoid", Geometric Tools, 2013). Exact to round-off.
pub fn ellipsoid_closest_point(semi_axes: &Vector3<f64>, p: &Vector3<f64>) -> Vector3<f64> {
    use crate::collision::convert::{vec_from_glam, vec_to_glam};
    let e = crate::collision::ellipsoid::Ellipsoid::new(vec_to_glam(semi_axes));
    vec_from_glam(e.closest_surface_point(vec_to_glam(p)))
}

/// Signed distance (m, negative inside) of the local point `p` to the surface of the
/// ellipsoid with `semi_axes`, through [`ellipsoid_closest_point`].
pub fn ellipsoid_signed_distance(semi_axes: &Vector3<f64>, p: &Vector3<f64>) -> f64 {
    let d = (p - ellipsoid_closest_point(semi_axes, p)).norm();
    if p.component_div(semi_axes).norm_squared() < 1.0 {
        -d
    } else {
        d
    }
}

fn fmt_vec(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

fn check_positive_vec(field: &str, v: &Vector3<f64>) -> Result<()> {
    if v.iter().all(|c| c.is_finite() && *c > 0.0) {
        Ok(())
    } else {
        Err(ChronoError::invalid(
            field,
            fmt_vec(v),
            "every component must be finite and > 0",
        ))
    }
}

fn check_points_finite(field: &str, points: &[Vector3<f64>]) -> Result<()> {
    for (k, p) in points.iter().enumerate() {
        check_finite3(&format!("{field}[{k}]"), p)?;
    }
    Ok(())
}

fn validate_hull(field: &str, points: &[Vector3<f64>]) -> Result<()> {
    let f = format!("{field}.points");
    if points.len() < 4 {
        return Err(ChronoError::invalid(
            format!("{f}.len()"),
            points.len(),
            "a convex hull needs at least 4 points",
        ));
    }
    check_points_finite(&f, points)?;
    // Non-degeneracy: the largest tetrahedron found greedily must have a volume that is
    // not negligible against the cube of the cloud's size.
    let p0 = points[0];
    let far = |score: &dyn Fn(&Vector3<f64>) -> f64| {
        points
            .iter()
            .copied()
            .max_by(|a, b| score(a).total_cmp(&score(b)))
            .unwrap_or(p0)
    };
    let p1 = far(&|p| (p - p0).norm_squared());
    let size = (p1 - p0).norm();
    let d1 = p1 - p0;
    let p2 = far(&|p| d1.cross(&(p - p0)).norm_squared());
    let nrm = d1.cross(&(p2 - p0));
    let p3 = far(&|p| nrm.dot(&(p - p0)).abs());
    let vol6 = nrm.dot(&(p3 - p0)).abs();
    if !(size > 0.0 && vol6 > 1e-12 * size.powi(3)) {
        return Err(ChronoError::invalid(
            f,
            format!("{} points spanning {size} m", points.len()),
            "points are coincident, collinear or coplanar: the hull has no volume",
        ));
    }
    Ok(())
}

fn validate_mesh(field: &str, vertices: &[Vector3<f64>], indices: &[[u32; 3]]) -> Result<()> {
    if vertices.len() < 3 {
        return Err(ChronoError::invalid(
            format!("{field}.vertices.len()"),
            vertices.len(),
            "a mesh needs at least 3 vertices",
        ));
    }
    if indices.is_empty() {
        return Err(ChronoError::invalid(
            format!("{field}.indices.len()"),
            0,
            "a mesh needs at least one triangle",
        ));
    }
    check_points_finite(&format!("{field}.vertices"), vertices)?;
    let n = vertices.len();
    for (k, t) in indices.iter().enumerate() {
        let f = || format!("{field}.indices[{k}]");
        let v = || format!("[{}, {}, {}]", t[0], t[1], t[2]);
        if let Some(bad) = t.iter().find(|&&i| i as usize >= n) {
            return Err(ChronoError::invalid(
                f(),
                v(),
                format!("vertex index {bad} out of range ({n} vertices)"),
            ));
        }
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        if (b - a).cross(&(c - a)).norm_squared() == 0.0 {
            return Err(ChronoError::invalid(
                f(),
                v(),
                "degenerate triangle (zero area)",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn sphere(radius: f64) -> Shape {
        Shape::Sphere { radius }
    }
    fn cuboid(x: f64, y: f64, z: f64) -> Shape {
        Shape::Box {
            half_extents: Vector3::new(x, y, z),
        }
    }
    fn capsule(half_length: f64, radius: f64) -> Shape {
        Shape::Capsule {
            half_length,
            radius,
        }
    }
    fn cylinder(half_length: f64, radius: f64) -> Shape {
        Shape::Cylinder {
            half_length,
            radius,
        }
    }
    fn hull(z: f64) -> Shape {
        let p = |k: i32| {
            Vector3::new(
                (k & 1) as f64,
                ((k >> 1) & 1) as f64,
                z * ((k >> 2) & 1) as f64,
            )
        };
        Shape::ConvexHull {
            points: (0..8).map(p).collect(),
        }
    }
    fn mesh(indices: Vec<[u32; 3]>) -> Shape {
        let vertices = vec![Vector3::zeros(), Vector3::x(), Vector3::y()];
        Shape::TriMesh { vertices, indices }
    }
    fn field(n: usize, scale: Vector3<f64>) -> Shape {
        Shape::HeightField {
            heights: vec![0.0; n],
            nrows: 2,
            ncols: 3,
            scale,
        }
    }
    fn plane(normal: Vector3<f64>) -> Shape {
        Shape::HalfSpace { normal }
    }

    #[test]
    fn validation_names_field_and_value() {
        let cases: Vec<(Shape, &[&str])> = vec![
            (sphere(-0.5), &["collider.shape.radius", "-0.5"]),
            (
                cuboid(1.0, f64::NAN, 1.0),
                &["collider.shape.half_extents", "NaN"],
            ),
            (capsule(0.0, 1.0), &["collider.shape.half_length", "= 0"]),
            (
                cylinder(1.0, f64::INFINITY),
                &["collider.shape.radius", "inf"],
            ),
            (
                plane(Vector3::zeros()),
                &["collider.shape.normal", "[0, 0, 0]"],
            ),
            (hull(0.0), &["collider.shape.points", "coplanar"]),
            (
                Shape::ConvexHull {
                    points: vec![Vector3::zeros(); 2],
                },
                &["collider.shape.points.len()", "= 2"],
            ),
            (
                mesh(vec![[0, 1, 2], [0, 1, 7]]),
                &["collider.shape.indices[1]", "[0, 1, 7]", "out of range"],
            ),
            (mesh(vec![]), &["collider.shape.indices.len()"]),
            (
                mesh(vec![[0, 1, 1]]),
                &["collider.shape.indices[0]", "degenerate"],
            ),
            (
                field(5, Vector3::repeat(1.0)),
                &["collider.shape.heights.len()", "= 5"],
            ),
            (
                field(6, Vector3::new(1.0, -1.0, 1.0)),
                &["collider.shape.scale", "-1"],
            ),
            (
                ellipsoid(0.1, 0.0, 0.2),
                &["collider.shape.semi_axes", "[0.1, 0, 0.2]"],
            ),
        ];
        for (shape, needles) in cases {
            let e = shape.validate("collider.shape").unwrap_err().to_string();
            assert!(needles.iter().all(|n| e.contains(n)), "{shape:?}: {e}");
        }
        let valid = [
            sphere(0.1),
            cuboid(1.0, 2.0, 3.0),
            capsule(0.5, 0.1),
            cylinder(0.5, 0.1),
            hull(1.0),
            mesh(vec![[0, 1, 2]]),
            field(6, Vector3::repeat(1.0)),
            plane(Vector3::new(0.0, 0.0, 2.0)),
        ];
        for s in valid {
            s.validate("s").unwrap();
        }
    }

    #[test]
    fn volumes_match_formulas() {
        let cases = [
            (sphere(2.0), 32.0 / 3.0 * PI),
            (cuboid(0.5, 1.0, 1.5), 6.0),
            (cylinder(1.0, 0.5), 0.5 * PI),
            (capsule(1.0, 0.5), 0.5 * PI + 4.0 / 3.0 * PI / 8.0),
            (hull(2.0), 2.0),
        ];
        for (s, v) in cases {
            let got = s.volume().unwrap();
            assert!((got - v).abs() <= 1e-9 * v, "{s:?}: {got} != {v}");
        }
        assert!(plane(Vector3::z()).volume().is_none());
    }

    #[test]
    fn unit_inertia_matches_textbook() {
        let (a, b, c) = (1.0, 2.0, 3.0);
        let (r, l) = (0.5, 2.0);
        let t = (3.0 * r * r + l * l) / 12.0;
        let cases = [
            // Solid sphere: 2/5 m r^2.
            (sphere(2.0), Vector3::repeat(1.6)),
            // Box with sides a, b, c: m (b^2 + c^2) / 12 ...
            (
                cuboid(a / 2.0, b / 2.0, c / 2.0),
                Vector3::new(b * b + c * c, a * a + c * c, a * a + b * b) / 12.0,
            ),
            // Cylinder of length L along Y: axial m r^2 / 2, transverse m (3 r^2 + L^2) / 12.
            (cylinder(l / 2.0, r), Vector3::new(t, r * r / 2.0, t)),
            // Capsule with a vanishing segment is a sphere; with a vanishing radius a rod.
            (capsule(1e-12, 1.0), Vector3::repeat(0.4)),
            (
                capsule(1.0, 1e-9),
                Vector3::new(4.0 / 12.0, 0.0, 4.0 / 12.0),
            ),
        ];
        for (s, i) in cases {
            let got = s.unit_inertia().unwrap();
            assert!(
                (got - i).norm() <= 1e-8 * i.norm(),
                "{s:?}: {got:?} != {i:?}"
            );
        }
        // A capsule between the two limits: cylinder + hemispheres (r = h = 1, m = 1).
        let (mc, ms) = (2.0 / (2.0 + 4.0 / 3.0), (4.0 / 3.0) / (2.0 + 4.0 / 3.0));
        let got = capsule(1.0, 1.0).unit_inertia().unwrap();
        assert!((got.y - (mc / 2.0 + ms * 0.4)).abs() < 1e-12, "{got:?}");
        assert!(
            (got.x - (mc * (0.25 + 1.0 / 3.0) + ms * (0.4 + 1.0 + 0.75))).abs() < 1e-12,
            "{got:?}"
        );
        assert!(plane(Vector3::z()).unit_inertia().is_none());
    }

    fn ellipsoid(a: f64, b: f64, c: f64) -> Shape {
        Shape::Ellipsoid {
            semi_axes: Vector3::new(a, b, c),
        }
    }

    #[test]
    fn ellipsoid_mass_properties() {
        // Volume 4/3 pi a b c; inertia per unit mass (b^2 + c^2) / 5 etc.
        let (a, b, c) = (0.3, 0.2, 0.1);
        let s = ellipsoid(a, b, c);
        let v = s.volume().unwrap();
        assert!((v - 4.0 / 3.0 * PI * 0.006).abs() < 1e-15, "{v}");
        let i = s.unit_inertia().unwrap();
        let want = Vector3::new(0.05, 0.1, 0.13) / 5.0;
        assert!((i - want).norm() < 1e-15, "{i:?}");
        // a = b = c is the sphere, to round-off.
        let (e, r) = (ellipsoid(0.7, 0.7, 0.7), sphere(0.7));
        assert!((e.volume().unwrap() - r.volume().unwrap()).abs() < 1e-14);
        assert!((e.unit_inertia().unwrap() - r.unit_inertia().unwrap()).norm() < 1e-15);
        assert_eq!(e.curvature_radius(), 0.7);
        // Parry's mass properties of the collision shape agree (density 2).
        let p = crate::collision::convert::to_parry(&s, "s").unwrap().shape;
        let mp = p.mass_properties(2.0);
        assert!((mp.mass() - 2.0 * v).abs() < 1e-14);
        let ip = mp.principal_inertia();
        let ip = Vector3::new(ip.x, ip.y, ip.z);
        assert!((ip - i * 2.0 * v).norm() < 1e-15, "{ip:?}");
        // The bounding box is the semi-axes.
        let bb = p.compute_local_aabb();
        assert_eq!(bb.maxs.to_array(), [a, b, c]);
        assert_eq!(bb.mins.to_array(), [-a, -b, -c]);
        // Its visualization mesh lies on the surface.
        let (verts, tris) = s.to_trimesh(12, 1.0).unwrap();
        assert!(!tris.is_empty());
        for p in verts {
            let q = p.component_div(&Vector3::new(a, b, c)).norm();
            assert!((q - 1.0).abs() < 1e-12, "{p:?}");
        }
    }
}
