//! The rigid carriers of a [`SphSystem`](super::SphSystem): placing their markers at a
//! time, and the fluid's loads and impulses on them (see [`crate::carrier`]).

use std::time::Instant;

use rayon::prelude::*;

use super::{SphSystem, make_ctx};
use crate::carrier::{NO_CARRIER, RigidMotion};
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
        let (lo, hi, per) = (
            self.settings.domain_lower,
            self.settings.domain_upper,
            self.settings.periodic,
        );
        let carriers = &self.carriers;
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
        )
            .into_par_iter()
            .for_each(|(x, y, z, vx, vy, vz, acc, a, &k)| {
                if k == NO_CARRIER {
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
    }

    /// The fluid's force and torque on every carrier at the current state (after the
    /// force pass: the packed records hold the no-slip wall velocities).
    pub(super) fn carrier_loads(&mut self) {
        if self.carriers.is_empty() {
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
        );
        let support2 = self.kernel.support() * self.kernel.support();
        let d = &self.data;
        let nb = &self.packed;
        self.marker_f.resize(d.len(), [0.0; 3]);
        self.marker_f
            .par_iter_mut()
            .enumerate()
            .for_each(|(w, out)| {
                *out = [0.0; 3];
                if d.carrier[w] == NO_CARRIER {
                    return;
                }
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
            let c = &mut self.carriers[k as usize];
            let f = nalgebra::Vector3::from(self.marker_f[w]);
            let a = d.anchor[w];
            let r = c.rotation * nalgebra::Vector3::new(a[0], a[1], a[2]);
            c.load[0] += f;
            c.load[1] += r.cross(&f);
        }
        self.timings.forces += t0.elapsed().as_secs_f64();
    }
}
