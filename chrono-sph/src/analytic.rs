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

/// Viscous damping ratio `zeta = sigma / omega_1` of the first sloshing mode of a
/// quasi-2D rectangular tank (length `a`, depth `h`, m; no side walls: a slab of unit
/// breadth, as in the periodic-slab cases) filled with a liquid of kinematic viscosity
/// `nu` (m^2/s), `g` in m/s^2. The free amplitude decays as `exp(-zeta omega_1 t)`.
///
/// Two parts, both from the energy method of linear theory (time-averaged dissipation
/// over twice the mode's mean energy, `zeta = D / (2 omega E)`):
///
/// - the laminar Stokes layers on the wetted walls (the boundary-layer damping of Case
///   and Parkinson 1957, J. Fluid Mech. 2, 172-184, for a cylinder; Keulegan 1959,
///   J. Fluid Mech. 6, 33-50, for rectangular basins; Miles 1967, Proc. R. Soc. A 297,
///   459-475, for any basin): a wall under the inviscid slip velocity `U cos(omega t)`
///   dissipates `rho U^2 sqrt(nu omega / 2) / 2` per unit area (time average). With the
///   mode `phi = cos(k x) cosh(k z') cos(omega t)` (`z'` from the floor, `k = pi / a`)
///   the floor and the two end walls give, per unit breadth,
///
///   ```text
///   zeta_bl = sqrt(nu / (2 omega_1)) / a * (1 + (pi - 2 k h) / sinh(2 k h))
///   ```
///
///   (our evaluation of the integral for the slab: floor `a/2`, end walls
///   `sinh(2kh)/(2k) - h` for the squared slip velocity over `k^2`, energy
///   `a sinh(2kh) / (8 k)` in the same units; the side-wall terms of Keulegan's and
///   Miles' three-dimensional basins are absent in a slab);
/// - the interior dissipation of the potential flow, `zeta_int = 2 nu k^2 / omega_1`
///   (Lamb, *Hydrodynamics*, 6th ed. 1932, art. 348: amplitude decay rate `2 nu k^2`).
///
/// Returns `zeta_bl + zeta_int` (dimensionless). Water in a 0.4-1 m tank: ~5e-4.
pub fn sloshing_damping_ratio(a: f64, h: f64, nu: f64, g: f64) -> f64 {
    let k = PI / a;
    let omega = sloshing_mode(1, a, h, g);
    let s = (2.0 * k * h).sinh();
    let boundary = (nu / (2.0 * omega)).sqrt() / a * (1.0 + (PI - 2.0 * k * h) / s);
    boundary + 2.0 * nu * k * k / omega
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

    #[test]
    fn sloshing_damping_matches_the_hand_computed_number() {
        // a = 0.8 m, h = 0.3 m, nu = 1e-6 m^2/s, g = 9.81: k = pi/0.8 = 3.926991 1/m,
        // omega_1 = sqrt(9.81 k tanh(1.178097)) = 5.643883 rad/s, 2kh = 2.356194,
        // sinh(2kh) = 5.227971; sqrt(nu / (2 omega_1)) = 2.976409e-4 m;
        // zeta_bl = 2.976409e-4 / 0.8 * (1 + 0.785398 / 5.227971) = 4.279477e-4;
        // zeta_int = 2e-6 k^2 / omega_1 = 5.464769e-6; sum 4.334125e-4.
        let z = sloshing_damping_ratio(0.8, 0.3, 1e-6, 9.81);
        assert!((z / 4.334125e-4 - 1.0).abs() < 1e-5, "{z}");
        // deep-water limit: the end walls dominate, zeta_bl -> sqrt(nu / (2 omega)) / a
        let (a, g, nu) = (0.5, 9.81, 1e-6);
        let w = (PI * g / a).sqrt();
        let deep = sloshing_damping_ratio(a, 10.0, nu, g);
        let expect = (nu / (2.0 * w)).sqrt() / a + 2.0 * nu * (PI / a).powi(2) / w;
        assert!((deep / expect - 1.0).abs() < 1e-9, "{deep} {expect}");
        // Stokes layers scale as sqrt(nu): four times the viscosity, about twice the damping
        let r = sloshing_damping_ratio(0.8, 0.3, 4e-6, 9.81) / z;
        assert!((r - 2.0).abs() < 0.03, "{r}");
    }
}
