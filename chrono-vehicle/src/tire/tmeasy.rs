//! The TMeasy handling tire as a force element on the wheel (spindle) body.

use std::sync::Arc;

use chrono_core::BodyHandle;
use chrono_core::error::ChronoError;
use chrono_core::force::{BodyLoads, ForceElement, check_body};
use chrono_core::item::StepContext;
use chrono_core::math::Vector3;

use super::tmeasy_params::{TMeasyParams, combined_force};
use crate::error::{Result, VehicleError};
use crate::terrain::Terrain;

/// What the tire computed in its last evaluation (world frame, SI).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TireOutput {
    /// Whether the tire touched the terrain (positive deflection and load).
    pub in_contact: bool,
    /// Contact point on the terrain, m.
    pub contact_point: Vector3<f64>,
    /// Terrain normal at the contact point.
    pub normal: Vector3<f64>,
    /// Longitudinal direction `e_x` (in the wheel plane, tangent to the terrain).
    pub longitudinal_dir: Vector3<f64>,
    /// Lateral direction `e_y = n x e_x`.
    pub lateral_dir: Vector3<f64>,
    /// Radial deflection `dz`, m.
    pub deflection: f64,
    /// Vertical (normal) force `F_z`, N (>= 0).
    pub normal_force: f64,
    /// Kinematic longitudinal slip `(r_D Omega - v_x) / |r_D Omega|` (0 when not rolling).
    pub slip_long: f64,
    /// Kinematic lateral slip `-v_y / |r_D Omega|` (0 when not rolling).
    pub slip_lat: f64,
    /// Relaxed longitudinal slip (the one the forces use).
    pub relaxed_slip_long: f64,
    /// Relaxed lateral slip.
    pub relaxed_slip_lat: f64,
    /// Longitudinal force along `e_x`, N.
    pub fx: f64,
    /// Lateral force along `e_y`, N.
    pub fy: f64,
    /// Aligning torque about the normal, N m.
    pub mz: f64,
    /// Rolling-resistance torque about the spin axis, N m.
    pub my: f64,
    /// Dynamic rolling radius `r_D`, m.
    pub rolling_radius: f64,
    /// Wheel spin rate `Omega` about its axis, rad/s.
    pub spin_rate: f64,
}

/// The TMeasy handling tire (Hirschberg, Rill, Weinfurter, "Tire model TMeasy", Vehicle
/// System Dynamics 45, 2007): a [`ForceElement`] on the wheel body, which carries the wheel
/// center (at its center of mass unless [`with_center`](Self::with_center) says otherwise)
/// and spins about `spin_axis` (body frame, pointing left in the vehicle frame; normally
/// local Y).
///
/// Each step, at the state of the start of the step:
///
/// 1. **Contact geometry** (single point). With the spin axis `a` (world) and the terrain
///    normal `n` below the center `C`: `e_x = a x n / |a x n|` (forward), `e_y = n x e_x`,
///    `d = a x e_x` (down in the wheel plane). The terrain is queried again at
///    `C + R d`; with its height `h` and normal `n` there, the distance from `C` to the
///    terrain plane along `d` is `r = ((C - Q) . n) / (-d . n)` (`Q` the terrain point),
///    the contact point `P = C + r d` and the radial deflection `dz = R - r`.
/// 2. **Vertical force** `F_z = max(0, c_z dz + d_z dz_dot)` with
///    `dz_dot = -(v_C . n)/(-d . n)`: zero when airborne, never pulling.
/// 3. **Slips.** Spin `Omega = w . a`, dynamic rolling radius `r_D = R - dz/3`
///    (Rill: `r_D ~ 2/3 R + 1/3 r_S`), rolling speed `v_r = r_D Omega`, sliding
///    velocities `v_sx = v_C . e_x - v_r`, `v_sy = v_C . e_y`. The slips
///    `s_x = -v_sx/|v_r|`, `s_y = -v_sy/|v_r|` are not used directly (they are singular at
///    standstill); instead the **relaxed slips** follow the first-order relaxation
///    (relaxation lengths `sigma`):
///
///    ```text
///    sigma_x ds'_x/dt + |v_r| s'_x = -v_sx,      sigma_y ds'_y/dt + |v_r| s'_y = -v_sy
///    ```
///
///    integrated by implicit Euler. In steady rolling `s' = s`; at standstill
///    (`v_r = 0`) `s'` integrates the sliding distance, so the tread acts as a spring of
///    stiffness `dF0/sigma` and a standing wheel on a slope holds still instead of creeping
///    (the low-speed regularization). When either relaxed slip exceeds `max(1, 2 s_S)`
///    (beyond which the force no longer changes) both are scaled down together, which
///    keeps the direction of the combined slip. At `v_r = 0` (a locked wheel) the
///    relaxed slips integrate `v_s / sigma`, so the force direction of a long skid
///    weights the sliding velocity by `1/sigma_x`, `1/sigma_y`.
/// 4. **Forces** `(F_x, F_y)` from the relaxed slips by the combined-slip
///    characteristic ([`combined_force`]) at the load `F_z`, the maximum and sliding
///    forces scaled by `mu_terrain / reference_friction`. Below `low_speed` a tread damping
///    `-w d v_s` is added, `w = max(0, 1 - max(|v_r|, |v_C|)/low_speed)`, so that the
///    undamped standstill spring settles (Pacejka's low-speed remedy for relaxation
///    models).
/// 5. **Aligning torque** `M_z = -sgn(v_x) n_t F_y` about `n`, with the pneumatic trail
///    `n_t = n_0 (1 - |s'_y|/s_My)` up to `s_My`, then
///    `-n_0 (|s'_y| - s_My)/s_My ((s_Sy - |s'_y|)/(s_Sy - s_My))^2` up to `s_Sy`, then 0
///    (Rill, Road Vehicle Dynamics, ch. 3), `n_0 = trail_ratio L` with the contact length
///    `L = 2 sqrt(dz (2R - dz))`; `sgn(v_x) = clamp(v_x / low_speed, -1, 1)`.
/// 6. **Rolling resistance** `M_y = -f_r r_D F_z clamp(v_r/low_speed, -1, 1)` about `a`.
///
/// The force `F_x e_x + F_y e_y + F_z n` acts at `P`, plus the torque `M_z n + M_y a`.
/// Camber effects are not modelled. Evaluating allocates nothing.
pub struct TMeasyTire {
    name: String,
    body: BodyHandle,
    axis_local: Vector3<f64>,
    center_local: Vector3<f64>,
    params: TMeasyParams,
    terrain: Arc<dyn Terrain>,
    slip_limit: f64,
    sx: f64,
    sy: f64,
    out: TireOutput,
}

impl TMeasyTire {
    /// A tire on `body` spinning about `spin_axis` (body frame, need not be unit), on
    /// `terrain`. Errors name the field (the parameters, a zero or non-finite axis).
    pub fn new(
        name: impl Into<String>,
        body: BodyHandle,
        spin_axis: Vector3<f64>,
        params: TMeasyParams,
        terrain: Arc<dyn Terrain>,
    ) -> Result<Self> {
        params.validate()?;
        let norm = spin_axis.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(VehicleError::invalid(
                "tmeasy_tire.spin_axis",
                format!("{:?}", spin_axis.as_slice()),
                "must be finite and non-zero",
            ));
        }
        let slip_limit = (2.0 * params.longitudinal.s_slide[0])
            .max(2.0 * params.longitudinal.s_slide[1])
            .max(2.0 * params.lateral.s_slide[0])
            .max(2.0 * params.lateral.s_slide[1])
            .max(1.0);
        Ok(Self {
            name: name.into(),
            body,
            axis_local: spin_axis / norm,
            center_local: Vector3::zeros(),
            params,
            terrain,
            slip_limit,
            sx: 0.0,
            sy: 0.0,
            out: TireOutput::default(),
        })
    }

    /// Put the wheel center at `center` in the body frame (default: the body's center of
    /// mass). Errors if it is not finite.
    pub fn with_center(mut self, center: Vector3<f64>) -> Result<Self> {
        if !center.iter().all(|x| x.is_finite()) {
            return Err(VehicleError::invalid(
                "tmeasy_tire.center",
                format!("{:?}", center.as_slice()),
                "must be finite",
            ));
        }
        self.center_local = center;
        Ok(self)
    }

    /// The last evaluation's results.
    pub fn output(&self) -> &TireOutput {
        &self.out
    }

    /// The parameters.
    pub fn params(&self) -> &TMeasyParams {
        &self.params
    }

    /// The wheel body.
    pub fn body(&self) -> BodyHandle {
        self.body
    }

    /// Pneumatic trail (m) at lateral slip `sy` for the zero-slip trail `n0` and the
    /// lateral slips of the maximum `sm` and of sliding `ss`.
    fn trail(n0: f64, sy: f64, sm: f64, ss: f64) -> f64 {
        let s = sy.abs();
        if s <= sm {
            n0 * (1.0 - s / sm)
        } else if s < ss {
            let q = (ss - s) / (ss - sm);
            -n0 * (s - sm) / sm * q * q
        } else {
            0.0
        }
    }

    fn no_contact(&mut self) {
        self.sx = 0.0;
        self.sy = 0.0;
        self.out = TireOutput {
            rolling_radius: self.params.radius,
            spin_rate: self.out.spin_rate,
            ..TireOutput::default()
        };
    }
}

impl ForceElement for TMeasyTire {
    fn name(&self) -> &str {
        &self.name
    }

    fn body_handles(&self) -> Vec<BodyHandle> {
        vec![self.body]
    }

    fn attach(&mut self, bodies: &chrono_core::Bodies) -> chrono_core::Result<()> {
        check_body(
            &format!("tmeasy tire \"{}\".body", self.name),
            self.body,
            bodies,
        )
    }

    fn evaluate(
        &mut self,
        ctx: &StepContext,
        bodies: &chrono_core::Bodies,
        loads: &mut BodyLoads,
    ) -> chrono_core::Result<()> {
        let p = &self.params;
        let b = &bodies[self.body];
        let c = b.pose().transform_point(&self.center_local.into()).coords;
        let a = b.rotation() * self.axis_local;
        let v = b.point_velocity(&c);
        let w = b.angular_velocity();
        self.out.spin_rate = w.dot(&a);
        if !(c
            .iter()
            .chain(v.iter())
            .chain(w.iter())
            .all(|x| x.is_finite()))
        {
            return Err(ChronoError::NonFinite {
                item: format!("tmeasy tire \"{}\"", self.name),
                step: ctx.step,
                time: ctx.time,
                what: "wheel position or velocity".into(),
            });
        }

        // 1. Contact geometry.
        let frame = |n: &Vector3<f64>| {
            let ex = a.cross(n);
            let l = ex.norm();
            (l > 1e-6).then(|| {
                let ex = ex / l;
                (ex, n.cross(&ex), a.cross(&ex))
            })
        };
        let Some((_, _, d0)) = frame(&self.terrain.normal(c.x, c.y)) else {
            self.no_contact();
            return Ok(());
        };
        let p0 = c + p.radius * d0;
        let n = self.terrain.normal(p0.x, p0.y);
        let q = Vector3::new(p0.x, p0.y, self.terrain.height(p0.x, p0.y));
        let Some((ex, ey, d)) = frame(&n) else {
            self.no_contact();
            return Ok(());
        };
        let cos = -d.dot(&n);
        let r = (c - q).dot(&n) / cos;
        let dz = p.radius - r;
        if cos < 0.1 || dz <= 0.0 {
            self.no_contact();
            return Ok(());
        }
        let contact = c + r * d;

        // 2. Vertical force.
        let dz_dot = -v.dot(&n) / cos;
        let fz = (p.vertical_stiffness * dz + p.vertical_damping * dz_dot).max(0.0);
        if fz <= 0.0 {
            self.no_contact();
            return Ok(());
        }

        // 3. Slips and their relaxation (implicit Euler).
        let omega = self.out.spin_rate;
        let rd = p.radius - dz / 3.0;
        let vr = rd * omega;
        let (vx, vy) = (v.dot(&ex), v.dot(&ey));
        let (vsx, vsy) = (vx - vr, vy);
        let h = ctx.h;
        let [sig_x, sig_y] = p.relaxation_length;
        self.sx = (self.sx - h * vsx / sig_x) / (1.0 + h * vr.abs() / sig_x);
        self.sy = (self.sy - h * vsy / sig_y) / (1.0 + h * vr.abs() / sig_y);
        let big = self.sx.abs().max(self.sy.abs());
        if big > self.slip_limit {
            // scale both, keeping the direction of the combined slip
            let k = self.slip_limit / big;
            self.sx *= k;
            self.sy *= k;
        }

        // 4. Forces.
        let mu = self.terrain.friction(contact.x, contact.y);
        let mu_scale = mu / p.reference_friction;
        let xc = p.longitudinal.at_load(fz, p.nominal_load, mu_scale);
        let yc = p.lateral.at_load(fz, p.nominal_load, mu_scale);
        let (mut fx, mut fy) = combined_force(self.sx, self.sy, &xc, &yc);
        let wl = (1.0 - vr.abs().max(v.norm()) / p.low_speed).max(0.0);
        fx -= wl * p.low_speed_damping[0] * vsx;
        fy -= wl * p.low_speed_damping[1] * vsy;

        // 5. Aligning torque, 6. rolling resistance.
        let len = 2.0 * (dz * (2.0 * p.radius - dz)).max(0.0).sqrt();
        let n0 = p.trail_ratio * len;
        let sgn = (vx / p.low_speed).clamp(-1.0, 1.0);
        let mz = -sgn * Self::trail(n0, self.sy, yc.s_max, yc.s_slide) * fy;
        let my = -p.rolling_resistance * rd * fz * (vr / p.low_speed).clamp(-1.0, 1.0);

        let force = fx * ex + fy * ey + fz * n;
        loads.add_force_at(self.body, &force, &contact);
        loads.add_torque(self.body, &(mz * n + my * a));

        let (kx, ky) = if vr.abs() > 0.0 {
            (-vsx / vr.abs(), -vsy / vr.abs())
        } else {
            (0.0, 0.0)
        };
        self.out = TireOutput {
            in_contact: true,
            contact_point: contact,
            normal: n,
            longitudinal_dir: ex,
            lateral_dir: ey,
            deflection: dz,
            normal_force: fz,
            slip_long: kx,
            slip_lat: ky,
            relaxed_slip_long: self.sx,
            relaxed_slip_lat: self.sy,
            fx,
            fy,
            mz,
            my,
            rolling_radius: rd,
            spin_rate: omega,
        };
        Ok(())
    }
}
