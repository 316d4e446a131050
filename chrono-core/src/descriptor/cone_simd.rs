//! Many friction-cone projections at once ([`project_friction_cones`]): the projection of
//! [`project_friction_cone`] on consecutive triplets, lane by lane with `pulp` (safe,
//! runtime dispatch: AVX2 where the CPU has it, one lane otherwise).
//!
//! Why: in a granular bed about half the contacts stick, a quarter slide and a quarter
//! are open, so the scalar projection's three-way branch is mispredicted about every
//! other triplet, and its surface case is a chain of a square root and two divisions.
//! APGD projects twice per iteration (the step and the residual's trial step); in the
//! 10 000-grain pour those projections took about 40 % of the iteration (perf, 2026-12-06).
//! Lanes compute every case and select, so there is no branch and the latency is shared.
//!
//! Every lane does the scalar function's operations in the same order, without fused
//! multiply-adds, and selects the scalar branch's result: the output is bit-identical to
//! [`project_friction_cone`] on every triplet, for any lane count (checked by the tests
//! below, NaN and signed zeros included). Blocks with a `mu <= 0` triplet (frictionless
//! contacts, whose scalar branch uses `f64::max`) take the scalar function.

use pulp::{Arch, Simd, WithSimd};

use super::cone::project_friction_cone;

/// The largest lane count (AVX-512's eight doubles): the size of the stack buffers.
const MAX_LANES: usize = 8;

/// Project each triplet `g[3k..3k + 3]` onto the friction cone of `mu[k]`, as
/// [`project_friction_cone`] does one by one (bit for bit).
///
/// # Panics
/// If `g.len() != 3 * mu.len()`.
pub fn project_friction_cones(mu: &[f64], g: &mut [f64]) {
    assert_eq!(g.len(), 3 * mu.len(), "one triplet of g per mu");
    Arch::new().dispatch(ProjectOp { mu, g });
}

/// Triplets per block of [`friction_residual_terms`] (its stack buffer).
const RES_BLOCK: usize = 128;

/// Each friction triplet's share of the squared residual ([`super::CcpProblem::residual`],
/// (m/s)^2): with `h` the triplet's scale (`scale[3k]`), the trial step
/// `z = g - h (N g + r)` projected onto the cone of `mu[k]` ([`project_friction_cones`],
/// a block at a time) and `terms[k] = sum_j ((g_j - z_j) / h)^2` (0 where `h <= 0`).
/// `gamma`, `grad` (`N g + r`) and `scale` hold the triplets' rows (`3 mu.len()` each).
/// The operations of the scalar formula, so the same bits.
///
/// # Panics
/// If the lengths do not match.
pub fn friction_residual_terms(
    gamma: &[f64],
    grad: &[f64],
    scale: &[f64],
    mu: &[f64],
    terms: &mut [f64],
) {
    let n = mu.len();
    assert!(
        gamma.len() == 3 * n && grad.len() == 3 * n && scale.len() == 3 * n && terms.len() == n,
        "three rows of gamma, grad and scale and one term per triplet"
    );
    let mut z = [0.0f64; 3 * RES_BLOCK];
    for (b, terms) in terms.chunks_mut(RES_BLOCK).enumerate() {
        let (k0, nb) = (b * RES_BLOCK, terms.len());
        let rows = 3 * k0..3 * (k0 + nb);
        let (g, gr, sc) = (&gamma[rows.clone()], &grad[rows.clone()], &scale[rows]);
        let z = &mut z[..3 * nb];
        for (((z, g), gr), &h) in (z.chunks_exact_mut(3))
            .zip(g.chunks_exact(3))
            .zip(gr.chunks_exact(3))
            .zip(sc.iter().step_by(3))
        {
            for j in 0..3 {
                z[j] = g[j] - h * gr[j];
            }
        }
        project_friction_cones(&mu[k0..k0 + nb], z);
        for (k, term) in terms.iter_mut().enumerate() {
            let t = 3 * k;
            let h = sc[t];
            *term = if h <= 0.0 {
                0.0
            } else {
                // One division per triplet.
                let ih = 1.0 / h;
                (0..3).map(|j| ((g[t + j] - z[t + j]) * ih).powi(2)).sum()
            };
        }
    }
}

struct ProjectOp<'a> {
    mu: &'a [f64],
    g: &'a mut [f64],
}

impl WithSimd for ProjectOp<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, s: S) -> Self::Output {
        let Self { mu, g } = self;
        let lanes = S::F64_LANES;
        let n = mu.len();
        let full = if lanes <= MAX_LANES { n - n % lanes } else { 0 };
        let mut k = 0;
        while k < full {
            let m = &mu[k..k + lanes];
            let t = &mut g[3 * k..3 * (k + lanes)];
            if m.iter().all(|&m| m > 0.0) {
                project_lanes(s, m, t);
            } else {
                for (&m, t) in m.iter().zip(t.chunks_exact_mut(3)) {
                    project_friction_cone(m, t);
                }
            }
            k += lanes;
        }
        for (&m, t) in mu[k..].iter().zip(g[3 * k..].chunks_exact_mut(3)) {
            project_friction_cone(m, t);
        }
    }
}

/// One vector from a stack buffer.
#[inline(always)]
fn from_buf<S: Simd>(x: &[f64; MAX_LANES]) -> S::f64s {
    S::as_simd_f64s(&x[..S::F64_LANES]).0[0]
}

/// A vector into a stack buffer.
#[inline(always)]
fn to_buf<S: Simd>(v: S::f64s, x: &mut [f64; MAX_LANES]) {
    S::as_mut_simd_f64s(&mut x[..S::F64_LANES]).0[0] = v;
}

/// The projection of `S::F64_LANES` triplets `t` with friction coefficients `mu > 0`.
#[inline(always)]
fn project_lanes<S: Simd>(s: S, mu: &[f64], t: &mut [f64]) {
    let lanes = S::F64_LANES;
    let (mut bn, mut bu, mut bw) = ([0.0; MAX_LANES], [0.0; MAX_LANES], [0.0; MAX_LANES]);
    for l in 0..lanes {
        bn[l] = t[3 * l];
        bu[l] = t[3 * l + 1];
        bw[l] = t[3 * l + 2];
    }
    // The coefficients are contiguous: one load.
    let mu = S::as_simd_f64s(&mu[..lanes]).0[0];
    let (gn, gu, gw) = (from_buf::<S>(&bn), from_buf::<S>(&bu), from_buf::<S>(&bw));
    let zero = s.splat_f64s(0.0);
    // The scalar function's inside test.
    let t2 = s.add_f64s(s.mul_f64s(gu, gu), s.mul_f64s(gw, gw));
    let radius = s.mul_f64s(mu, gn);
    let inside = s.and_m64s(
        s.greater_than_or_equal_f64s(gn, zero),
        s.less_than_or_equal_f64s(t2, s.mul_f64s(radius, radius)),
    );
    // The polar cone.
    let gt = s.sqrt_f64s(t2);
    let polar = s.less_than_or_equal_f64s(s.mul_f64s(mu, gt), s.neg_f64s(gn));
    // The surface (computed in every lane; the other lanes' values are discarded).
    let gn_new = s.div_f64s(
        s.add_f64s(s.mul_f64s(mu, gt), gn),
        s.add_f64s(s.mul_f64s(mu, mu), s.splat_f64s(1.0)),
    );
    let radius = s.mul_f64s(mu, gn_new);
    let scale = s.div_f64s(radius, gt);
    let (mut u, mut w) = (s.mul_f64s(gu, scale), s.mul_f64s(gw, scale));
    let shrink = s.splat_f64s(1.0 - f64::EPSILON);
    let r2 = s.mul_f64s(radius, radius);
    let surface = s.not_m64s(s.or_m64s(inside, polar));
    // The scalar loop stops at the first pass of the inside test; a lane that passed keeps
    // its values, so shrinking only the others is the same. The first shrink is done
    // unconditionally (whether a lane is an ulp outside is a coin toss, a branch on it
    // would be mispredicted), the other three only while a surface lane (the inside and
    // polar lanes' values are discarded) is still outside, which is rare.
    for pass in 0..4 {
        let out = s.not_m64s(
            s.less_than_or_equal_f64s(s.add_f64s(s.mul_f64s(u, u), s.mul_f64s(w, w)), r2),
        );
        if pass > 0 && s.first_true_m64s(s.and_m64s(out, surface)) == S::F64_LANES {
            break;
        }
        u = s.select_f64s(out, s.mul_f64s(u, shrink), u);
        w = s.select_f64s(out, s.mul_f64s(w, shrink), w);
    }
    // inside ? g : (polar ? 0 : surface). No closure: it would not inherit the target
    // features.
    let on = s.select_f64s(inside, gn, s.select_f64s(polar, zero, gn_new));
    let ou = s.select_f64s(inside, gu, s.select_f64s(polar, zero, u));
    let ow = s.select_f64s(inside, gw, s.select_f64s(polar, zero, w));
    to_buf::<S>(on, &mut bn);
    to_buf::<S>(ou, &mut bu);
    to_buf::<S>(ow, &mut bw);
    for l in 0..lanes {
        t[3 * l] = bn[l];
        t[3 * l + 1] = bu[l];
        t[3 * l + 2] = bw[l];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn scalar(mu: &[f64], g: &[f64]) -> Vec<f64> {
        let mut out = g.to_vec();
        for (&m, t) in mu.iter().zip(out.chunks_exact_mut(3)) {
            project_friction_cone(m, t);
        }
        out
    }

    fn same_bits(a: &[f64], b: &[f64]) -> bool {
        a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    #[test]
    fn every_case_matches_the_scalar_projection_bit_for_bit() {
        // Inside, apex, polar, surface, on the surface, signed zeros, NaN, infinities,
        // a frictionless triplet in a block, and a tail shorter than a vector.
        let cases: &[(f64, [f64; 3])] = &[
            (0.5, [1.0, 0.1, -0.2]),
            (0.5, [0.0, 0.0, 0.0]),
            (0.5, [-0.0, 0.0, -0.0]),
            (0.5, [-1.0, 0.1, 0.1]),
            (0.5, [1.0, 3.0, -4.0]),
            (0.5, [2.0, 0.6, 0.8]),
            (0.3, [-0.1, 1.0, 0.0]),
            (0.5, [f64::NAN, 0.1, 0.2]),
            (0.5, [1.0, f64::NAN, 0.2]),
            (0.5, [f64::INFINITY, 1.0, 1.0]),
            (0.5, [1.0, f64::INFINITY, 0.0]),
            (0.0, [-1.0, 2.0, 3.0]),
            (0.7, [1e-300, 1e-300, 1e-300]),
            (0.7, [1e200, -1e200, 1e200]),
            (1e-9, [1.0, 1.0, 1.0]),
            (0.5, [0.0, 1e-12, 0.0]),
            (0.5, [-2.0, 0.0, 0.0]),
        ];
        let mu: Vec<f64> = cases.iter().map(|c| c.0).collect();
        let g: Vec<f64> = cases.iter().flat_map(|c| c.1).collect();
        let want = scalar(&mu, &g);
        let mut got = g.clone();
        project_friction_cones(&mu, &mut got);
        for (k, (a, b)) in got.chunks(3).zip(want.chunks(3)).enumerate() {
            assert!(
                same_bits(a, b),
                "triplet {k} {:?}: {a:?} != {b:?}",
                cases[k]
            );
        }
    }

    proptest! {
        #[test]
        fn random_triplets_match_the_scalar_projection_bit_for_bit(
            t in proptest::collection::vec(
                (0.0f64..2.0, -10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0), 0..40),
        ) {
            let mu: Vec<f64> = t.iter().map(|x| x.0).collect();
            let g: Vec<f64> = t.iter().flat_map(|x| [x.1, x.2, x.3]).collect();
            let want = scalar(&mu, &g);
            let mut got = g.clone();
            project_friction_cones(&mu, &mut got);
            prop_assert!(same_bits(&got, &want));
        }

        #[test]
        fn projected_triplets_are_in_the_cone_and_stay(
            t in proptest::collection::vec(
                (0.01f64..2.0, -10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0), 1..40),
        ) {
            let mu: Vec<f64> = t.iter().map(|x| x.0).collect();
            let mut g: Vec<f64> = t.iter().flat_map(|x| [x.1, x.2, x.3]).collect();
            project_friction_cones(&mu, &mut g);
            for (&m, x) in mu.iter().zip(g.chunks(3)) {
                prop_assert!(x[0] >= 0.0);
                prop_assert!(x[1] * x[1] + x[2] * x[2] <= (m * x[0]) * (m * x[0]));
            }
            let again = g.clone();
            project_friction_cones(&mu, &mut g);
            prop_assert!(same_bits(&g, &again));
        }
    }
}
