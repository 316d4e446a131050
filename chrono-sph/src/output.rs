//! VTK frames for ParaView: positions with velocity, pressure, density, kind and id.

use std::path::Path;

use chrono_core::io::write_points_vtp;
use nalgebra::Vector3;

use crate::error::Result;
use crate::system::SphSystem;

impl SphSystem {
    /// Writes the particles (fluid and, if `with_walls`, wall markers) as a `.vtp` frame
    /// with point data `velocity` (m/s), `pressure` (Pa), `density` (kg/m^3), `kind`
    /// (0 fluid, 1 wall) and `id`. Allocates (it is output, not the step loop).
    pub fn write_vtk(&self, path: impl AsRef<Path>, with_walls: bool) -> Result<()> {
        let d = &self.data;
        let keep: Vec<usize> = (0..d.len())
            .filter(|&i| with_walls || d.kind[i] == crate::data::FLUID)
            .collect();
        let pts: Vec<Vector3<f64>> = keep
            .iter()
            .map(|&i| Vector3::new(d.x[i], d.y[i], d.z[i]))
            .collect();
        let vel: Vec<Vector3<f64>> = keep
            .iter()
            .map(|&i| Vector3::new(d.vx[i], d.vy[i], d.vz[i]))
            .collect();
        let p: Vec<f64> = keep.iter().map(|&i| d.p[i]).collect();
        let rho: Vec<f64> = keep.iter().map(|&i| d.rho[i]).collect();
        let kind: Vec<f64> = keep.iter().map(|&i| d.kind[i] as f64).collect();
        let id: Vec<f64> = keep.iter().map(|&i| d.id[i] as f64).collect();
        write_points_vtp(
            path,
            &pts,
            &[
                ("pressure", &p),
                ("density", &rho),
                ("kind", &kind),
                ("id", &id),
            ],
            &[("velocity", &vel)],
        )?;
        Ok(())
    }
}
