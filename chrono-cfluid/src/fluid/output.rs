//! Output of a [`ConstraintFluid`] (issue 6, "output like chrono-sph"): VTK frames for
//! ParaView, and probes — the pressure at a point and the free-surface height at a
//! station — with the same definitions as chrono-sph's, so the two fluids' figures compare.
//!
//! Output allocates (it is not in the step loop) and reads the state of the last step:
//! positions now, densities and pressures of the last solve.

use std::path::Path;

use chrono_core::error::{ChronoError, Result};
use chrono_core::io::write_points_vtp;
use chrono_core::math::Vector3;

use super::ConstraintFluid;

/// Point-data `kind` of a fluid particle in [`ConstraintFluid::write_vtk`].
pub const KIND_FLUID: f64 = 0.0;
/// Point-data `kind` of a wall marker.
pub const KIND_WALL: f64 = 1.0;
/// Point-data `kind` of a body marker.
pub const KIND_BODY_MARKER: f64 = 2.0;

impl ConstraintFluid {
    /// The support fractions `phi_i` of the fluid particles at the start of the last step
    /// (the reference of each density row, `C_i = rho_i / rho_0 - phi_i`; all 1 without
    /// [`CfluidSettings::surface_reference`](crate::CfluidSettings::surface_reference)).
    pub fn support_fractions(&self) -> &[f64] {
        &self.phi
    }

    /// Write the particles as a VTK PolyData frame (`.vtp`, ASCII) with point data
    /// `velocity` (m/s), `density` (kg/m^3), `compression` (`rho / rho_0 - 1`), `pressure`
    /// (Pa, `p_i = g_i rho_0 / (h m_k)` of the last solve, see [`pressure`](Self::pressure))
    /// and `kind` ([`KIND_FLUID`], [`KIND_WALL`], [`KIND_BODY_MARKER`]).
    ///
    /// With `with_markers` the wall and body markers follow the fluid particles. Wall
    /// markers have no row: they are written at `rho_0`, zero pressure and zero velocity.
    /// Body markers carry their density and, with
    /// [`body_marker_rows`](crate::CfluidSettings::body_marker_rows), their row's pressure;
    /// their velocity (the body's, known to the system, not to the fluid) is written as 0.
    /// Errors: the file cannot be written (the path is named).
    pub fn write_vtk(&self, path: impl AsRef<Path>, with_markers: bool) -> Result<()> {
        let n = if with_markers {
            self.pos[0].len()
        } else {
            self.n_fluid
        };
        let r0 = self.settings.rest_density;
        let pts: Vec<Vector3<f64>> = (0..n)
            .map(|i| Vector3::new(self.pos[0][i], self.pos[1][i], self.pos[2][i]))
            .collect();
        let mut vel = vec![Vector3::zeros(); n];
        let mut rho = vec![r0; n];
        let mut p = vec![0.0; n];
        let mut kind = vec![KIND_WALL; n];
        for i in 0..self.n_fluid {
            vel[i] = Vector3::from(self.vel[i]);
            rho[i] = self.rho[i];
            p[i] = self.pressure(i);
            kind[i] = KIND_FLUID;
        }
        if with_markers {
            for k in 0..self.marker_local.len() {
                let i = self.n_static + k;
                rho[i] = self.marker_rho[k];
                p[i] = self.impulse_to_pressure(self.marker_gamma[k]);
                kind[i] = KIND_BODY_MARKER;
            }
        }
        let compression: Vec<f64> = rho.iter().map(|r| r / r0 - 1.0).collect();
        write_points_vtp(
            path,
            &pts,
            &[
                ("density", &rho),
                ("compression", &compression),
                ("pressure", &p),
                ("kind", &kind),
            ],
            &[("velocity", &vel)],
        )
    }

    /// Pressure at a point (Pa): the Shepard-normalized kernel interpolation of the
    /// particle pressures of the last solve over the fluid particles,
    /// `p(x) = sum_i p_i V_i W(|x - x_i|) / sum_i V_i W(|x - x_i|)`, `V_i = m / rho_i`
    /// (as chrono-sph's `pressure_at`); `None` when no fluid particle is within the kernel
    /// support (the point is dry). A probe, O(N) per call (no grid query).
    /// Errors: a non-finite point (the coordinate is named).
    pub fn pressure_at(&self, point: [f64; 3]) -> Result<Option<f64>> {
        for (a, c) in point.iter().enumerate() {
            if !c.is_finite() {
                return Err(ChronoError::invalid(
                    format!("point[{a}]"),
                    *c,
                    "must be finite",
                ));
            }
        }
        let support = self.kernel.support();
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..self.n_fluid {
            let d = [
                self.pos[0][i] - point[0],
                self.pos[1][i] - point[1],
                self.pos[2][i] - point[2],
            ];
            let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if r < support {
                let w = self.kernel.w(r) / self.rho[i];
                num += w * self.pressure(i);
                den += w;
            }
        }
        Ok((den > 0.0).then(|| num / den))
    }

    /// Free-surface height at the station `x = x_s` (m): the highest fluid particle centre
    /// with `|x - x_s| <= half_width`, plus `dp / 2` (as chrono-sph's
    /// `free_surface_height`); `None` if the station is dry. Errors: `half_width` not
    /// finite and positive, `x_s` not finite.
    pub fn free_surface_height(&self, x_s: f64, half_width: f64) -> Result<Option<f64>> {
        if !(half_width.is_finite() && half_width > 0.0) {
            return Err(ChronoError::invalid(
                "half_width",
                half_width,
                "must be finite and > 0",
            ));
        }
        if !x_s.is_finite() {
            return Err(ChronoError::invalid("x_s", x_s, "must be finite"));
        }
        let top = (0..self.n_fluid)
            .filter(|&i| (self.pos[0][i] - x_s).abs() <= half_width)
            .map(|i| self.pos[2][i])
            .fold(f64::NEG_INFINITY, f64::max);
        Ok(top.is_finite().then_some(top + 0.5 * self.settings.spacing))
    }

    /// `p = g rho_0 / (h m_k)` for an impulse `g` of the last step (0 before the first),
    /// `m_k` the kernel mass of the density rows.
    pub(super) fn impulse_to_pressure(&self, g: f64) -> f64 {
        if self.last_h > 0.0 {
            g * self.settings.rest_density / (self.last_h * self.kernel_mass)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CfluidSettings, lattice_box};

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("chrono-cfluid-output-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// The values of the `DataArray` named `name` in an ASCII VTK file.
    fn data_array(text: &str, name: &str) -> Vec<f64> {
        let tag = format!("Name=\"{name}\"");
        let start = text.find(&tag).unwrap_or_else(|| panic!("no array {name}"));
        let body = &text[start..];
        let open = body.find('>').unwrap() + 1;
        let close = body.find("</DataArray>").unwrap();
        body[open..close]
            .split_whitespace()
            .map(|s| s.parse().unwrap())
            .collect()
    }

    fn block(dp: f64) -> ConstraintFluid {
        let settings = CfluidSettings {
            spacing: dp,
            domain_lower: [-1.0; 3],
            domain_upper: [1.0; 3],
            ..CfluidSettings::default()
        };
        let fluid = lattice_box([0.0; 3], [4.0 * dp, 3.0 * dp, 5.0 * dp], dp).unwrap();
        let walls = lattice_box([0.0, 0.0, -2.0 * dp], [4.0 * dp, 3.0 * dp, 0.0], dp).unwrap();
        ConstraintFluid::new("water", settings, &fluid, &walls).unwrap()
    }

    #[test]
    fn vtk_frame_holds_the_state() {
        let dp = 0.01;
        let mut f = block(dp);
        let v: Vec<[f64; 3]> = (0..f.n_fluid())
            .map(|i| [i as f64 * 1e-3, -0.5, 2.0])
            .collect();
        f.set_velocities(&v).unwrap();
        f.compute_densities().unwrap();
        let path = temp("frame.vtp");
        f.write_vtk(&path, false).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let n = f.n_fluid();
        assert!(text.contains(&format!("NumberOfPoints=\"{n}\"")));
        let rho = data_array(&text, "density");
        assert_eq!(rho.len(), n);
        for (a, b) in rho.iter().zip(f.densities()) {
            assert_eq!(a, b, "densities are written at full precision");
        }
        let comp = data_array(&text, "compression");
        assert!((comp[0] - (f.densities()[0] / 1000.0 - 1.0)).abs() < 1e-15);
        let vel = data_array(&text, "velocity");
        assert_eq!(vel.len(), 3 * n);
        assert_eq!(&vel[3 * 7..3 * 8], &[7e-3, -0.5, 2.0]);
        assert!(data_array(&text, "kind").iter().all(|k| *k == KIND_FLUID));

        f.write_vtk(&path, true).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let kind = data_array(&text, "kind");
        assert_eq!(kind.len(), n + f.n_walls());
        assert_eq!(
            kind.iter().filter(|k| **k == KIND_WALL).count(),
            f.n_walls()
        );
        let p = data_array(&text, "pressure");
        assert!(p[n..].iter().all(|p| *p == 0.0), "walls have no row");
    }

    #[test]
    fn probes_read_the_particles() {
        let dp = 0.01;
        let mut f = block(dp);
        f.compute_densities().unwrap();
        // before any solve every pressure is 0, inside the block the probe reads it
        assert_eq!(
            f.pressure_at([2.0 * dp, 1.5 * dp, 2.0 * dp]).unwrap(),
            Some(0.0)
        );
        // far from every particle the point is dry
        assert_eq!(f.pressure_at([0.5, 0.5, 0.5]).unwrap(), None);
        // the lattice's top layer is at z = 4.5 dp (cell centres), the surface dp/2 above
        let top = f.free_surface_height(2.0 * dp, dp).unwrap().unwrap();
        assert!((top - 5.0 * dp).abs() < 1e-12, "surface at {top}");
        assert_eq!(f.free_surface_height(0.5, dp).unwrap(), None);
        let e = f.free_surface_height(0.0, -1.0).unwrap_err().to_string();
        assert!(e.contains("half_width") && e.contains("-1"), "{e}");
        let e = f.pressure_at([0.0, f64::NAN, 0.0]).unwrap_err().to_string();
        assert!(e.contains("point[1]"), "{e}");
    }

    #[test]
    fn pressure_probe_interpolates_a_linear_field() {
        let dp = 0.01;
        let mut f = block(dp);
        // a solve's state, set by hand: uniform density, pressure p = 2000 + 9810 (z0 - z)
        let h = 1e-3;
        f.last_h = h;
        f.rho.fill(1000.0);
        let field = |z: f64| 2000.0 + 9810.0 * (0.05 - z);
        for i in 0..f.n_fluid() {
            f.gamma[i] = field(f.pos[2][i]) * h * f.kernel_mass / 1000.0;
        }
        for i in 0..f.n_fluid() {
            assert!((f.pressure(i) - field(f.pos[2][i])).abs() < 1e-9);
        }
        // at the block's centre of symmetry a linear field is interpolated exactly
        let c = [2.0 * dp, 1.5 * dp, 2.5 * dp];
        let p = f.pressure_at(c).unwrap().unwrap();
        assert!(
            (p - field(c[2])).abs() < 1e-9 * field(c[2]),
            "{p} vs {}",
            field(c[2])
        );
        // off the centre the Shepard sum is a weighted mean of the neighbours: between
        // the extreme pressures of the particles within the support
        let q = [1.0 * dp, 1.0 * dp, 1.2 * dp];
        let p = f.pressure_at(q).unwrap().unwrap();
        let (lo, hi) = (
            field(q[2] + f.kernel().support()),
            field(q[2] - f.kernel().support()),
        );
        assert!(p > lo && p < hi, "{p} not in ({lo}, {hi})");
    }
}
