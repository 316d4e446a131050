//! Analytic references used by the validation cases and tests.

use std::f64::consts::PI;

/// Start-up plane Poiseuille flow between plates at `y = 0` and `y = L` driven by a body
/// force `F` (m/s^2) from rest (Morris, Fox and Zhu, J. Comput. Phys. 136 (1997) 214-226,
/// eq. 5.1, written with a positive steady profile):
///
/// ```text
/// v(y, t) = F / (2 nu) y (L - y)
///         - sum_{n >= 0} 4 F L^2 / (nu pi^3 (2n+1)^3) sin((2n+1) pi y / L) exp(-(2n+1)^2 pi^2 nu t / L^2)
/// ```
///
/// `terms` terms of the series (50 is plenty for `t > 0`). Units: m/s.
pub fn poiseuille_startup(y: f64, t: f64, l: f64, nu: f64, force: f64, terms: usize) -> f64 {
    let steady = force / (2.0 * nu) * y * (l - y);
    let mut s = 0.0;
    for n in 0..terms {
        let k = (2 * n + 1) as f64;
        s += 4.0 * force * l * l / (nu * PI.powi(3) * k.powi(3))
            * (k * PI * y / l).sin()
            * (-k * k * PI * PI * nu * t / (l * l)).exp();
    }
    steady - s
}

/// Natural frequency `omega_n` (rad/s) of the antisymmetric sloshing mode `n >= 1` in a
/// rectangular tank of length `a` filled to depth `h` (linear potential theory; seed
/// slides, "Sloshing Validation"; Abramson 1966, NASA SP-106):
/// `omega_n^2 = (2n-1) pi g / a tanh((2n-1) pi h / a)`.
pub fn sloshing_mode(n: usize, a: f64, h: f64, g: f64) -> f64 {
    let k = (2 * n - 1) as f64 * PI / a;
    (k * g * (k * h).tanh()).sqrt()
}

/// The amplitude of the horizontal fluid force in a tank oscillated as
/// `x = X_0 sin(Omega t)` (steady state, linear theory), over the rigid-mass force
/// `Omega^2 X_0 m_l` (seed slides, "Sloshing Validation"):
///
/// ```text
/// F_x0 / (Omega^2 X_0 m_l) = 1 + 8 a/h sum_{n=1}^{N} tanh((2n-1) pi h/a) / ((2n-1)^3 pi^3)
///                                 Omega^2 / (omega_n^2 - Omega^2)
/// ```
///
/// Signed: the fluid force is `-ratio Omega^2 X_0 m_l sin(Omega t)`, in phase with the
/// tank acceleration when positive.
pub fn sloshing_force_ratio(a: f64, h: f64, omega: f64, g: f64, modes: usize) -> f64 {
    let mut s = 0.0;
    for n in 1..=modes {
        let k = (2 * n - 1) as f64;
        let wn = sloshing_mode(n, a, h, g);
        s += (k * PI * h / a).tanh() / (k.powi(3) * PI.powi(3)) * omega * omega
            / (wn * wn - omega * omega);
    }
    1.0 + 8.0 * a / h * s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poiseuille_series_starts_at_rest_and_reaches_the_parabola() {
        let (l, nu, f) = (1e-3, 1e-6, 2e-4);
        for i in 1..10 {
            let y = l * i as f64 / 10.0;
            assert!(poiseuille_startup(y, 0.0, l, nu, f, 2000).abs() < 1e-3 * 2.5e-5);
            let steady = f / (2.0 * nu) * y * (l - y);
            assert!((poiseuille_startup(y, 10.0, l, nu, f, 50) - steady).abs() < 1e-12);
        }
        // Centre-line velocity at tau = 0.1125 from the reference table: 0.65999 v0.
        let v0 = f * l * l / (8.0 * nu);
        let v = poiseuille_startup(0.5 * l, 0.1125, l, nu, f, 50) / v0;
        assert!((v - 0.65999).abs() < 1e-4, "{v}");
    }

    #[test]
    fn sloshing_ratio_is_one_at_low_frequency_and_changes_sign_at_resonance() {
        let (a, h, g) = (1.0, 0.5, -chrono_core::math::GRAVITY.z);
        assert!((sloshing_force_ratio(a, h, 1e-4, g, 20) - 1.0).abs() < 1e-6);
        let w1 = sloshing_mode(1, a, h, g);
        assert!(sloshing_force_ratio(a, h, 0.99 * w1, g, 20) > 10.0);
        assert!(sloshing_force_ratio(a, h, 1.01 * w1, g, 20) < -10.0);
        // deep-water limit: omega_1^2 -> pi g / a
        assert!((sloshing_mode(1, 1.0, 10.0, g).powi(2) - PI * g).abs() < 1e-9);
    }
}
