//! Compressible `mu(I)` sand with critical-state dilatancy: an elastoplastic granular
//! material whose plastic flow changes its volume until the packing fraction reaches the
//! critical value of its inertial number (issue 25, the column collapse's "next": a
//! well-posed rheology).
//!
//! # The model
//!
//! Hencky elasticity (`tau` the Kirchhoff stress, Pa; the principal Hencky strains
//! `eps = ln s` of `F_E`; the bulk modulus `K = lambda + 2 mu / 3` and the shear modulus
//! `mu_e`, Pa), the Kirchhoff pressure `p = -tr(tau)/3 = -K tr(eps)` and the deviator
//! norm `q = |dev tau| = 2 mu_e |dev eps|`. With the packing fraction `phi` (the volume of
//! grains per volume, -) and the inertial number
//!
//! ```text
//! I = gamma_dot d / sqrt(p / rho_s),   gamma_dot = sqrt(2) |dev D_p|   (1/s)
//! ```
//!
//! (`d` the grain diameter, m; `rho_s` the grains' density, kg/m^3; `D_p` the plastic rate
//! of deformation), the yield condition and the flow rule are
//!
//! ```text
//! q <= sqrt(2) mu_eff p,                      mu_eff = max(mu(I) + tan(psi), 0)
//! mu(I)    = mu_s + (mu_2 - mu_s) I / (I0 + I)               (Jop, Forterre & Pouliquen 2006)
//! tan(psi) = K_d (phi - phi_eq(I)),  phi_eq(I) = max(phi_c - delta_phi I, 0)
//! dev D_p  = (gamma_dot / sqrt(2)) dev(tau) / q,   tr D_p = gamma_dot tan(psi)
//! ```
//!
//! `sqrt(2) mu p` is the plane-strain shear `t = (sigma_1 - sigma_3)/2 = mu p` at steady
//! flow (the radial flow has `s_yy = 0` out of the plane; the same match as
//! [`super::DruckerPrager::plane_strain`]), so `t / p = mu(I)` in steady simple shear.
//! The dilatancy is Roux & Radjai's critical-state law (in Herrmann et al., eds.,
//! "Physics of Dry Granular Media", NATO ASI E 350, 1998) in the form of Pailha &
//! Pouliquen (J. Fluid Mech. 633, 2009): a packing denser than the critical one dilates
//! when it is sheared and is stronger by `tan(psi)` (the work against the pressure), a
//! looser one compacts and is weaker, and steady shear ends at `phi = phi_eq(I)`, the
//! `phi(I)` law of dense flow (GDR MiDi, Eur. Phys. J. E 14, 2004). Compressibility of
//! this kind, with enough dissipation on volume change, is what makes the `mu(I)`
//! equations well-posed (Barker, Schaeffer, Shearer & Gray, Proc. R. Soc. A 473, 2017;
//! Heyman, Delannay, Tabuteau & Valance, J. Fluid Mech. 830, R5, 2017); see
//! [`CriticalStateSand::bulk_friction`] for the check of Heyman et al.'s criterion.
//!
//! The packing fraction is kinematic: `phi = phi0 / J` with `J = det(F_E F_P)` the total
//! volume ratio of the marker and `phi0` its packing at `J = 1` (its bulk density over
//! `rho_s`), so the model needs no state beyond `F_E` and `F_P`.
//!
//! # The return (one step of `dt` seconds)
//!
//! A trial state with `p_tr <= 0` (the grains separated) goes to the apex, stress-free
//! (cohesionless). Else, with the plastic deviatoric increment `Delta = |dev eps_p| >= 0`
//! (so `gamma_dot = sqrt(2) Delta / dt`) and `I` evaluated at the trial pressure,
//!
//! ```text
//! p(Delta) = max(p_tr + K sqrt(2) tan(psi) Delta, 0)      (plastic dilation compresses the elastic part)
//! R(Delta) = q_tr - 2 mu_e Delta - sqrt(2) mu_eff(I(Delta)) p(Delta) = 0
//! ```
//!
//! is solved by bisection on `[0, q_tr / (2 mu_e)]` (`R(0) > 0` for a plastic step and
//! `R <= 0` at the right end: a root exists); then `dev eps' = dev eps (1 - 2 mu_e Delta /
//! q_tr)` and `tr eps' = min(tr eps - sqrt(2) tan(psi) Delta, 0)`.
//!
//! # Parameters ([`CriticalStateSand::glass_beads`])
//!
//! Glass beads of Jop, Forterre & Pouliquen (Nature 441, 2006): `mu_s = tan 20.9 deg`,
//! `mu_2 = tan 32.76 deg`, `I0 = 0.279`, `d = 0.53 mm`, `rho_s = 2450 kg/m^3`. The
//! dilatancy constant `K_d = 4.09` of Pailha & Pouliquen (2009); `phi_eq(I) = phi_c -
//! delta_phi I` with `phi_c = 0.6`, `delta_phi = 0.1` (the linear `phi(I)` of dense glass
//! beads, from about 0.6 at rest to 0.5, as summarized by Forterre & Pouliquen, Annu.
//! Rev. Fluid Mech. 40, 2008). **`K_d`, `phi_c` and `delta_phi` are quoted from memory of
//! these papers, not from their text (not accessible to this session): to be verified.**

use nalgebra::{Matrix3, Vector3};

use super::Elasticity;
use super::hencky::{self, split};
use crate::error::{Result, invalid};

const SQRT2: f64 = std::f64::consts::SQRT_2;

/// The grains' density of Jop et al. (2006)'s glass beads, kg/m^3.
pub const GLASS_BEAD_DENSITY: f64 = 2450.0;

/// Compressible `mu(I)` sand with critical-state dilatancy (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriticalStateSand {
    /// Elastic moduli (Hencky elasticity).
    pub elastic: Elasticity,
    /// Quasi-static friction `mu_s`, -.
    pub mu_s: f64,
    /// Friction at large `I`, `mu_2 > mu_s`, -.
    pub mu_2: f64,
    /// `I0` of `mu(I)`, -.
    pub i0: f64,
    /// Grain diameter `d`, m.
    pub grain_diameter: f64,
    /// Grain density `rho_s`, kg/m^3.
    pub grain_density: f64,
    /// Dilatancy constant `K_d` of `tan(psi) = K_d (phi - phi_eq(I))`, -.
    pub dilatancy: f64,
    /// Critical packing fraction at `I -> 0`, `phi_c`, -.
    pub phi_c: f64,
    /// Slope of `phi_eq(I) = phi_c - delta_phi I`, -.
    pub delta_phi: f64,
    /// The markers' packing fraction at `J = 1`, `phi0`, -.
    pub phi0: f64,
}

impl CriticalStateSand {
    /// The glass beads of the module docs (Jop et al. 2006; Pailha & Pouliquen 2009;
    /// Forterre & Pouliquen 2008) with Hencky moduli `young` (Pa), `poisson` and the
    /// markers' packing fraction `phi0` at `J = 1` (their bulk density over 2450 kg/m^3).
    /// Errors name the field.
    pub fn glass_beads(young: f64, poisson: f64, phi0: f64) -> Result<Self> {
        Self {
            elastic: Elasticity::new("material", young, poisson)?,
            mu_s: 20.9f64.to_radians().tan(),
            mu_2: 32.76f64.to_radians().tan(),
            i0: 0.279,
            grain_diameter: 0.53e-3,
            grain_density: GLASS_BEAD_DENSITY,
            dilatancy: 4.09,
            phi_c: 0.6,
            delta_phi: 0.1,
            phi0,
        }
        .validated()
    }

    /// Checks every field; errors name it (`material.critical_state.*`).
    pub fn validated(self) -> Result<Self> {
        let field = |name: &str, v: f64, ok: bool, why: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(invalid(&format!("material.critical_state.{name}"), v, why))
            }
        };
        field("mu_s", self.mu_s, self.mu_s > 0.0, "must be finite and > 0")?;
        field(
            "mu_2",
            self.mu_2,
            self.mu_2 >= self.mu_s,
            "must be finite and >= mu_s",
        )?;
        field("i0", self.i0, self.i0 > 0.0, "must be finite and > 0")?;
        field(
            "grain_diameter",
            self.grain_diameter,
            self.grain_diameter > 0.0,
            "must be finite and > 0",
        )?;
        field(
            "grain_density",
            self.grain_density,
            self.grain_density > 0.0,
            "must be finite and > 0",
        )?;
        field(
            "dilatancy",
            self.dilatancy,
            self.dilatancy >= 0.0,
            "must be finite and >= 0",
        )?;
        field(
            "phi_c",
            self.phi_c,
            self.phi_c > 0.0 && self.phi_c < 1.0,
            "must lie in (0, 1)",
        )?;
        field(
            "delta_phi",
            self.delta_phi,
            self.delta_phi >= 0.0,
            "must be finite and >= 0",
        )?;
        field(
            "phi0",
            self.phi0,
            self.phi0 > 0.0 && self.phi0 < 1.0,
            "must lie in (0, 1) (the bulk density over the grains' density)",
        )?;
        Ok(self)
    }

    /// `mu(I)`, -.
    pub fn mu(&self, i: f64) -> f64 {
        self.mu_s + (self.mu_2 - self.mu_s) * i / (self.i0 + i)
    }

    /// The critical packing fraction at inertial number `i`, `phi_eq(I)`, -.
    pub fn phi_eq(&self, i: f64) -> f64 {
        (self.phi_c - self.delta_phi * i).max(0.0)
    }

    /// The dilatancy `tan(psi) = K_d (phi - phi_eq(I))` at packing `phi`, -.
    pub fn tan_psi(&self, phi: f64, i: f64) -> f64 {
        self.dilatancy * (phi - self.phi_eq(i))
    }

    /// The packing fraction of a marker of total volume ratio `j = det(F_E F_P)`, -.
    pub fn packing(&self, j: f64) -> f64 {
        self.phi0 / j
    }

    /// Heyman et al.'s bulk friction of this law at steady flow of inertial number `i`,
    /// -: in the rigid limit the flow rule `div v = gamma_dot K_d (phi - phi_eq(I))` at
    /// a given `phi` fixes `I` by `div v / gamma_dot`, and `p = rho_s (gamma_dot d / I)^2`
    /// then responds to the dilation rate as `dp = -mu_b p div v / gamma_dot` with
    ///
    /// ```text
    /// mu_b = 2 / (K_d delta_phi I)
    /// ```
    ///
    /// (linearized about `div v = 0`; this reading of the critical-state law as Heyman,
    /// Delannay, Tabuteau & Valance's bulk friction, J. Fluid Mech. 830, R5, 2017, is
    /// ours). Their linear analysis finds the compressible `mu(I)` equations well-posed
    /// when `mu_b > 1 - 7 mu / 6` (the published abstract; the preprint's two-dimensional
    /// form `mu_b > 2 - 2 mu` is stricter): [`CriticalStateSand::well_posed_at`] checks
    /// both. Infinite without a `phi(I)` dependence (`delta_phi = 0`) or at `I = 0`.
    pub fn bulk_friction(&self, i: f64) -> f64 {
        2.0 / (self.dilatancy * self.delta_phi * i)
    }

    /// Whether Heyman et al.'s criterion (both printed forms, see
    /// [`CriticalStateSand::bulk_friction`]) holds at inertial number `i`. Without
    /// dilatancy (`K_d = 0`) the flow is not compressible and the check does not apply:
    /// false.
    pub fn well_posed_at(&self, i: f64) -> bool {
        if self.dilatancy == 0.0 {
            return false;
        }
        let mu = self.mu(i);
        let mu_b = self.bulk_friction(i);
        mu_b > 1.0 - 7.0 * mu / 6.0 && mu_b > 2.0 - 2.0 * mu
    }

    /// The returned principal Hencky strains of trial strains `eps`, for a marker of total
    /// volume ratio `j` over a step of `dt` seconds (module docs).
    pub fn return_strain(&self, eps: &Vector3<f64>, j: f64, dt: f64) -> Vector3<f64> {
        let el = &self.elastic;
        let (dev, tr) = split(eps);
        let bulk = el.lambda + 2.0 * el.mu / 3.0;
        let p_tr = -bulk * tr;
        if p_tr <= 0.0 {
            // separated grains: stress-free
            return Vector3::zeros();
        }
        let g2 = 2.0 * el.mu;
        let q_tr = g2 * dev.norm();
        let phi = self.packing(j);
        // `I` per unit `Delta`, at the trial pressure
        let rate = if dt > 0.0 && dt.is_finite() {
            SQRT2 * self.grain_diameter / (dt * (p_tr / self.grain_density).sqrt())
        } else {
            0.0
        };
        let state = |delta: f64| {
            let i = rate * delta;
            let tan_psi = self.tan_psi(phi, i);
            let p = (p_tr + bulk * SQRT2 * tan_psi * delta).max(0.0);
            let mu_eff = (self.mu(i) + tan_psi).max(0.0);
            (q_tr - g2 * delta - SQRT2 * mu_eff * p, tan_psi)
        };
        if state(0.0).0 <= 0.0 {
            return *eps;
        }
        let (mut lo, mut hi) = (0.0, q_tr / g2);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if state(mid).0 > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let delta = hi;
        let tan_psi = state(delta).1;
        let keep = (1.0 - g2 * delta / q_tr).max(0.0);
        let tr_new = (tr - SQRT2 * tan_psi * delta).min(0.0);
        dev * keep + Vector3::repeat(tr_new / 3.0)
    }

    /// The return mapping of `(F_E trial, F_P)` over `dt` seconds; `None` for a
    /// degenerate state.
    pub fn project_step(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
        dt: f64,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        let j = fe_trial.determinant() * fp.determinant();
        if !(j.is_finite() && j > 0.0) {
            return None;
        }
        hencky::project(fe_trial, fp, |eps| self.return_strain(eps, j, dt))
    }

    /// The rate-independent return (`dt` infinite: `I = 0`).
    pub fn project(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        self.project_step(fe_trial, fp, f64::INFINITY)
    }

    /// Principal Kirchhoff stresses of principal Hencky strains, Pa.
    pub fn principal_stress(&self, eps: &Vector3<f64>) -> Vector3<f64> {
        hencky::principal_stress(&self.elastic, eps)
    }

    /// The packing fraction of `(F_E, F_P)`, -.
    pub fn packing_of(&self, fe: &Matrix3<f64>, fp: &Matrix3<f64>) -> f64 {
        self.packing(fe.determinant() * fp.determinant())
    }
}

/// Principal Hencky strains of `fe` (`None` if degenerate).
#[cfg(test)]
fn strains_of(fe: &Matrix3<f64>) -> Option<Vector3<f64>> {
    super::svd::SignedSvd::new(fe).and_then(|s| hencky::strains(&s.s))
}

#[cfg(test)]
#[path = "critical_state_tests.rs"]
mod tests;
