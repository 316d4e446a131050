//! Von Mises cohesive clay, return mapping in Hencky strain.
//!
//! With the Kirchhoff stress deviator `s` (Pa) and the yield stress `sigma_y` (the
//! uniaxial one, Pa):
//!
//! ```text
//! f(tau) = |s| - sqrt(2/3) sigma_y <= 0
//! ```
//!
//! The return scales the deviator of the trial Hencky strain radially back to the cylinder
//! and keeps its trace (isochoric plastic flow; Simo & Hughes, "Computational
//! Inelasticity", Springer 1998, sec. 3.3, here in logarithmic strain). For an undrained
//! clay of shear strength `c_u` in plane strain (the Tresca material of Prandtl's footing
//! problem), [`VonMises::from_undrained_strength`] takes `sigma_y = sqrt(3) c_u`, which
//! gives the same limit shear stress `c_u` in plane strain.

use nalgebra::{Matrix3, Vector3};

use super::Elasticity;
use super::hencky::{principal_stress, split};
use crate::error::{Result, positive};

/// Von Mises clay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VonMises {
    /// Elastic moduli (Hencky elasticity).
    pub elastic: Elasticity,
    /// Uniaxial yield stress `sigma_y`, Pa.
    pub yield_stress: f64,
}

impl VonMises {
    /// Clay of uniaxial `yield_stress` (> 0 Pa); errors name the field.
    pub fn new(young: f64, poisson: f64, yield_stress: f64) -> Result<Self> {
        Ok(Self {
            elastic: Elasticity::new("material", young, poisson)?,
            yield_stress: positive("material.yield_stress", yield_stress)?,
        })
    }

    /// Clay of undrained shear strength `c_u` (Pa) matched in plane strain:
    /// `sigma_y = sqrt(3) c_u`.
    pub fn from_undrained_strength(young: f64, poisson: f64, cohesion: f64) -> Result<Self> {
        positive("material.cohesion", cohesion)?;
        Self::new(young, poisson, 3.0f64.sqrt() * cohesion)
    }

    /// The radius of the yield cylinder, `sqrt(2/3) sigma_y`, Pa.
    pub fn radius(&self) -> f64 {
        (2.0f64 / 3.0).sqrt() * self.yield_stress
    }

    /// The yield function of principal Kirchhoff stresses, Pa (<= 0 admissible).
    pub fn yield_function(&self, tau: &Vector3<f64>) -> f64 {
        split(tau).0.norm() - self.radius()
    }

    /// The returned principal Hencky strains of trial strains `eps`.
    pub fn return_strain(&self, eps: &Vector3<f64>) -> Vector3<f64> {
        let (dev, tr) = split(eps);
        let s_norm = 2.0 * self.elastic.mu * dev.norm();
        let r = self.radius();
        if s_norm <= r {
            return *eps;
        }
        dev * (r / s_norm) + Vector3::repeat(tr / 3.0)
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

    proptest! {
        #[test]
        fn clay_return_lands_on_or_inside_and_is_idempotent(
            a in prop::array::uniform6(-3.0f64..3.0),
            e in prop::array::uniform3(-0.05f64..0.05),
            sy in 1e2f64..1e5,
        ) {
            let m = VonMises::new(1e6, 0.3, sy).unwrap();
            let r1 = Rotation3::from_euler_angles(a[0], a[1], a[2]).into_inner();
            let r2 = Rotation3::from_euler_angles(a[3], a[4], a[5]).into_inner();
            let s = Vector3::from(e).map(f64::exp);
            let fe = r1 * Matrix3::from_diagonal(&s) * r2;
            let fp = Matrix3::identity();
            let (fe1, fp1) = m.project(&fe, &fp).unwrap();
            let eps1 = strains(&SignedSvd::new(&fe1).unwrap().s).unwrap();
            let f = m.yield_function(&m.principal_stress(&eps1));
            let scale = sy + 1e6 * Vector3::from(e).norm();
            prop_assert!(f <= 1e-9 * scale, "f = {f}");
            if m.yield_function(&m.principal_stress(&Vector3::from(e))) > 0.0 {
                prop_assert!(f.abs() <= 1e-9 * scale, "plastic but f = {f}");
            }
            // Isochoric flow: J of F_E keeps the trial's.
            prop_assert!((fe1.determinant() - fe.determinant()).abs() < 1e-12);
            prop_assert!((fe1 * fp1 - fe * fp).norm() < 1e-9);
            let (fe2, fp2) = m.project(&fe1, &fp1).unwrap();
            prop_assert!((fe2 - fe1).norm() < 1e-10, "not idempotent");
            prop_assert!((fp2 - fp1).norm() < 1e-10);
        }
    }

    #[test]
    fn plane_strain_pure_shear_limit_is_the_undrained_strength() {
        // Plane strain pure shear: principal tau (t, -t, 0): |s| = sqrt(2) t, so the limit
        // t = sqrt(2/3) sigma_y / sqrt(2) = sigma_y / sqrt(3) = c_u.
        let cu = 2.0e4;
        let m = VonMises::from_undrained_strength(1e7, 0.3, cu).unwrap();
        assert!(m.yield_function(&Vector3::new(cu, -cu, 0.0)).abs() < 1e-9);
        let e = VonMises::new(1e7, 0.3, -1.0).unwrap_err();
        assert!(e.to_string().contains("material.yield_stress"), "{e}");
        let e = VonMises::from_undrained_strength(1e7, 0.3, 0.0).unwrap_err();
        assert!(e.to_string().contains("material.cohesion"), "{e}");
    }
}
