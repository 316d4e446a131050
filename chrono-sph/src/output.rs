//! VTK frames for ParaView: positions with velocity, pressure, density, kind and id.

use std::path::Path;

use chrono_core::io::write_points_vtp;
use nalgebra::Vector3;

use crate::error::Result;
use crate::system::SphSystem;

impl SphSystem {
    /// Writes the particles (fluid and, if `with_walls`, wall markers) as a `.vtp` frame
    /// with point data `velocity` (m/s), `pressure` (Pa), `density` (kg/m^3), `kind`
    /// (0 fluid, 1 wall) and `id`. Allocates (it is output, not the step loop). A rank of
    /// a distributed system writes the particles it owns (no ghost), with a `rank` field:
    /// one file per rank and frame, listed as the parts of a frame by
    /// [`chrono_core::io::write_pvd_parts`].
    pub fn write_vtk(&self, path: impl AsRef<Path>, with_walls: bool) -> Result<()> {
        let d = &self.data;
        let keep: Vec<usize> = (0..d.len())
            .filter(|&i| (with_walls || d.kind[i] == crate::data::FLUID) && self.is_owned(i))
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
        let mut scalars: Vec<(&str, &[f64])> = vec![
            ("pressure", &p),
            ("density", &rho),
            ("kind", &kind),
            ("id", &id),
        ];
        let rank: Vec<f64>;
        if let Some(r) = self.rank() {
            rank = vec![r as f64; keep.len()];
            scalars.push(("rank", &rank));
        }
        write_points_vtp(path, &pts, &scalars, &[("velocity", &vel)])?;
        Ok(())
    }
}
