//! VTK frames of grains for ParaView: one point per sphere collider of every dynamic body,
//! with the point data `radius` (m), `velocity` (m/s, the body's velocity at the sphere's
//! center), `speed` (m/s) and `body` (the owner's index). In ParaView, apply the Glyph
//! filter (sphere, scale by `radius`, factor 2) to see the grains.

use std::path::Path;

use nalgebra::Vector3;

use crate::error::Result;
use crate::shape::Shape;
use crate::system::System;

/// Write the grains of `sys` (sphere colliders of dynamic bodies) as a `.vtp` file;
/// returns the number of points written.
pub fn write_grains_vtp(path: impl AsRef<Path>, sys: &System) -> Result<usize> {
    let mut points = Vec::new();
    let (mut radius, mut speed, mut body, mut velocity) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (i, b) in sys.bodies().iter().enumerate() {
        if !b.is_dynamic() {
            continue;
        }
        for c in b.colliders() {
            if let Shape::Sphere { radius: r } = c.shape {
                let p = b.pose() * c.local_pose.translation.vector;
                let p = Vector3::new(p.x, p.y, p.z);
                let v = b.point_velocity(&p);
                points.push(p);
                radius.push(r);
                speed.push(v.norm());
                body.push(i as f64);
                velocity.push(v);
            }
        }
    }
    super::vtk::write_points_vtp(
        path,
        &points,
        &[("radius", &radius), ("speed", &speed), ("body", &body)],
        &[("velocity", &velocity)],
    )?;
    Ok(points.len())
}
