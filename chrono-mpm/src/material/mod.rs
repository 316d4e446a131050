//! Constitutive models of MPM markers: stress from the elastic deformation gradient `F_E`
//! and a return mapping that keeps `F_E` admissible, moving the excess into the plastic
//! gradient `F_P` (multiplicative split `F = F_E F_P`).
//!
//! - [`corotated`]: fixed-corotated elasticity with optional snow plasticity and hardening
//!   (Stomakhin et al. 2013).
//! - [`drucker_prager`]: Drucker–Prager sand in Hencky strain (Klar et al. 2016), with
//!   cohesion.
//! - [`von_mises`]: von Mises cohesive clay (yield stress) in Hencky strain.
//! - [`critical_state`]: compressible `mu(I)` sand with critical-state dilatancy (the
//!   packing fraction relaxes to `phi_eq(I)`), Hencky elasticity.
//!
//! Stresses are Kirchhoff stresses `tau = P F_E^T = J sigma`, Pa, so the grid force of a
//! marker with reference volume `V0` is `f_i = -V0 tau grad w_ip` (no inverse of `F`).

pub mod corotated;
pub mod critical_state;
pub mod drucker_prager;
mod hencky;
pub mod svd;
pub mod von_mises;

use nalgebra::Matrix3;

pub use corotated::{FixedCorotated, SnowHardening};
pub use critical_state::CriticalStateSand;
pub use drucker_prager::{DruckerPrager, MuI};
pub use svd::SignedSvd;
pub use von_mises::VonMises;

use crate::error::{Result, invalid, positive};

/// Isotropic linear-elastic moduli from Young's modulus and Poisson's ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elasticity {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Poisson's ratio `nu`, -.
    pub poisson: f64,
    /// Shear modulus `mu = E / (2 (1 + nu))`, Pa.
    pub mu: f64,
    /// Lame's first parameter `lambda = E nu / ((1 + nu)(1 - 2 nu))`, Pa.
    pub lambda: f64,
}

impl Elasticity {
    /// Moduli from `young` (> 0, Pa) and `poisson` (in (-1, 0.5)); an error names the field
    /// (`field_prefix.young`, `field_prefix.poisson`).
    pub fn new(field_prefix: &str, young: f64, poisson: f64) -> Result<Self> {
        positive(&format!("{field_prefix}.young"), young)?;
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(invalid(
                &format!("{field_prefix}.poisson"),
                poisson,
                "must lie in (-1, 0.5)",
            ));
        }
        Ok(Self {
            young,
            poisson,
            mu: young / (2.0 * (1.0 + poisson)),
            lambda: young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson)),
        })
    }

    /// The P-wave (constrained) modulus `lambda + 2 mu`, Pa.
    pub fn p_modulus(&self) -> f64 {
        self.lambda + 2.0 * self.mu
    }
}

/// The material of an MPM body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// Fixed-corotated elasticity, optionally with snow plasticity.
    Corotated(FixedCorotated),
    /// Drucker–Prager sand in Hencky strain.
    DruckerPrager(DruckerPrager),
    /// Von Mises clay in Hencky strain.
    VonMises(VonMises),
    /// Compressible `mu(I)` sand with critical-state dilatancy in Hencky strain.
    CriticalState(CriticalStateSand),
}

impl Material {
    /// Kirchhoff stress `tau = P F_E^T`, Pa, of the elastic gradient `fe` (and plastic
    /// gradient `fp`, which sets the hardening).
    #[inline]
    pub fn kirchhoff(&self, fe: &Matrix3<f64>, fp: &Matrix3<f64>) -> Matrix3<f64> {
        match self {
            Material::Corotated(m) => m.kirchhoff(fe, fp),
            Material::DruckerPrager(m) => hencky::kirchhoff(&m.elastic, fe),
            Material::VonMises(m) => hencky::kirchhoff(&m.elastic, fe),
            Material::CriticalState(m) => hencky::kirchhoff(&m.elastic, fe),
        }
    }

    /// The Kirchhoff stress the grid takes from a marker, Pa: [`kirchhoff`](Self::kirchhoff),
    /// or its deviator `tau - tr(tau)/3 I` when `deviatoric` (the split, whose density rows
    /// carry the volumetric part).
    #[inline]
    pub fn grid_stress(
        &self,
        fe: &Matrix3<f64>,
        fp: &Matrix3<f64>,
        deviatoric: bool,
    ) -> Matrix3<f64> {
        let mut tau = self.kirchhoff(fe, fp);
        if deviatoric {
            let mean = tau.trace() / 3.0;
            for a in 0..3 {
                tau[(a, a)] -= mean;
            }
        }
        tau
    }

    /// Elastic energy per reference volume, J/m^3.
    pub fn energy_density(&self, fe: &Matrix3<f64>, fp: &Matrix3<f64>) -> f64 {
        match self {
            Material::Corotated(m) => m.energy_density(fe, fp),
            Material::DruckerPrager(m) => hencky::energy_density(&m.elastic, fe),
            Material::VonMises(m) => hencky::energy_density(&m.elastic, fe),
            Material::CriticalState(m) => hencky::energy_density(&m.elastic, fe),
        }
    }

    /// The return mapping: the admissible `(F_E, F_P)` for the trial elastic gradient
    /// `fe_trial` and the previous plastic gradient `fp`. `None` when the state is
    /// degenerate (non-finite, or a Hencky model with a non-positive stretch).
    #[inline]
    pub fn project(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        match self {
            Material::Corotated(m) => m.project(fe_trial, fp),
            Material::DruckerPrager(m) => m.project(fe_trial, fp),
            Material::VonMises(m) => m.project(fe_trial, fp),
            Material::CriticalState(m) => m.project(fe_trial, fp),
        }
    }

    /// The return mapping over a step of `dt` seconds: [`Material::project`], with the
    /// rate-dependent friction of a Drucker–Prager sand with [`MuI`].
    #[inline]
    pub fn project_step(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
        dt: f64,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        match self {
            Material::DruckerPrager(m) if m.mu_i.is_some() => m.project_step(fe_trial, fp, dt),
            Material::CriticalState(m) => m.project_step(fe_trial, fp, dt),
            _ => self.project(fe_trial, fp),
        }
    }

    /// The split's return mapping over a step of `dt` seconds with the density rows'
    /// pressure `pressure` (Pa, compression positive): a Drucker–Prager sand's cone is
    /// evaluated at it ([`DruckerPrager::project_at_pressure`]); the other models'
    /// yield does not depend on the pressure ([`Material::project_step`]).
    #[inline]
    pub fn project_at_pressure(
        &self,
        fe_trial: &Matrix3<f64>,
        fp: &Matrix3<f64>,
        pressure: f64,
        dt: f64,
    ) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
        match self {
            Material::DruckerPrager(m) => m.project_at_pressure(fe_trial, fp, pressure, dt),
            _ => self.project_step(fe_trial, fp, dt),
        }
    }

    /// The current P-wave modulus, Pa (with hardening), for the explicit time-step limit.
    pub fn p_modulus(&self, fp: &Matrix3<f64>) -> f64 {
        match self {
            Material::Corotated(m) => m.p_modulus(fp),
            Material::DruckerPrager(m) => m.elastic.p_modulus(),
            Material::VonMises(m) => m.elastic.p_modulus(),
            Material::CriticalState(m) => m.elastic.p_modulus(),
        }
    }

    /// The current shear modulus `mu`, Pa (with hardening), for the split's time-step limit.
    pub fn shear_modulus(&self, fp: &Matrix3<f64>) -> f64 {
        match self {
            Material::Corotated(m) => m.lame(fp).0,
            Material::DruckerPrager(m) => m.elastic.mu,
            Material::VonMises(m) => m.elastic.mu,
            Material::CriticalState(m) => m.elastic.mu,
        }
    }

    /// The plastic volume change of the flow rule: a Drucker–Prager sand's dilatancy
    /// `beta`, the critical-state sand's `K_d`, 0 for the isochoric flows. The split's
    /// fixed rest density needs 0.
    pub fn plastic_dilatancy(&self) -> f64 {
        match self {
            Material::DruckerPrager(m) => m.dilatancy,
            Material::CriticalState(m) => m.dilatancy,
            _ => 0.0,
        }
    }

    /// Whether the stress depends on `F_P` (hardening), so the wave speed has to be
    /// evaluated per marker.
    pub fn hardens(&self) -> bool {
        matches!(self, Material::Corotated(m) if m.snow.is_some())
    }
}

impl From<FixedCorotated> for Material {
    fn from(m: FixedCorotated) -> Self {
        Material::Corotated(m)
    }
}

impl From<DruckerPrager> for Material {
    fn from(m: DruckerPrager) -> Self {
        Material::DruckerPrager(m)
    }
}

impl From<CriticalStateSand> for Material {
    fn from(m: CriticalStateSand) -> Self {
        Material::CriticalState(m)
    }
}

impl From<VonMises> for Material {
    fn from(m: VonMises) -> Self {
        Material::VonMises(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_moduli_name_the_field() {
        let e = Elasticity::new("material", -1.0, 0.2).unwrap_err();
        assert!(e.to_string().contains("material.young"), "{e}");
        let e = Elasticity::new("material", 1e6, 0.5).unwrap_err();
        assert!(e.to_string().contains("material.poisson"), "{e}");
        let e = Elasticity::new("material", f64::NAN, 0.2).unwrap_err();
        assert!(e.to_string().contains("material.young"), "{e}");
        let m = Elasticity::new("m", 2.6e6, 0.3).unwrap();
        assert!((m.mu - 1e6).abs() < 1e-6);
        assert!((m.lambda - 1.5e6).abs() < 1e-6);
    }
}
