//! The one place where nalgebra (our public math) meets glam (parry's math).
//!
//! Conversions go through nalgebra's `convert-glam033` and glamx's `nalgebra` features.
//! They are done once per collider per step (poses) and once per contact point (output),
//! never inside parry's loops. Also: our [`Shape`] to a parry [`SharedShape`].

use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::{Ball, Capsule, ConvexPolyhedron, Cuboid, Cylinder, SharedShape};
use parry3d_f64::utils::Array2;

use crate::error::{ChronoError, Result};
use crate::math::{Isometry3, UnitQuaternion, Vector3};
use crate::shape::{Shape, TriangleMesh};

/// nalgebra vector to glam.
#[inline]
pub(crate) fn vec_to_glam(v: &Vector3<f64>) -> Vector {
    (*v).into()
}

/// glam vector to nalgebra.
#[inline]
pub(crate) fn vec_from_glam(v: Vector) -> Vector3<f64> {
    v.into()
}

/// nalgebra isometry to a glam pose.
#[inline]
pub(crate) fn pose_to_glam(p: &Isometry3<f64>) -> Pose {
    (*p).into()
}

/// glam pose to a nalgebra isometry.
#[cfg_attr(not(test), allow(dead_code))]
#[inline]
pub(crate) fn pose_from_glam(p: &Pose) -> Isometry3<f64> {
    (*p).into()
}

/// The fixed rotation from parry's Y-up height field frame to our Z-up one: a rotation of
/// +90 degrees about X, mapping parry's +Y (up) to our +Z and parry's +Z to our -Y.
pub(crate) fn heightfield_rotation() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2)
}

/// A parry shape built from our [`Shape`], with the extra local pose (identity except for
/// height fields, see [`heightfield_rotation`]) that places parry's shape in our local frame.
pub(crate) struct ParryShape {
    /// The parry shape.
    pub shape: SharedShape,
    /// Pose of the parry shape in our shape's local frame.
    pub offset: Isometry3<f64>,
}

fn points_to_glam(points: &[Vector3<f64>]) -> Vec<Vector> {
    points.iter().map(vec_to_glam).collect()
}

/// Build the parry shape of a validated [`Shape`]. `field` names it in errors.
pub(crate) fn to_parry(shape: &Shape, field: &str) -> Result<ParryShape> {
    let mut offset = Isometry3::identity();
    let s = match shape {
        Shape::Sphere { radius } => SharedShape::ball(*radius),
        Shape::Box { half_extents: e } => SharedShape::cuboid(e.x, e.y, e.z),
        Shape::Ellipsoid { semi_axes } => {
            SharedShape::new(super::ellipsoid::Ellipsoid::new(vec_to_glam(semi_axes)))
        }
        Shape::Capsule {
            half_length,
            radius,
        } => SharedShape::capsule_y(*half_length, *radius),
        Shape::Cylinder {
            half_length,
            radius,
        } => SharedShape::cylinder(*half_length, *radius),
        Shape::ConvexHull { points } => SharedShape::convex_hull(&points_to_glam(points))
            .ok_or_else(|| {
                ChronoError::invalid(
                    format!("{field}.points"),
                    points.len(),
                    "parry could not build a convex hull",
                )
            })?,
        Shape::TriMesh { vertices, indices } => {
            SharedShape::trimesh(points_to_glam(vertices), indices.clone()).map_err(|e| {
                ChronoError::invalid(
                    format!("{field}.indices"),
                    indices.len(),
                    format!("parry rejected the mesh: {e:?}"),
                )
            })?
        }
        Shape::HeightField {
            heights,
            nrows,
            ncols,
            scale,
        } => {
            // Parry: rows along its +Z (= our -Y), columns along X, heights along its Y.
            let (nr, nc) = (*nrows, *ncols);
            let array = Array2::from_fn(nr, nc, |i, j| heights[(nr - 1 - i) * nc + j]);
            offset = Isometry3::from_parts(Default::default(), heightfield_rotation());
            SharedShape::heightfield(array, Vector::new(scale.x, scale.z, scale.y))
        }
        Shape::HalfSpace { normal } => SharedShape::halfspace(vec_to_glam(&normal.normalize())),
    };
    Ok(ParryShape { shape: s, offset })
}

/// Triangulate a sphere, box, ellipsoid, capsule, cylinder or convex hull with parry's `to_trimesh`.
pub(crate) fn parry_trimesh(shape: &Shape, subdivisions: u32) -> Result<TriangleMesh> {
    let (v, i) = match shape {
        Shape::Sphere { radius } => {
            Ball::new(*radius).to_trimesh(subdivisions, subdivisions.div_ceil(2))
        }
        Shape::Box { half_extents } => Cuboid::new(vec_to_glam(half_extents)).to_trimesh(),
        Shape::Ellipsoid { semi_axes } => {
            // The unit sphere's mesh stretched along the axes.
            let (v, i) = Ball::new(1.0).to_trimesh(subdivisions, subdivisions.div_ceil(2));
            let e = vec_to_glam(semi_axes);
            (v.into_iter().map(|p| p * e).collect(), i)
        }
        Shape::Capsule {
            half_length,
            radius,
        } => {
            Capsule::new_y(*half_length, *radius).to_trimesh(subdivisions, subdivisions.div_ceil(2))
        }
        Shape::Cylinder {
            half_length,
            radius,
        } => Cylinder::new(*half_length, *radius).to_trimesh(subdivisions),
        Shape::ConvexHull { points } => ConvexPolyhedron::from_convex_hull(&points_to_glam(points))
            .ok_or_else(|| {
                ChronoError::invalid(
                    "shape.points",
                    points.len(),
                    "parry could not build a convex hull",
                )
            })?
            .to_trimesh(),
        other => {
            return Err(ChronoError::invalid(
                "shape",
                other.kind_name(),
                "not triangulated by parry",
            ));
        }
    };
    Ok((v.into_iter().map(vec_from_glam).collect(), i))
}

/// Volume of a convex hull through parry's mass properties (`None` if degenerate).
pub(crate) fn convex_hull_volume(shape: &Shape) -> Option<f64> {
    match shape {
        Shape::ConvexHull { points } => {
            let hull = ConvexPolyhedron::from_convex_hull(&points_to_glam(points))?;
            Some(parry3d_f64::shape::Shape::mass_properties(&hull, 1.0).mass())
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips() {
        let v = Vector3::new(1.0, -2.0, 3.5);
        assert_eq!(vec_from_glam(vec_to_glam(&v)), v);
        let iso = Isometry3::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(0.1, -0.2, 0.3));
        let back = pose_from_glam(&pose_to_glam(&iso));
        assert!((back.translation.vector - iso.translation.vector).norm() < 1e-15);
        assert!(back.rotation.angle_to(&iso.rotation) < 1e-12);
        let p = Vector3::new(0.3, 0.4, -0.5);
        let a = iso * nalgebra::Point3::from(p);
        let b = pose_to_glam(&iso) * vec_to_glam(&p);
        assert!((a.coords - vec_from_glam(b)).norm() < 1e-14);
    }

    #[test]
    fn heightfield_rotation_maps_y_up_to_z_up() {
        let r = heightfield_rotation();
        assert!((r * Vector3::y() - Vector3::z()).norm() < 1e-15);
        assert!((r * Vector3::z() + Vector3::y()).norm() < 1e-15);
    }
}
