//! VTK frames of a whole system for ParaView: every collider of every body as a surface
//! (`write_shapes_vtp`), with the owner's index as cell data `body`.

use std::path::Path;

use crate::error::Result;
use crate::system::System;

/// Write the colliders of every body of `sys`, posed at the current state, as one `.vtp`
/// file (see [`write_shapes_vtp`](super::write_shapes_vtp) for the tessellation); returns
/// the number of shapes written. With [`FrameSeries`](super::FrameSeries):
/// `frames.record(step, sys.time(), |p| write_bodies_vtp(p, &sys).map(drop))`.
pub fn write_bodies_vtp(path: impl AsRef<Path>, sys: &System) -> Result<usize> {
    let shapes: Vec<_> = (sys.bodies().iter().enumerate())
        .flat_map(|(i, b)| {
            (b.colliders().iter()).map(move |c| (b.pose() * c.local_pose, &c.shape, i as u32))
        })
        .collect();
    super::vtk::write_shapes_vtp(path, &shapes)?;
    Ok(shapes.len())
}
