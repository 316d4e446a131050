//! Drucker–Prager sand with cohesion, return mapping in Hencky strain (Klar, Gast, Pradhana,
//! Fu, Schroeder, Jiang & Teran, "Drucker-Prager elastoplasticity for sand animation",
//! ACM TOG 35(4), 2016, sec. 7.3), extended with a cohesion that moves the cone's apex.
//!
//! With the Kirchhoff stress `tau` (Pa), its deviator `s` and the yield function
//!
//! ```text
//! f(tau) = |s| + alpha tr(tau) - kappa <= 0
//! alpha = 2 sqrt(2/3) sin(phi) / (3 - sin(phi))
//! kappa = 2 sqrt(6) c cos(phi) / (3 - sin(phi))
//! ```
//!
//! the cone circumscribes the Mohr–Coulomb hexagon at its compressive meridian (friction
//! angle `phi`, cohesion `c` in Pa); `alpha` is Klar's eq. 27 and `c = 0` is Klar's sand.
//! The flow is non-associated (no dilatancy, as Klar's): the trial Hencky strain `eps`
//! keeps its trace and its deviator is scaled back radially onto the cone; a trial state
//! beyond the apex (tension past `kappa / alpha`) goes to the apex.

use nalgebra::{Matrix3, Vector3};

use super::Elasticity;
use super::hencky::{principal_stress, split};
use crate::error::{Result, invalid};

/// Drucker–Prager sand with cohesion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DruckerPrager {
    /// Elastic moduli (Hencky elasticity).
    pub elastic: Elasticity,
    /// Friction angle `phi`, rad.
    pub friction_angle: f64,
    /// Cohesion `c`, Pa.
    pub cohesion: f64,
    /// `alpha` of the yield function, -.
    pub alpha: f64,
    /// `kappa` of the yield function, Pa.
    pub kappa: f64,
    /// `beta` of the plastic potential `g = |s| + beta tr(tau)`: 0 is the non-dilatant
    /// flow (Klar's, the default), `alpha` the associated one
    /// ([`DruckerPrager::associated`]).
    pub dilatancy: f64,
    /// The rate dependence of the friction (`mu(I)`, [`DruckerPrager::with_mu_i`]); `None`:
    /// rate-independent.
    pub mu_i: Option<MuI>,
}

/// The `mu(I)` rheology of dense granular flow (GDR MiDi, Eur. Phys. J. E 14, 2004; Jop,
/// Forterre & Pouliquen, Nature 441, 2006):
///
/// ```text
/// mu(I) = mu_s + (mu_2 - mu_s) I / (I0 + I),   I = gamma_dot d / sqrt(p / rho_s)
/// ```
///
/// with `gamma_dot = sqrt(2 D:D)` the shear rate (1/s), `d` the grain diameter (m), `p`
/// the pressure (Pa) and `rho_s` the grains' density (kg/m^3). Here `mu_s` is the
/// quasi-static friction of the cone (the plane-strain `sin(phi)`, see
/// [`DruckerPrager::with_mu_i`]) and `mu_2 - mu_s` is [`MuI::delta_mu`]. Jop et al.'s
/// glass beads: `mu_2 - mu_s` = 0.26, `I0` = 0.279, `d` = 0.53 mm, `rho_s` = 2450.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MuI {
    /// `mu_2 - mu_s`, -, >= 0.
    pub delta_mu: f64,
    /// `I0`, -, > 0.
    pub i0: f64,
    /// Grain diameter `d`, m, > 0.
    pub grain_diameter: f64,
    /// Grain density `rho_s`, kg/m^3, > 0.
    pub grain_density: f64,
}

impl MuI {
    /// Jop, Forterre & Pouliquen (2006)'s glass beads (`delta_mu` 0.26, `I0` 0.279,
    /// `d` 0.53 mm, `rho_s` 2450 kg/m^3).
    pub fn jop_2006() -> Self {
        Self {
            delta_mu: 0.26,
            i0: 0.279,
            grain_diameter: 0.53e-3,
            grain_density: 2450.0,
        }
    }
}

impl DruckerPrager {
    /// Sand of friction angle `friction_angle_deg` (in [0, 90) degrees) and `cohesion`
    /// (>= 0 Pa; > 0 when the friction angle is 0). Errors name the field.
    pub fn new(young: f64, poisson: f64, friction_angle_deg: f64, cohesion: f64) -> Result<Self> {
        let elastic = Elasticity::new("material", young, poisson)?;
        if !(friction_angle_deg.is_finite() && (0.0..90.0).contains(&friction_angle_deg)) {
            return Err(invalid(
                "material.friction_angle_deg",
                friction_angle_deg,
                "must lie in [0, 90)",
            ));
        }
        if !(cohesion.is_finite() && cohesion >= 0.0) {
            return Err(invalid(
                "material.cohesion",
                cohesion,
                "must be finite and >= 0",
            ));
        }
        if friction_angle_deg == 0.0 && cohesion == 0.0 {
            return Err(invalid(
                "material.cohesion",
                cohesion,
                "must be > 0 when the friction angle is 0 (the material would have no strength)",
            ));
        }
        let phi = friction_angle_deg.to_radians();
        let (sin, cos) = phi.sin_cos();
        Ok(Self {
            elastic,
            friction_angle: phi,
            cohesion,
            alpha: 2.0 * (2.0f64 / 3.0).sqrt() * sin / (3.0 - sin),
            kappa: 2.0 * 6.0f64.sqrt() * cohesion * cos / (3.0 - sin),
            dilatancy: 0.0,
            mu_i: None,
        })
    }

    /// The cone matched to Mohr–Coulomb (friction angle `friction_angle_deg`, cohesion
    /// `cohesion`, Pa) in plane strain with this model's flow rule: the radial return
    /// flows along the deviator `s`, so at steady plastic flow with no out-of-plane strain
    /// `s_zz = 0`, the out-of-plane stress is the mean of the in-plane ones, and with
    /// `t = (sigma_1 - sigma_3)/2`, `p = (sigma_1 + sigma_3)/2` (tension positive) the
    /// cone reads `sqrt(2) t + 3 alpha p <= kappa`. Mohr–Coulomb's `t + p sin(phi) <= c
    /// cos(phi)` is the same line for
    ///
    /// ```text
    /// alpha = sqrt(2) sin(phi) / 3,   kappa = sqrt(2) c cos(phi)
    /// ```
    ///
    /// (the plane-strain match of a non-dilatant Drucker–Prager flow; e.g. de Souza Neto,
    /// Perić & Owen, "Computational Methods for Plasticity", Wiley 2008, sec. 6.4.2, which
    /// gives the associated match beside it). At `phi = 0` it is the von Mises cylinder of
    /// [`super::VonMises::from_undrained_strength`]. Errors as [`DruckerPrager::new`].
    pub fn plane_strain(
        young: f64,
        poisson: f64,
        friction_angle_deg: f64,
        cohesion: f64,
    ) -> Result<Self> {
        let mut m = Self::new(young, poisson, friction_angle_deg, cohesion)?;
        let (sin, cos) = m.friction_angle.sin_cos();
        m.alpha = 2.0f64.sqrt() * sin / 3.0;
        m.kappa = 2.0f64.sqrt() * cohesion * cos;
        Ok(m)
    }

    /// The same cone with the associated flow rule: the plastic strain increment normal to
    /// the cone, `d eps_p = dgamma (s/|s| + alpha I)` (dilatancy `beta = alpha`), returned
    /// in one step in Hencky strain:
    ///
    /// ```text
    /// dgamma = f(tau_trial) / (2 mu + 3 alpha beta (3 lambda + 2 mu))
    /// ```
    ///
    /// (the cone is linear in the principal stresses and the Hencky response linear, so the
    /// return is exact), to the apex when the deviator would change sign. A rigid-plastic
    /// Coulomb flow without dilatancy is ill-posed (Schaeffer, J. Differential Equations
    /// 66, 1987); the associated one is not.
    pub fn associated(mut self) -> Self {
        self.dilatancy = self.alpha;
        self
    }

    /// The same cone with a rate-dependent friction ([`MuI`]): the admissible deviator at
    /// pressure `p` grows from the cone's `|s| = kappa + 3 alpha p` (the quasi-static
    /// `mu_s`) by `3 alpha p (mu(I) - mu_s) / mu_s`, with `I` from the plastic shear rate
    /// of the step. Non-dilatant flow only. Errors name the field (`material.mu_i.*`).
    pub fn with_mu_i(mut self, mu_i: MuI) -> Result<Self> {
        let check = |name: &str, v: f64, zero_ok: bool| {
            if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
                Ok(())
            } else {
                Err(invalid(
                    &format!("material.mu_i.{name}"),
                    v,
                    if zero_ok {
                        "must be finite and >= 0"
                    } else {
                        "must be finite and > 0"
                    },
                ))
            }
        };
        check("delta_mu", mu_i.delta_mu, true)?;
        check("i0", mu_i.i0, false)?;
        check("grain_diameter", mu_i.grain_diameter, false)?;
        check("grain_density", mu_i.grain_density, false)?;
        if self.dilatancy != 0.0 {
            return Err(invalid(
                "material.mu_i",
                "associated flow",
                "mu(I) is implemented for the non-dilatant flow only",
            ));
        }
        self.mu_i = Some(mu_i);
        Ok(self)
    }

    /// The returned principal Hencky strains of trial strains `eps` over a step of `dt`
    /// seconds: [`DruckerPrager::return_strain`] when rate-independent; with [`MuI`] the
    /// radial return whose plastic deviatoric increment `Delta = |dev eps_p|` solves
    ///
    /// ```text
    /// |s_trial| - 2 mu_e Delta = k0 + B I / (I0 + I),   I = c Delta,
    /// k0 = kappa + 3 alpha p,   B = 3 alpha p delta_mu / mu_s,
    /// c = sqrt(2) d / (dt sqrt(p / rho_s))
    /// ```
    ///
    /// (`gamma_dot = sqrt(2) Delta / dt`; `mu_e` the shear modulus), a quadratic in
    /// `Delta` with one positive root (Dunatunga & Kamrin, J. Fluid Mech. 779, 2015,
    /// return the same rheology in their explicit MPM step).
    pub fn return_strain_rate(&self, eps: &Vector3<f64>, dt: f64) -> Vector3<f64> {
        let Some(mi) = self.mu_i else {
            return self.return_strain(eps);
        };
        let el = &self.elastic;
        let (dev, tr) = split(eps);
        let bulk3 = 3.0 * el.lambda + 2.0 * el.mu;
        let tr_tau = bulk3 * tr;
        let p = -tr_tau / 3.0;
        let k0 = self.kappa - self.alpha * tr_tau;
        if p <= 0.0 || self.alpha == 0.0 || dt.is_nan() || dt <= 0.0 {
            return self.return_strain(eps);
        }
        let s_norm = 2.0 * el.mu * dev.norm();
        let a = s_norm - k0;
        if a <= 0.0 {
            return *eps;
        }
        let g2 = 2.0 * el.mu;
        let delta = self.mu_i_plastic_strain(&mi, a, p, dt);
        dev * (1.0 - g2 * delta / s_norm) + Vector3::repeat(tr / 3.0)
    }

    /// The plastic deviatoric increment `Delta` of the `mu(I)` return (see
    /// [`DruckerPrager::return_strain_rate`]) for the excess `a = |s_trial| - k0 > 0` (Pa)
    /// at the Kirchhoff pressure `p > 0` (Pa) over `dt > 0` seconds.
    fn mu_i_plastic_strain(&self, mi: &MuI, a: f64, p: f64, dt: f64) -> f64 {
        let mu_s = 1.5 * self.alpha * 2.0f64.sqrt(); // sin(phi) of the plane-strain cone
        let b = 3.0 * self.alpha * p * mi.delta_mu / mu_s;
        let c = 2.0f64.sqrt() * mi.grain_diameter / (dt * (p / mi.grain_density).sqrt());
        let g2 = 2.0 * self.elastic.mu;
        // (a - g2 D)(I0 + c D) = b c D  ->  g2 c D^2 + (g2 I0 + (b - a) c) D - a I0 = 0.
        let qb = g2 * mi.i0 + (b - a) * c;
        let disc = (qb * qb + 4.0 * g2 * c * a * mi.i0).sqrt();
        if qb >= 0.0 {
            2.0 * a * mi.i0 / (qb + disc)
        } else {
            (disc - qb) / (2.0 * g2 * c)
        }
    }

    /// The split's return (`docs/mpm.md`, "The split"): the cone evaluated at the pressure
    /// `pressure` of the density rows (Pa, compression positive; the Cauchy pressure of
    /// [`crate::pressure::PressureRows::pressure`]) instead of the trace of the trial
    /// strain, which in the split carries no stress. With the Kirchhoff pressure
    /// `p = J max(pressure, 0)`, `J = exp(tr eps)`,
    ///
    /// ```text
    /// |s| <= k(p) = kappa + 3 alpha p      (the cone |s| + alpha tr(tau) <= kappa at tr(tau) = -3 p)
    /// ```
    ///
    /// and a trial deviator beyond it is scaled back radially onto it (`mu(I)`: the rate
    /// dependent `k` of [`DruckerPrager::return_strain_rate`]); the trace of `eps` is kept
    /// (the volume is the rows'). A row that holds no pressure (a slack surface row, a
    /// marker in tension) gives `p = 0`: cohesionless sand has no shear strength there
    /// (`s = 0`, the apex). Non-dilatant flow only (a dilatant flow would change the
    /// rows' rest volume; [`crate::MpmBody::set_pressure_rows`] refuses it).
    pub fn return_strain_at_pressure(
        &self,
        eps: &Vector3<f64>,
        pressure: f64,
        dt: f64,
    ) -> Vector3<f64> {
        let (dev, tr) = split(eps);
        let p = if pressure > 0.0 {
            pressure * tr.exp()
        } else {
            0.0
        };
        let g2 = 2.0 * self.elastic.mu;
        let s_norm = g2 * dev.norm();
        let k0 = self.kappa + 3.0 * self.alpha * p;
        if s_norm <= k0 {
            return *eps;
        }
        let keep = match self.mu_i {
            Some(mi) if p > 0.0 && self.alpha > 0.0 && dt > 0.0 => {
                let delta = self.mu_i_plastic_strain(&mi, s_norm - k0, p, dt);
                1.0 - g2 * delta / s_norm
            }
            _ => k0 / s_norm,
        };
        dev * keep + Vector3::repeat(tr / 3.0)
    }

    /// The split's return mapping of `(F_E trial, F_P)` at the rows' pressure (Pa; see
    /// [`DruckerPrager::return_strain_at_pressure`]) over `dt` seconds; `None` for a
    /// degenerate state.
    pub fn project_at_pressure(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
        pressure: f64,
        dt: f64,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        super::hencky::project(fe_trial, fp, |eps| {
            self.return_strain_at_pressure(eps, pressure, dt)
        })
    }

    /// The return mapping over a step of `dt` seconds (the rate-dependent friction's;
    /// [`DruckerPrager::project`] when rate-independent).
    pub fn project_step(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
        dt: f64,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        super::hencky::project(fe_trial, fp, |eps| self.return_strain_rate(eps, dt))
    }

    /// The yield function `f(tau)` of principal Kirchhoff stresses, Pa (<= 0 admissible).
    pub fn yield_function(&self, tau: &Vector3<f64>) -> f64 {
        let (dev, tr) = split(tau);
        dev.norm() + self.alpha * tr - self.kappa
    }

    /// The returned principal Hencky strains of trial strains `eps`.
    pub fn return_strain(&self, eps: &Vector3<f64>) -> Vector3<f64> {
        let el = &self.elastic;
        let (dev, tr) = split(eps);
        // tr(tau) = (3 lambda + 2 mu) tr(eps); |s| = 2 mu |dev eps|.
        let bulk3 = 3.0 * el.lambda + 2.0 * el.mu;
        let tr_tau = bulk3 * tr;
        if self.alpha > 0.0 && self.alpha * tr_tau >= self.kappa {
            // Beyond the apex: the apex, tr(tau) = kappa / alpha, s = 0.
            return Vector3::repeat(self.kappa / (self.alpha * bulk3) / 3.0);
        }
        let dev_norm = dev.norm();
        let s_norm = 2.0 * el.mu * dev_norm;
        let limit = self.kappa - self.alpha * tr_tau; // the admissible |s| at this pressure
        if s_norm <= limit {
            return *eps;
        }
        if self.dilatancy == 0.0 {
            return dev * (limit / s_norm) + Vector3::repeat(tr / 3.0);
        }
        // Dilatant flow: `dgamma` along `n + beta I`, `n = dev / |dev|`.
        let beta = self.dilatancy;
        let dgamma = (s_norm - limit) / (2.0 * el.mu + 3.0 * self.alpha * beta * bulk3);
        if 2.0 * el.mu * dgamma >= s_norm {
            // The deviator would reverse: the apex (for the dilated trace).
            return Vector3::repeat(self.kappa / (self.alpha * bulk3) / 3.0);
        }
        dev * (1.0 - 2.0 * el.mu * dgamma / s_norm) + Vector3::repeat(tr / 3.0 - beta * dgamma)
    }

    /// The return mapping of `(F_E trial, F_P)`; `None` for a degenerate state.
    pub fn project(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        super::hencky::project(fe_trial, fp, |eps| self.return_strain(eps))
    }

    /// Principal Kirchhoff stresses of principal Hencky strains, Pa.
    pub fn principal_stress(&self, eps: &Vector3<f64>) -> Vector3<f64> {
        principal_stress(&self.elastic, eps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::SignedSvd;
    use crate::material::hencky::strains;
    use nalgebra::Rotation3;
    use proptest::prelude::*;

    fn check(
        m: &DruckerPrager,
        a: [f64; 6],
        e: [f64; 3],
    ) -> std::result::Result<(), TestCaseError> {
        let r1 = Rotation3::from_euler_angles(a[0], a[1], a[2]).into_inner();
        let r2 = Rotation3::from_euler_angles(a[3], a[4], a[5]).into_inner();
        let s = Vector3::from(e).map(f64::exp);
        let fe = r1 * Matrix3::from_diagonal(&s) * r2;
        let fp = Matrix3::identity();
        let (fe1, fp1) = m.project(&fe, &fp).unwrap();
        let eps1 = strains(&SignedSvd::new(&fe1).unwrap().s).unwrap();
        let tau = m.principal_stress(&eps1);
        let scale = m.elastic.young * (1e-3 + Vector3::from(e).norm()) + m.kappa;
        let f = m.yield_function(&tau);
        // On or inside the cone.
        prop_assert!(f <= 1e-9 * scale, "f = {f}, scale {scale}");
        // A plastic step lands on the surface.
        let eps0 = Vector3::from(e);
        if m.yield_function(&m.principal_stress(&eps0)) > 1e-9 * scale {
            prop_assert!(f.abs() <= 1e-9 * scale, "plastic but f = {f}");
        }
        prop_assert!((fe1 * fp1 - fe * fp).norm() < 1e-9);
        let (fe2, fp2) = m.project(&fe1, &fp1).unwrap();
        prop_assert!((fe2 - fe1).norm() < 1e-10, "not idempotent");
        prop_assert!((fp2 - fp1).norm() < 1e-10);
        Ok(())
    }

    proptest! {
        #[test]
        fn sand_return_lands_on_or_inside_and_is_idempotent(
            a in prop::array::uniform6(-3.0f64..3.0),
            e in prop::array::uniform3(-0.05f64..0.05),
            phi in 0.0f64..50.0,
            c in 0.0f64..2e3,
        ) {
            let c = if phi == 0.0 { c + 1.0 } else { c };
            let m = DruckerPrager::new(1e6, 0.3, phi, c).unwrap();
            check(&m, a, e)?;
            check(&m.associated(), a, e)?;
        }
    }

    /// The split's return at the rows' pressure `pressure` (Pa) of a random trial state:
    /// on or inside `|s| <= kappa + 3 alpha J max(p, 0)`, on it after a plastic step, the
    /// trace kept, `F_E F_P` kept, idempotent at the same pressure.
    fn check_at_pressure(
        m: &DruckerPrager,
        a: [f64; 6],
        e: [f64; 3],
        pressure: f64,
    ) -> std::result::Result<(), TestCaseError> {
        let r1 = Rotation3::from_euler_angles(a[0], a[1], a[2]).into_inner();
        let r2 = Rotation3::from_euler_angles(a[3], a[4], a[5]).into_inner();
        let fe = r1 * Matrix3::from_diagonal(&Vector3::from(e).map(f64::exp)) * r2;
        let fp = Matrix3::identity();
        let (fe1, fp1) = m.project_at_pressure(&fe, &fp, pressure, 1e-4).unwrap();
        let eps0 = Vector3::from(e);
        let eps1 = strains(&SignedSvd::new(&fe1).unwrap().s).unwrap();
        let (dev0, tr0) = split(&eps0);
        let (dev1, tr1) = split(&eps1);
        let g2 = 2.0 * m.elastic.mu;
        let k = m.kappa + 3.0 * m.alpha * pressure.max(0.0) * tr0.exp();
        let scale = m.elastic.young * (1e-3 + eps0.norm()) + k;
        prop_assert!((tr1 - tr0).abs() < 1e-12, "trace {tr0} -> {tr1}");
        let s1 = g2 * dev1.norm();
        prop_assert!(s1 <= k + 1e-9 * scale, "|s| {s1} > k {k}");
        if g2 * dev0.norm() > k + 1e-9 * scale {
            prop_assert!(
                (s1 - k).abs() <= 1e-9 * scale,
                "plastic but |s| {s1}, k {k}"
            );
            // radial: the deviator keeps its direction (principal values compared in
            // order: the SVD may order the axes differently)
            if k > 1e-9 * scale {
                let sorted = |v: &Vector3<f64>| {
                    let mut a = [v[0], v[1], v[2]];
                    a.sort_by(f64::total_cmp);
                    Vector3::from(a)
                };
                let (d0, d1) = (sorted(&dev0), sorted(&dev1));
                let cos = d0.dot(&d1) / (d0.norm() * d1.norm());
                prop_assert!(cos > 1.0 - 1e-9, "not radial: cos {cos}");
            }
        } else {
            prop_assert!(fe1 == fe && fp1 == fp, "elastic step changed the state");
        }
        prop_assert!((fe1 * fp1 - fe * fp).norm() < 1e-9);
        let (fe2, fp2) = m.project_at_pressure(&fe1, &fp1, pressure, 1e-4).unwrap();
        prop_assert!((fe2 - fe1).norm() < 1e-10, "not idempotent");
        prop_assert!((fp2 - fp1).norm() < 1e-10);
        Ok(())
    }

    proptest! {
        #[test]
        fn split_return_at_the_rows_pressure_lands_on_or_inside_and_is_idempotent(
            a in prop::array::uniform6(-3.0f64..3.0),
            e in prop::array::uniform3(-0.05f64..0.05),
            phi in 0.0f64..50.0,
            c in 0.0f64..2e3,
            pressure in -2e4f64..2e5,
            plane in any::<bool>(),
        ) {
            let c = if phi == 0.0 { c + 1.0 } else { c };
            let m = if plane {
                DruckerPrager::plane_strain(1e6, 0.3, phi, c).unwrap()
            } else {
                DruckerPrager::new(1e6, 0.3, phi, c).unwrap()
            };
            check_at_pressure(&m, a, e, pressure)?;
            // mu(I): at least the quasi-static cone (the rate only adds strength)
            if phi > 1.0 {
                let mi = m.with_mu_i(MuI::jop_2006()).unwrap();
                let eps = Vector3::from(e);
                let out = mi.return_strain_at_pressure(&eps, pressure, 1e-4);
                let ri = m.return_strain_at_pressure(&eps, pressure, 1e-4);
                prop_assert!(split(&out).0.norm() >= split(&ri).0.norm() - 1e-15);
                prop_assert!(split(&out).0.norm() <= split(&eps).0.norm() + 1e-15);
            }
        }
    }

    #[test]
    fn split_return_is_the_plain_return_at_the_strains_own_pressure() {
        // Given the pressure the trial strain's trace carries in plain MPM (Cauchy
        // p = -(3 lambda + 2 mu) tr(eps) / (3 J), J = exp tr(eps)), the split's return is
        // the plain one wherever that does not go to the apex; with no pressure the
        // cohesionless sand keeps no deviator (the apex in the deviatoric plane) and keeps
        // its trace.
        let m = DruckerPrager::plane_strain(2e6, 0.3, 30.0, 0.0).unwrap();
        let bulk3 = 3.0 * m.elastic.lambda + 2.0 * m.elastic.mu;
        let mut checked = 0;
        for (vol, shear) in [(-1e-3, 5e-3), (-2e-3, 1e-4), (-5e-4, 2e-2), (-1e-2, 3e-3)] {
            let eps = Vector3::new(
                vol / 3.0 + shear,
                vol / 3.0 - 0.3 * shear,
                vol / 3.0 - 0.7 * shear,
            );
            let p = -bulk3 * eps.sum() / 3.0 / eps.sum().exp();
            let split_ret = m.return_strain_at_pressure(&eps, p, 1e-4);
            let plain = m.return_strain(&eps);
            assert!(
                (split_ret - plain).norm() < 1e-15,
                "{split_ret:?} vs {plain:?}"
            );
            if plain != eps {
                checked += 1;
            }
            let none = m.return_strain_at_pressure(&eps, 0.0, 1e-4);
            assert!(split(&none).0.norm() < 1e-18, "{none:?}");
            assert!((none.sum() - eps.sum()).abs() < 1e-18);
            let tension = m.return_strain_at_pressure(&eps, -1e3, 1e-4);
            assert_eq!(tension, none);
        }
        assert!(checked >= 2, "{checked} plastic cases");
    }

    #[test]
    fn plane_strain_match_is_mohr_coulomb_at_steady_flow() {
        // Principal stresses (sigma_1, (sigma_1 + sigma_3)/2, sigma_3) on Mohr-Coulomb's
        // line t = c cos(phi) - p sin(phi) are on the matched cone, for any p.
        for (phi, c) in [(0.0, 1e4), (20.0, 1e4), (35.0, 2e3)] {
            let m = DruckerPrager::plane_strain(1e7, 0.3, phi, c).unwrap();
            let (sin, cos) = phi.to_radians().sin_cos();
            for p in [-5e4, -1e4, 0.0, 0.5 * c * cos / sin.max(1e-3)] {
                let t = c * cos - p * sin;
                if t < 0.0 {
                    continue;
                }
                let tau = Vector3::new(p + t, p, p - t);
                let f = m.yield_function(&tau);
                assert!(f.abs() < 1e-9 * (c + p.abs()), "phi {phi}, p {p}: f = {f}");
            }
            proptest::test_runner::TestRunner::default()
                .run(
                    &(
                        prop::array::uniform6(-3.0f64..3.0),
                        prop::array::uniform3(-0.05f64..0.05),
                    ),
                    |(a, e)| check(&m, a, e),
                )
                .unwrap();
        }
        let vm = crate::material::VonMises::from_undrained_strength(1e7, 0.3, 1e4).unwrap();
        let m = DruckerPrager::plane_strain(1e7, 0.3, 0.0, 1e4).unwrap();
        assert!((m.kappa - vm.radius()).abs() < 1e-9 * vm.radius());
    }

    #[test]
    fn cohesionless_tension_goes_to_the_apex() {
        let m = DruckerPrager::new(1e6, 0.3, 30.0, 0.0).unwrap();
        let eps = m.return_strain(&Vector3::new(0.01, 0.002, -0.001));
        assert!(eps.norm() < 1e-15, "{eps}");
        // Compression inside the cone stays.
        let e0 = Vector3::new(-0.01, -0.01, -0.011);
        assert_eq!(m.return_strain(&e0), e0);
    }

    #[test]
    fn bad_input_names_the_field() {
        let e = DruckerPrager::new(1e6, 0.3, 95.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("material.friction_angle_deg"), "{e}");
        let e = DruckerPrager::new(1e6, 0.3, 30.0, -1.0).unwrap_err();
        assert!(e.to_string().contains("material.cohesion"), "{e}");
        let e = DruckerPrager::new(1e6, 0.3, 0.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("material.cohesion"), "{e}");
        let e = DruckerPrager::new(-1e6, 0.3, 30.0, 0.0).unwrap_err();
        assert!(e.to_string().contains("material.young"), "{e}");
    }

    #[test]
    fn mu_i_return_holds_the_rheology_at_the_step_rate() {
        // Trial states in plane-strain simple shear under pressure: after the return the
        // deviator is |s| = sqrt(2) p mu(I) (the plane-strain cone, `t = mu p`), with
        // I = gamma_dot d / sqrt(p / rho_s) from the step's plastic shear rate
        // gamma_dot = sqrt(2) |dev eps_p| / dt; mu -> mu_s = sin(phi) for slow steps and
        // the rate-independent return when I is negligible; the trace is kept.
        let base = DruckerPrager::plane_strain(2e6, 0.3, 30.0, 0.0).unwrap();
        let mi = MuI::jop_2006();
        let m = base.with_mu_i(mi).unwrap();
        let g2 = 2.0 * m.elastic.mu;
        let bulk3 = 3.0 * m.elastic.lambda + 2.0 * m.elastic.mu;
        for (vol, shear, dt) in [
            (-1e-3, 5e-3, 1e-4),
            (-2e-4, 1e-3, 1e-5),
            (-1e-3, 2e-2, 1e-3),
        ] {
            let eps = Vector3::new(vol / 3.0 + shear, vol / 3.0, vol / 3.0 - shear);
            let out = m.return_strain_rate(&eps, dt);
            let (dev0, tr0) = split(&eps);
            let (dev1, tr1) = split(&out);
            assert!((tr1 - tr0).abs() < 1e-15, "trace {tr0} -> {tr1}");
            let p = -bulk3 * tr0 / 3.0;
            let delta = dev0.norm() - dev1.norm();
            assert!(delta > 0.0, "no plastic flow: {eps:?}");
            let i = 2.0f64.sqrt() * delta / dt * mi.grain_diameter / (p / mi.grain_density).sqrt();
            let mu = 0.5 + mi.delta_mu * i / (mi.i0 + i);
            let s = g2 * dev1.norm();
            assert!(
                (s - 2.0f64.sqrt() * p * mu).abs() < 1e-9 * s,
                "I {i}: |s| {s} vs sqrt(2) p mu(I) {}",
                2.0f64.sqrt() * p * mu
            );
            // Slow: the rate-independent cone.
            let slow = m.return_strain_rate(&eps, 1e6);
            let ri = base.return_strain(&eps);
            assert!((slow - ri).norm() < 1e-9 * eps.norm(), "{slow:?} vs {ri:?}");
        }
        // Inside the cone: unchanged.
        let e = Vector3::new(-1e-3, -1e-3, -1e-3);
        assert_eq!(m.return_strain_rate(&e, 1e-4), e);
        // Bad parameters name the field.
        for (bad, field) in [
            (MuI { i0: 0.0, ..mi }, "material.mu_i.i0"),
            (
                MuI {
                    delta_mu: -1.0,
                    ..mi
                },
                "material.mu_i.delta_mu",
            ),
            (
                MuI {
                    grain_diameter: f64::NAN,
                    ..mi
                },
                "material.mu_i.grain_diameter",
            ),
            (
                MuI {
                    grain_density: 0.0,
                    ..mi
                },
                "material.mu_i.grain_density",
            ),
        ] {
            let e = base.with_mu_i(bad).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
        assert!(base.associated().with_mu_i(mi).is_err());
    }
}
