//! Open boundaries: a through-flow channel with an inflow and an outflow section
//! ([`OpenChannel`], set by [`SphSettings::open_channel`](crate::SphSettings::open_channel)).
//!
//! **Layout.** Along the flow axis `a` (not periodic) the domain `[L, U]` of the settings
//! has two buffer zones of depth `b` at its ends: the *inlet buffer* `[L, L + b)` and the
//! *outlet buffer* `[U - b, U)`; the fluid proper lies between the inlet plane `L + b` and
//! the outlet plane `U - b`. The buffers hold fluid particles whose state is imposed
//! instead of integrated (they are neighbours of the fluid, never stepped):
//!
//! - *inlet*: velocity = the prescribed inflow `u_in(x, t)` along the axis ([`Inflow`],
//!   times a C1 ramp over [`OpenChannel::ramp_time`]); pressure extrapolated from the fluid
//!   with a zero normal gradient (with the hydrostatic and body-force term of the wall
//!   markers, `p_i = sum_f (p_f + rho_f b . (x_i - x_f)) W_if / sum_f W_if`), and the mass
//!   `rho_i dp^3` of its lattice cell at that density: a velocity inlet whose mass flux is
//!   `rho_in u_in`. The inlet buffer is a conveyor of lattice rows: each row (a lattice point of
//!   the section) moves at its inflow speed, and a new particle is put at the row's rear
//!   (one spacing behind its last particle, with the row's mass and the rest density)
//!   whenever the rear has moved a spacing into the buffer, so the inflow enters at the
//!   lattice's number density and the imposed velocity: the mass flux is imposed too;
//! - *outlet*: velocity extrapolated from the fluid the same way (zero normal gradient),
//!   and the pressure either imposed ([`Outflow::Pressure`], with the density from the
//!   equation of state: the "do-nothing" outflow `nu du/dn - p n = 0` of a developed flow,
//!   which also fixes the pressure level and reflects pressure waves as an open pipe end
//!   does) or extrapolated too ([`Outflow::ZeroGradient`]: the level then floats with the
//!   mass in the domain); a particle past the domain's end `U` is removed;
//! - a buffer particle farther than the kernel support from the fluid has no fluid
//!   neighbour and keeps its last values (it touches no fluid particle either).
//!
//! A particle crossing the inlet plane becomes fluid with the state it had (as a particle
//! entering the active domain does, [`crate::system::active`]: no jump in density or
//! pressure); a fluid particle crossing the outlet plane completes its step and becomes an
//! outlet-buffer particle. Particles are added and removed only when the neighbour list
//! is rebuilt (the rear gap of a row and a particle past `U` stay out of the fluid's
//! reach in between: the buffers hold at least one kernel support), so the particle count
//! changes between list builds and the arrays keep their order otherwise. New particles
//! get new ids (above every id so far).
//!
//! Where the method comes from: buffer zones with imposed inflow velocity and
//! extrapolated pressure are the standard weakly compressible SPH inlet (Lastiwka, Basa
//! and Quinlan 2009, Int. J. Numer. Meth. Fluids 61:709; Federico, Marrone, Colagrossi,
//! Aristodemo and Antuono 2012, Eur. J. Mech. B 34:35); the extrapolation here is the
//! kernel average of the wall markers (Adami, Hu and Adams 2012) over the fluid side,
//! zero-order, not the first-order corrected mirror of Tafuni, Domínguez, Vacondio and
//! Crespo (2018, Comput. Methods Appl. Mech. Eng. 342:604).

use serde::{Deserialize, Serialize};

use crate::error::{Result, SphError};

/// The prescribed inflow velocity across the inlet section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Inflow {
    /// The same speed along the flow axis everywhere in the section.
    Uniform {
        /// The speed, m/s (> 0).
        speed: f64,
    },
    /// Plane Poiseuille flow between two walls across axis `across`, with wall surfaces at
    /// `lower` and `upper` (m): `u = 4 u_max s (1 - s)` along the flow axis,
    /// `s = (q - lower) / (upper - lower)` the position across (0 outside `[0, 1]`).
    /// The mean speed is `2 u_max / 3`.
    PlanePoiseuille {
        /// The centreline speed, m/s (> 0: the flow enters at the lower end of the axis).
        u_max: f64,
        /// The axis across the channel (0, 1, 2; not the flow axis).
        across: usize,
        /// The lower wall surface along `across`, m.
        lower: f64,
        /// The upper wall surface along `across`, m.
        upper: f64,
    },
}

/// The outlet's pressure condition.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outflow {
    /// The gauge pressure `p` (Pa) on every outlet-buffer particle (uniform: no gravity
    /// across the flow, checked).
    Pressure {
        /// The outlet pressure, Pa.
        p: f64,
    },
    /// The pressure extrapolated from the fluid (zero normal gradient).
    ZeroGradient,
    /// The gauge pressure `p` (Pa) plus the acoustic impedance term of a plane wave,
    /// `p_b = p + rho_0 c_s (u_out - U_in)`, with `u_out` the mean axial velocity of the
    /// outlet-buffer particles next to the fluid and `U_in` the inflow's section mean at
    /// the same time ([`OpenChannel::inflow_mean`]): a plane acoustic wave carries
    /// `p' = rho_0 c_s u'`, so the channel's plane mode leaves through the outlet instead
    /// of ringing between a velocity inlet (a closed end) and a pressure outlet (an open
    /// end). In the steady state `u_out = U_in` (the same flux through the same section)
    /// and this is [`Outflow::Pressure`]. For channels whose outlet section equals the
    /// inlet's (uniform gravity across the flow is refused as for `Pressure`).
    Absorbing {
        /// The outlet pressure, Pa.
        p: f64,
    },
}

/// A through-flow channel along a (non-periodic) axis with a velocity inlet and a zero-gradient
/// outlet (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OpenChannel {
    /// The flow axis (0, 1, 2); not periodic in the settings. The flow goes from the
    /// lower end of the domain (inlet) to the upper end (outlet).
    pub axis: usize,
    /// The depth of each buffer zone along the axis, m (at least the kernel support `2 h`).
    pub buffer: f64,
    /// The inflow velocity.
    pub inflow: Inflow,
    /// The outlet's pressure condition.
    pub outflow: Outflow,
    /// The inflow is ramped up from zero over this time with `3 s^2 - 2 s^3`,
    /// `s = t / ramp_time` (C1 at both ends), s; 0: at full speed from the start.
    pub ramp_time: f64,
}

/// Zone code of a fluid particle: the fluid proper.
pub(crate) const ZONE_FLUID: u8 = 0;
/// Zone code: the inlet buffer.
pub(crate) const ZONE_INLET: u8 = 1;
/// Zone code: the outlet buffer.
pub(crate) const ZONE_OUTLET: u8 = 2;

impl OpenChannel {
    /// Checks the channel against the settings' domain (`lower`, `upper`, `periodic`) and
    /// kernel support `support` (m); the error names the field.
    pub(crate) fn validate(
        &self,
        lower: [f64; 3],
        upper: [f64; 3],
        periodic: [bool; 3],
        support: f64,
        gravity: [f64; 3],
    ) -> Result<()> {
        let a = self.axis;
        if a > 2 {
            return Err(SphError::invalid(
                "settings.open_channel.axis",
                a,
                "must be 0, 1 or 2",
            ));
        }
        if periodic[a] {
            return Err(SphError::invalid(
                "settings.open_channel.axis",
                a,
                "the flow axis must not be periodic (the fluid enters and leaves at its ends)",
            ));
        }
        let len = upper[a] - lower[a];
        if !(self.buffer.is_finite() && self.buffer >= support * (1.0 - 1e-12)) {
            return Err(SphError::invalid(
                "settings.open_channel.buffer",
                self.buffer,
                format!("must be finite and at least the kernel support 2 h = {support} m"),
            ));
        }
        if 2.0 * self.buffer + support > len {
            return Err(SphError::invalid(
                "settings.open_channel.buffer",
                self.buffer,
                format!("two buffers and a kernel support of fluid must fit the domain's {len} m"),
            ));
        }
        if !(self.ramp_time.is_finite() && self.ramp_time >= 0.0) {
            return Err(SphError::invalid(
                "settings.open_channel.ramp_time",
                self.ramp_time,
                "must be finite and >= 0",
            ));
        }
        if let Outflow::Pressure { p } | Outflow::Absorbing { p } = self.outflow {
            if !p.is_finite() {
                return Err(SphError::invalid(
                    "settings.open_channel.outflow.p",
                    p,
                    "must be finite",
                ));
            }
            if (0..3).any(|k| k != a && gravity[k] != 0.0) {
                return Err(SphError::invalid(
                    "settings.open_channel.outflow",
                    "pressure",
                    "a uniform outlet pressure needs no gravity across the flow (use zero_gradient)",
                ));
            }
        }
        match self.inflow {
            Inflow::Uniform { speed } => {
                if !(speed.is_finite() && speed > 0.0) {
                    return Err(SphError::invalid(
                        "settings.open_channel.inflow.speed",
                        speed,
                        "must be finite and > 0 (the flow enters at the lower end of the axis)",
                    ));
                }
            }
            Inflow::PlanePoiseuille {
                u_max,
                across,
                lower: lo,
                upper: hi,
            } => {
                if !(u_max.is_finite() && u_max > 0.0) {
                    return Err(SphError::invalid(
                        "settings.open_channel.inflow.u_max",
                        u_max,
                        "must be finite and > 0 (the flow enters at the lower end of the axis)",
                    ));
                }
                if across > 2 || across == a {
                    return Err(SphError::invalid(
                        "settings.open_channel.inflow.across",
                        across,
                        "must be an axis (0, 1, 2) other than the flow axis",
                    ));
                }
                if !(lo.is_finite() && hi.is_finite() && hi > lo) {
                    return Err(SphError::invalid(
                        "settings.open_channel.inflow.upper",
                        hi,
                        format!("must be finite and above lower = {lo}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The ramp factor at time `t` (s): `3 s^2 - 2 s^3`, `s = clamp(t / ramp_time, 0, 1)`.
    pub fn ramp(&self, t: f64) -> f64 {
        if self.ramp_time <= 0.0 {
            return 1.0;
        }
        let s = (t / self.ramp_time).clamp(0.0, 1.0);
        s * s * (3.0 - 2.0 * s)
    }

    /// The inflow speed along the axis at position `x` and time `t` (m/s), ramp included.
    pub fn inflow_speed(&self, x: [f64; 3], t: f64) -> f64 {
        let r = self.ramp(t);
        match self.inflow {
            Inflow::Uniform { speed } => r * speed,
            Inflow::PlanePoiseuille {
                u_max,
                across,
                lower,
                upper,
            } => {
                let s = (x[across] - lower) / (upper - lower);
                if (0.0..=1.0).contains(&s) {
                    r * 4.0 * u_max * s * (1.0 - s)
                } else {
                    0.0
                }
            }
        }
    }

    /// The inflow's mean speed over its section at time `t` (m/s, ramp included): the
    /// speed of a uniform inflow, `2 u_max / 3` of a plane Poiseuille one.
    pub fn inflow_mean(&self, t: f64) -> f64 {
        let r = self.ramp(t);
        match self.inflow {
            Inflow::Uniform { speed } => r * speed,
            Inflow::PlanePoiseuille { u_max, .. } => r * 2.0 * u_max / 3.0,
        }
    }

    /// The inflow velocity at position `x` and time `t` (m/s): [`inflow_speed`](Self::inflow_speed)
    /// along the axis.
    pub fn inflow_velocity(&self, x: [f64; 3], t: f64) -> [f64; 3] {
        let mut v = [0.0; 3];
        v[self.axis] = self.inflow_speed(x, t);
        v
    }

    /// The zone of a fluid particle at coordinate `q` along the flow axis, in the domain
    /// `[lower, upper)` of that axis: [`ZONE_INLET`], [`ZONE_OUTLET`] or [`ZONE_FLUID`].
    #[inline]
    pub(crate) fn zone(&self, q: f64, lower: f64, upper: f64) -> u8 {
        if q < lower + self.buffer {
            ZONE_INLET
        } else if q >= upper - self.buffer {
            ZONE_OUTLET
        } else {
            ZONE_FLUID
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel() -> OpenChannel {
        OpenChannel {
            axis: 0,
            buffer: 0.03,
            inflow: Inflow::PlanePoiseuille {
                u_max: 0.3,
                across: 2,
                lower: 0.0,
                upper: 0.41,
            },
            ramp_time: 1.0,
            outflow: Outflow::Pressure { p: 0.0 },
        }
    }

    #[test]
    fn the_poiseuille_profile_has_its_mean_and_walls() {
        let c = channel();
        // mean over the section by the midpoint rule: 2/3 u_max
        let n = 100_000;
        let mean: f64 = (0..n)
            .map(|k| {
                let z = 0.41 * (k as f64 + 0.5) / n as f64;
                c.inflow_velocity([0.0, 0.0, z], 2.0)[0]
            })
            .sum::<f64>()
            / n as f64;
        assert!((mean - 0.2).abs() < 1e-9, "{mean}");
        assert_eq!(c.inflow_velocity([0.0, 0.0, 0.0], 2.0), [0.0; 3]);
        assert_eq!(c.inflow_velocity([0.0, 0.0, -0.01], 2.0), [0.0; 3]);
        assert!((c.inflow_velocity([0.0, 0.0, 0.205], 2.0)[0] - 0.3).abs() < 1e-12);
    }

    #[test]
    fn the_ramp_is_c1_and_reaches_one() {
        let c = channel();
        assert_eq!(c.ramp(0.0), 0.0);
        assert_eq!(c.ramp(1.0), 1.0);
        assert_eq!(c.ramp(5.0), 1.0);
        assert!((c.ramp(0.5) - 0.5).abs() < 1e-15);
        // slope zero at both ends
        let e = 1e-6;
        assert!(c.ramp(e) / e < 1e-5);
        assert!((1.0 - c.ramp(1.0 - e)) / e < 1e-5);
        let c0 = OpenChannel {
            ramp_time: 0.0,
            ..c
        };
        assert_eq!(c0.ramp(0.0), 1.0);
    }

    #[test]
    fn zones_split_the_period() {
        let c = channel();
        assert_eq!(c.zone(0.0, 0.0, 1.0), ZONE_INLET);
        assert_eq!(c.zone(0.029, 0.0, 1.0), ZONE_INLET);
        assert_eq!(c.zone(0.03, 0.0, 1.0), ZONE_FLUID);
        assert_eq!(c.zone(0.969, 0.0, 1.0), ZONE_FLUID);
        assert_eq!(c.zone(0.97, 0.0, 1.0), ZONE_OUTLET);
    }

    #[test]
    fn bad_channels_are_named() {
        let lo = [0.0; 3];
        let hi = [1.0, 0.1, 0.41];
        let per = [false, true, false];
        let s = 0.026;
        let g = [0.0; 3];
        assert!(channel().validate(lo, hi, per, s, g).is_ok());
        let e = channel()
            .validate(lo, hi, per, s, [0.0, 0.0, -9.81])
            .unwrap_err()
            .to_string();
        assert!(e.contains("outflow"), "{e}");
        let zg = OpenChannel {
            outflow: Outflow::ZeroGradient,
            ..channel()
        };
        assert!(zg.validate(lo, hi, per, s, [0.0, 0.0, -9.81]).is_ok());
        let cases: Vec<(&str, OpenChannel, [bool; 3])> = vec![
            (
                "axis",
                OpenChannel {
                    axis: 1,
                    ..channel()
                },
                per,
            ),
            (
                "axis",
                OpenChannel {
                    axis: 4,
                    ..channel()
                },
                per,
            ),
            (
                "buffer",
                OpenChannel {
                    buffer: 0.01,
                    ..channel()
                },
                per,
            ),
            (
                "buffer",
                OpenChannel {
                    buffer: 0.49,
                    ..channel()
                },
                per,
            ),
            (
                "ramp_time",
                OpenChannel {
                    ramp_time: -1.0,
                    ..channel()
                },
                per,
            ),
            (
                "u_max",
                OpenChannel {
                    inflow: Inflow::PlanePoiseuille {
                        u_max: -0.3,
                        across: 2,
                        lower: 0.0,
                        upper: 0.41,
                    },
                    ..channel()
                },
                per,
            ),
            (
                "across",
                OpenChannel {
                    inflow: Inflow::PlanePoiseuille {
                        u_max: 0.3,
                        across: 0,
                        lower: 0.0,
                        upper: 0.41,
                    },
                    ..channel()
                },
                per,
            ),
            (
                "speed",
                OpenChannel {
                    inflow: Inflow::Uniform { speed: 0.0 },
                    ..channel()
                },
                per,
            ),
            ("axis", channel(), [true, true, false]),
            (
                "outflow.p",
                OpenChannel {
                    outflow: Outflow::Pressure { p: f64::NAN },
                    ..channel()
                },
                per,
            ),
        ];
        for (field, c, p) in cases {
            let e = c.validate(lo, hi, p, s, g).unwrap_err().to_string();
            assert!(e.contains(field), "{field}: {e}");
        }
    }
}
