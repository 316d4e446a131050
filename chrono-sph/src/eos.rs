//! The Tait equation of state and the choice of the artificial sound speed.
//!
//! Weakly compressible SPH replaces the incompressibility constraint by a stiff
//! barotropic law (Batchelor 1967; Monaghan 1994, 2005):
//!
//! ```text
//! p = c_s^2 rho_0 / gamma ((rho / rho_0)^gamma - 1)        (Pa)
//! ```
//!
//! with `gamma = 7` for water. The density fluctuation scales with the Mach number
//! squared, `|rho/rho_0 - 1| ~ M^2`, so `M = |v|_max / c_s <= 0.1` keeps it near 1 %.
//! When viscous stresses or body forces dominate (creeping flow), Morris, Fox and Zhu
//! (J. Comput. Phys. 136 (1997) 214-226, eq. 4.1-4.3) ask in addition
//! `c_s^2 >= nu v / (L delta)` and `c_s^2 >= F L / delta`; [`sound_speed_for`] returns
//! the largest of the three.

use crate::error::{Result, SphError, positive};

/// The Tait equation of state `p(rho) = B ((rho/rho_0)^gamma - 1)`, `B = c_s^2 rho_0 / gamma`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tait {
    /// Reference density `rho_0`, kg/m^3.
    pub rho0: f64,
    /// Exponent `gamma` (7 for water).
    pub gamma: f64,
    /// Artificial sound speed `c_s`, m/s.
    pub sound_speed: f64,
    b: f64,
    inv_rho0: f64,
}

impl Tait {
    /// A Tait law; all arguments finite and positive.
    pub fn new(rho0: f64, gamma: f64, sound_speed: f64) -> Result<Self> {
        positive("settings.rho0", rho0)?;
        positive("settings.gamma", gamma)?;
        positive("settings.sound_speed", sound_speed)?;
        Ok(Self {
            rho0,
            gamma,
            sound_speed,
            b: sound_speed * sound_speed * rho0 / gamma,
            inv_rho0: 1.0 / rho0,
        })
    }

    /// Pressure `p(rho)`, Pa.
    #[inline]
    pub fn pressure(&self, rho: f64) -> f64 {
        let r = rho * self.inv_rho0;
        let p = if self.gamma == 7.0 {
            let r2 = r * r;
            r2 * r2 * r2 * r
        } else {
            r.powf(self.gamma)
        };
        self.b * (p - 1.0)
    }

    /// The inverse law `rho(p) = rho_0 (1 + p / B)^(1/gamma)`, kg/m^3 (for `p > -B`;
    /// lower pressures give a tiny positive density).
    #[inline]
    pub fn density(&self, p: f64) -> f64 {
        let t = (1.0 + p / self.b).max(1e-6);
        self.rho0 * t.powf(1.0 / self.gamma)
    }
}

impl Tait {
    /// The density at `depth` (m) below a free surface at rest under gravity `g` (m/s^2),
    /// in exact compressible hydrostatic balance `dp/dz = -rho(p) g`, kg/m^3. Integrating
    /// `dp / rho(p) = g d(depth)` with the Tait law from `p = 0` at the surface gives
    ///
    /// ```text
    /// rho = rho_0 (1 + (gamma - 1)/gamma rho_0 g depth / B)^(1/(gamma - 1)),   B = c_s^2 rho_0 / gamma
    /// ```
    ///
    /// (`p = rho_0 g depth` to first order). Negative depths give 0 pressure (`rho_0`).
    pub fn hydrostatic_density(&self, g: f64, depth: f64) -> f64 {
        let d = depth.max(0.0);
        let k = (self.gamma - 1.0) / self.gamma * self.rho0 * g * d / self.b;
        if self.gamma == 1.0 {
            // isothermal limit: rho = rho_0 exp(rho_0 g depth / B)
            return self.rho0 * (self.rho0 * g * d / self.b).exp();
        }
        self.rho0 * (1.0 + k).powf(1.0 / (self.gamma - 1.0))
    }
}

/// The sound speed for an expected maximum speed `v_max` (m/s), a length scale `length`
/// (m), a body-force acceleration `force` (m/s^2) and a kinematic viscosity `nu` (m^2/s),
/// so that the relative density variation stays near `delta` (e.g. 0.01):
/// `c_s = sqrt(max(v^2/delta, nu v/(L delta), F L/delta))` (Morris et al. 1997; with
/// `delta = 0.01` the first term is the usual `c_s = 10 v_max`, Monaghan 1994).
pub fn sound_speed_for(v_max: f64, length: f64, force: f64, nu: f64, delta: f64) -> Result<f64> {
    positive("delta", delta)?;
    positive("length", length)?;
    for (f, v) in [("v_max", v_max), ("force", force), ("nu", nu)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(SphError::invalid(f, v, "must be finite and >= 0"));
        }
    }
    let c2 = (v_max * v_max / delta)
        .max(nu * v_max / (length * delta))
        .max(force * length / delta);
    positive("sound speed (all of v_max, force are 0)", c2.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tait_round_trips_and_is_zero_at_rest() {
        let eos = Tait::new(1000.0, 7.0, 20.0).unwrap();
        assert_eq!(eos.pressure(1000.0), 0.0);
        for p in [-1e4, -10.0, 0.0, 5.0, 1e3, 4e4] {
            let rho = eos.density(p);
            assert!(
                (eos.pressure(rho) - p).abs() < 1e-9 * (1.0 + p.abs()),
                "{p}"
            );
        }
        // small compressions: dp/drho = c_s^2
        let d = 1e-4;
        let slope = (eos.pressure(1000.0 + d) - eos.pressure(1000.0 - d)) / (2.0 * d);
        assert!((slope - 400.0).abs() < 1e-6);
        let eos5 = Tait::new(1000.0, 5.0, 20.0).unwrap();
        assert!((eos5.pressure(eos5.density(123.0)) - 123.0).abs() < 1e-9);
    }

    #[test]
    fn hydrostatic_density_satisfies_dp_dz_equals_rho_g() {
        let eos = Tait::new(1000.0, 7.0, 28.0).unwrap();
        let g = -chrono_core::math::GRAVITY.z;
        assert_eq!(eos.hydrostatic_density(g, 0.0), 1000.0);
        for depth in [0.05, 0.4, 3.0] {
            let e = 1e-5;
            let dp = eos.pressure(eos.hydrostatic_density(g, depth + e))
                - eos.pressure(eos.hydrostatic_density(g, depth - e));
            let rho = eos.hydrostatic_density(g, depth);
            assert!((dp / (2.0 * e) / (rho * g) - 1.0).abs() < 1e-7, "{depth}");
        }
    }

    #[test]
    fn sound_speed_follows_the_largest_criterion() {
        assert!((sound_speed_for(2.0, 1.0, 0.0, 0.0, 0.01).unwrap() - 20.0).abs() < 1e-12);
        // Morris Poiseuille: F L / delta dominates
        let c = sound_speed_for(2.5e-5, 1e-3, 2e-4, 1e-6, 0.01).unwrap();
        assert!((c - (2e-4f64 * 1e-3 / 0.01).sqrt()).abs() < 1e-12);
        assert!(sound_speed_for(0.0, 1.0, 0.0, 0.0, 0.01).is_err());
        let e = Tait::new(1000.0, 7.0, -1.0).unwrap_err();
        assert!(e.to_string().contains("settings.sound_speed"));
    }
}
