//! Hencky (logarithmic-strain) elasticity, the elastic law of the Drucker–Prager and von
//! Mises models: with `F_E = U diag(s) V^T` and the principal Hencky strains
//! `eps = ln s`,
//!
//! ```text
//! Psi = mu |eps|^2 + lambda/2 (tr eps)^2,     tau = U diag(2 mu eps + lambda tr(eps) 1) U^T
//! ```
//!
//! (Klar et al., "Drucker-Prager elastoplasticity for sand animation", ACM TOG 35(4), 2016,
//! eq. 24 with the St. Venant–Kirchhoff energy in Hencky strain.)

use nalgebra::{Matrix3, Vector3};

use super::{Elasticity, SignedSvd};

/// Principal Kirchhoff stresses of the principal Hencky strains `eps`, Pa.
#[inline]
pub fn principal_stress(el: &Elasticity, eps: &Vector3<f64>) -> Vector3<f64> {
    let tr = eps.sum();
    eps * (2.0 * el.mu) + Vector3::repeat(el.lambda * tr)
}

/// Principal Hencky strains of signed singular values; `None` if any is not positive.
#[inline]
pub fn strains(s: &Vector3<f64>) -> Option<Vector3<f64>> {
    if s.iter().all(|&x| x > 0.0 && x.is_finite()) {
        Some(s.map(f64::ln))
    } else {
        None
    }
}

/// Kirchhoff stress of `fe`, Pa. A degenerate `fe` (non-positive stretch) gives NaN, which
/// the step reports as a diverged marker.
pub fn kirchhoff(el: &Elasticity, fe: &Matrix3<f64>) -> Matrix3<f64> {
    let Some(svd) = SignedSvd::new(fe) else {
        return Matrix3::repeat(f64::NAN);
    };
    match strains(&svd.s) {
        Some(eps) => svd.compose_left(&principal_stress(el, &eps)),
        None => Matrix3::repeat(f64::NAN),
    }
}

/// Energy per reference volume, J/m^3.
pub fn energy_density(el: &Elasticity, fe: &Matrix3<f64>) -> f64 {
    let Some(eps) = SignedSvd::new(fe).and_then(|s| strains(&s.s)) else {
        return f64::NAN;
    };
    el.mu * eps.norm_squared() + 0.5 * el.lambda * eps.sum().powi(2)
}

/// The deviatoric part and the trace of `v`.
#[inline]
pub fn split(v: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let tr = v.sum();
    (v - Vector3::repeat(tr / 3.0), tr)
}

/// The return mapping of `(F_E trial, F_P)` for a plasticity model whose yield surface
/// lives in principal Hencky strains: `ret` maps the trial strains `eps = ln s` onto the
/// surface (or leaves them), and the plastic part takes what the elastic part gave up,
/// `F_E = U diag(exp eps') V^T`, `F_P = V diag(s / exp eps') V^T F_P`. `None` for a
/// degenerate `F_E`; an elastic step returns the input unchanged (same bits).
pub fn project(
    fe_trial: &Matrix3<f64>,
    fp: &Matrix3<f64>,
    ret: impl Fn(&Vector3<f64>) -> Vector3<f64>,
) -> Option<(Matrix3<f64>, Matrix3<f64>)> {
    let svd = SignedSvd::new(fe_trial)?;
    let eps = strains(&svd.s)?;
    let eps_new = ret(&eps);
    if eps_new == eps {
        return Some((*fe_trial, *fp));
    }
    let s_new = eps_new.map(f64::exp);
    Some((svd.compose(&s_new), svd.plastic_update(&s_new, fp)))
}
