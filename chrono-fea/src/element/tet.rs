//! The linear 4-node tetrahedron with a St. Venant–Kirchhoff or a corotational linear
//! material.
//!
//! Four nodes with a position each (3 coordinates, see
//! [`SolidNode`](crate::node::SolidNode)): 12 coordinates `x = [x_0, x_1, x_2, x_3]`. The
//! shape functions are the barycentric coordinates; with the reference edge matrix
//! `D = [X_1 - X_0, X_2 - X_0, X_3 - X_0]` (reference positions `X_a`) the reference
//! gradients of the shape functions are the rows of `D^-1`,
//!
//! ```text
//! G_b = (D^-1)^T e_b  (b = 1, 2, 3),    G_0 = -(G_1 + G_2 + G_3)      [1/m]
//! ```
//!
//! and the reference volume is `V = det(D) / 6` (> 0: the edges `X_1 - X_0`,
//! `X_2 - X_0`, `X_3 - X_0` are right-handed).
//! Everything is constant over the element ("constant strain tetrahedron"):
//!
//! ```text
//! F = sum_a x_a G_a^T                       deformation gradient
//! E = (F^T F - I) / 2                       Green–Lagrange strain
//! S = lambda tr(E) I + 2 mu E               second Piola–Kirchhoff stress, Pa
//! U = V (lambda/2 tr(E)^2 + mu E:E)         strain energy, J
//! f_a = dU/dx_a = V F S G_a                 internal (elastic) force on node a, N
//! ```
//!
//! This is the St. Venant–Kirchhoff material: Hooke's law between the Green strain and
//! the second Piola–Kirchhoff stress. It is geometrically exact (rigid rotations of any
//! size give no strain and no force) and reduces to linear elasticity for small
//! strains; it is meant for large displacements with small strains (under strong
//! compression, `lambda_stretch < 1/sqrt(3)` in uniaxial compression, it softens and is
//! not a model of real material; see Bonet & Wood, *Nonlinear Continuum Mechanics for
//! Finite Element Analysis*, 2nd ed. 2008, sec. 6.4.1 and 9.4 for the element
//! quantities used here).
//!
//! The tangent stiffness `K = d f / d x` (material + geometric part), block `(a, b)`:
//!
//! ```text
//! K_ab = V [ (G_a . S G_b) I                        geometric (initial stress)
//!          + lambda g_a g_b^T + mu g_b g_a^T + mu (G_a . G_b) F F^T ]   material
//! g_a = F G_a
//! ```
//!
//! (from `dP = dF S + F dS`, `dS = lambda tr(dE) I + 2 mu dE`, `dE = sym(F^T dF)`,
//! `dF = dx_b G_b^T`). It is symmetric; at `F = I` it is the linear element stiffness
//! `V B^T C B`. Both `f` and `K` are checked against central differences of `U` and `f`
//! in the tests.
//!
//! # Corotational linear model
//!
//! With [`SolidModel::Corotational`] the element is the small-strain (linear) element
//! carried along by its rotation: with the polar decomposition `F = R U` (`R` a rotation,
//! `U` the symmetric stretch, from the SVD of `F`),
//!
//! ```text
//! eps = U - I                      corotated (Biot) strain
//! T   = lambda tr(eps) I + 2 mu eps
//! P   = R T                        first Piola–Kirchhoff stress
//! U_e = V (lambda/2 tr(eps)^2 + mu eps:eps),   f_a = V P G_a
//! ```
//!
//! For this isotropic law `f_a = V R T G_a` is exactly the corotational force
//! `R K_0 (R^T x - X)` of Chrono's `ChElementTetraCorot_4` (`K_0` the linear stiffness;
//! `R^T F - I = U - I` is symmetric, so the small-strain element sees exactly `eps`), and it is
//! the gradient of `U_e`. The tangent here is the consistent one, including the
//! derivative of the rotation (Chrono uses the approximation `R K_0 R^T`): with
//! `dF = dx_b G_b^T`, `W = R^T dF`, the spin `Omega = R^T dR` (skew, axial vector `w`)
//! solves `Omega U + U Omega = W - W^T`, i.e. `w = (tr(U) I - U)^-1 axial(W - W^T)`; then
//! `dU = W - Omega U`, `dT = lambda tr(dU) I + 2 mu dU` and `dP = R (Omega T + dT)`.
//! Checked against central differences like the St. Venant–Kirchhoff tangent. An
//! inverted element (`det F <= 0`) has no proper polar rotation: the decomposition then
//! takes the reflection out of the smallest singular direction, and the results are not
//! physical.
//!
//! Mass: consistent, `M_ab = rho V (1 + delta_ab) / 20 I_3` (exact integral of
//! `rho N_a N_b`; total `rho V`); gravity `f_a = rho V g / 4`.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::error::{FeaError, Result};
use crate::material::{SolidMaterial, SolidModel};

/// A 12-vector of tetrahedron coordinates or nodal forces `[x_0, x_1, x_2, x_3]`.
pub type TetVector = SVector<f64, 12>;
/// A 12 x 12 tetrahedron matrix (stiffness or mass).
pub type TetMatrix = SMatrix<f64, 12, 12>;

/// Relative volume below which a tetrahedron counts as degenerate: `|6 V| <= 1e-10 l^3`
/// with `l` its longest edge.
pub const DEGENERATE_VOLUME: f64 = 1e-10;

/// The linear 4-node tetrahedron, St. Venant–Kirchhoff or corotational (the material's
/// [`SolidModel`]; see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Tet4 {
    /// Global indices of the four nodes.
    pub nodes: [usize; 4],
    volume: f64,
    grad: [Vector3<f64>; 4],
    material: SolidMaterial,
}

impl Tet4 {
    /// Number of coordinates of the element.
    pub const NDOF: usize = 12;

    /// The element on `nodes` with reference positions `reference` (m). Errors (naming the
    /// nodes and the value): an invalid material, a degenerate reference shape
    /// (`|det D| <= 1e-10 l^3`, [`DEGENERATE_VOLUME`]), an inverted one (`det D < 0`: swap
    /// two nodes), a non-finite position.
    pub fn new(
        nodes: [usize; 4],
        reference: &[Vector3<f64>; 4],
        material: SolidMaterial,
    ) -> Result<Self> {
        material.validate()?;
        let label = || format!("tet {nodes:?}");
        if let Some(a) = reference
            .iter()
            .position(|x| !x.iter().all(|c| c.is_finite()))
        {
            return Err(FeaError::invalid(
                format!("{}.node[{a}].position", label()),
                format!("{:?}", reference[a]),
                "must be finite",
            ));
        }
        let d = Matrix3::from_columns(&[
            reference[1] - reference[0],
            reference[2] - reference[0],
            reference[3] - reference[0],
        ]);
        let det = d.determinant();
        let mut longest: f64 = 0.0;
        for a in 0..4 {
            for b in a + 1..4 {
                longest = longest.max((reference[b] - reference[a]).norm());
            }
        }
        if det.abs() <= DEGENERATE_VOLUME * longest.powi(3) {
            return Err(FeaError::invalid(
                format!("{}.volume", label()),
                det / 6.0,
                format!(
                    "degenerate tetrahedron: |6 V| must exceed {DEGENERATE_VOLUME:e} l^3 (l = {longest} m, the longest edge)"
                ),
            ));
        }
        if det < 0.0 {
            return Err(FeaError::invalid(
                format!("{}.volume", label()),
                det / 6.0,
                "inverted tetrahedron: (X1-X0, X2-X0, X3-X0) must be right-handed (swap two nodes)",
            ));
        }
        let inv = d.try_inverse().ok_or_else(|| {
            FeaError::invalid(format!("{}.volume", label()), det / 6.0, "singular shape")
        })?;
        let g1 = inv.row(0).transpose();
        let g2 = inv.row(1).transpose();
        let g3 = inv.row(2).transpose();
        Ok(Self {
            nodes,
            volume: det / 6.0,
            grad: [-(g1 + g2 + g3), g1, g2, g3],
            material,
        })
    }

    /// Reference volume `V`, m^3.
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Reference gradients `G_a` of the four shape functions, 1/m.
    pub fn shape_gradients(&self) -> &[Vector3<f64>; 4] {
        &self.grad
    }

    /// The material.
    pub fn material(&self) -> &SolidMaterial {
        &self.material
    }

    /// Deformation gradient `F = sum_a x_a G_a^T` for the current coordinates `x`.
    pub fn deformation_gradient(&self, x: &TetVector) -> Matrix3<f64> {
        let mut f = Matrix3::zeros();
        for a in 0..4 {
            let xa = x.fixed_rows::<3>(3 * a);
            f += xa * self.grad[a].transpose();
        }
        f
    }

    /// Green–Lagrange strain `E = (F^T F - I) / 2`, -.
    pub fn green_strain(&self, x: &TetVector) -> Matrix3<f64> {
        let f = self.deformation_gradient(x);
        0.5 * (f.transpose() * f - Matrix3::identity())
    }

    /// Second Piola–Kirchhoff stress `S = lambda tr(E) I + 2 mu E` of a Green strain, Pa.
    pub fn pk2_stress_of(&self, e: &Matrix3<f64>) -> Matrix3<f64> {
        let (lambda, mu) = self.material.lame();
        Matrix3::identity() * (lambda * e.trace()) + e * (2.0 * mu)
    }

    /// The strain the material's Hooke law acts on: the Green strain `E` (St. Venant–
    /// Kirchhoff) or the corotated stretch `U - I` (corotational), with the rotation `R`
    /// of the polar decomposition (identity for St. Venant–Kirchhoff, where it is unused).
    fn model_strain(&self, f: &Matrix3<f64>) -> (Matrix3<f64>, Matrix3<f64>) {
        match self.material.model {
            SolidModel::StVenantKirchhoff => (
                Matrix3::identity(),
                0.5 * (f.transpose() * f - Matrix3::identity()),
            ),
            SolidModel::Corotational => {
                let (r, u) = polar(f);
                (r, u - Matrix3::identity())
            }
        }
    }

    /// First Piola–Kirchhoff stress `P(F)` of the material model for a deformation
    /// gradient `f`: `F S` (St. Venant–Kirchhoff) or `R T` (corotational), Pa.
    pub fn first_piola_of(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let (r, eps) = self.model_strain(f);
        let t = self.pk2_stress_of(&eps);
        match self.material.model {
            SolidModel::StVenantKirchhoff => f * t,
            SolidModel::Corotational => r * t,
        }
    }

    /// First Piola–Kirchhoff stress `P` (force per reference area), Pa.
    pub fn first_piola_stress(&self, x: &TetVector) -> Matrix3<f64> {
        self.first_piola_of(&self.deformation_gradient(x))
    }

    /// Second Piola–Kirchhoff stress `S = F^-1 P`, Pa (for St. Venant–Kirchhoff the
    /// Hooke stress of the Green strain itself).
    pub fn pk2_stress(&self, x: &TetVector) -> Matrix3<f64> {
        let f = self.deformation_gradient(x);
        match self.material.model {
            SolidModel::StVenantKirchhoff => {
                self.pk2_stress_of(&(0.5 * (f.transpose() * f - Matrix3::identity())))
            }
            SolidModel::Corotational => {
                f.try_inverse()
                    .unwrap_or_else(|| Matrix3::from_element(f64::NAN))
                    * self.first_piola_of(&f)
            }
        }
    }

    /// Cauchy (true) stress `sigma = P F^T / det F`, Pa. `det F <= 0` (an inverted
    /// element) gives non-finite or meaningless values; check [`jacobian`](Self::jacobian).
    pub fn cauchy_stress(&self, x: &TetVector) -> Matrix3<f64> {
        let f = self.deformation_gradient(x);
        self.first_piola_of(&f) * f.transpose() / f.determinant()
    }

    /// Volume ratio `J = det F` (current / reference volume), -.
    pub fn jacobian(&self, x: &TetVector) -> f64 {
        self.deformation_gradient(x).determinant()
    }

    /// Strain energy `U = V (lambda/2 tr(e)^2 + mu e:e)` with `e` the Green strain
    /// (St. Venant–Kirchhoff) or the corotated stretch `U - I` (corotational), J.
    pub fn strain_energy(&self, x: &TetVector) -> f64 {
        let (_, e) = self.model_strain(&self.deformation_gradient(x));
        let (lambda, mu) = self.material.lame();
        self.volume * (0.5 * lambda * e.trace().powi(2) + mu * e.component_mul(&e).sum())
    }

    /// Internal force `f = dU/dx` and, if `tangent`, the tangent stiffness `K = df/dx`
    /// (material + geometric, see the module docs; zero matrix otherwise). No allocation.
    pub fn force_and_tangent(&self, x: &TetVector, tangent: bool) -> (TetVector, TetMatrix) {
        if self.material.model == SolidModel::Corotational {
            return self.corotational_force_and_tangent(x, tangent);
        }
        let f = self.deformation_gradient(x);
        let e = 0.5 * (f.transpose() * f - Matrix3::identity());
        let s = self.pk2_stress_of(&e);
        let v = self.volume;
        let p = f * s; // first Piola–Kirchhoff stress
        let mut q = TetVector::zeros();
        for a in 0..4 {
            q.fixed_rows_mut::<3>(3 * a)
                .copy_from(&(p * self.grad[a] * v));
        }
        let mut k = TetMatrix::zeros();
        if tangent {
            let (lambda, mu) = self.material.lame();
            let fft = f * f.transpose();
            let g: [Vector3<f64>; 4] = std::array::from_fn(|a| f * self.grad[a]);
            for a in 0..4 {
                let sga = s * self.grad[a];
                for b in 0..4 {
                    let geo = sga.dot(&self.grad[b]);
                    let gab = self.grad[a].dot(&self.grad[b]);
                    let blk = Matrix3::identity() * geo
                        + g[a] * g[b].transpose() * lambda
                        + g[b] * g[a].transpose() * mu
                        + fft * (mu * gab);
                    k.fixed_view_mut::<3, 3>(3 * a, 3 * b).copy_from(&(blk * v));
                }
            }
        }
        (q, k)
    }

    /// The corotational force `f_a = V R T G_a` and its consistent tangent (module docs).
    fn corotational_force_and_tangent(
        &self,
        x: &TetVector,
        tangent: bool,
    ) -> (TetVector, TetMatrix) {
        let f = self.deformation_gradient(x);
        let (r, u) = polar(&f);
        let t = self.pk2_stress_of(&(u - Matrix3::identity()));
        let p = r * t;
        let v = self.volume;
        let mut q = TetVector::zeros();
        for a in 0..4 {
            q.fixed_rows_mut::<3>(3 * a)
                .copy_from(&(p * self.grad[a] * v));
        }
        let mut k = TetMatrix::zeros();
        if tangent {
            // (tr U I - U) is positive definite for positive stretches.
            let m = (Matrix3::identity() * u.trace() - u)
                .try_inverse()
                .unwrap_or_else(|| Matrix3::from_element(f64::NAN));
            let rt = r.transpose();
            for b in 0..4 {
                for j in 0..3 {
                    // dF = e_j G_b^T, so W = R^T dF = (R^T e_j) G_b^T.
                    let w = rt.column(j) * self.grad[b].transpose();
                    let a_skew = w - w.transpose();
                    let axial = Vector3::new(a_skew[(2, 1)], a_skew[(0, 2)], a_skew[(1, 0)]);
                    let om = m * axial;
                    let omega = om.cross_matrix();
                    let du = w - omega * u;
                    let dt = self.pk2_stress_of(&du);
                    let dp = r * (omega * t + dt);
                    for a in 0..4 {
                        let col = dp * self.grad[a] * v;
                        for i in 0..3 {
                            k[(3 * a + i, 3 * b + j)] = col[i];
                        }
                    }
                }
            }
        }
        (q, k)
    }

    /// Consistent mass matrix `M_ab = rho V (1 + delta_ab) / 20 I_3`, kg.
    pub fn mass_matrix(&self) -> TetMatrix {
        let m = self.material.density * self.volume / 20.0;
        let mut out = TetMatrix::zeros();
        for a in 0..4 {
            for b in 0..4 {
                let w = if a == b { 2.0 * m } else { m };
                for i in 0..3 {
                    out[(3 * a + i, 3 * b + i)] = w;
                }
            }
        }
        out
    }

    /// Mass `rho V`, kg.
    pub fn mass(&self) -> f64 {
        self.material.density * self.volume
    }

    /// Gravity force `f_a = rho V g / 4` on each node (`g` in m/s^2), N.
    pub fn gravity_force(&self, gravity: &Vector3<f64>) -> TetVector {
        let w = gravity * (self.mass() / 4.0);
        let mut out = TetVector::zeros();
        for a in 0..4 {
            out.fixed_rows_mut::<3>(3 * a).copy_from(&w);
        }
        out
    }
}

/// Polar decomposition `F = R U` (`R` a rotation, `U` symmetric) from the SVD
/// `F = W Sigma V^T`: `R = W V^T`, with the last singular direction flipped when
/// `det F < 0` so that `R` stays a rotation; `U = R^T F` (symmetrized).
pub fn polar(f: &Matrix3<f64>) -> (Matrix3<f64>, Matrix3<f64>) {
    let svd = f.svd(true, true);
    let (Some(mut w), Some(vt)) = (svd.u, svd.v_t) else {
        let nan = Matrix3::from_element(f64::NAN);
        return (nan, nan);
    };
    if (w * vt).determinant() < 0.0 {
        // Flip the direction of the smallest singular value.
        let (k, _) = svd.singular_values.argmin();
        let c = -w.column(k);
        w.set_column(k, &c);
    }
    let r = w * vt;
    let u = r.transpose() * f;
    (r, 0.5 * (u + u.transpose()))
}

/// Von Mises equivalent stress of a (symmetric) stress tensor,
/// `sqrt(3/2 s:s)` with `s` the deviator, Pa.
pub fn von_mises(sigma: &Matrix3<f64>) -> f64 {
    let dev = sigma - Matrix3::identity() * (sigma.trace() / 3.0);
    (1.5 * dev.component_mul(&dev).sum()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn material() -> SolidMaterial {
        SolidMaterial::new(2.0e9, 0.3, 1200.0, 0.0).unwrap()
    }

    fn both() -> [SolidMaterial; 2] {
        [material(), material().with_model(SolidModel::Corotational)]
    }

    fn reference() -> [Vector3<f64>; 4] {
        [
            Vector3::new(0.1, -0.05, 0.02),
            Vector3::new(1.2, 0.1, -0.1),
            Vector3::new(0.3, 0.9, 0.15),
            Vector3::new(0.2, 0.25, 1.1),
        ]
    }

    fn coords(x: &[Vector3<f64>; 4]) -> TetVector {
        TetVector::from_fn(|i, _| x[i / 3][i % 3])
    }

    /// A deformed state with finite strain and rotation.
    fn deformed() -> TetVector {
        let r = reference();
        let rot = Rotation3::from_euler_angles(0.4, -0.3, 0.8);
        let shift = [
            Vector3::new(0.02, -0.01, 0.03),
            Vector3::new(-0.05, 0.04, 0.0),
            Vector3::new(0.01, 0.06, -0.02),
            Vector3::new(0.0, -0.03, 0.07),
        ];
        coords(&std::array::from_fn(|a| {
            rot * (r[a] + shift[a]) + Vector3::new(1.0, 2.0, 3.0)
        }))
    }

    #[test]
    fn gradients_partition_unity_and_volume() {
        let r = reference();
        let el = Tet4::new([0, 1, 2, 3], &r, material()).unwrap();
        // sum_a G_a = 0 and sum_a X_a G_a^T = I.
        let sum: Vector3<f64> = el.grad.iter().sum();
        assert!(sum.norm() < 1e-14);
        let f = el.deformation_gradient(&coords(&r));
        assert!((f - Matrix3::identity()).norm() < 1e-14);
        let d = Matrix3::from_columns(&[r[1] - r[0], r[2] - r[0], r[3] - r[0]]);
        assert!((el.volume() - d.determinant() / 6.0).abs() < 1e-15);
        let m = el.mass_matrix();
        // Total mass rho V along each axis; a row sums to the node's lumped share V/4.
        assert!((m.sum() / 3.0 / el.mass() - 1.0).abs() < 1e-14);
        let row: f64 = (0..12).map(|j| m[(0, j)]).sum();
        assert!((row / (el.mass() / 4.0) - 1.0).abs() < 1e-14, "{row}");
    }

    #[test]
    fn rigid_motion_gives_no_force() {
        let r = reference();
        for m in both() {
            let el = Tet4::new([0, 1, 2, 3], &r, m).unwrap();
            let rot = Rotation3::from_euler_angles(1.1, -0.7, 2.5);
            let x = coords(&std::array::from_fn(|a| {
                rot * r[a] + Vector3::new(5.0, -3.0, 2.0)
            }));
            let (q, _) = el.force_and_tangent(&x, false);
            assert!(q.norm() < 1e-15 * 2.0e9, "{:?}: {}", m.model, q.norm());
            assert!(el.strain_energy(&x).abs() < 1e-20 * 2.0e9);
        }
    }

    #[test]
    fn force_is_gradient_of_energy() {
        let r = reference();
        for m in both() {
            let el = Tet4::new([0, 1, 2, 3], &r, m).unwrap();
            let x = deformed();
            let (q, _) = el.force_and_tangent(&x, false);
            let h = 1e-6;
            let mut fd = TetVector::zeros();
            for i in 0..12 {
                let (mut xp, mut xm) = (x, x);
                xp[i] += h;
                xm[i] -= h;
                fd[i] = (el.strain_energy(&xp) - el.strain_energy(&xm)) / (2.0 * h);
            }
            let err = (q - fd).amax() / q.amax();
            assert!(err < 1e-7, "{:?}: force vs dU/dx: {err:e}", m.model);
        }
    }

    #[test]
    fn tangent_is_jacobian_of_force() {
        let r = reference();
        for m in both() {
            let el = Tet4::new([0, 1, 2, 3], &r, m).unwrap();
            for x in [coords(&r), deformed()] {
                let (_, k) = el.force_and_tangent(&x, true);
                assert!((k - k.transpose()).amax() < 1e-12 * k.amax());
                let h = 1e-7;
                let mut fd = TetMatrix::zeros();
                for j in 0..12 {
                    let (mut xp, mut xm) = (x, x);
                    xp[j] += h;
                    xm[j] -= h;
                    let col = (el.force_and_tangent(&xp, false).0
                        - el.force_and_tangent(&xm, false).0)
                        / (2.0 * h);
                    fd.set_column(j, &col);
                }
                let err = (k - fd).amax() / k.amax();
                assert!(err < 1e-7, "{:?}: tangent vs df/dx: {err:e}", m.model);
                // The geometric part matters in the deformed state: dropping it fails.
                let s = el.pk2_stress(&x);
                if m.model == SolidModel::StVenantKirchhoff && s.amax() > 1e-6 * el.material.young {
                    let mut kmat = k;
                    for a in 0..4 {
                        for b in 0..4 {
                            let geo = (s * el.grad[a]).dot(&el.grad[b]) * el.volume;
                            for i in 0..3 {
                                kmat[(3 * a + i, 3 * b + i)] -= geo;
                            }
                        }
                    }
                    assert!((kmat - fd).amax() / k.amax() > 1e-4);
                }
                // Chrono's approximate corotational tangent R K0 R^T misses the rotation
                // derivative: in the deformed state it differs from the FD Jacobian.
                if m.model == SolidModel::Corotational && x != coords(&r) {
                    let f = el.deformation_gradient(&x);
                    let (rot, _) = polar(&f);
                    let k0 = Tet4::new([0, 1, 2, 3], &r, material())
                        .unwrap()
                        .force_and_tangent(&coords(&r), true)
                        .1;
                    let mut rr = TetMatrix::zeros();
                    for a in 0..4 {
                        rr.fixed_view_mut::<3, 3>(3 * a, 3 * a).copy_from(&rot);
                    }
                    let approx = rr * k0 * rr.transpose();
                    assert!((approx - fd).amax() / k.amax() > 1e-3);
                }
            }
        }
    }

    #[test]
    fn corotational_is_rotated_linear_elasticity() {
        // F = R (I + eps) with a symmetric small strain: P = R (lambda tr eps I + 2 mu eps)
        // exactly, and at small strain both models give the same force.
        let r = reference();
        let m = material().with_model(SolidModel::Corotational);
        let el = Tet4::new([0, 1, 2, 3], &r, m).unwrap();
        let rot = *Rotation3::from_euler_angles(0.9, 0.2, -1.4).matrix();
        let eps = Matrix3::new(2e-3, 5e-4, 0.0, 5e-4, -1e-3, 3e-4, 0.0, 3e-4, 1e-3);
        let f = rot * (Matrix3::identity() + eps);
        let x = coords(&std::array::from_fn(|a| f * r[a]));
        let p = el.first_piola_stress(&x);
        let expected = rot * el.pk2_stress_of(&eps);
        assert!(
            (p - expected).amax() < 1e-12 * expected.amax(),
            "{p} vs {expected}"
        );
        let svk = Tet4::new([0, 1, 2, 3], &r, material()).unwrap();
        let (qc, _) = el.force_and_tangent(&x, false);
        let (qs, _) = svk.force_and_tangent(&x, false);
        assert!((qc - qs).amax() < 5e-3 * qs.amax());
    }

    #[test]
    fn small_strain_matches_linear_elasticity() {
        // Uniaxial stretch eps along x with free lateral contraction: sigma_xx = E eps.
        let r = reference();
        let m = material();
        let el = Tet4::new([0, 1, 2, 3], &r, m).unwrap();
        let eps = 1e-7;
        let lat = -m.poisson * eps;
        let h = Matrix3::from_diagonal(&Vector3::new(eps, lat, lat));
        let x = coords(&std::array::from_fn(|a| r[a] + h * r[a]));
        let sigma = el.cauchy_stress(&x);
        assert!((sigma[(0, 0)] / (m.young * eps) - 1.0).abs() < 1e-6);
        assert!(sigma[(1, 1)].abs() < 1e-6 * m.young * eps);
        assert!((von_mises(&sigma) / sigma[(0, 0)] - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_shapes_and_materials_are_rejected() {
        let r = reference();
        let mut flat = r;
        flat[3] = (r[0] + r[1] + r[2]) / 3.0;
        let e = Tet4::new([4, 5, 6, 7], &flat, material())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tet [4, 5, 6, 7].volume") && e.contains("degenerate"),
            "{e}"
        );
        let inverted = [r[0], r[2], r[1], r[3]];
        let e = Tet4::new([0, 2, 1, 3], &inverted, material())
            .unwrap_err()
            .to_string();
        assert!(e.contains("volume") && e.contains("inverted"), "{e}");
        let e = SolidMaterial::new(-1.0, 0.3, 1.0, 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("material.young") && e.contains("-1"), "{e}");
        for nu in [0.5, -1.0, 0.7, f64::NAN] {
            let e = SolidMaterial::new(1.0, nu, 1.0, 0.0)
                .unwrap_err()
                .to_string();
            assert!(e.contains("material.poisson"), "{e}");
        }
        let e = SolidMaterial::new(1.0, 0.3, 0.0, 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("material.density"), "{e}");
    }
}
