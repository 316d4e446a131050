//! The end-of-step check of an [`SphSystem`]: every stepped particle finite and below
//! the speed limits, and the next time step from the stability criteria (over every
//! rank of a decomposition).

use rayon::prelude::*;

use super::SphSystem;
use super::active::ACT_NOW;
use crate::data::FLUID;
use crate::distributed::Transport;
use crate::error::{Result, SphError};
use crate::settings::MachPolicy;

impl SphSystem {
    /// Checks the fluid state (finite, below the speed limits) and sets the next `dt`.
    pub(super) fn check_and_set_dt(
        &mut self,
        net: Option<&mut (dyn Transport + 'static)>,
    ) -> Result<()> {
        let d = &self.data;
        // (value, slot) maxima with the lowest slot on ties: deterministic.
        let pick = |a: (f64, usize), b: (f64, usize)| {
            if b.0 > a.0 || (b.0 == a.0 && b.1 < a.1) {
                b
            } else {
                a
            }
        };
        let act = &self.act;
        let (bad, (v2, iv), (a2, _)) = (0..d.len())
            .into_par_iter()
            .map(|i| {
                // frozen particles: held state, stale derivatives (see `active`)
                if d.kind[i] != FLUID || act[i] & ACT_NOW == 0 {
                    return (usize::MAX, (0.0, i), (0.0, i));
                }
                let v2 = d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i] + d.vz[i] * d.vz[i];
                let a = d.deriv[i].acc;
                let a2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
                let finite = v2.is_finite()
                    && a2.is_finite()
                    && d.rho[i].is_finite()
                    && d.x[i].is_finite()
                    && d.y[i].is_finite()
                    && d.z[i].is_finite();
                (if finite { usize::MAX } else { i }, (v2, i), (a2, i))
            })
            .reduce(
                || (usize::MAX, (0.0, usize::MAX), (0.0, usize::MAX)),
                |x, y| (x.0.min(y.0), pick(x.1, y.1), pick(x.2, y.2)),
            );
        let (mut v2, mut a2) = (v2, a2);
        if let Some(t) = net {
            // one reduction: the failing rank (+1, 0 = none), the fastest speed and the
            // largest acceleration, so every rank takes the same dt
            let me = t.rank();
            let mut g = [
                if bad != usize::MAX {
                    (me + 1) as f64
                } else {
                    0.0
                },
                v2,
                a2,
            ];
            t.all_max(&mut g)?;
            if g[0] > 0.0 && bad == usize::MAX {
                return Err(SphError::Rank {
                    rank: g[0] as usize - 1,
                    reason: format!("a particle turned non-finite at step {}", self.steps),
                });
            }
            let c2 = self.settings.sound_speed * self.settings.sound_speed;
            let limit = self.settings.mach_limit * self.settings.mach_limit;
            let fails = g[1] / c2 > 1.0
                || (g[1] / c2 > limit && matches!(self.settings.mach_policy, MachPolicy::Error));
            if fails {
                // the stop is global: the rank of the fastest particle names it
                let mut who = [if v2 == g[1] { (me + 1) as f64 } else { 0.0 }];
                t.all_max(&mut who)?;
                if who[0] as usize != me + 1 {
                    return Err(SphError::Rank {
                        rank: who[0] as usize - 1,
                        reason: format!(
                            "its particle reached {:.4e} m/s at step {} (sound speed {} m/s)",
                            g[1].sqrt(),
                            self.steps,
                            self.settings.sound_speed
                        ),
                    });
                }
            }
            (v2, a2) = (g[1], g[2]);
        }
        if bad != usize::MAX {
            let what = if !(d.x[bad].is_finite() && d.y[bad].is_finite() && d.z[bad].is_finite()) {
                "position"
            } else if !d.rho[bad].is_finite() {
                "density"
            } else if !(d.vx[bad].is_finite() && d.vy[bad].is_finite() && d.vz[bad].is_finite()) {
                "velocity"
            } else {
                "acceleration"
            };
            return Err(SphError::NonFinite {
                particle: d.id[bad],
                step: self.steps,
                time: self.time,
                quantity: what,
            });
        }
        let vmax = v2.sqrt();
        let amax = a2.sqrt();
        let c = self.settings.sound_speed;
        let mach = vmax / c;
        self.stats.max_speed = vmax;
        self.stats.max_acc = amax;
        self.stats.max_mach = self.stats.max_mach.max(mach);
        if mach > 1.0 {
            return Err(SphError::Diverged {
                particle: d.id[iv],
                step: self.steps,
                time: self.time,
                what: format!("speed {vmax:.4e} m/s exceeds the sound speed {c} m/s"),
            });
        }
        if mach > self.settings.mach_limit {
            self.stats.mach_warnings += 1;
            match self.settings.mach_policy {
                MachPolicy::Error => {
                    return Err(SphError::MachExceeded {
                        particle: d.id[iv],
                        step: self.steps,
                        time: self.time,
                        mach,
                        limit: self.settings.mach_limit,
                    });
                }
                MachPolicy::Warn => {
                    if self.stats.mach_warnings == 1 {
                        tracing::warn!(
                            "SPH Mach number {mach:.3} > {} at step {} (particle {}): raise the sound speed",
                            self.settings.mach_limit,
                            self.steps,
                            d.id[iv]
                        );
                    }
                }
            }
        }
        let s = &self.settings;
        let h = self.kernel.h();
        let mut dt = s.cfl * h / (c + vmax);
        if amax > 0.0 {
            dt = dt.min(s.force_coef * (h / amax).sqrt());
        }
        if s.viscosity > 0.0 {
            dt = dt.min(s.visc_coef * h * h * s.rho0 / s.viscosity);
        }
        self.dt = dt.min(s.max_dt);
        Ok(())
    }
}
