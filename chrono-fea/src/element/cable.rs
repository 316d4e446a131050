//! The gradient-deficient ANCF cable/beam element.
//!
//! Gerstmayr, J. & Shabana, A. A. (2006), "Analysis of thin beams and cables using the
//! absolute nodal co-ordinate formulation", Nonlinear Dynamics 45: 109–130.
//!
//! Two nodes `A`, `B`, each with a position `r` and a slope `r_x` (see
//! [`GradientNode`](crate::node::GradientNode)): 12 coordinates
//! `e = [r_A, r_x,A, r_B, r_x,B]`. With `xi = x / L` in `[0, 1]` along the reference
//! length `L`, the centre line is the cubic Hermite interpolation
//!
//! ```text
//! r(x) = S1 r_A + S2 r_x,A + S3 r_B + S4 r_x,B
//! S1 = 1 - 3 xi^2 + 2 xi^3     S2 = L (xi - 2 xi^2 + xi^3)
//! S3 = 3 xi^2 - 2 xi^3         S4 = L (xi^3 - xi^2)
//! ```
//!
//! Strain energy (Euler–Bernoulli: no shear, no torsion, no cross-section deformation):
//!
//! ```text
//! U = 1/2 ∫_0^L [ E A eps^2 + E I kappa^2 ] dx
//! eps   = (r_x . r_x - 1) / 2                       (Green strain of the centre line)
//! kappa = |r_x x r_xx| / |r_x|^3                    (exact curvature)
//! ```
//!
//! The exact curvature is used, not the simplified `kappa ~ |r_xx|`: `r_xx` also holds the
//! rate of change of the stretch `d|r_x|/dx`, which the simplified form would count as
//! bending; with the exact form a stretched but straight element has no bending energy
//! (tested), and the large-deflection cantilever needs no small-strain assumption. It is
//! the "elastic line" curvature of Gerstmayr & Shabana (2006), eq. for `kappa` in sec. 3.
//! `kappa^2 = f / g^3` with `f = |a|^2 |b|^2 - (a.b)^2`, `g = |a|^2`, `a = r_x`,
//! `b = r_xx`, so its derivatives are rational and the tangent stiffness is exact.
//!
//! The internal force is `Q = dU/de` (the force the element needs at its nodes to be in
//! this shape; static equilibrium is `Q = F_ext`) and the tangent stiffness
//! `K = d^2U/de^2` (symmetric), both in closed form (checked against central finite
//! differences in the tests). The reference configuration must be straight and stress
//! free: unit slopes along the chord, `L` the node distance (checked by the mesh).
//!
//! Quadrature ([`CableQuadrature`]): Gauss–Legendre with 5 points for the axial term by
//! default — `eps` is quartic in `xi`, so `eps^2`, its gradient and Hessian are
//! polynomials of degree 8, integrated exactly — and 4 points for the rational bending
//! term (exact at the straight state, where it is quadratic). The consistent mass
//! `M = rho A ∫ S^T S dx` has a degree-6 integrand: 4 points, exact.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::error::{FeaError, Result, positive};
use crate::material::BeamMaterial;
use crate::quadrature::gauss_unit;

/// A 12-vector of element coordinates or forces `[r_A, r_x,A, r_B, r_x,B]`.
pub type ElementVector = SVector<f64, 12>;
/// A 12 x 12 element matrix (stiffness or mass).
pub type ElementMatrix = SMatrix<f64, 12, 12>;

/// Numbers of Gauss points along the element for each energy term.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CableQuadrature {
    /// Points for the axial (Green strain) term, 1..=5; 5 is exact.
    pub axial: usize,
    /// Points for the bending (curvature) term, 1..=5.
    pub bending: usize,
}

impl Default for CableQuadrature {
    fn default() -> Self {
        Self {
            axial: 5,
            bending: 4,
        }
    }
}

impl CableQuadrature {
    fn validate(&self) -> Result<()> {
        for (field, n) in [
            ("quadrature.axial", self.axial),
            ("quadrature.bending", self.bending),
        ] {
            if !(1..=5).contains(&n) {
                return Err(FeaError::invalid(field, n, "must be in 1..=5"));
            }
        }
        Ok(())
    }
}

/// One gradient-deficient ANCF cable/beam element (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct AncfCable {
    /// The two node indices in the mesh.
    pub nodes: [usize; 2],
    length: f64,
    material: BeamMaterial,
    quadrature: CableQuadrature,
}

/// Shape functions of the cubic Hermite interpolation at `xi` for an element of length
/// `l`: values, first and second derivatives with respect to `x = xi l`.
pub fn hermite(xi: f64, l: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let s = [
        1.0 - 3.0 * x2 + 2.0 * x3,
        l * (xi - 2.0 * x2 + x3),
        3.0 * x2 - 2.0 * x3,
        l * (x3 - x2),
    ];
    let sx = [
        (-6.0 * xi + 6.0 * x2) / l,
        1.0 - 4.0 * xi + 3.0 * x2,
        (6.0 * xi - 6.0 * x2) / l,
        3.0 * x2 - 2.0 * xi,
    ];
    let sxx = [
        (-6.0 + 12.0 * xi) / (l * l),
        (-4.0 + 6.0 * xi) / l,
        (6.0 - 12.0 * xi) / (l * l),
        (6.0 * xi - 2.0) / l,
    ];
    (s, sx, sxx)
}

/// `sum_k w[k] e_k` with `e_k` the k-th 3-block of `e`.
fn combine(w: &[f64; 4], e: &ElementVector) -> Vector3<f64> {
    let mut v = Vector3::zeros();
    for k in 0..4 {
        v += w[k] * Vector3::new(e[3 * k], e[3 * k + 1], e[3 * k + 2]);
    }
    v
}

fn add_block(m: &mut ElementMatrix, k: usize, l: usize, b: &Matrix3<f64>) {
    let mut view = m.fixed_view_mut::<3, 3>(3 * k, 3 * l);
    view += b;
}

fn add_vec(v: &mut ElementVector, k: usize, x: &Vector3<f64>) {
    let mut view = v.fixed_rows_mut::<3>(3 * k);
    view += x;
}

/// The bending energy density factor `phi = kappa^2 = f / g^3` and its first and second
/// derivatives with respect to `a = r_x` and `b = r_xx`.
struct Curvature {
    phi: f64,
    da: Vector3<f64>,
    db: Vector3<f64>,
    daa: Matrix3<f64>,
    dab: Matrix3<f64>,
    dbb: Matrix3<f64>,
}

fn curvature(a: &Vector3<f64>, b: &Vector3<f64>, hessian: bool) -> Curvature {
    let g = a.dot(a);
    let bb = b.dot(b);
    let ab = a.dot(b);
    let f = g * bb - ab * ab;
    let (g3, g4) = (g * g * g, g * g * g * g);
    // f_a = 2 a (b.b) - 2 (a.b) b,  f_b = 2 b (a.a) - 2 (a.b) a,  g_a = 2 a.
    let fa = 2.0 * bb * a - 2.0 * ab * b;
    let fb = 2.0 * g * b - 2.0 * ab * a;
    let phi = f / g3;
    let da = fa / g3 - 6.0 * f / g4 * a;
    let db = fb / g3;
    let (mut daa, mut dab, mut dbb) = (Matrix3::zeros(), Matrix3::zeros(), Matrix3::zeros());
    if hessian {
        let id = Matrix3::identity();
        let g5 = g4 * g;
        // f_aa = 2 (b.b) I - 2 b b^T;  f_bb = 2 (a.a) I - 2 a a^T;
        // f_ab[i][j] = d2f / da_i db_j = 4 a b^T - 2 b a^T - 2 (a.b) I.
        let faa = 2.0 * bb * id - 2.0 * b * b.transpose();
        let fbb = 2.0 * g * id - 2.0 * a * a.transpose();
        let fab = 4.0 * a * b.transpose() - 2.0 * b * a.transpose() - 2.0 * ab * id;
        // phi = f g^-3 with g_a = 2 a, g_aa = 2 I.
        daa = faa / g3 - 6.0 / g4 * (fa * a.transpose() + a * fa.transpose())
            + 48.0 * f / g5 * a * a.transpose()
            - 6.0 * f / g4 * id;
        dab = fab / g3 - 6.0 / g4 * a * fb.transpose();
        dbb = fbb / g3;
    }
    Curvature {
        phi,
        da,
        db,
        daa,
        dab,
        dbb,
    }
}

impl AncfCable {
    /// Number of coordinates of the element.
    pub const NDOF: usize = 12;

    /// An element between mesh nodes `nodes` with reference length `length` (m).
    pub fn new(
        nodes: [usize; 2],
        length: f64,
        material: BeamMaterial,
        quadrature: CableQuadrature,
    ) -> Result<Self> {
        positive("element.length", length)?;
        material.validate()?;
        quadrature.validate()?;
        Ok(Self {
            nodes,
            length,
            material,
            quadrature,
        })
    }

    /// Reference length `L`, m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The material and section.
    pub fn material(&self) -> &BeamMaterial {
        &self.material
    }

    /// The quadrature orders.
    pub fn quadrature(&self) -> CableQuadrature {
        self.quadrature
    }

    /// Axial (Green) strain `eps = (|r_x|^2 - 1) / 2` and curvature `kappa` (1/m) at `xi`.
    pub fn strain_and_curvature(&self, e: &ElementVector, xi: f64) -> (f64, f64) {
        let (_, sx, sxx) = hermite(xi, self.length);
        let a = combine(&sx, e);
        let b = combine(&sxx, e);
        let c = curvature(&a, &b, false);
        (0.5 * (a.dot(&a) - 1.0), c.phi.max(0.0).sqrt())
    }

    /// Strain energy `U(e)`, J.
    pub fn strain_energy(&self, e: &ElementVector) -> f64 {
        let (ea, ei, l) = (
            self.material.axial_stiffness(),
            self.material.bending_stiffness(),
            self.length,
        );
        let mut u = 0.0;
        for &(xi, w) in gauss_unit(self.quadrature.axial) {
            let (_, sx, _) = hermite(xi, l);
            let a = combine(&sx, e);
            let eps = 0.5 * (a.dot(&a) - 1.0);
            u += 0.5 * ea * eps * eps * w * l;
        }
        for &(xi, w) in gauss_unit(self.quadrature.bending) {
            let (_, sx, sxx) = hermite(xi, l);
            let c = curvature(&combine(&sx, e), &combine(&sxx, e), false);
            u += 0.5 * ei * c.phi * w * l;
        }
        u
    }

    /// Internal force `Q = dU/de` (N for the position rows, N m for the slope rows).
    pub fn internal_force(&self, e: &ElementVector) -> ElementVector {
        self.force_and_tangent(e, false).0
    }

    /// Internal force `Q = dU/de` and, if `tangent`, the tangent stiffness
    /// `K = d^2U/de^2` (exact, symmetric); otherwise the matrix is zero.
    ///
    /// Axial term at a Gauss point: `dW/da = E A eps a`, `d2W/da2 = E A (a a^T + eps I)`.
    /// Bending term: `W = E I phi / 2` with the derivatives of `phi = f / g^3` (module
    /// docs). Both are pulled back with `a = sum_k S'_k e_k`, `b = sum_k S''_k e_k`.
    pub fn force_and_tangent(
        &self,
        e: &ElementVector,
        tangent: bool,
    ) -> (ElementVector, ElementMatrix) {
        let (ea, ei, l) = (
            self.material.axial_stiffness(),
            self.material.bending_stiffness(),
            self.length,
        );
        let mut q = ElementVector::zeros();
        let mut k = ElementMatrix::zeros();
        for &(xi, w) in gauss_unit(self.quadrature.axial) {
            let (_, sx, _) = hermite(xi, l);
            let a = combine(&sx, e);
            let eps = 0.5 * (a.dot(&a) - 1.0);
            let wl = w * l;
            let fa = (wl * ea * eps) * a;
            for i in 0..4 {
                add_vec(&mut q, i, &(sx[i] * fa));
            }
            if tangent {
                let h = wl * ea * (a * a.transpose() + eps * Matrix3::identity());
                for i in 0..4 {
                    for j in 0..4 {
                        add_block(&mut k, i, j, &(sx[i] * sx[j] * h));
                    }
                }
            }
        }
        for &(xi, w) in gauss_unit(self.quadrature.bending) {
            let (_, sx, sxx) = hermite(xi, l);
            let a = combine(&sx, e);
            let b = combine(&sxx, e);
            let c = curvature(&a, &b, tangent);
            let s = 0.5 * ei * w * l;
            for i in 0..4 {
                add_vec(&mut q, i, &(s * (sx[i] * c.da + sxx[i] * c.db)));
            }
            if tangent {
                let dba = c.dab.transpose();
                for i in 0..4 {
                    for j in 0..4 {
                        let blk = sx[i] * sx[j] * c.daa
                            + sx[i] * sxx[j] * c.dab
                            + sxx[i] * sx[j] * dba
                            + sxx[i] * sxx[j] * c.dbb;
                        add_block(&mut k, i, j, &(s * blk));
                    }
                }
            }
        }
        (q, k)
    }

    /// Tangent stiffness `K = d^2U/de^2`, N/m (position rows and columns).
    pub fn tangent_stiffness(&self, e: &ElementVector) -> ElementMatrix {
        self.force_and_tangent(e, true).1
    }

    /// Consistent mass matrix `M = rho A ∫_0^L S^T S dx` (constant in ANCF), kg.
    pub fn mass_matrix(&self) -> ElementMatrix {
        let (rho_a, l) = (self.material.mass_per_length(), self.length);
        let mut m = ElementMatrix::zeros();
        for &(xi, w) in gauss_unit(4) {
            let (s, _, _) = hermite(xi, l);
            for i in 0..4 {
                for j in 0..4 {
                    add_block(
                        &mut m,
                        i,
                        j,
                        &(rho_a * w * l * s[i] * s[j] * Matrix3::identity()),
                    );
                }
            }
        }
        m
    }

    /// Generalized gravity force `Q_g = ∫ rho A S^T g dx = rho A L g [1/2, L/12, 1/2, -L/12]`
    /// (per 3-block), N and N m.
    pub fn gravity_force(&self, gravity: &Vector3<f64>) -> ElementVector {
        let (rho_a, l) = (self.material.mass_per_length(), self.length);
        let mut q = ElementVector::zeros();
        let w = [0.5, l / 12.0, 0.5, -l / 12.0];
        for i in 0..4 {
            add_vec(&mut q, i, &(rho_a * l * w[i] * gravity));
        }
        q
    }

    /// Position `r(xi)` on the centre line, m.
    pub fn position_at(&self, e: &ElementVector, xi: f64) -> Vector3<f64> {
        combine(&hermite(xi, self.length).0, e)
    }
}
