//! Probes: pressure at a point, free-surface height at a station, forces on walls,
//! and simple integrals of the fluid state.

use nalgebra::Vector3;

use crate::data::{FLUID, WALL};
use crate::error::{Result, SphError};
use crate::interact::{PackVelocity, Packed, pack, pair_accel};
use crate::system::SphSystem;

impl SphSystem {
    /// Pressure at a point (Pa), the Shepard-normalized kernel interpolation over fluid
    /// particles, `p(x) = sum_f p_f V_f W / sum_f V_f W` with `V_f = m_f / rho_f`; `None`
    /// when no fluid particle is within the support `2 h` (the point is dry).
    pub fn pressure_at(&self, point: [f64; 3]) -> Result<Option<f64>> {
        let d = &self.data;
        let (mut num, mut den) = (0.0, 0.0);
        self.grid.for_each_in_radius(
            [&d.x, &d.y, &d.z],
            point,
            self.kernel.support(),
            |j, _, r2| {
                if d.kind[j] == FLUID {
                    let w = self.kernel.w(r2.sqrt()) * d.mass[j] / d.rho[j];
                    num += w * self.eos.pressure(d.rho[j]);
                    den += w;
                }
            },
        )?;
        Ok((den > 0.0).then(|| num / den))
    }

    /// Free-surface height at the station `x = x_s` (m): the highest fluid particle
    /// centre with `|x - x_s| <= half_width`, plus `dp / 2`; `None` if the station is dry.
    pub fn free_surface_height(&self, x_s: f64, half_width: f64) -> Result<Option<f64>> {
        if !(half_width.is_finite() && half_width > 0.0) {
            return Err(SphError::invalid("half_width", half_width, "must be > 0"));
        }
        let d = &self.data;
        let mut top = f64::NEG_INFINITY;
        for i in 0..d.len() {
            if d.kind[i] == FLUID && (d.x[i] - x_s).abs() <= half_width {
                top = top.max(d.z[i]);
            }
        }
        Ok(top.is_finite().then_some(top + 0.5 * self.settings.spacing))
    }

    /// The force the walls exert on the fluid (N): `sum_f m_f (a_f - g - f)` over the fluid,
    /// exact because the fluid-fluid pair forces cancel in pairs.
    pub fn fluid_force(&self) -> Vector3<f64> {
        let d = &self.data;
        let s = &self.settings;
        let acc = [
            s.gravity[0] + s.body_force[0],
            s.gravity[1] + s.body_force[1],
            s.gravity[2] + s.body_force[2],
        ];
        let mut f = Vector3::zeros();
        for i in 0..d.len() {
            if d.kind[i] == FLUID {
                let a = d.deriv[i].acc;
                f += d.mass[i] * Vector3::new(a[0] - acc[0], a[1] - acc[1], a[2] - acc[2]);
            }
        }
        f
    }

    /// The force the fluid exerts on the wall markers of `group` (N), summed over the
    /// pair terms of the last force evaluation (pressure and viscosity).
    pub fn wall_force(&self, group: u16) -> Vector3<f64> {
        let d = &self.data;
        let ctx = self.pass_ctx();
        let support2 = self.kernel.support() * self.kernel.support();
        // the records of the last force pass; before the first one, from the arrays
        let mut fresh = Vec::new();
        let nb: &[Packed] = if self.packed.len() == d.len() {
            &self.packed
        } else {
            pack(d, PackVelocity::NoSlip, &mut fresh);
            &fresh
        };
        let mut f = Vector3::zeros();
        for a in 0..d.len() {
            if d.kind[a] != FLUID {
                continue;
            }
            for &b in self.list.neighbors(a) {
                let b = b as usize;
                if d.kind[b] == WALL && d.group[b] == group {
                    let acc = pair_accel(&ctx, &nb[a], &nb[b], support2);
                    f -= d.mass[a] * Vector3::new(acc[0], acc[1], acc[2]);
                }
            }
        }
        f
    }

    /// Number of fluid particles outside the box `[lower, upper]` (leak check).
    pub fn fluid_outside(&self, lower: [f64; 3], upper: [f64; 3]) -> usize {
        let d = &self.data;
        (0..d.len())
            .filter(|&i| {
                d.kind[i] == FLUID
                    && (d.x[i] < lower[0]
                        || d.x[i] > upper[0]
                        || d.y[i] < lower[1]
                        || d.y[i] > upper[1]
                        || d.z[i] < lower[2]
                        || d.z[i] > upper[2])
            })
            .count()
    }

    /// Total fluid momentum, kg m/s.
    pub fn fluid_momentum(&self) -> Vector3<f64> {
        let d = &self.data;
        let mut m = Vector3::zeros();
        for i in 0..d.len() {
            if d.kind[i] == FLUID {
                m += d.mass[i] * Vector3::new(d.vx[i], d.vy[i], d.vz[i]);
            }
        }
        m
    }

    /// Total fluid mass, kg.
    pub fn fluid_mass(&self) -> f64 {
        let d = &self.data;
        (0..d.len())
            .filter(|&i| d.kind[i] == FLUID)
            .map(|i| d.mass[i])
            .sum()
    }
}
