//! Fully developed laminar flow in a rectangular duct, the reference flow of the channel
//! scene ([`crate::channel`]): the velocity profile, the mean velocity, and the driving
//! body force for a given mean velocity.
//!
//! A duct `-a <= y <= a`, `-b <= z <= b` driven along x by a uniform pressure gradient
//! `-dp/dx = G` (or, in a periodic channel, a body force `f = G / rho` on the fluid),
//! dynamic viscosity `mu`. With the sums over odd `i = 1, 3, 5, ...` (White 2006, *Viscous
//! Fluid Flow*, 3rd ed., eqs. 3-48 and 3-49; Shah & London 1978, *Laminar Flow Forced
//! Convection in Ducts*):
//!
//! ```text
//! u(y, z) = 16 G a^2 / (mu pi^3) sum_i (-1)^((i-1)/2) [1 - cosh(i pi z / 2a) / cosh(i pi b / 2a)]
//!                                                      cos(i pi y / 2a) / i^3
//! U_mean  = G a^2 / (3 mu) [1 - 192 a / (pi^5 b) sum_i tanh(i pi b / 2a) / i^5]
//! ```
//!
//! The series are taken along the shorter side (`a <= b`, the faster one). Checks: the
//! square duct gives `U_mean = 0.14058 G a^2 / mu` (the Darcy friction factor
//! `f Re_Dh = 2 G D_h^2 / (mu U_mean)` = 56.91, Shah & London's table) and
//! `u_max / U_mean` = 2.0962; `b -> inf` gives plane Poiseuille flow, `G a^2 / (3 mu)`.

use std::f64::consts::PI;

use crate::error::{FsiError, Result, check_positive};

/// Terms of the series kept (odd `i` up to `2 N - 1`); the velocity's terms fall as
/// `i^-3` with alternating signs, so `N = 400` truncates at about `16 / (pi^3 (2N)^3)`
/// = `1e-9` of `G a^2 / mu`; the mean's fall as `i^-5` (`1e-16`).
const TERMS: usize = 400;

/// `cosh(x) / cosh(xm)` for `|x| <= xm` without overflow.
fn cosh_ratio(x: f64, xm: f64) -> f64 {
    let x = x.abs();
    (x - xm).exp() * (1.0 + (-2.0 * x).exp()) / (1.0 + (-2.0 * xm).exp())
}

fn check_sides(half_y: f64, half_z: f64) -> Result<()> {
    for (f, v) in [("half_y", half_y), ("half_z", half_z)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(FsiError::invalid(
                format!("duct.{f}"),
                v,
                "must be finite and > 0",
            ));
        }
    }
    Ok(())
}

/// The axial velocity (m/s) at `(y, z)` (m, from the duct's centre) of the duct with
/// half-sides `half_y`, `half_z` (m) driven by `G / mu = g_over_mu` (1/(m s)); zero
/// outside the duct. See the [module docs](self).
pub fn duct_velocity(g_over_mu: f64, half_y: f64, half_z: f64, y: f64, z: f64) -> Result<f64> {
    check_sides(half_y, half_z)?;
    // the series along the shorter side
    let (a, b, s, t) = if half_y <= half_z {
        (half_y, half_z, y, z)
    } else {
        (half_z, half_y, z, y)
    };
    if s.abs() >= a || t.abs() >= b {
        return Ok(0.0);
    }
    let mut sum = 0.0;
    for k in 0..TERMS {
        let i = (2 * k + 1) as f64;
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        let k_i = i * PI / (2.0 * a);
        sum += sign * (1.0 - cosh_ratio(k_i * t, k_i * b)) * (k_i * s).cos() / (i * i * i);
    }
    Ok(16.0 * g_over_mu * a * a / PI.powi(3) * sum)
}

/// The mean velocity over the cross-section as a fraction of `G a^2 / mu`, `a` the
/// shorter half-side: `(1/3) [1 - 192 a / (pi^5 b) sum_i tanh(i pi b / 2a) / i^5]`.
pub fn duct_mean_coefficient(half_y: f64, half_z: f64) -> Result<f64> {
    check_sides(half_y, half_z)?;
    let (a, b) = (half_y.min(half_z), half_y.max(half_z));
    let sum: f64 = (0..TERMS)
        .map(|k| {
            let i = (2 * k + 1) as f64;
            (i * PI * b / (2.0 * a)).tanh() / i.powi(5)
        })
        .sum();
    Ok((1.0 - 192.0 * a / (PI.powi(5) * b) * sum) / 3.0)
}

/// The body force on the fluid (m/s^2, along the duct) that drives the mean velocity
/// `mean_velocity` (m/s) through the duct of half-sides `half_y`, `half_z` (m) with density
/// `rho` (kg/m^3) and dynamic viscosity `mu` (Pa s): `f = mu U_mean / (rho k a^2)`, `k` the
/// [`duct_mean_coefficient`]. Errors name a value that is not finite and positive.
pub fn body_force_for_mean_velocity(
    mean_velocity: f64,
    rho: f64,
    mu: f64,
    half_y: f64,
    half_z: f64,
) -> Result<f64> {
    for (f, v) in [("mean_velocity", mean_velocity), ("rho", rho), ("mu", mu)] {
        check_positive(f, v)?;
    }
    let a = half_y.min(half_z);
    let k = duct_mean_coefficient(half_y, half_z)?;
    Ok(mu * mean_velocity / (rho * k * a * a))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shah & London (1978): the square duct's Darcy `f Re` = 56.908, i.e.
    /// `U_mean = 8 G a^2 / (56.908 mu)`; `u_max / U_mean` = 2.0962 (their table 43).
    #[test]
    fn square_duct_against_shah_and_london() {
        let k = duct_mean_coefficient(0.5, 0.5).unwrap();
        assert!((k - 8.0 / 56.908).abs() < 2e-5, "{k}");
        let u_max = duct_velocity(1.0, 0.5, 0.5, 0.0, 0.0).unwrap();
        let ratio = u_max / (k * 0.25);
        assert!((ratio - 2.0962).abs() < 5e-4, "{ratio}");
        // symmetric in y and z, zero on the walls
        let (u1, u2) = (
            duct_velocity(1.0, 0.5, 0.5, 0.2, 0.1).unwrap(),
            duct_velocity(1.0, 0.5, 0.5, 0.1, 0.2).unwrap(),
        );
        assert!((u1 - u2).abs() < 1e-9 * 0.25, "{u1} {u2}");
        assert!(
            duct_velocity(1.0, 0.5, 0.5, 0.5 - 1e-12, 0.0)
                .unwrap()
                .abs()
                < 1e-10
        );
    }

    /// The mean of the profile (midpoint rule) equals the mean formula; a wide duct tends
    /// to plane Poiseuille flow, `G a^2 / (3 mu)` mean and `G a^2 / (2 mu)` at the centre.
    #[test]
    fn profile_mean_and_plane_limit() {
        let (hy, hz) = (0.09, 0.13);
        let n = 120;
        let mut s = 0.0;
        for i in 0..n {
            for j in 0..n {
                let y = -hy + (i as f64 + 0.5) * 2.0 * hy / n as f64;
                let z = -hz + (j as f64 + 0.5) * 2.0 * hz / n as f64;
                s += duct_velocity(2.0, hy, hz, y, z).unwrap();
            }
        }
        let mean = s / (n * n) as f64;
        let k = duct_mean_coefficient(hy, hz).unwrap();
        assert!((mean / (2.0 * k * hy * hy) - 1.0).abs() < 1e-3, "{mean}");
        let k_wide = duct_mean_coefficient(1.0, 1e3).unwrap();
        assert!((k_wide - 1.0 / 3.0).abs() < 1e-3, "{k_wide}");
        let u0 = duct_velocity(1.0, 1.0, 1e3, 0.0, 0.0).unwrap();
        assert!((u0 - 0.5).abs() < 1e-8, "{u0}");
        // the same duct turned: same mean, same profile transposed
        let k_t = duct_mean_coefficient(hz, hy).unwrap();
        assert_eq!(k, k_t);
        let f = body_force_for_mean_velocity(0.045, 1000.0, 1.0, hy, hz).unwrap();
        assert!((f * 1000.0 * k * hy * hy / 1.0 - 0.045).abs() < 1e-15);
    }

    #[test]
    fn bad_input_names_the_field() {
        let e = duct_mean_coefficient(0.0, 1.0).unwrap_err().to_string();
        assert!(e.contains("half_y"), "{e}");
        let e = body_force_for_mean_velocity(f64::NAN, 1000.0, 1.0, 0.1, 0.1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("mean_velocity"), "{e}");
    }
}
