//! The rotation-variant (signed) SVD of a 3x3 deformation gradient.
//!
//! `F = U diag(s) V^T` with `U`, `V` proper rotations (det +1); a reflection is carried by
//! the sign of the singular value of smallest magnitude (Irving, Teran & Fedkiw, "Invertible
//! finite elements for robust simulation of large deformation", SCA 2004). The polar
//! rotation is then `R = U V^T` for any `F`, also an inverted one.

use nalgebra::{Matrix3, Vector3};

/// A signed SVD: `F = u diag(s) v^T`, `u` and `v` rotations.
#[derive(Clone, Copy, Debug)]
pub struct SignedSvd {
    /// Left rotation.
    pub u: Matrix3<f64>,
    /// Signed singular values.
    pub s: Vector3<f64>,
    /// Right rotation.
    pub v: Matrix3<f64>,
}

impl SignedSvd {
    /// The signed SVD of `f`; `None` if the decomposition failed (non-finite input).
    pub fn new(f: &Matrix3<f64>) -> Option<Self> {
        if !f.iter().all(|x| x.is_finite()) {
            return None;
        }
        let svd = f.svd(true, true);
        let mut u = svd.u?;
        let mut v = svd.v_t?.transpose();
        let mut s = svd.singular_values;
        let k = s.imin();
        if u.determinant() < 0.0 {
            u.column_mut(k).neg_mut();
            s[k] = -s[k];
        }
        if v.determinant() < 0.0 {
            v.column_mut(k).neg_mut();
            s[k] = -s[k];
        }
        Some(Self { u, s, v })
    }

    /// `u diag(d) v^T`.
    pub fn compose(&self, d: &Vector3<f64>) -> Matrix3<f64> {
        self.u * Matrix3::from_diagonal(d) * self.v.transpose()
    }

    /// `u diag(d) u^T` (a Kirchhoff stress from principal values: it shares `F`'s left
    /// singular vectors for an isotropic material).
    pub fn compose_left(&self, d: &Vector3<f64>) -> Matrix3<f64> {
        self.u * Matrix3::from_diagonal(d) * self.u.transpose()
    }

    /// The plastic gradient after a return mapping that changed `s` into `s_new` with the
    /// same singular vectors: `F_P' = V diag(s / s_new) V^T F_P`, so that
    /// `F_E' F_P' = F_E F_P` (the total deformation is unchanged).
    pub fn plastic_update(&self, s_new: &Vector3<f64>, fp: &Matrix3<f64>) -> Matrix3<f64> {
        let r = Vector3::new(
            self.s[0] / s_new[0],
            self.s[1] / s_new[1],
            self.s[2] / s_new[2],
        );
        self.v * Matrix3::from_diagonal(&r) * self.v.transpose() * fp
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    #[test]
    fn reconstructs_including_inverted() {
        let r1 = Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
        let r2 = Rotation3::from_euler_angles(-0.7, 0.4, 0.9).into_inner();
        for d in [
            Vector3::new(1.2, 0.9, 0.8),
            Vector3::new(1.2, 0.9, -0.3),
            Vector3::new(1.0, 1.0, 1.0),
        ] {
            let f = r1 * Matrix3::from_diagonal(&d) * r2;
            let svd = SignedSvd::new(&f).unwrap();
            assert!((svd.compose(&svd.s) - f).norm() < 1e-12);
            assert!((svd.u.determinant() - 1.0).abs() < 1e-12);
            assert!((svd.v.determinant() - 1.0).abs() < 1e-12);
            assert!((svd.s.product() - f.determinant()).abs() < 1e-12);
        }
    }
}
