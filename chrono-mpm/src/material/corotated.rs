//! Fixed-corotated elasticity (Stomakhin et al., "Energetically consistent invertible
//! elasticity", SCA 2012) with optional snow plasticity and hardening (Stomakhin, Schroeder,
//! Chai, Teran & Selle, "A material point method for snow simulation", ACM TOG 32(4), 2013).
//!
//! ```text
//! Psi(F_E, F_P) = mu(F_P) |F_E - R_E|^2 + lambda(F_P)/2 (J_E - 1)^2
//! tau = P F_E^T = 2 mu (F_E - R_E) F_E^T + lambda (J_E - 1) J_E 1
//! mu(F_P) = mu0 exp(xi (1 - J_P)),  lambda(F_P) = lambda0 exp(xi (1 - J_P))
//! ```
//!
//! with `R_E` the polar rotation of `F_E` and `J = det F`. Snow plasticity clamps the
//! singular values of `F_E` to `[1 - theta_c, 1 + theta_s]` (critical compression and
//! stretch); what is clamped off moves into `F_P`. Stomakhin 2013's values:
//! `theta_c = 2.5e-2`, `theta_s = 7.5e-3`, `xi = 10`, `E0 = 1.4e5 Pa`, `nu = 0.2`,
//! `rho = 400 kg/m^3` ([`SnowHardening::stomakhin_2013`]). The seed's mud uses
//! `theta_c = theta_s = 2.5e-2` and names no `xi`; [`SnowHardening::seed_mud`] takes
//! Stomakhin's `xi = 10` for it.

use nalgebra::{Matrix3, Vector3};

use super::{Elasticity, SignedSvd};
use crate::error::{Result, invalid, positive};

/// Snow plasticity: critical compression and stretch and the hardening coefficient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnowHardening {
    /// Critical compression `theta_c` (> 0, < 1), -.
    pub theta_c: f64,
    /// Critical stretch `theta_s` (> 0), -.
    pub theta_s: f64,
    /// Hardening coefficient `xi` (>= 0), -.
    pub xi: f64,
}

impl SnowHardening {
    /// Checked parameters; an error names the field (`snow.theta_c`, ...).
    pub fn new(theta_c: f64, theta_s: f64, xi: f64) -> Result<Self> {
        positive("snow.theta_c", theta_c)?;
        if theta_c >= 1.0 {
            return Err(invalid("snow.theta_c", theta_c, "must be < 1"));
        }
        positive("snow.theta_s", theta_s)?;
        if !(xi.is_finite() && xi >= 0.0) {
            return Err(invalid("snow.xi", xi, "must be finite and >= 0"));
        }
        Ok(Self {
            theta_c,
            theta_s,
            xi,
        })
    }

    /// Stomakhin et al. 2013's reference snow: `theta_c 2.5e-2`, `theta_s 7.5e-3`, `xi 10`.
    pub fn stomakhin_2013() -> Self {
        Self {
            theta_c: 2.5e-2,
            theta_s: 7.5e-3,
            xi: 10.0,
        }
    }

    /// The seed's mud: `theta_c = theta_s = 2.5e-2`; the seed names no `xi`, this takes
    /// Stomakhin 2013's `xi = 10`.
    pub fn seed_mud() -> Self {
        Self {
            theta_c: 2.5e-2,
            theta_s: 2.5e-2,
            xi: 10.0,
        }
    }

    /// The hardening factor `exp(xi (1 - J_P))`.
    #[inline]
    pub fn factor(&self, fp: &Matrix3<f64>) -> f64 {
        (self.xi * (1.0 - fp.determinant())).exp()
    }

    /// Clamp of one singular value to `[1 - theta_c, 1 + theta_s]`.
    #[inline]
    pub fn clamp(&self, s: f64) -> f64 {
        s.clamp(1.0 - self.theta_c, 1.0 + self.theta_s)
    }
}

/// Fixed-corotated elasticity, with snow plasticity when `snow` is set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedCorotated {
    /// Moduli at `J_P = 1`.
    pub elastic: Elasticity,
    /// Snow plasticity and hardening; `None` for a purely elastic material.
    pub snow: Option<SnowHardening>,
}

impl FixedCorotated {
    /// Elastic material; an error names `material.young` or `material.poisson`.
    pub fn elastic(young: f64, poisson: f64) -> Result<Self> {
        Ok(Self {
            elastic: Elasticity::new("material", young, poisson)?,
            snow: None,
        })
    }

    /// Snow: elasticity with plasticity and hardening.
    pub fn snow(young: f64, poisson: f64, snow: SnowHardening) -> Result<Self> {
        // Re-check: the struct's fields are public.
        let snow = SnowHardening::new(snow.theta_c, snow.theta_s, snow.xi)?;
        Ok(Self {
            elastic: Elasticity::new("material", young, poisson)?,
            snow: Some(snow),
        })
    }

    /// `(mu, lambda)` at the plastic state `fp`, Pa.
    #[inline]
    pub fn lame(&self, fp: &Matrix3<f64>) -> (f64, f64) {
        let h = self.snow.map_or(1.0, |s| s.factor(fp));
        (self.elastic.mu * h, self.elastic.lambda * h)
    }

    /// Kirchhoff stress, Pa (see the module documentation).
    #[inline]
    pub fn kirchhoff(&self, fe: &Matrix3<f64>, fp: &Matrix3<f64>) -> Matrix3<f64> {
        let (mu, lambda) = self.lame(fp);
        let Some(svd) = SignedSvd::new(fe) else {
            return Matrix3::repeat(f64::NAN);
        };
        let r = svd.u * svd.v.transpose();
        let j = svd.s.product();
        (fe - r) * fe.transpose() * (2.0 * mu) + Matrix3::identity() * (lambda * (j - 1.0) * j)
    }

    /// The axial Cauchy stress `sigma_zz` (Pa, negative in compression) of the material in
    /// uniaxial strain `F = diag(1, 1, s)` reached monotonically from `F = 1` (the
    /// confined compaction of a column, `s = 1 - strain`).
    ///
    /// Derivation. The elastic part is `F_E = diag(1, 1, s_E)`, so `R_E = 1`, `J_E = s_E`,
    /// and the Kirchhoff stress of the module documentation has
    /// `tau_zz = 2 mu (s_E - 1) s_E + lambda (s_E - 1) s_E = (lambda + 2 mu)(s_E - 1) s_E`
    /// (the lateral singular values stay 1, inside the clamp). The Cauchy stress is
    /// `sigma = tau / J` with `J = det F = s`:
    ///
    /// ```text
    /// sigma_zz = (lambda + 2 mu) (s_E - 1) s_E / s
    /// ```
    ///
    /// - elastic (`s >= 1 - theta_c`, or no snow): `s_E = s`, `J_P = 1`:
    ///   `sigma_zz = (lambda0 + 2 mu0)(s - 1)`, linear in the strain for any magnitude;
    /// - compaction (`s < 1 - theta_c`): the clamp holds `s_E = 1 - theta_c`, the rest goes
    ///   into `F_P = diag(1, 1, J_P)`, `J_P = s / (1 - theta_c)`, and both moduli carry the
    ///   hardening `h = exp(xi (1 - J_P))`:
    ///   `sigma_zz = -h (lambda0 + 2 mu0) theta_c (1 - theta_c) / s
    ///             = -exp(xi (1 - J_P)) (lambda0 + 2 mu0) theta_c / J_P`.
    ///
    /// The plastic branch rises monotonically with compaction (`d/dJ_P` of
    /// `exp(xi (1 - J_P)) / J_P` is negative), so the quasi-static column is uniform. For
    /// Stomakhin 2013's snow (`E0 1.4e5 Pa`, `nu 0.2`, `theta_c 2.5e-2`, `xi 10`) the
    /// elastic limit is `-3.9 kPa` at 2.5 % strain and the stress at 30 % strain `-91 kPa`.
    /// `s` must be in (0, 1].
    pub fn uniaxial_strain_stress(&self, s: f64) -> f64 {
        let (se, h) = match self.snow {
            Some(snow) if s < 1.0 - snow.theta_c => {
                let jp = s / (1.0 - snow.theta_c);
                (1.0 - snow.theta_c, (snow.xi * (1.0 - jp)).exp())
            }
            _ => (s, 1.0),
        };
        h * self.elastic.p_modulus() * (se - 1.0) * se / s
    }

    /// Energy per reference volume, J/m^3.
    pub fn energy_density(&self, fe: &Matrix3<f64>, fp: &Matrix3<f64>) -> f64 {
        let (mu, lambda) = self.lame(fp);
        let Some(svd) = SignedSvd::new(fe) else {
            return f64::NAN;
        };
        let d = svd.s - Vector3::repeat(1.0);
        mu * d.norm_squared() + 0.5 * lambda * (svd.s.product() - 1.0).powi(2)
    }

    /// The snow return mapping (identity without `snow`).
    pub fn project(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        let Some(snow) = self.snow else {
            return fe_trial
                .iter()
                .all(|x| x.is_finite())
                .then_some((*fe_trial, *fp));
        };
        let svd = SignedSvd::new(fe_trial)?;
        let s_new = svd.s.map(|s| snow.clamp(s));
        if s_new == svd.s {
            return Some((*fe_trial, *fp));
        }
        Some((svd.compose(&s_new), svd.plastic_update(&s_new, fp)))
    }

    /// P-wave modulus with hardening, Pa.
    pub fn p_modulus(&self, fp: &Matrix3<f64>) -> f64 {
        let (mu, lambda) = self.lame(fp);
        lambda + 2.0 * mu
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;
    use proptest::prelude::*;

    fn f_of(angles: [f64; 6], s: [f64; 3]) -> Matrix3<f64> {
        let r1 = Rotation3::from_euler_angles(angles[0], angles[1], angles[2]).into_inner();
        let r2 = Rotation3::from_euler_angles(angles[3], angles[4], angles[5]).into_inner();
        r1 * Matrix3::from_diagonal(&Vector3::from(s)) * r2
    }

    #[test]
    fn stress_is_the_derivative_of_the_energy() {
        // tau = dPsi/dF F^T: check P = dPsi/dF by central differences.
        let m = FixedCorotated::elastic(1e6, 0.3).unwrap();
        let fe = f_of([0.1, 0.2, -0.3, 0.5, -0.2, 0.1], [1.1, 0.95, 0.9]);
        let fp = Matrix3::identity();
        let p = m.kirchhoff(&fe, &fp) * fe.transpose().try_inverse().unwrap();
        let e = 1e-6;
        for i in 0..3 {
            for j in 0..3 {
                let (mut a, mut b) = (fe, fe);
                a[(i, j)] += e;
                b[(i, j)] -= e;
                let fd = (m.energy_density(&a, &fp) - m.energy_density(&b, &fp)) / (2.0 * e);
                assert!((fd - p[(i, j)]).abs() < 1e-3 * (1.0 + fd.abs()), "{i}{j}");
            }
        }
    }

    #[test]
    fn bad_snow_parameters_name_the_field() {
        let e = SnowHardening::new(0.0, 7.5e-3, 10.0).unwrap_err();
        assert!(e.to_string().contains("snow.theta_c"), "{e}");
        let e = SnowHardening::new(2.5e-2, -1.0, 10.0).unwrap_err();
        assert!(e.to_string().contains("snow.theta_s"), "{e}");
        let e = SnowHardening::new(2.5e-2, 7.5e-3, f64::NAN).unwrap_err();
        assert!(e.to_string().contains("snow.xi"), "{e}");
        let bad = SnowHardening {
            theta_c: -1.0,
            ..SnowHardening::stomakhin_2013()
        };
        let e = FixedCorotated::snow(1.4e5, 0.2, bad).unwrap_err();
        assert!(e.to_string().contains("snow.theta_c"), "{e}");
        let e = FixedCorotated::elastic(-1.4e5, 0.2).unwrap_err();
        assert!(e.to_string().contains("material.young"), "{e}");
    }

    #[test]
    fn hardening_factor_follows_jp() {
        let s = SnowHardening::stomakhin_2013();
        let fp = Matrix3::from_diagonal(&Vector3::new(0.9, 1.0, 1.0));
        assert!((s.factor(&fp) - (10.0f64 * 0.1).exp()).abs() < 1e-12);
    }

    fn uniaxial_analytic(m: &FixedCorotated, s: f64) -> f64 {
        m.uniaxial_strain_stress(s)
    }

    #[test]
    fn uniaxial_compaction_follows_the_analytic_curve() {
        // Stomakhin 2013's snow compacted in 2000 increments of the velocity gradient
        // (as MPM's F_E <- (I + dt grad v) F_E) to 30 % strain, against the closed form.
        let m = FixedCorotated::snow(1.4e5, 0.2, SnowHardening::stomakhin_2013()).unwrap();
        let (mut fe, mut fp) = (Matrix3::identity(), Matrix3::identity());
        let n = 2000;
        let rate = 0.3 / n as f64;
        let mut s = 1.0;
        for k in 1..=n {
            // The total stretch goes s -> s - rate: grad v dt = -rate / s on zz.
            let mut l = Matrix3::identity();
            l[(2, 2)] = 1.0 - rate / s;
            s -= rate;
            let (a, b) = m.project(&(l * fe), &fp).unwrap();
            fe = a;
            fp = b;
            let jp: f64 = fp.determinant();
            let sigma = m.kirchhoff(&fe, &fp)[(2, 2)] / (fe.determinant() * jp);
            let exact = uniaxial_analytic(&m, s);
            assert!(
                (sigma - exact).abs() <= 1e-9 * exact.abs().max(1.0),
                "step {k}, s {s}: {sigma} vs {exact}"
            );
        }
        // Past the elastic limit the stress grows only by the hardening exp(xi (1 - J_P)),
        // 16.8 at 30 % strain: the compressed snow carries over 10 times its elastic limit.
        let limit = uniaxial_analytic(&m, 1.0 - 2.5e-2);
        assert!(uniaxial_analytic(&m, s).abs() > 10.0 * limit.abs());
    }

    proptest! {
        #[test]
        fn snow_return_lands_inside_and_is_idempotent(
            a in prop::array::uniform6(-3.0f64..3.0),
            s in prop::array::uniform3(0.6f64..1.4),
            fp_s in prop::array::uniform3(0.8f64..1.2),
        ) {
            let snow = SnowHardening::stomakhin_2013();
            let m = FixedCorotated::snow(1.4e5, 0.2, snow).unwrap();
            let fe = f_of(a, s);
            let fp0 = Matrix3::from_diagonal(&Vector3::from(fp_s));
            let (fe1, fp1) = m.project(&fe, &fp0).unwrap();
            // On or inside the admissible box of singular values.
            let sv = SignedSvd::new(&fe1).unwrap().s;
            for k in 0..3 {
                prop_assert!(sv[k] >= 1.0 - snow.theta_c - 1e-12);
                prop_assert!(sv[k] <= 1.0 + snow.theta_s + 1e-12);
            }
            // The total deformation is kept.
            prop_assert!((fe1 * fp1 - fe * fp0).norm() < 1e-10);
            // Idempotent.
            let (fe2, fp2) = m.project(&fe1, &fp1).unwrap();
            prop_assert!((fe2 - fe1).norm() < 1e-10);
            prop_assert!((fp2 - fp1).norm() < 1e-10);
        }
    }
}
