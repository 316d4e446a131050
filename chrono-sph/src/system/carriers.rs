//! The rigid and point carriers of a [`SphSystem`](super::SphSystem): placing their
//! markers at a time, and the fluid's loads and impulses on them (see
//! [`crate::carrier`]).

use std::time::Instant;

use rayon::prelude::*;

use super::{SphSystem, make_ctx};
use crate::carrier::{NO_CARRIER, POINT_CARRIER, RigidMotion};
use crate::data::FLUID;
use crate::error::{Result, SphError};
use crate::interact;

impl SphSystem {
    /// Places the markers of the rigid carriers at time `t`: position, velocity and the
    /// acceleration of the pressure extrapolation (see [`crate::carrier`]), wrapped into
    /// the periodic axes.
    pub(super) fn move_carriers(&mut self, t: f64) {
        for c in &mut self.carriers {
            (c.centre, c.rotation) = c.motion.pose_at(t);
        }
        self.carrier_omega.resize(self.carriers.len(), [0.0; 3]);
        for (o, c) in self.carrier_omega.iter_mut().zip(&self.carriers) {
            let w = c.motion.angular_velocity;
            *o = [w.x, w.y, w.z];
        }
        let (lo, hi, per) = (
            self.settings.domain_lower,
            self.settings.domain_upper,
            self.settings.periodic,
        );
        let carriers = &self.carriers;
        let points = &self.point_carriers;
        let d = &mut self.data;
        (
            d.x.par_iter_mut(),
            d.y.par_iter_mut(),
            d.z.par_iter_mut(),
            d.vx.par_iter_mut(),
            d.vy.par_iter_mut(),
            d.vz.par_iter_mut(),
            d.wall_a.par_iter_mut(),
            d.anchor.par_iter(),
            d.carrier.par_iter(),
            d.id.par_iter(),
        )
            .into_par_iter()
            .for_each(|(x, y, z, vx, vy, vz, acc, a, &k, &id)| {
                if k == NO_CARRIER {
                    return;
                }
                if k & POINT_CARRIER != 0 {
                    // a point carrier's marker: its own constant velocity from t0
                    let c = &points[(k & !POINT_CARRIER) as usize];
                    let i = (id - c.first_id) as usize;
                    let (x0, v) = (c.x0[i], c.v[i]);
                    let s = t - c.t0;
                    let mut p = [x0[0] + s * v[0], x0[1] + s * v[1], x0[2] + s * v[2]];
                    for ax in 0..3 {
                        if per[ax] {
                            let l = hi[ax] - lo[ax];
                            p[ax] = lo[ax] + (p[ax] - lo[ax]).rem_euclid(l);
                        }
                    }
                    (*x, *y, *z) = (p[0], p[1], p[2]);
                    (*vx, *vy, *vz) = (v[0], v[1], v[2]);
                    *acc = [0.0; 3];
                    return;
                }
                let c = &carriers[k as usize];
                let m = &c.motion;
                let r = c.rotation * nalgebra::Vector3::new(a[0], a[1], a[2]);
                let mut p = [c.centre.x + r.x, c.centre.y + r.y, c.centre.z + r.z];
                for ax in 0..3 {
                    if per[ax] {
                        let l = hi[ax] - lo[ax];
                        p[ax] = lo[ax] + (p[ax] - lo[ax]).rem_euclid(l);
                    }
                }
                (*x, *y, *z) = (p[0], p[1], p[2]);
                let w = m.angular_velocity;
                let v = m.velocity + w.cross(&r);
                (*vx, *vy, *vz) = (v.x, v.y, v.z);
                let ac = m.acceleration + m.angular_acceleration.cross(&r) + w.cross(&w.cross(&r));
                *acc = [ac.x, ac.y, ac.z];
            });
    }

    /// Sets the motion of rigid carrier `carrier` (from its `t0` on; see
    /// [`crate::carrier`]): its markers follow it from the next step. The impulse
    /// accumulated so far is kept.
    pub fn set_carrier_motion(&mut self, carrier: usize, motion: RigidMotion) -> Result<()> {
        motion.validate(&format!("carrier {carrier} motion"))?;
        let n = self.carriers.len();
        let c = self
            .carriers
            .get_mut(carrier)
            .ok_or_else(|| SphError::invalid("carrier", carrier, format!("only {n} carriers")))?;
        c.motion = motion;
        Ok(())
    }

    /// Sets the motion of point carrier `carrier` from time `t0` (s) on: marker `i` (in
    /// the order of [`SphBuilder::add_point_markers`](crate::SphBuilder::add_point_markers))
    /// at `positions[i]` (m) at `t0`, moving with `velocities[i]` (m/s); see
    /// [`crate::carrier`]. The markers follow from the next step; the impulse accumulated
    /// so far is kept. Errors: an unknown carrier, a length that is not the number of
    /// markers, a value that is not finite.
    pub fn set_point_motion(
        &mut self,
        carrier: usize,
        t0: f64,
        positions: &[[f64; 3]],
        velocities: &[[f64; 3]],
    ) -> Result<()> {
        let c = self.point_carrier_mut(carrier)?;
        let n = c.x0.len();
        for (what, len) in [
            ("positions", positions.len()),
            ("velocities", velocities.len()),
        ] {
            if len != n {
                return Err(SphError::invalid(
                    format!("point carrier {carrier} {what}"),
                    len,
                    format!("must have one entry per marker ({n})"),
                ));
            }
        }
        let bad = |v: &[[f64; 3]]| v.iter().position(|p| p.iter().any(|x| !x.is_finite()));
        if !t0.is_finite() {
            return Err(SphError::invalid(
                format!("point carrier {carrier} t0"),
                t0,
                "must be finite",
            ));
        }
        for (what, v) in [("positions", positions), ("velocities", velocities)] {
            if let Some(i) = bad(v) {
                return Err(SphError::invalid(
                    format!("point carrier {carrier} {what}[{i}]"),
                    format!("{:?}", v[i]),
                    "must be finite",
                ));
            }
        }
        c.t0 = t0;
        c.x0.copy_from_slice(positions);
        c.v.copy_from_slice(velocities);
        Ok(())
    }

    fn point_carrier_mut(&mut self, carrier: usize) -> Result<&mut crate::carrier::PointCarrier> {
        let n = self.point_carriers.len();
        self.point_carriers.get_mut(carrier).ok_or_else(|| {
            SphError::invalid("point carrier", carrier, format!("only {n} point carriers"))
        })
    }

    /// Number of point carriers.
    pub fn num_point_carriers(&self) -> usize {
        self.point_carriers.len()
    }

    /// The fluid's force on each marker of point carrier `carrier` (N) at the last force
    /// evaluation (zero before the first); `None` for an unknown carrier.
    pub fn point_forces(&self, carrier: usize) -> Option<&[[f64; 3]]> {
        self.point_carriers.get(carrier).map(|c| c.force.as_slice())
    }

    /// Copies into `out` and zeroes the impulse (N s) of the fluid on each marker of point
    /// carrier `carrier` summed over the steps since the last call (per step
    /// `dt (F^n + F^(n+1)) / 2`, as for rigid carriers). Errors: an unknown carrier, `out`
    /// not one entry per marker.
    pub fn take_point_impulses(&mut self, carrier: usize, out: &mut [[f64; 3]]) -> Result<()> {
        let c = self.point_carrier_mut(carrier)?;
        if out.len() != c.impulse.len() {
            return Err(SphError::invalid(
                format!("point carrier {carrier} impulse buffer"),
                out.len(),
                format!("must have one entry per marker ({})", c.impulse.len()),
            ));
        }
        out.copy_from_slice(&c.impulse);
        c.impulse.fill([0.0; 3]);
        Ok(())
    }

    /// Number of rigid carriers.
    pub fn num_carriers(&self) -> usize {
        self.carriers.len()
    }

    /// The force (N) and torque about the carrier's centre (N m) of the fluid on the
    /// markers of `carrier` at the last force evaluation (zero before the first;
    /// `carrier` past [`num_carriers`](Self::num_carriers) panics).
    pub fn carrier_load(&self, carrier: usize) -> [nalgebra::Vector3<f64>; 2] {
        self.carriers[carrier].load
    }

    /// The carrier's centre (m) at the current time.
    pub fn carrier_centre(&self, carrier: usize) -> nalgebra::Vector3<f64> {
        self.carriers[carrier].centre
    }

    /// Returns and zeroes the impulse (N s) and angular impulse about the centre (N m s)
    /// of the fluid on `carrier` summed over the steps since the last call: per step
    /// `dt (F^n + F^(n+1)) / 2`, the forces of the fluid's two half kicks.
    pub fn take_carrier_impulse(&mut self, carrier: usize) -> [nalgebra::Vector3<f64>; 2] {
        std::mem::replace(
            &mut self.carriers[carrier].impulse,
            [nalgebra::Vector3::zeros(); 2],
        )
    }

    /// Adds `half` times the current loads to the carriers' impulses.
    pub(super) fn kick_carriers(&mut self, half: f64) {
        for c in &mut self.carriers {
            c.impulse[0] += half * c.load[0];
            c.impulse[1] += half * c.load[1];
        }
        for c in &mut self.point_carriers {
            for (j, f) in c.impulse.iter_mut().zip(&c.force) {
                for a in 0..3 {
                    j[a] += half * f[a];
                }
            }
        }
    }

    /// The fluid's force and torque on every carrier at the current state (after the
    /// force pass: the packed records hold the no-slip wall velocities).
    pub(super) fn carrier_loads(&mut self) {
        if self.carriers.is_empty() && self.point_carriers.is_empty() {
            return;
        }
        let t0 = Instant::now();
        let ctx = make_ctx(
            &self.settings,
            &self.kernel,
            &self.eos,
            &self.grid,
            &self.list,
            &self.motion,
            self.time,
            &self.belts,
            &self.carrier_omega,
        );
        let support2 = self.kernel.support() * self.kernel.support();
        let d = &self.data;
        let nb = &self.packed;
        let omega = &self.carrier_omega;
        self.marker_f.resize(d.len(), [0.0; 3]);
        self.marker_g.resize(d.len(), [0.0; 3]);
        self.marker_f
            .par_iter_mut()
            .zip(self.marker_g.par_iter_mut())
            .enumerate()
            .for_each(|(w, (out, rot))| {
                *out = [0.0; 3];
                *rot = [0.0; 3];
                let k = d.carrier[w];
                if k == NO_CARRIER {
                    return;
                }
                let o = if k & POINT_CARRIER == 0 {
                    omega.get(k as usize).copied().filter(|o| *o != [0.0; 3])
                } else {
                    None
                };
                for &f in ctx.list.neighbors(w) {
                    let f = f as usize;
                    if d.kind[f] != FLUID {
                        continue;
                    }
                    // the reaction of the term marker w adds to fluid f's acceleration
                    let a = interact::pair_accel(&ctx, &nb[f], &nb[w], support2);
                    let m = d.mass[f];
                    out[0] -= m * a[0];
                    out[1] -= m * a[1];
                    out[2] -= m * a[2];
                    if let Some(o) = o {
                        // the Morris term's share of a co-rotation, v_fw = w x x_fw
                        let (x, k) = interact::pair_visc(&ctx, &nb[f], &nb[w], support2);
                        let g = [
                            o[1] * x[2] - o[2] * x[1],
                            o[2] * x[0] - o[0] * x[2],
                            o[0] * x[1] - o[1] * x[0],
                        ];
                        rot[0] -= m * k * g[0];
                        rot[1] -= m * k * g[1];
                        rot[2] -= m * k * g[2];
                    }
                }
            });
        for c in &mut self.carriers {
            c.load = [nalgebra::Vector3::zeros(); 2];
        }
        // slot order: deterministic for any thread count
        for w in 0..d.len() {
            let k = d.carrier[w];
            if k == NO_CARRIER {
                continue;
            }
            if k & POINT_CARRIER != 0 {
                let c = &mut self.point_carriers[(k & !POINT_CARRIER) as usize];
                c.force[(d.id[w] - c.first_id) as usize] = self.marker_f[w];
                continue;
            }
            let c = &mut self.carriers[k as usize];
            let f = nalgebra::Vector3::from(self.marker_f[w]);
            let a = d.anchor[w];
            let r = c.rotation * nalgebra::Vector3::new(a[0], a[1], a[2]);
            c.load[0] += f;
            // The Morris force of a pair is along v_ab, not x_ab: it does not conserve
            // angular momentum, and a fluid co-rotating rigidly with the body puts a
            // torque ~ mu w a^3 on it at any resolution (the markers' fluid neighbours lie
            // on one side; measured: a sphere in shear spun at 0.66 gamma instead of
            // gamma / 2). The torque leaves out that share: zero for rigid co-rotation,
            // the viscous stress of the flow relative to the body otherwise. The force
            // keeps it (linear momentum stays exact).
            let g = self.marker_g[w];
            if g != [0.0; 3] {
                let g = nalgebra::Vector3::from(g);
                c.load[1] += r.cross(&(f - g));
            } else {
                c.load[1] += r.cross(&f);
            }
        }
        self.timings.markers += t0.elapsed().as_secs_f64();
    }
}
