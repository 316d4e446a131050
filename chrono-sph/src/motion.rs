//! Prescribed (kinematic) motion of the wall markers: a tank that moves.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::error::{Result, SphError, finite3, non_negative};

/// Displacement (m), velocity (m/s) and acceleration (m/s^2) of a rigid translation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Kinematics {
    /// Displacement from the initial position, m.
    pub disp: [f64; 3],
    /// Velocity, m/s.
    pub vel: [f64; 3],
    /// Acceleration, m/s^2.
    pub acc: [f64; 3],
}

/// The motion of all wall markers (a rigid translation of the tank).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum WallMotion {
    /// Walls at rest.
    #[default]
    Fixed,
    /// `x(t) = A e(t) sin(Omega t)` with a smooth start `e(t) = (1 - cos(pi t / T_r)) / 2`
    /// for `t < T_r` and 1 after (`T_r = ramp`, 0 = impulsive start): lateral
    /// oscillation of a sloshing tank.
    Sinusoid {
        /// Amplitude vector `A`, m.
        amplitude: [f64; 3],
        /// Angular frequency `Omega`, rad/s.
        omega: f64,
        /// Ramp duration `T_r`, s.
        ramp: f64,
    },
}

impl WallMotion {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<()> {
        if let WallMotion::Sinusoid {
            amplitude,
            omega,
            ramp,
        } = *self
        {
            finite3("motion.amplitude", amplitude)?;
            non_negative("motion.ramp", ramp)?;
            if !omega.is_finite() {
                return Err(SphError::invalid("motion.omega", omega, "must be finite"));
            }
        }
        Ok(())
    }

    /// The kinematics at time `t`.
    pub fn at(&self, t: f64) -> Kinematics {
        match *self {
            WallMotion::Fixed => Kinematics::default(),
            WallMotion::Sinusoid {
                amplitude,
                omega,
                ramp,
            } => {
                let (e, de, dde) = if ramp > 0.0 && t < ramp {
                    let k = PI / ramp;
                    (
                        0.5 * (1.0 - (k * t).cos()),
                        0.5 * k * (k * t).sin(),
                        0.5 * k * k * (k * t).cos(),
                    )
                } else {
                    (1.0, 0.0, 0.0)
                };
                let (s, c) = (omega * t).sin_cos();
                let f = e * s;
                let df = de * s + e * omega * c;
                let ddf = dde * s + 2.0 * de * omega * c - e * omega * omega * s;
                Kinematics {
                    disp: amplitude.map(|a| a * f),
                    vel: amplitude.map(|a| a * df),
                    acc: amplitude.map(|a| a * ddf),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinusoid_derivatives_match_finite_differences() {
        let m = WallMotion::Sinusoid {
            amplitude: [0.01, 0.0, 0.002],
            omega: 7.0,
            ramp: 0.5,
        };
        for t in [0.0, 0.1, 0.3, 0.49, 0.7, 2.0] {
            let e = 1e-6;
            let (a, b, k) = (m.at(t + e), m.at((t - e).max(0.0)), m.at(t));
            let span = t + e - (t - e).max(0.0);
            for ax in [0, 2] {
                let v = (a.disp[ax] - b.disp[ax]) / span;
                assert!((v - k.vel[ax]).abs() < 1e-6, "t={t}");
                let acc = (a.vel[ax] - b.vel[ax]) / span;
                assert!(
                    (acc - k.acc[ax]).abs() < 1e-4,
                    "t={t}: {acc} vs {}",
                    k.acc[ax]
                );
            }
        }
        assert_eq!(m.at(0.0).disp, [0.0; 3]);
        assert_eq!(WallMotion::Fixed.at(3.0), Kinematics::default());
    }
}
