//! The ANCF 4-node shell element with ANS and EAS (Yamashita, Valkeapää, Jayakumar &
//! Sugiyama 2015).
//!
//! Reference: H. Yamashita, A. I. Valkeapää, P. Jayakumar, H. Sugiyama (2015),
//! "Continuum mechanics based bilinear shear deformable shell element using absolute
//! nodal coordinate formulation", J. Comput. Nonlinear Dynam. 10(5): 051012. The same
//! element is Chrono's `ChElementShellANCF_3423`; this is our own implementation.
//!
//! # Kinematics
//!
//! Four nodes ([`GradientNode`](crate::node::GradientNode)) with a position `r_i` (m) and
//! a transverse gradient `d_i = dr/dz` (dimensionless; the unit director of the mid
//! surface in the reference state): 24 coordinates
//! `e = [r_1, d_1, r_2, d_2, r_3, d_3, r_4, d_4]`, eight 3-vector blocks `p_n`. With the
//! bilinear shape functions `N_i = (1 + xi_i xi)(1 + eta_i eta)/4` (nodes at
//! `(xi_i, eta_i) = (-1,-1), (1,-1), (1,1), (-1,1)`, counter-clockwise about the
//! directors) and the physical thickness coordinate `z = zeta t/2`, `zeta in [-1, 1]`,
//!
//! ```text
//! r(xi, eta, z) = sum_i N_i (r_i + z d_i)           current position
//! X(xi, eta, z) = sum_i N_i (X_i + z D_i)           reference position (curved allowed)
//! ```
//!
//! Each column of `J = [r_xi, r_eta, r_z]` is a linear combination `sum_n s_a[n] p_n` of
//! the blocks, so the covariant Green–Lagrange strain `E_ab = (r_a . r_b - X_a . X_b)/2`
//! is the quadratic form `E_ab = 1/2 sum_nm A_ab[n, m] (p_n . p_m - P_n . P_m)` with the
//! 8 x 8 matrix `A_ab = (s_a s_b^T + s_b s_a^T)/2` (`P_n` the reference blocks).
//!
//! # Strain in the local frame
//!
//! At each integration point the local orthonormal frame `A = [e_1, e_2, e_3]`: `e_3`
//! the unit normal `X_xi x X_eta / |.|` of the mid surface, `e_1` the unit projection of
//! `X_xi` on the tangent plane, `e_2 = e_3 x e_1`. With `J0 = [X_xi, X_eta, X_z]` and
//! `G = J0^-1 A` the Cartesian strain is `E_loc = G^T E_cov G` (Voigt order
//! `[11, 22, 33, 23, 13, 12]`, engineering shears `2 E_ij`). So every local strain
//! component is again a quadratic form, `eps_v = 1/2 sum B_v[n, m] (p_n . p_m - P_n . P_m)`
//! with constant 8 x 8 matrices `B_v` computed once per integration point. Then, with
//! `p` the 3 x 8 block matrix,
//!
//! ```text
//! d eps_v / d p_n = sum_m B_v[n, m] p_m                  (the rows of B, 6 x 24)
//! d^2 eps_v / d p_n d p_m = B_v[n, m] I_3
//! ```
//!
//! # Locking remedies (both on by default, [`ShellLocking`])
//!
//! - ANS (assumed natural strain) for the transverse shear and the thickness strain, as
//!   in Yamashita et al. 2015 (after Bathe & Dvorkin 1986 and Betsch & Stein 1995): the
//!   covariant `E_xi z` is interpolated linearly in `eta` between the tying points
//!   `(0, -1)` and `(0, 1)`, `E_eta z` linearly in `xi` between `(-1, 0)` and `(1, 0)`,
//!   `E_zz` bilinearly from its values at the four nodes; tying values on the mid surface
//!   (`z = 0`). Without it a bilinear element locks in transverse shear (a thin plate
//!   in bending becomes far too stiff: see the tests) and a curved one in thickness
//!   (curvature thickness locking).
//! - EAS (enhanced assumed strain, Simo & Rifai 1990, Büchter, Ramm & Roehl 1994) with
//!   five parameters `alpha`: the covariant in-plane strains get `xi` (`E_xi xi`),
//!   `eta` (`E_eta eta`), `xi` and `eta` (`E_xi eta`), the thickness strain `zeta`
//!   (`E_zz`), mapped to the local frame of the point with the element-centre Jacobian,
//!   `G_c = J0_c^-1 A`, and scaled by `det J0_c / det J0`: `eps_enh = Gamma alpha`
//!   (so `int Gamma dV = 0` in one frame and a constant strain does not excite
//!   `alpha`: the membrane patch test passes on distorted elements; with the centre
//!   frame `A_c` instead of `A` it did not). The in-plane modes remove in-plane shear (parasitic
//!   shear) locking; the `zeta` mode lets the thickness strain vary linearly through the
//!   thickness, which removes Poisson thickness locking in bending (the director
//!   interpolation makes `E_zz` constant in `z`). The enhanced strain is added to the
//!   Green–Lagrange strain, so with the St. Venant–Kirchhoff law the energy is quadratic
//!   in `alpha`: `alpha` is found per element by one linear solve (static condensation,
//!   exact, no inner iteration):
//!
//! ```text
//! U(e, alpha) = sum_gp w 1/2 (eps + Gamma alpha)^T C (eps + Gamma alpha)
//! H = sum w Gamma^T C Gamma (constant),  b = sum w Gamma^T C eps,  alpha = -H^-1 b
//! Q = dU/de = sum w B^T S,   S = C (eps + Gamma alpha)         (dU/d alpha = 0)
//! K = sum w B^T C B + (sum w sum_v S_v B_v) (x) I_3 - L^T H^-1 L,   L = sum w Gamma^T C B
//! ```
//!
//! `K` is the exact derivative of `Q` (the condensed energy's Hessian; symmetric),
//! checked against central differences in the tests. `sum_gp w` runs over the
//! integration points with `w = w_xi w_eta w_zeta det(J0) t/2` (m^3): 2 x 2 Gauss points
//! in the plane (full integration: ANS removes the locking, no hourglass modes) and 3
//! through the thickness.
//!
//! # Material
//!
//! St. Venant–Kirchhoff `S = C eps` with a 3-D orthotropic (or isotropic) elasticity
//! matrix in the local frame ([`ShellMaterial`]): `e_1` along `X_xi`, `e_3` the normal.
//! No shear correction factor is applied (the transverse shear strain is constant
//! through the thickness, as in the reference).
//!
//! # Mass
//!
//! Consistent: `M = rho int S^T S dV` with `r = S e`, i.e. the 8 x 8 matrix
//! `M8[n, m] = rho int s0_n s0_m dV` (`s0 = [N_1, z N_1, ...]`) times `I_3`; 3 x 3 x 3
//! Gauss points (exact for a flat element). Its position-block sum is `rho V`
//! (`V = A t` for a flat element).
//!
//! # Pressure
//!
//! [`AncfShell::pressure_force`]: a follower pressure `p` (Pa) on the mid surface along
//! the current normal `n da = r_xi x r_eta dxi deta` (the side of the directors: `p > 0`
//! pushes towards `+d`),
//!
//! ```text
//! F_i = p int N_i (r_xi x r_eta) dxi deta                         (position rows only)
//! dF_i/dr_j = p int N_i (N_j,eta [r_xi]x - N_j,xi [r_eta]x) dxi deta
//! ```
//!
//! with 2 x 2 Gauss points (exact: the integrand is quadratic in each of `xi`, `eta`).
//! The load stiffness is not symmetric; the static solver uses it (sparse LU).

use std::ops::AddAssign;

use nalgebra::{Matrix3, Matrix6, SMatrix, SVector, Vector3, Vector6};

use crate::error::{FeaError, Result, positive};
use crate::quadrature::gauss_unit;

/// A 24-vector of shell coordinates or forces `[r_1, d_1, ..., r_4, d_4]`.
pub type ShellVector = SVector<f64, 24>;
/// A 24 x 24 shell matrix (stiffness or mass).
pub type ShellMatrix = SMatrix<f64, 24, 24>;
type M8 = SMatrix<f64, 8, 8>;
type V8 = SVector<f64, 8>;
/// EAS interpolation: 6 local strains x 5 parameters.
type Gamma = SMatrix<f64, 6, 5>;
/// Number of EAS parameters.
const NEAS: usize = 5;

/// Node positions in the parent square, counter-clockwise.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
/// Voigt order of the local strain: `[11, 22, 33, 23, 13, 12]`.
const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// Bilinear shape functions and their `xi`, `eta` derivatives at `(xi, eta)`.
pub fn shape(xi: f64, eta: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let mut n = [0.0; 4];
    let mut nx = [0.0; 4];
    let mut ny = [0.0; 4];
    for (i, &(a, b)) in CORNERS.iter().enumerate() {
        n[i] = 0.25 * (1.0 + a * xi) * (1.0 + b * eta);
        nx[i] = 0.25 * a * (1.0 + b * eta);
        ny[i] = 0.25 * b * (1.0 + a * xi);
    }
    (n, nx, ny)
}

/// Gauss points and weights on `[-1, 1]`.
fn gauss(n: usize) -> Vec<(f64, f64)> {
    gauss_unit(n)
        .iter()
        .map(|&(x, w)| (2.0 * x - 1.0, 2.0 * w))
        .collect()
}

/// The coefficient vectors `s_xi, s_eta, s_z` of `J = [r_xi, r_eta, r_z]` at
/// `(xi, eta, z)`: `r_a = sum_n s_a[n] p_n`.
fn columns(xi: f64, eta: f64, z: f64) -> [V8; 3] {
    let (n, nx, ny) = shape(xi, eta);
    let mut s = [V8::zeros(); 3];
    for i in 0..4 {
        s[0][2 * i] = nx[i];
        s[0][2 * i + 1] = z * nx[i];
        s[1][2 * i] = ny[i];
        s[1][2 * i + 1] = z * ny[i];
        s[2][2 * i + 1] = n[i];
    }
    s
}

fn sym_outer(a: &V8, b: &V8) -> M8 {
    0.5 * (a * b.transpose() + b * a.transpose())
}

/// Which locking remedies an element uses (see the module docs). Default: both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShellLocking {
    /// Assumed natural strain for the transverse shear and thickness strains.
    pub ans: bool,
    /// Five-parameter enhanced assumed strain (in-plane and thickness).
    pub eas: bool,
}

impl Default for ShellLocking {
    fn default() -> Self {
        Self {
            ans: true,
            eas: true,
        }
    }
}

impl ShellLocking {
    /// No remedy: the plain displacement-based element (locks; for comparison).
    pub const NONE: Self = Self {
        ans: false,
        eas: false,
    };
}

/// St. Venant–Kirchhoff material of the shell: density and the 6 x 6 elasticity matrix
/// `C` (Pa) in the local frame, Voigt order `[11, 22, 33, 23, 13, 12]` with engineering
/// shear strains. Axis 1 is along the element's `xi` direction, 3 the normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellMaterial {
    /// Density `rho`, kg/m^3.
    pub density: f64,
    elasticity: Matrix6<f64>,
}

impl ShellMaterial {
    /// Isotropic: `young` `E` (Pa, positive), `poisson` `nu` in (-1, 0.5), `density`
    /// (kg/m^3, positive). `C` is the 3-D Hooke matrix with `lambda = E nu / ((1 + nu)(1 - 2 nu))`,
    /// `mu = E / (2 (1 + nu))`. Errors name the field and value.
    pub fn isotropic(young: f64, poisson: f64, density: f64) -> Result<Self> {
        let e = positive("material.young", young)?;
        check_poisson("material.poisson", poisson)?;
        let nu = poisson;
        let g = e / (2.0 * (1.0 + nu));
        Self::orthotropic(density, [e; 3], [nu; 3], [g; 3])
    }

    /// Orthotropic in the local frame: `young = [E1, E2, E3]`, `poisson =
    /// [nu12, nu13, nu23]`, `shear = [G12, G13, G23]` (Pa), `C` the inverse of the
    /// compliance matrix. Errors: a non-positive or non-finite modulus or density, a
    /// compliance that is not positive definite (naming `material.poisson`).
    pub fn orthotropic(
        density: f64,
        young: [f64; 3],
        poisson: [f64; 3],
        shear: [f64; 3],
    ) -> Result<Self> {
        let density = positive("material.density", density)?;
        for (k, e) in young.iter().enumerate() {
            positive(&format!("material.young[{k}]"), *e)?;
        }
        for (k, g) in shear.iter().enumerate() {
            positive(&format!("material.shear[{k}]"), *g)?;
        }
        for (k, nu) in poisson.iter().enumerate() {
            if !nu.is_finite() {
                return Err(FeaError::invalid(
                    format!("material.poisson[{k}]"),
                    nu,
                    "must be finite",
                ));
            }
        }
        let [e1, e2, e3] = young;
        let [n12, n13, n23] = poisson;
        let [g12, g13, g23] = shear;
        let mut s = Matrix6::zeros();
        s[(0, 0)] = 1.0 / e1;
        s[(1, 1)] = 1.0 / e2;
        s[(2, 2)] = 1.0 / e3;
        s[(0, 1)] = -n12 / e1;
        s[(1, 0)] = -n12 / e1;
        s[(0, 2)] = -n13 / e1;
        s[(2, 0)] = -n13 / e1;
        s[(1, 2)] = -n23 / e2;
        s[(2, 1)] = -n23 / e2;
        s[(3, 3)] = 1.0 / g23;
        s[(4, 4)] = 1.0 / g13;
        s[(5, 5)] = 1.0 / g12;
        let chol = s.cholesky().ok_or_else(|| {
            FeaError::invalid(
                "material.poisson",
                format!("{poisson:?}"),
                "the compliance matrix is not positive definite",
            )
        })?;
        let c = chol.inverse();
        Ok(Self {
            density,
            elasticity: 0.5 * (c + c.transpose()),
        })
    }

    /// The elasticity matrix `C`, Pa.
    pub fn elasticity(&self) -> &Matrix6<f64> {
        &self.elasticity
    }

    /// Checks the density and that `C` is finite and symmetric positive definite.
    pub fn validate(&self) -> Result<()> {
        positive("material.density", self.density)?;
        if self.elasticity.iter().any(|c| !c.is_finite()) || self.elasticity.cholesky().is_none() {
            return Err(FeaError::invalid(
                "material.elasticity",
                "C",
                "must be finite and positive definite",
            ));
        }
        Ok(())
    }
}

fn check_poisson(field: &str, nu: f64) -> Result<()> {
    if nu.is_finite() && nu > -1.0 && nu < 0.5 {
        Ok(())
    } else {
        Err(FeaError::invalid(
            field,
            nu,
            "must be in the open interval (-1, 0.5)",
        ))
    }
}

/// Precomputed data of one integration point.
#[derive(Debug, Clone, PartialEq)]
struct Point {
    /// `w_xi w_eta w_zeta det(J0) t/2`, m^3.
    weight: f64,
    /// The 8 x 8 quadratic forms of the six local strains.
    forms: [M8; 6],
    /// EAS interpolation (zero without EAS).
    gamma: Gamma,
}

/// The ANCF 4-node shell element (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct AncfShell {
    /// Global indices of the four nodes (counter-clockwise about the directors).
    pub nodes: [usize; 4],
    thickness: f64,
    material: ShellMaterial,
    locking: ShellLocking,
    points: Vec<Point>,
    gram0: M8,
    /// `H^-1` of the EAS condensation.
    h_inv: SMatrix<f64, NEAS, NEAS>,
    mass8: M8,
    area: f64,
    volume: f64,
}

impl AncfShell {
    /// Number of coordinates of the element.
    pub const NDOF: usize = 24;

    /// The element on `nodes` with reference positions `positions` (m) and directors
    /// `directors` (normalized here) of thickness `thickness` (m). Errors (naming the
    /// field and value): a non-positive thickness, an invalid material, non-finite or
    /// zero vectors, a reference Jacobian `det J0 <= 0` at an integration point (nodes
    /// not counter-clockwise about the directors, a degenerate quadrilateral, or a
    /// director in the tangent plane).
    pub fn new(
        nodes: [usize; 4],
        positions: &[Vector3<f64>; 4],
        directors: &[Vector3<f64>; 4],
        thickness: f64,
        material: ShellMaterial,
        locking: ShellLocking,
    ) -> Result<Self> {
        let t = positive("section.thickness", thickness)?;
        material.validate()?;
        let mut p0 = SMatrix::<f64, 3, 8>::zeros();
        for i in 0..4 {
            crate::error::finite3(&format!("node[{i}].position"), &positions[i])?;
            crate::error::finite3(&format!("node[{i}].director"), &directors[i])?;
            let len = directors[i].norm();
            if len <= 0.0 {
                return Err(FeaError::invalid(
                    format!("node[{i}].director"),
                    "[0, 0, 0]",
                    "must be non-zero",
                ));
            }
            p0.set_column(2 * i, &positions[i]);
            p0.set_column(2 * i + 1, &(directors[i] / len));
        }
        let c = material.elasticity;
        // Element centre: the EAS transformation.
        let (jc, jc_inv, _) = frame(&p0, 0.0, 0.0, 0.0);
        let size = (positions[2] - positions[0])
            .norm()
            .max((positions[3] - positions[1]).norm());
        let mut points = Vec::with_capacity(12);
        let g2 = gauss(2);
        let g3 = gauss(3);
        // Tying points of ANS (mid surface).
        let tie = |xi: f64, eta: f64| columns(xi, eta, 0.0);
        let [ta, tc, tb, td] = [tie(0.0, -1.0), tie(0.0, 1.0), tie(-1.0, 0.0), tie(1.0, 0.0)];
        let ezz_nodes: Vec<M8> = CORNERS
            .iter()
            .map(|&(a, b)| {
                let s = tie(a, b);
                sym_outer(&s[2], &s[2])
            })
            .collect();
        let mut h = SMatrix::<f64, NEAS, NEAS>::zeros();
        let mut area = 0.0;
        for &(eta, weta) in &g2 {
            for &(xi, wxi) in &g2 {
                for &(zeta, wz) in &g3 {
                    let z = 0.5 * t * zeta;
                    let (j, j_inv, a_loc) = frame(&p0, xi, eta, z);
                    let g = j_inv * a_loc;
                    // EAS: the centre Jacobian, the local frame of this point.
                    let gc = jc_inv * a_loc;
                    if j.is_nan() || j <= 1e-12 * size * size {
                        return Err(FeaError::invalid(
                            "element.jacobian",
                            format!("{j:e} at (xi, eta, zeta) = ({xi:.3}, {eta:.3}, {zeta:.3})"),
                            "must be > 0: order the nodes counter-clockwise about the directors; \
                             the quadrilateral must not be degenerate nor a director tangent to it",
                        ));
                    }
                    let s = columns(xi, eta, z);
                    let mut cov = [[M8::zeros(); 3]; 3];
                    for a in 0..3 {
                        for b in a..3 {
                            cov[a][b] = sym_outer(&s[a], &s[b]);
                        }
                    }
                    if locking.ans {
                        cov[0][2] = 0.5 * (1.0 - eta) * sym_outer(&ta[0], &ta[2])
                            + 0.5 * (1.0 + eta) * sym_outer(&tc[0], &tc[2]);
                        cov[1][2] = 0.5 * (1.0 - xi) * sym_outer(&tb[1], &tb[2])
                            + 0.5 * (1.0 + xi) * sym_outer(&td[1], &td[2]);
                        let (n, _, _) = shape(xi, eta);
                        cov[2][2] = (0..4).map(|i| n[i] * ezz_nodes[i]).sum();
                    }
                    let mut forms = [M8::zeros(); 6];
                    for (v, &(i, k)) in VOIGT.iter().enumerate() {
                        let factor = if i == k { 1.0 } else { 2.0 };
                        for a in 0..3 {
                            for b in 0..3 {
                                let form = if a <= b { &cov[a][b] } else { &cov[b][a] };
                                forms[v] += (factor * g[(a, i)] * g[(b, k)]) * form;
                            }
                        }
                    }
                    let mut gamma = Gamma::zeros();
                    if locking.eas {
                        let modes: [(usize, usize, f64); NEAS] = [
                            (0, 0, xi),
                            (1, 1, eta),
                            (0, 1, xi),
                            (0, 1, eta),
                            (2, 2, zeta),
                        ];
                        for (k, &(a, b, f)) in modes.iter().enumerate() {
                            let mut m = Matrix3::zeros();
                            m[(a, b)] = f;
                            m[(b, a)] = f;
                            let loc = gc.transpose() * m * gc * (jc / j);
                            for (v, &(i, l)) in VOIGT.iter().enumerate() {
                                let factor = if i == l { 1.0 } else { 2.0 };
                                gamma[(v, k)] = factor * loc[(i, l)];
                            }
                        }
                    }
                    let weight = wxi * weta * wz * j * 0.5 * t;
                    h += weight * gamma.transpose() * c * gamma;
                    if zeta == g3[1].0 {
                        // Mid surface area element |X_xi x X_eta|.
                        let s0 = columns(xi, eta, 0.0);
                        let xx = p0 * s0[0];
                        let xe = p0 * s0[1];
                        area += wxi * weta * xx.cross(&xe).norm();
                    }
                    points.push(Point {
                        weight,
                        forms,
                        gamma,
                    });
                }
            }
        }
        let h_inv = if locking.eas {
            h.try_inverse().ok_or_else(|| {
                FeaError::invalid("element.eas", "H", "the EAS matrix is singular")
            })?
        } else {
            SMatrix::zeros()
        };
        // Consistent mass, 3 x 3 x 3 points.
        let mut mass8 = M8::zeros();
        let mut volume = 0.0;
        for &(eta, weta) in &g3 {
            for &(xi, wxi) in &g3 {
                for &(zeta, wz) in &g3 {
                    let z = 0.5 * t * zeta;
                    let (j, _, _) = frame(&p0, xi, eta, z);
                    let (n, _, _) = shape(xi, eta);
                    let mut s0 = V8::zeros();
                    for i in 0..4 {
                        s0[2 * i] = n[i];
                        s0[2 * i + 1] = z * n[i];
                    }
                    let w = wxi * weta * wz * j * 0.5 * t;
                    volume += w;
                    mass8 += (material.density * w) * s0 * s0.transpose();
                }
            }
        }
        Ok(Self {
            nodes,
            thickness: t,
            material,
            locking,
            points,
            gram0: p0.transpose() * p0,
            h_inv,
            mass8,
            area,
            volume,
        })
    }

    /// Thickness, m.
    pub fn thickness(&self) -> f64 {
        self.thickness
    }

    /// The material.
    pub fn material(&self) -> &ShellMaterial {
        &self.material
    }

    /// The locking remedies in use.
    pub fn locking(&self) -> ShellLocking {
        self.locking
    }

    /// Reference mid-surface area, m^2.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Reference volume `int dV`, m^3.
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Mass `rho V`, kg.
    pub fn mass(&self) -> f64 {
        self.material.density * self.volume
    }

    /// The consistent mass matrix (24 x 24), kg.
    pub fn mass_matrix(&self) -> ShellMatrix {
        kron3(&self.mass8)
    }

    /// The consistent load of a uniform body force (gravity) `g` (m/s^2): the virtual
    /// work `int rho g . dr dV` with `r = sum_n s0_n p_n` gives the block
    /// `F_n = rho int s0_n dV g`, and since `sum_i N_i = 1` (the position entries of
    /// `s0` sum to 1) that is `F_n = sum_i M8[n, 2i] g` (N on the positions, N m on
    /// the directors: a nonzero moment for a curved element, where `int z dV != 0`).
    /// The position blocks sum to `rho V g`. The load is constant, so its potential is
    /// `-F . e`.
    pub fn gravity_force(&self, g: &Vector3<f64>) -> ShellVector {
        let mut f = ShellVector::zeros();
        for n in 0..8 {
            let w: f64 = (0..4).map(|i| self.mass8[(n, 2 * i)]).sum();
            for c in 0..3 {
                f[3 * n + c] = w * g[c];
            }
        }
        f
    }

    /// Strain energy at coordinates `e`, J.
    pub fn strain_energy(&self, e: &ShellVector) -> f64 {
        self.evaluate(e, false).0
    }

    /// The internal force `Q = dU/de`, N (position rows) and N m (gradient rows).
    pub fn internal_force(&self, e: &ShellVector) -> ShellVector {
        self.evaluate(e, false).1
    }

    /// The internal force and, if `tangent`, the tangent stiffness `dQ/de` (zero
    /// otherwise).
    pub fn force_and_tangent(&self, e: &ShellVector, tangent: bool) -> (ShellVector, ShellMatrix) {
        let (_, q, k) = self.evaluate(e, tangent);
        (q, k)
    }

    /// The local Green–Lagrange strains (Voigt `[11, 22, 33, 23, 13, 12]`, engineering
    /// shears, ANS applied, EAS included) at the integration points, in the order
    /// `eta`, `xi`, `zeta` (outermost first).
    pub fn strains(&self, e: &ShellVector) -> Vec<Vector6<f64>> {
        let p = SMatrix::<f64, 3, 8>::from_column_slice(e.as_slice());
        let dg = p.transpose() * p - self.gram0;
        let eps: Vec<Vector6<f64>> = self.points.iter().map(|pt| strain(pt, &dg)).collect();
        let alpha = self.eas_parameters(&eps);
        eps.iter()
            .zip(&self.points)
            .map(|(s, pt)| s + pt.gamma * alpha)
            .collect()
    }

    fn eas_parameters(&self, eps: &[Vector6<f64>]) -> SVector<f64, NEAS> {
        if !self.locking.eas {
            return SVector::zeros();
        }
        let c = &self.material.elasticity;
        let b: SVector<f64, NEAS> = self
            .points
            .iter()
            .zip(eps)
            .map(|(pt, s)| pt.weight * pt.gamma.transpose() * (c * s))
            .sum();
        -(self.h_inv * b)
    }

    /// Energy, force and (if `tangent`) tangent.
    fn evaluate(&self, e: &ShellVector, tangent: bool) -> (f64, ShellVector, ShellMatrix) {
        let c = &self.material.elasticity;
        let p = SMatrix::<f64, 3, 8>::from_column_slice(e.as_slice());
        let dg = p.transpose() * p - self.gram0;
        let mut eps = Vec::with_capacity(self.points.len());
        let mut bmats = Vec::with_capacity(self.points.len());
        let mut l = SMatrix::<f64, NEAS, 24>::zeros();
        let mut b = SVector::<f64, NEAS>::zeros();
        for pt in &self.points {
            let s = strain(pt, &dg);
            let mut bm = SMatrix::<f64, 6, 24>::zeros();
            for v in 0..6 {
                let row = p * pt.forms[v];
                for (k, x) in row.iter().enumerate() {
                    bm[(v, k)] = *x;
                }
            }
            if self.locking.eas {
                let gc = pt.weight * pt.gamma.transpose() * c;
                b += gc * s;
                if tangent {
                    l += gc * bm;
                }
            }
            eps.push(s);
            bmats.push(bm);
        }
        let alpha = -(self.h_inv * b);
        let mut energy = 0.0;
        let mut q = ShellVector::zeros();
        let mut k = ShellMatrix::zeros();
        let mut k8 = M8::zeros();
        for ((pt, s), bm) in self.points.iter().zip(&eps).zip(&bmats) {
            let total = s + pt.gamma * alpha;
            let stress = c * total;
            energy += 0.5 * pt.weight * total.dot(&stress);
            q += pt.weight * bm.transpose() * stress;
            if tangent {
                let cb = c * bm;
                k += pt.weight * bm.transpose() * cb;
                for v in 0..6 {
                    k8 += (pt.weight * stress[v]) * pt.forms[v];
                }
            }
        }
        if tangent {
            k += kron3(&k8);
            if self.locking.eas {
                k -= l.transpose() * self.h_inv * l;
            }
            k = 0.5 * (k + k.transpose());
        }
        (energy, q, k)
    }

    /// The follower pressure load `F` (Pa `p` along the current mid-surface normal,
    /// towards `+d`) and, if `tangent`, its derivative `dF/de` (module docs).
    pub fn pressure_force(
        &self,
        e: &ShellVector,
        pressure: f64,
        tangent: bool,
    ) -> (ShellVector, ShellMatrix) {
        let mut f = ShellVector::zeros();
        let mut k = ShellMatrix::zeros();
        let r = |i: usize| Vector3::new(e[6 * i], e[6 * i + 1], e[6 * i + 2]);
        for &(eta, weta) in &gauss(2) {
            for &(xi, wxi) in &gauss(2) {
                let (n, nx, ny) = shape(xi, eta);
                let mut rx = Vector3::zeros();
                let mut ry = Vector3::zeros();
                for i in 0..4 {
                    rx += nx[i] * r(i);
                    ry += ny[i] * r(i);
                }
                let w = wxi * weta * pressure;
                let normal = rx.cross(&ry);
                let skx = rx.cross_matrix();
                let sky = ry.cross_matrix();
                for i in 0..4 {
                    for c in 0..3 {
                        f[6 * i + c] += w * n[i] * normal[c];
                    }
                    if tangent {
                        for j in 0..4 {
                            let blk = (w * n[i]) * (ny[j] * skx - nx[j] * sky);
                            k.fixed_view_mut::<3, 3>(6 * i, 6 * j).add_assign(&blk);
                        }
                    }
                }
            }
        }
        (f, k)
    }
}

/// The local strains at a point from the Gram difference `p^T p - P^T P`.
fn strain(pt: &Point, dg: &M8) -> Vector6<f64> {
    Vector6::from_fn(|v, _| 0.5 * pt.forms[v].component_mul(dg).sum())
}

/// `det J0`, `J0^-1` and the local frame `A` at `(xi, eta, z)` of the reference blocks
/// `p0` (`A` from the mid-surface tangents at `(xi, eta)`).
fn frame(p0: &SMatrix<f64, 3, 8>, xi: f64, eta: f64, z: f64) -> (f64, Matrix3<f64>, Matrix3<f64>) {
    let s = columns(xi, eta, z);
    let j0 = Matrix3::from_columns(&[p0 * s[0], p0 * s[1], p0 * s[2]]);
    let m = columns(xi, eta, 0.0);
    let (ax, ay) = (p0 * m[0], p0 * m[1]);
    let e3 = ax.cross(&ay).normalize();
    let e1 = (ax - ax.dot(&e3) * e3).normalize();
    let e2 = e3.cross(&e1);
    let a = Matrix3::from_columns(&[e1, e2, e3]);
    let det = j0.determinant();
    let inv = j0.try_inverse().unwrap_or_else(Matrix3::zeros);
    (det, inv, a)
}

/// `m (x) I_3`: the 24 x 24 matrix of an 8 x 8 block matrix.
fn kron3(m: &M8) -> ShellMatrix {
    ShellMatrix::from_fn(|i, j| {
        if i % 3 == j % 3 {
            m[(i / 3, j / 3)]
        } else {
            0.0
        }
    })
}
