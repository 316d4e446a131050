//! The fully parameterized 3D ANCF beam element, with a structural-mechanics strain
//! energy, the shear and cross-section strains sampled at the nodes (the locking
//! remedy), a curved (pre-shaped) reference configuration and torsion.
//!
//! Nodes carry 12 coordinates `[r, r_x, r_y, r_z]` ([`BeamNode`](crate::node::BeamNode)):
//! the position and the three position gradients, as in the element of Shabana & Yakoub
//! (2001, "Three dimensional absolute nodal coordinate formulation for beam elements",
//! J. Mech. Design 123: 606–621). With `xi = x / L` in `[0, 1]` (`L` the reference
//! parameter length, about the arc length) the position field is
//!
//! ```text
//! r(x, y, z) = r_c(x) + y a(x) + z b(x)
//! r_c = h1 r_A + L h2 r_x,A + h3 r_B + L h4 r_x,B        (cubic Hermite centre line)
//! a   = (1 - xi) r_y,A + xi r_y,B,   b = (1 - xi) r_z,A + xi r_z,B   (linear)
//! h1 = 1 - 3 xi^2 + 2 xi^3, h2 = xi - 2 xi^2 + xi^3, h3 = 3 xi^2 - 2 xi^3, h4 = xi^3 - xi^2
//! ```
//!
//! ## Strain energy (structural mechanics approach)
//!
//! The continuum-mechanics energy of this element (St. Venant–Kirchhoff over the volume)
//! locks: its bending curvature comes from `a'`, `b'` (constant per element) while the
//! shear ties them to the cubic centre line; the linear cross-section cannot contract
//! (Poisson locking); its torsion stiffness is the polar moment `I_y + I_z`, not `J`.
//! Following the structural-mechanics idea of Gerstmayr, Matikainen & Mikkola (2008, "A
//! geometrically exact beam element based on the absolute nodal coordinate formulation",
//! Multibody Syst. Dyn. 20: 359–384) and Nachbagauer, Gruber & Gerstmayr (2013,
//! "Structural and continuum mechanics approaches for a 3D shear deformable ANCF beam
//! finite element", J. Comput. Nonlinear Dyn. 8: 021004), the energy is written with
//! beam strains of the centre line `t = r_c'`, its derivative `t' = r_c''` and the
//! cross-section vectors `a`, `b` (`'` = `d/dx`; `0`: reference; `l0 = |t0|`,
//! `na = |a0|`, `nb = |b0|`; the strain definitions are this crate's own):
//!
//! ```text
//! eps  = (t.t - t0.t0) / (2 l0^2)                              axial        E A
//! K_z  = (t'.a / |a| - t0'.a0 / na) / l0^2                     bending (y)  E I_z
//! K_y  = (t'.b / |b| - t0'.b0 / nb) / l0^2                     bending (z)  E I_y
//! K_x  = ((a'.b - b'.a) / |a||b| - (a0'.b0 - b0'.a0) / na nb) / (2 l0)   twist  G J
//! g_y  = (t.a - t0.a0) / (l0 na),  g_z likewise                shear        k G A
//! e_yy = (a.a - a0.a0) / (2 na^2), e_zz likewise               section      E A
//! g_yz = (a.b - a0.b0) / (na nb)                               section      G A
//! U = 1/2 ∫ sum_s C_s s^2 l0 dx
//! ```
//!
//! For an orthonormal frame `(t, a, b)` these are the material strains of Reissner's
//! (Simo's) geometrically exact beam: `K_z = t'.a` and `K_y = -b'.t` are the bending
//! curvatures, `K_x = a'.b` the twist. Each is built from dot products and lengths of
//! deformed vectors, so any rigid motion leaves every strain (and the force) zero, and
//! the reference configuration — straight or curved — is stress free by construction.
//! Bending is carried by the cubic centre line (`t'` is linear in `xi`), so a tip-loaded
//! cantilever is represented exactly, as in an Euler–Bernoulli element. The transverse
//! shear strain ties the section vectors to the centre line (its stiffness `k G A` acts
//! on the tilt of the section) but does not add deflection: the centre line bends like
//! an Euler–Bernoulli beam, which slender beams are (Timoshenko's shear term
//! `3 E I / (k G A L^2)` is `1e-4` at `L / h = 100`); thick beams come out too stiff by
//! that term. The curvatures
//! and the twist divide by the current `|a|`, `|b|`: the linear interpolation of two
//! section vectors at an angle `D` is shorter inside the element (by `(1 - cos D) / 4`
//! at the middle), which would otherwise read as a smaller curvature and make coarse
//! meshes too flexible under large rotations (the 45-degree bend, `J = 0.1406`, 4
//! elements: tip `z` 55.35 without the division, 53.54 with it, 53.6 converged).
//!
//! ## Locking remedy: shear and section strains at the nodes
//!
//! `eps`, `K_y`, `K_z` use 3 Gauss points ([`BeamQuadrature::bending`], exact for the
//! linearized energy), `K_x` 2 points ([`BeamQuadrature::twist`]). The shear strains
//! `g_y`, `g_z` and the section strains `e_yy`, `e_zz`, `g_yz` are sampled at the two
//! nodes with weights `L/2` ([`BeamQuadrature::shear`] = 0), where `t`, `a`, `b` are the
//! nodal coordinates themselves: the shear constraint `r_x . r_y = 0` ties the section
//! vectors to the nodal slopes only and leaves the cubic centre line free to bend, and
//! the section vectors' rotation inside an element is never seen as a stretch (a tying
//! of the constraints at the nodes, in the spirit of assumed natural strains). Inside
//! the element, by contrast, `t` is quadratic and `a` linear: sampling the shear at 3
//! Gauss points gives a constant curvature per element (one element of a tip-loaded
//! cantilever: 3/4 of the Euler–Bernoulli deflection), at 2 Gauss points the clamp
//! contradicts the 2-point shear field and rotating elements lock (the 45-degree bend
//! with 4 elements: tip `z` 40.4 instead of 53.5). The rank stays complete: 18
//! deformation modes of the 24 coordinates (6 rigid motions), checked by the tests.
//!
//! Internal force `Q = dU/de` and the tangent `K = d^2U/de^2` are exact: every strain is
//! `s = (sum_k c_k U_k.V_k) prod_m |W_m|^-1 - s0` with `U_k`, `V_k`, `W_m` linear in `e`
//! (product rule, checked against finite differences in the tests).
//!
//! Consistent mass and gravity from `r(x, y, z)` over the volume (centroidal, doubly
//! symmetric section): `M = rho ∫ (A S_c^T S_c + I_z S_a^T S_a + I_y S_b^T S_b) l0 dx`,
//! `Q_g = rho A ∫ S_c^T g l0 dx`, 5 Gauss points.

use nalgebra::{SMatrix, SVector, Vector3};

use crate::error::{FeaError, Result, positive};
use crate::material::BeamSection;
use crate::quadrature::gauss_unit;

/// The 24 element coordinates (or forces) `[r_A, r_x,A, r_y,A, r_z,A, r_B, ...]`.
pub type BeamVector = SVector<f64, 24>;
/// A 24 x 24 element matrix.
pub type BeamMatrix = SMatrix<f64, 24, 24>;

/// Where the element samples its strains (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BeamQuadrature {
    /// Gauss points for the axial and bending strains, 1..=5 (default 3).
    pub bending: usize,
    /// Gauss points for the twist, 1..=5 (default 2).
    pub twist: usize,
    /// Sampling of the transverse shear and cross-section strains: 0 (default) at the
    /// two nodes (weights 1/2, the locking remedy), 1..=5 Gauss points (2 and more lock
    /// under large rotations, 3 and more also in small-deflection bending).
    pub shear: usize,
}

impl Default for BeamQuadrature {
    fn default() -> Self {
        Self {
            bending: 3,
            twist: 2,
            shear: 0,
        }
    }
}

impl BeamQuadrature {
    fn validate(&self) -> Result<()> {
        for (field, n, min) in [
            ("quadrature.bending", self.bending, 1),
            ("quadrature.twist", self.twist, 1),
            ("quadrature.shear", self.shear, 0),
        ] {
            if !(min..=5).contains(&n) {
                return Err(FeaError::invalid(field, n, format!("must be in {min}..=5")));
            }
        }
        Ok(())
    }

    /// The sampling points `(xi, weight)` of the shear and cross-section strains.
    fn shear_points(&self) -> &'static [(f64, f64)] {
        if self.shear == 0 {
            &NODES
        } else {
            gauss_unit(self.shear)
        }
    }
}

/// The two nodes as sampling points (trapezoidal weights).
const NODES: [(f64, f64); 2] = [(0.0, 0.5), (1.0, 0.5)];

/// Scalar weights of the 8 nodal vectors `[r_A, r_x,A, r_y,A, r_z,A, r_B, ..]` in a field.
type Weights = [f64; 8];

/// The interpolation weights at `xi` for an element of parameter length `l`:
/// `(r_c, t = r_c', t' = r_c'', a, a', b, b')`.
fn shape(xi: f64, l: f64) -> [Weights; 7] {
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let h = [
        1.0 - 3.0 * x2 + 2.0 * x3,
        xi - 2.0 * x2 + x3,
        3.0 * x2 - 2.0 * x3,
        x3 - x2,
    ];
    let d = [
        -6.0 * xi + 6.0 * x2,
        1.0 - 4.0 * xi + 3.0 * x2,
        6.0 * xi - 6.0 * x2,
        3.0 * x2 - 2.0 * xi,
    ];
    let dd = [
        -6.0 + 12.0 * xi,
        -4.0 + 6.0 * xi,
        6.0 - 12.0 * xi,
        6.0 * xi - 2.0,
    ];
    let r = [h[0], l * h[1], 0.0, 0.0, h[2], l * h[3], 0.0, 0.0];
    let t = [d[0] / l, d[1], 0.0, 0.0, d[2] / l, d[3], 0.0, 0.0];
    let tp = [
        dd[0] / (l * l),
        dd[1] / l,
        0.0,
        0.0,
        dd[2] / (l * l),
        dd[3] / l,
        0.0,
        0.0,
    ];
    let a = [0.0, 0.0, 1.0 - xi, 0.0, 0.0, 0.0, xi, 0.0];
    let ap = [0.0, 0.0, -1.0 / l, 0.0, 0.0, 0.0, 1.0 / l, 0.0];
    let b = [0.0, 0.0, 0.0, 1.0 - xi, 0.0, 0.0, 0.0, xi];
    let bp = [0.0, 0.0, 0.0, -1.0 / l, 0.0, 0.0, 0.0, 1.0 / l];
    [r, t, tp, a, ap, b, bp]
}

fn field(w: &Weights, q: &[Vector3<f64>; 8]) -> Vector3<f64> {
    w.iter().zip(q).map(|(wi, qi)| *wi * qi).sum()
}

/// The 8 nodal vectors of a coordinate vector.
fn vectors(e: &BeamVector) -> [Vector3<f64>; 8] {
    std::array::from_fn(|i| Vector3::new(e[3 * i], e[3 * i + 1], e[3 * i + 2]))
}

/// One strain measure at one sampling point:
/// `s = (sum_k c_k U_k . V_k) prod_m |W_m|^-1 - s0` with `U_k = sum_i u_k,i q_i` (likewise
/// `V_k`, `W_m`) and energy weight `w` (stiffness x Gauss weight x `L l0`):
/// `U_s = w s^2 / 2`. The divisions by the current `|a|`, `|b|` (`norms`) make the
/// curvatures and the twist those of the unit section axes.
#[derive(Debug, Clone, PartialEq)]
struct StrainTerm {
    terms: Vec<(f64, Weights, Weights)>,
    norms: Vec<Weights>,
    reference: f64,
    weight: f64,
}

/// A factor of a strain: value, gradient and Hessian in the 24 coordinates.
type Factor = (f64, BeamVector, BeamMatrix);

/// Hessian block `(i, j)` of a scalar times the identity, dense.
fn kron_identity(h: &SMatrix<f64, 8, 8>) -> BeamMatrix {
    BeamMatrix::from_fn(|r, c| {
        if r % 3 == c % 3 {
            h[(r / 3, c / 3)]
        } else {
            0.0
        }
    })
}

impl StrainTerm {
    fn raw(&self, q: &[Vector3<f64>; 8]) -> f64 {
        let f: f64 = self
            .terms
            .iter()
            .map(|(c, u, v)| c * field(u, q).dot(&field(v, q)))
            .sum();
        self.norms.iter().fold(f, |acc, w| acc / field(w, q).norm())
    }

    /// The dot-product part `f = sum_k c_k U_k . V_k` and its gradient.
    fn dot_part(&self, q: &[Vector3<f64>; 8]) -> (f64, BeamVector) {
        let mut s = 0.0;
        let mut g = BeamVector::zeros();
        for (c, u, v) in &self.terms {
            let (uu, vv) = (field(u, q), field(v, q));
            s += c * uu.dot(&vv);
            for i in 0..8 {
                let gi = *c * (u[i] * vv + v[i] * uu);
                for k in 0..3 {
                    g[3 * i + k] += gi[k];
                }
            }
        }
        (s, g)
    }

    /// The constant Hessian of the dot-product part, as 8 x 8 scalar blocks (times the
    /// 3 x 3 identity).
    fn dot_hessian(&self) -> SMatrix<f64, 8, 8> {
        let mut h = SMatrix::<f64, 8, 8>::zeros();
        for (c, u, v) in &self.terms {
            for i in 0..8 {
                for j in 0..8 {
                    h[(i, j)] += c * (u[i] * v[j] + v[i] * u[j]);
                }
            }
        }
        h
    }

    /// `n = |W|^-1` with its gradient and Hessian:
    /// `dn/dq_i = -n^3 w_i W`, `d^2n/dq_i dq_j = w_i w_j (3 n^5 W W^T - n^3 I)`.
    fn inverse_norm(w: &Weights, q: &[Vector3<f64>; 8], hessian: bool) -> Factor {
        let ww = field(w, q);
        let n = 1.0 / ww.norm();
        let n3 = n * n * n;
        let g = BeamVector::from_fn(|r, _| -n3 * w[r / 3] * ww[r % 3]);
        let h = if hessian {
            let n5 = n3 * n * n;
            BeamMatrix::from_fn(|r, c| {
                let (i, j) = (r / 3, c / 3);
                let id = if r % 3 == c % 3 { 1.0 } else { 0.0 };
                w[i] * w[j] * (3.0 * n5 * ww[r % 3] * ww[c % 3] - n3 * id)
            })
        } else {
            BeamMatrix::zeros()
        };
        (n, g, h)
    }

    /// The strain, its gradient and (if `hessian`) its Hessian; a plain dot-product
    /// strain returns `None` for the Hessian: it is `dot_hessian`, constant.
    fn evaluate(
        &self,
        q: &[Vector3<f64>; 8],
        hessian: bool,
    ) -> (f64, BeamVector, Option<BeamMatrix>) {
        let (f, gf) = self.dot_part(q);
        if self.norms.is_empty() {
            return (f - self.reference, gf, None);
        }
        // Product rule over the factors f, n_1, .., n_m.
        let hf = if hessian {
            kron_identity(&self.dot_hessian())
        } else {
            BeamMatrix::zeros()
        };
        let mut factors: Vec<Factor> = vec![(f, gf, hf)];
        factors.extend(self.norms.iter().map(|w| Self::inverse_norm(w, q, hessian)));
        let others = |skip: &[usize]| -> f64 {
            factors
                .iter()
                .enumerate()
                .filter(|(k, _)| !skip.contains(k))
                .map(|(_, x)| x.0)
                .product()
        };
        let value = others(&[]);
        let mut g = BeamVector::zeros();
        let mut h = BeamMatrix::zeros();
        for (a, fa) in factors.iter().enumerate() {
            g += others(&[a]) * fa.1;
            if hessian {
                h += others(&[a]) * fa.2;
                for (b, fb) in factors.iter().enumerate() {
                    if b != a {
                        h.ger(others(&[a, b]), &fa.1, &fb.1, 1.0);
                    }
                }
            }
        }
        (value - self.reference, g, hessian.then_some(h))
    }
}

/// A fully parameterized ANCF beam element on two nodes (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct AncfBeam {
    /// Indices of the two nodes in the mesh.
    pub nodes: [usize; 2],
    length: f64,
    section: BeamSection,
    quadrature: BeamQuadrature,
    strains: Vec<StrainTerm>,
    /// Mass matrix (8 x 8 scalar blocks) and gravity weights of the 8 nodal vectors.
    mass8: SMatrix<f64, 8, 8>,
    gravity8: Weights,
}

impl AncfBeam {
    /// The parameter length `L` of an element whose reference nodal vectors are
    /// `reference` (`[r_A, r_x,A, r_y,A, r_z,A, r_B, ..]`, unit slopes `r_x`): the fixed
    /// point of `L = ∫_0^1 |dr_c/dxi(L)| dxi` (the arc length of the Hermite centre line
    /// built with that `L`), so that `x` is close to the arc length (`|t0| = 1` on
    /// average). The chord for a straight element; `2e-5` shorter than `R phi` for an
    /// arc of `phi = 20` degrees (the Hermite interpolation error, `~ phi^4`).
    pub fn reference_length(reference: &[Vector3<f64>; 8]) -> f64 {
        let mut l = (reference[4] - reference[0]).norm();
        for _ in 0..50 {
            let next: f64 = gauss_unit(5)
                .iter()
                .map(|&(xi, w)| w * l * field(&shape(xi, l)[1], reference).norm())
                .sum();
            let done = (next - l).abs() <= 1e-15 * l;
            l = next;
            if done {
                break;
            }
        }
        l
    }

    /// An element on `nodes` with reference nodal vectors `reference`, parameter length
    /// `length` (m, see [`reference_length`](Self::reference_length)), `section` and
    /// `quadrature`. The reference must be regular at every Gauss point (`t0`, `a0`, `b0`
    /// non-zero).
    pub fn new(
        nodes: [usize; 2],
        reference: &[Vector3<f64>; 8],
        length: f64,
        section: BeamSection,
        quadrature: BeamQuadrature,
    ) -> Result<Self> {
        let l = positive("element.length", length)?;
        section.validate()?;
        quadrature.validate()?;
        if reference.iter().any(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(FeaError::invalid(
                "element.reference",
                format!("{reference:?}"),
                "must be finite",
            ));
        }
        let s = &section;
        let (ea, ga) = (s.young * s.area, s.shear_modulus * s.area);
        let mut strains = Vec::new();
        let frame = |xi: f64| -> Result<([Weights; 7], f64, f64, f64)> {
            let w = shape(xi, l);
            let (t0, a0, b0) = (
                field(&w[1], reference),
                field(&w[3], reference),
                field(&w[5], reference),
            );
            let (l0, na, nb) = (t0.norm(), a0.norm(), b0.norm());
            if !(l0 > 0.0 && na > 0.0 && nb > 0.0) {
                return Err(FeaError::invalid(
                    "element.reference",
                    format!("|r_x| = {l0}, |r_y| = {na}, |r_z| = {nb} at xi = {xi}"),
                    "the reference gradients must be non-zero inside the element",
                ));
            }
            Ok((w, l0, na, nb))
        };
        let mut push = |terms: Vec<(f64, Weights, Weights)>,
                        norms: Vec<Weights>,
                        stiffness: f64,
                        gw: f64,
                        l0: f64| {
            let mut st = StrainTerm {
                terms,
                norms,
                reference: 0.0,
                weight: stiffness * gw * l * l0,
            };
            st.reference = st.raw(reference);
            strains.push(st);
        };
        for &(xi, gw) in gauss_unit(quadrature.bending) {
            let (w, l0, _, _) = frame(xi)?;
            let [_, t, tp, a, _, b, _] = w;
            push(vec![(0.5 / (l0 * l0), t, t)], vec![], ea, gw, l0);
            push(
                vec![(1.0 / (l0 * l0), tp, a)],
                vec![a],
                s.young * s.iz,
                gw,
                l0,
            );
            push(
                vec![(1.0 / (l0 * l0), tp, b)],
                vec![b],
                s.young * s.iy,
                gw,
                l0,
            );
        }
        for &(xi, gw) in gauss_unit(quadrature.twist) {
            let (w, l0, _, _) = frame(xi)?;
            let [_, _, _, a, ap, b, bp] = w;
            let c = 0.5 / l0;
            push(
                vec![(c, ap, b), (-c, bp, a)],
                vec![a, b],
                s.shear_modulus * s.torsion,
                gw,
                l0,
            );
        }
        for &(xi, gw) in quadrature.shear_points() {
            let (w, l0, na, nb) = frame(xi)?;
            let [_, t, _, a, _, b, _] = w;
            let kga = s.shear_factor * ga;
            push(vec![(1.0 / (l0 * na), t, a)], vec![], kga, gw, l0);
            push(vec![(1.0 / (l0 * nb), t, b)], vec![], kga, gw, l0);
            push(vec![(0.5 / (na * na), a, a)], vec![], ea, gw, l0);
            push(vec![(0.5 / (nb * nb), b, b)], vec![], ea, gw, l0);
            push(vec![(1.0 / (na * nb), a, b)], vec![], ga, gw, l0);
        }
        let mut mass8 = SMatrix::<f64, 8, 8>::zeros();
        let mut gravity8 = [0.0; 8];
        for &(xi, gw) in gauss_unit(5) {
            let (w, l0, _, _) = frame(xi)?;
            let ds = gw * l * l0 * s.density;
            let (r, a, b) = (w[0], w[3], w[5]);
            for i in 0..8 {
                gravity8[i] += ds * s.area * r[i];
                for j in 0..8 {
                    mass8[(i, j)] +=
                        ds * (s.area * r[i] * r[j] + s.iz * a[i] * a[j] + s.iy * b[i] * b[j]);
                }
            }
        }
        Ok(Self {
            nodes,
            length: l,
            section,
            quadrature,
            strains,
            mass8,
            gravity8,
        })
    }

    /// Parameter length `L`, m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The section.
    pub fn section(&self) -> &BeamSection {
        &self.section
    }

    /// The quadrature.
    pub fn quadrature(&self) -> BeamQuadrature {
        self.quadrature
    }

    /// Strain energy, J.
    pub fn strain_energy(&self, e: &BeamVector) -> f64 {
        let q = vectors(e);
        self.strains
            .iter()
            .map(|s| {
                let v = s.raw(&q) - s.reference;
                0.5 * s.weight * v * v
            })
            .sum()
    }

    /// The internal force `Q = dU/de` and, if `tangent`, the tangent stiffness
    /// `K = d^2U/de^2` (otherwise zeros).
    pub fn force_and_tangent(&self, e: &BeamVector, tangent: bool) -> (BeamVector, BeamMatrix) {
        let q = vectors(e);
        let mut f = BeamVector::zeros();
        let mut k = BeamMatrix::zeros();
        for st in &self.strains {
            let (s, g, dense) = st.evaluate(&q, tangent);
            f += st.weight * s * g;
            if tangent {
                k.ger(st.weight, &g, &g, 1.0);
                if let Some(h) = dense {
                    k += (st.weight * s) * h;
                    continue;
                }
                let h = st.dot_hessian();
                for i in 0..8 {
                    for j in 0..8 {
                        let hij = st.weight * s * h[(i, j)];
                        if hij != 0.0 {
                            for c in 0..3 {
                                k[(3 * i + c, 3 * j + c)] += hij;
                            }
                        }
                    }
                }
            }
        }
        (f, k)
    }

    /// The internal force `Q = dU/de`, N (position rows) and N m (gradient rows).
    pub fn internal_force(&self, e: &BeamVector) -> BeamVector {
        self.force_and_tangent(e, false).0
    }

    /// The tangent stiffness `dQ/de`.
    pub fn tangent_stiffness(&self, e: &BeamVector) -> BeamMatrix {
        self.force_and_tangent(e, true).1
    }

    /// The consistent mass matrix, kg (constant).
    pub fn mass_matrix(&self) -> BeamMatrix {
        let mut m = BeamMatrix::zeros();
        for i in 0..8 {
            for j in 0..8 {
                for c in 0..3 {
                    m[(3 * i + c, 3 * j + c)] = self.mass8[(i, j)];
                }
            }
        }
        m
    }

    /// The generalized gravity force `rho A ∫ S_c^T g l0 dx` for the acceleration
    /// `gravity` (m/s^2).
    pub fn gravity_force(&self, gravity: &Vector3<f64>) -> BeamVector {
        BeamVector::from_fn(|r, _| self.gravity8[r / 3] * gravity[r % 3])
    }

    /// Reference mass `rho A ∫ l0 dx`, kg.
    pub fn mass(&self) -> f64 {
        self.gravity8[0] + self.gravity8[4]
    }

    /// Position of the centre line at `xi` in `[0, 1]`, m.
    pub fn position_at(&self, e: &BeamVector, xi: f64) -> Vector3<f64> {
        field(&shape(xi, self.length)[0], &vectors(e))
    }
}

#[cfg(test)]
#[path = "beam_tests.rs"]
mod tests;
