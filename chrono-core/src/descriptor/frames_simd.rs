//! The SIMD kernels of the matrix-free product ([`super::frames`]): the sphere pass
//! (`M^-1 D g` of the spheres) and the triplet pass (`D'` of their velocity changes), with
//! `pulp` (safe, runtime dispatch: AVX2 where the CPU has it, one lane otherwise).
//!
//! Lanes run over consecutive entries of the component-wise (structure-of-arrays) copies
//! of the geometry, so the normals, arms and frame divisions load straight into vectors;
//! only `g` (3 per contact side) and the spheres' velocity changes (6 per contact side) are
//! gathered, with 4 lanes as whole rows transposed (4 loads and 8 shuffles for 16 values).
//!
//! Every lane does the scalar operations of [`MatrixFree::triplet`] and of the sphere
//! sums in the same order, without fused multiply-adds, and the sums over a sphere's
//! sides are added one by one in side order: the results are bit-identical for every lane
//! count (and every thread count), checked by `frames_tests`.

use pulp::{Arch, Simd, WithSimd};

use super::frames::{MatrixFree, NONE};

/// Contact sides per block of the sphere pass (stack buffers of the per-side terms).
const SIDE_BLOCK: usize = 64;
/// Room after a block for a whole vector (the largest lane count, AVX-512).
const PAD: usize = 8;

/// The zero velocity change of a side without a sphere (a fixed body): its terms are
/// exact zeros that leave the scalar sums' bits unchanged (see [`MatrixFree::triplet`]).
const ZERO6: [f64; 6] = [0.0; 6];

/// `copysign(1, x)` lane by lane: the sign bit of `x` on `1.0` (exact).
#[inline(always)]
fn sign_of<S: Simd>(s: S, x: S::f64s) -> S::f64s {
    s.or_f64s(s.and_f64s(x, s.splat_f64s(-0.0)), s.splat_f64s(1.0))
}

/// The tangents of `frame_from` lane by lane (the same operations in the same order).
#[inline(always)]
fn tangents<S: Simd>(s: S, n: &[S::f64s; 3], a: S::f64s) -> ([S::f64s; 3], [S::f64s; 3]) {
    let sign = sign_of(s, n[2]);
    let b = s.mul_f64s(s.mul_f64s(n[0], n[1]), a);
    let sn0 = s.mul_f64s(sign, n[0]);
    let u = [
        s.add_f64s(s.splat_f64s(1.0), s.mul_f64s(s.mul_f64s(sn0, n[0]), a)),
        s.mul_f64s(sign, b),
        s.mul_f64s(s.neg_f64s(sign), n[0]),
    ];
    let w = [
        b,
        s.add_f64s(sign, s.mul_f64s(s.mul_f64s(n[1], n[1]), a)),
        s.neg_f64s(n[1]),
    ];
    (u, w)
}

/// `a x b` lane by lane.
#[inline(always)]
fn cross<S: Simd>(s: S, a: &[S::f64s; 3], b: &[S::f64s; 3]) -> [S::f64s; 3] {
    [
        s.sub_f64s(s.mul_f64s(a[1], b[2]), s.mul_f64s(a[2], b[1])),
        s.sub_f64s(s.mul_f64s(a[2], b[0]), s.mul_f64s(a[0], b[2])),
        s.sub_f64s(s.mul_f64s(a[0], b[1]), s.mul_f64s(a[1], b[0])),
    ]
}

/// `(a0 b0 + a1 b1) + a2 b2` lane by lane.
#[inline(always)]
fn dot<S: Simd>(s: S, a: &[S::f64s; 3], b: &[S::f64s; 3]) -> S::f64s {
    s.add_f64s(
        s.add_f64s(s.mul_f64s(a[0], b[0]), s.mul_f64s(a[1], b[1])),
        s.mul_f64s(a[2], b[2]),
    )
}

/// One vector from `x[j..]`: a whole one if `len` lanes remain, else the first `len`
/// values and zeros.
#[inline(always)]
fn load<S: Simd>(s: S, x: &[f64], j: usize, len: usize) -> S::f64s {
    if len == S::F64_LANES {
        S::as_simd_f64s(&x[j..j + len]).0[0]
    } else {
        s.partial_load_f64s(&x[j..j + len])
    }
}

/// One vector from a stack array of at least `lanes` values.
#[inline(always)]
fn from_buf<S: Simd>(x: &[f64]) -> S::f64s {
    S::as_simd_f64s(&x[..S::F64_LANES]).0[0]
}

/// Stores `v` into `x[j..j + lanes]`.
#[inline(always)]
fn store<S: Simd>(x: &mut [f64], j: usize, v: S::f64s) {
    S::as_mut_simd_f64s(&mut x[j..j + S::F64_LANES]).0[0] = v;
}

/// The first three columns of `rows` (one row of four values per lane; 4 lanes).
#[inline(always)]
fn columns4<S: Simd>(s: S, rows: [&[f64]; 4]) -> [S::f64s; 4] {
    // No closures here: a closure does not inherit the SIMD target features.
    s.deinterleave_shfl_f64s([
        S::as_simd_f64s(&rows[0][..4]).0[0],
        S::as_simd_f64s(&rows[1][..4]).0[0],
        S::as_simd_f64s(&rows[2][..4]).0[0],
        S::as_simd_f64s(&rows[3][..4]).0[0],
    ])
}

/// The sphere pass over spheres `s0..s0 + out.len() / 6`: `out` gets each sphere's
/// `[dv; dw]` (world frame).
pub(super) struct GatherOp<'a> {
    pub mf: &'a MatrixFree,
    pub gamma: &'a [f64],
    pub s0: usize,
    pub out: &'a mut [f64],
}

/// Per-side terms of one block: the impulse `F` on the side's sphere and its moment
/// `r x F`, by component.
struct SideTerms {
    f: [[f64; SIDE_BLOCK + PAD]; 3],
    t: [[f64; SIDE_BLOCK + PAD]; 3],
}

impl WithSimd for GatherOp<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, s: S) -> Self::Output {
        let Self { mf, gamma, s0, out } = self;
        if S::F64_LANES == 4 {
            gather4(s, mf, gamma, s0, out);
            return;
        }
        let n_sph = out.len() / 6;
        let ptr = &mf.b_ptr[s0..=s0 + n_sph];
        let (p0, p1) = (ptr[0] as usize, ptr[n_sph] as usize);
        let mut terms = SideTerms {
            f: [[0.0; SIDE_BLOCK + PAD]; 3],
            t: [[0.0; SIDE_BLOCK + PAD]; 3],
        };
        // The current sphere (local index), the end of its sides and its sums (from +0,
        // as the scalar sums).
        let mut k = 0usize;
        let mut end = ptr[1] as usize;
        let (mut f, mut t) = ([0.0f64; 3], [0.0f64; 3]);
        let finish = |k: usize, f: &[f64; 3], t: &[f64; 3], out: &mut [f64]| {
            let [im, ij] = mf.b_inv[s0 + k];
            let o: &mut [f64; 6] = (&mut out[6 * k..6 * k + 6]).try_into().expect("6");
            for c in 0..3 {
                o[c] = im * f[c];
                o[3 + c] = ij * t[c];
            }
        };
        let mut b0 = p0;
        while b0 < p1 {
            let b1 = (b0 + SIDE_BLOCK).min(p1);
            side_terms(s, mf, gamma, b0, b1, &mut terms);
            for j in b0..b1 {
                while j == end {
                    finish(k, &f, &t, out);
                    (f, t) = ([0.0; 3], [0.0; 3]);
                    k += 1;
                    end = ptr[k + 1] as usize;
                }
                let l = j - b0;
                for c in 0..3 {
                    f[c] += terms.f[c][l];
                    t[c] += terms.t[c][l];
                }
            }
            b0 = b1;
        }
        // The last sphere with sides, and any without sides after it.
        while k < n_sph {
            finish(k, &f, &t, out);
            (f, t) = ([0.0; 3], [0.0; 3]);
            k += 1;
        }
    }
}

/// The terms of sides `b0..b1` (at most [`SIDE_BLOCK`]) into `terms` (from index 0).
#[inline(always)]
fn side_terms<S: Simd>(
    s: S,
    mf: &MatrixFree,
    gamma: &[f64],
    b0: usize,
    b1: usize,
    terms: &mut SideTerms,
) {
    let lanes = S::F64_LANES;
    let mut j = b0;
    while j < b1 {
        let len = lanes.min(b1 - j);
        let (fc, tc) = side_vectors(s, mf, gamma, j, len);
        let l = j - b0;
        for c in 0..3 {
            store::<S>(&mut terms.f[c], l, fc[c]);
            store::<S>(&mut terms.t[c], l, tc[c]);
        }
        j += len;
    }
}

/// The terms of sides `j..j + len` (one lane each, zeros past `len`): with `g` the side's
/// triplet impulses, negated on side A, `F = n g_n + u g_u + w g_w` and `r x F`.
#[inline(always)]
fn side_vectors<S: Simd>(
    s: S,
    mf: &MatrixFree,
    gamma: &[f64],
    j: usize,
    len: usize,
) -> ([S::f64s; 3], [S::f64s; 3]) {
    let n = [
        load(s, &mf.s_n[0], j, len),
        load(s, &mf.s_n[1], j, len),
        load(s, &mf.s_n[2], j, len),
    ];
    let r = [
        load(s, &mf.s_r[0], j, len),
        load(s, &mf.s_r[1], j, len),
        load(s, &mf.s_r[2], j, len),
    ];
    let a = load(s, &mf.s_rc, j, len);
    let rows = &mf.s_row[j..j + len];
    // The side's sign as a sign bit (-0 on side A): `xor` negates exactly.
    let mut neg = [0.0f64; 16];
    for (x, &rs) in neg.iter_mut().zip(rows) {
        *x = if rs & 1 == 0 { -0.0 } else { 0.0 };
    }
    let g = gather_gamma(s, gamma, rows);
    let neg = from_buf::<S>(&neg);
    let sg = [
        s.xor_f64s(g[0], neg),
        s.xor_f64s(g[1], neg),
        s.xor_f64s(g[2], neg),
    ];
    let (u, w) = tangents(s, &n, a);
    let mut fc = [s.splat_f64s(0.0); 3];
    for c in 0..3 {
        fc[c] = s.add_f64s(
            s.add_f64s(s.mul_f64s(n[c], sg[0]), s.mul_f64s(u[c], sg[1])),
            s.mul_f64s(w[c], sg[2]),
        );
    }
    (fc, cross(s, &r, &fc))
}

/// The sphere pass with 4 lanes: the terms of 4 sides transposed into per-side vectors
/// `(F, t_x)` and `(t_y, t_z, 0, 0)` and added to the current sphere's sums in registers
/// (the same additions, component by component, in side order).
#[inline(always)]
fn gather4<S: Simd>(s: S, mf: &MatrixFree, gamma: &[f64], s0: usize, out: &mut [f64]) {
    let n_sph = out.len() / 6;
    let ptr = &mf.b_ptr[s0..=s0 + n_sph];
    let (p0, p1) = (ptr[0] as usize, ptr[n_sph] as usize);
    let zero = s.splat_f64s(0.0);
    let mut k = 0usize;
    let mut end = ptr[1] as usize;
    let (mut fa, mut fb) = (zero, zero);
    let mut j = p0;
    while j < p1 {
        let len = 4.min(p1 - j);
        let (fc, tc) = side_vectors(s, mf, gamma, j, len);
        let ta = s.deinterleave_shfl_f64s([fc[0], fc[1], fc[2], tc[0]]);
        let tb = s.deinterleave_shfl_f64s([tc[1], tc[2], zero, zero]);
        for l in 0..len {
            while j + l == end {
                finish4::<S>(mf, s0 + k, fa, fb, &mut out[6 * k..6 * k + 6]);
                (fa, fb) = (zero, zero);
                k += 1;
                end = ptr[k + 1] as usize;
            }
            fa = s.add_f64s(fa, ta[l]);
            fb = s.add_f64s(fb, tb[l]);
        }
        j += len;
    }
    while k < n_sph {
        finish4::<S>(mf, s0 + k, fa, fb, &mut out[6 * k..6 * k + 6]);
        (fa, fb) = (zero, zero);
        k += 1;
    }
}

/// Sphere `sph`'s `[dv; dw] = [F / m; t / J]` from its sums `(F, t_x)`, `(t_y, t_z, ..)`.
#[inline(always)]
fn finish4<S: Simd>(mf: &MatrixFree, sph: usize, fa: S::f64s, fb: S::f64s, o: &mut [f64]) {
    let (mut a, mut b) = ([0.0f64; 4], [0.0f64; 4]);
    store::<S>(&mut a, 0, fa);
    store::<S>(&mut b, 0, fb);
    let [im, ij] = mf.b_inv[sph];
    let o: &mut [f64; 6] = o.try_into().expect("6");
    o[0] = im * a[0];
    o[1] = im * a[1];
    o[2] = im * a[2];
    o[3] = ij * a[3];
    o[4] = ij * b[0];
    o[5] = ij * b[1];
}

/// `g_n, g_u, g_w` of the sides' triplets (`rows`: `2 i + side` with `i` the normal row),
/// one lane per side (zeros past `rows.len()`).
#[inline(always)]
fn gather_gamma<S: Simd>(s: S, gamma: &[f64], rows: &[u32]) -> [S::f64s; 3] {
    let lanes = S::F64_LANES;
    if lanes == 4 && rows.len() == 4 {
        let i = [
            (rows[0] >> 1) as usize,
            (rows[1] >> 1) as usize,
            (rows[2] >> 1) as usize,
            (rows[3] >> 1) as usize,
        ];
        if i.iter().all(|&i| i + 4 <= gamma.len()) {
            let c = columns4(
                s,
                [
                    &gamma[i[0]..i[0] + 4],
                    &gamma[i[1]..i[1] + 4],
                    &gamma[i[2]..i[2] + 4],
                    &gamma[i[3]..i[3] + 4],
                ],
            );
            return [c[0], c[1], c[2]];
        }
    }
    let mut g = [[0.0f64; 16]; 3];
    for l in 0..rows.len() {
        let i = (rows[l] >> 1) as usize;
        for c in 0..3 {
            g[c][l] = gamma[i + c];
        }
    }
    [
        from_buf::<S>(&g[0]),
        from_buf::<S>(&g[1]),
        from_buf::<S>(&g[2]),
    ]
}

/// The rows of a task of friction triplets of `N g (+ shift)`: per triplet `k` (global
/// rows `3 k..3 k + 3` of the slices below) its contact `of[k]` if matrix-free, else
/// [`NONE`] (then `explicit(k, rows)` fills its rows). The runs of consecutive
/// matrix-free contacts go through [`triplet_run`].
pub(super) struct TripletsOp<'a, F: Fn(usize, &mut [f64])> {
    pub mf: &'a MatrixFree,
    pub w: &'a [f64],
    pub of: &'a [u32],
    pub rows: RowData<'a>,
    pub explicit: F,
}

/// The per-row data of a task of triplets: `eps`, `g`, the optional shift (`r`) and the
/// output.
pub(super) struct RowData<'a> {
    pub eps: &'a [f64],
    pub g: &'a [f64],
    pub shift: Option<&'a [f64]>,
    pub out: &'a mut [f64],
}

impl<F: Fn(usize, &mut [f64])> WithSimd for TripletsOp<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, s: S) -> Self::Output {
        let Self {
            mf,
            w,
            of,
            rows,
            explicit,
        } = self;
        let nt = of.len();
        let mut k = 0;
        while k < nt {
            let c0 = of[k];
            if c0 == NONE {
                explicit(k, &mut rows.out[3 * k..3 * k + 3]);
                k += 1;
                continue;
            }
            let mut len = 1;
            while k + len < nt && of[k + len] == c0 + len as u32 {
                len += 1;
            }
            let r = 3 * k..3 * (k + len);
            let run = RowData {
                eps: &rows.eps[r.clone()],
                g: &rows.g[r.clone()],
                shift: rows.shift.map(|x| &x[r.clone()]),
                out: &mut rows.out[r],
            };
            triplet_run(s, mf, w, c0 as usize, run);
            k += len;
        }
    }
}

/// The rows of `N g (+ shift)` of the consecutive matrix-free contacts `c0..c0 + n`
/// (`rows`: their `3 n` rows): `D' w`, the relative velocity of the contact points along
/// `n, u, w` (the operations of [`MatrixFree::triplet`]), plus `eps g` (and the shift), in
/// the order of the scalar path: `(D' w + eps g) + shift`.
#[inline(always)]
pub(super) fn triplet_run<S: Simd>(s: S, mf: &MatrixFree, w: &[f64], c0: usize, rows: RowData<'_>) {
    let lanes = S::F64_LANES;
    let RowData { eps, g, shift, out } = rows;
    let n = out.len() / 3;
    let mut j = 0;
    while j < n {
        let len = lanes.min(n - j);
        let c = c0 + j;
        let nv = [
            load(s, &mf.c_n[0], c, len),
            load(s, &mf.c_n[1], c, len),
            load(s, &mf.c_n[2], c, len),
        ];
        let ra = [
            load(s, &mf.c_ra[0], c, len),
            load(s, &mf.c_ra[1], c, len),
            load(s, &mf.c_ra[2], c, len),
        ];
        let rb = [
            load(s, &mf.c_rb[0], c, len),
            load(s, &mf.c_rb[1], c, len),
            load(s, &mf.c_rb[2], c, len),
        ];
        let a = load(s, &mf.c_rc, c, len);
        let bodies = &mf.c_body[c..c + len];
        let [xa, xb] = sphere_velocities(s, w, bodies);
        // `rel = (0 - vp_A) + vp_B`; a missing side reads zeros (`vp = +0`), which leaves
        // the scalar path's bits (it skips the side).
        let vpa = point_velocity(s, &xa, &ra);
        let vpb = point_velocity(s, &xb, &rb);
        let zero = s.splat_f64s(0.0);
        let rel = [
            s.add_f64s(s.sub_f64s(zero, vpa[0]), vpb[0]),
            s.add_f64s(s.sub_f64s(zero, vpa[1]), vpb[1]),
            s.add_f64s(s.sub_f64s(zero, vpa[2]), vpb[2]),
        ];
        let (u, v) = tangents(s, &nv, a);
        let d = [dot(s, &nv, &rel), dot(s, &u, &rel), dot(s, &v, &rel)];
        let o0 = 3 * j;
        if lanes == 4 && len == 4 {
            // Contact by contact `(d_n, d_u, d_w, 0)`; the first three contacts' rows with
            // the next contact's first row, four rows at a time and in order (each fourth
            // value is overwritten by the next contact's), the fourth contact in scalar
            // code. The group's 12 rows are taken as arrays once (no bounds checks).
            let t = s.deinterleave_shfl_f64s([d[0], d[1], d[2], zero]);
            let e: &[f64; 12] = eps[o0..o0 + 12].try_into().expect("12");
            let gg: &[f64; 12] = g[o0..o0 + 12].try_into().expect("12");
            let sh: Option<&[f64; 12]> = shift.map(|r| r[o0..o0 + 12].try_into().expect("12"));
            let o: &mut [f64; 12] = (&mut out[o0..o0 + 12]).try_into().expect("12");
            for l in 0..3 {
                let i = 3 * l;
                let x = s.add_f64s(
                    t[l],
                    s.mul_f64s(
                        S::as_simd_f64s(&e[i..i + 4]).0[0],
                        S::as_simd_f64s(&gg[i..i + 4]).0[0],
                    ),
                );
                let x = match sh {
                    Some(r) => s.add_f64s(x, S::as_simd_f64s(&r[i..i + 4]).0[0]),
                    None => x,
                };
                S::as_mut_simd_f64s(&mut o[i..i + 4]).0[0] = x;
            }
            let mut buf = [0.0f64; 4];
            store::<S>(&mut buf, 0, t[3]);
            for q in 0..3 {
                let x = buf[q] + e[9 + q] * gg[9 + q];
                o[9 + q] = match sh {
                    Some(r) => x + r[9 + q],
                    None => x,
                };
            }
        } else {
            let mut buf = [[0.0f64; 16]; 3];
            for q in 0..3 {
                store::<S>(&mut buf[q], 0, d[q]);
            }
            for l in 0..len {
                let i = o0 + 3 * l;
                finish_rows([buf[0][l], buf[1][l], buf[2][l]], eps, g, shift, out, i);
            }
        }
        j += len;
    }
}

/// Rows `i..i + 3` of the output: `(d + eps g) + shift` in scalar code.
#[inline(always)]
fn finish_rows(
    d: [f64; 3],
    eps: &[f64],
    g: &[f64],
    shift: Option<&[f64]>,
    out: &mut [f64],
    i: usize,
) {
    for q in 0..3 {
        let x = d[q] + eps[i + q] * g[i + q];
        out[i + q] = match shift {
            Some(r) => x + r[i + q],
            None => x,
        };
    }
}

/// `dv + dw x r` lane by lane (`x = [dv; dw]`).
#[inline(always)]
fn point_velocity<S: Simd>(s: S, x: &[S::f64s; 6], r: &[S::f64s; 3]) -> [S::f64s; 3] {
    let c = cross(s, &[x[3], x[4], x[5]], r);
    [
        s.add_f64s(x[0], c[0]),
        s.add_f64s(x[1], c[1]),
        s.add_f64s(x[2], c[2]),
    ]
}

/// The velocity changes `[dv; dw]` of sides A and B of the contacts `bodies` (one lane
/// each; zeros for a side without a sphere and past `bodies.len()`).
#[inline(always)]
fn sphere_velocities<S: Simd>(s: S, w: &[f64], bodies: &[[u32; 2]]) -> [[S::f64s; 6]; 2] {
    let zero = s.splat_f64s(0.0);
    let mut x = [[zero; 6]; 2];
    for (side, x) in x.iter_mut().enumerate() {
        if S::F64_LANES == 4 && bodies.len() == 4 {
            // Values 0..4 and 2..6 of each record, transposed.
            let r = [
                record(w, bodies[0][side]),
                record(w, bodies[1][side]),
                record(w, bodies[2][side]),
                record(w, bodies[3][side]),
            ];
            let lo = columns4(s, [&r[0][0..4], &r[1][0..4], &r[2][0..4], &r[3][0..4]]);
            let hi = columns4(s, [&r[0][2..6], &r[1][2..6], &r[2][2..6], &r[3][2..6]]);
            *x = [lo[0], lo[1], lo[2], lo[3], hi[2], hi[3]];
        } else {
            let mut buf = [[0.0f64; 16]; 6];
            for (l, b) in bodies.iter().enumerate() {
                let r = record(w, b[side]);
                for k in 0..6 {
                    buf[k][l] = r[k];
                }
            }
            for k in 0..6 {
                x[k] = from_buf::<S>(&buf[k]);
            }
        }
    }
    x
}

/// Sphere `b`'s `[dv; dw]` in `w`, or zeros for [`NONE`].
#[inline(always)]
fn record(w: &[f64], b: u32) -> &[f64] {
    if b == NONE {
        &ZERO6
    } else {
        &w[6 * b as usize..6 * b as usize + 6]
    }
}

impl MatrixFree {
    /// The sphere pass over spheres `s0..`, into `out` (6 per sphere), at the CPU's SIMD
    /// level.
    pub(super) fn gather_task(&self, gamma: &[f64], s0: usize, out: &mut [f64]) {
        Arch::new().dispatch(GatherOp {
            mf: self,
            gamma,
            s0,
            out,
        });
    }

    /// The rows of a task of friction triplets ([`TripletsOp`]) at the CPU's SIMD level.
    pub(super) fn triplets_task(
        &self,
        w: &[f64],
        of: &[u32],
        rows: RowData<'_>,
        explicit: impl Fn(usize, &mut [f64]),
    ) {
        Arch::new().dispatch(TripletsOp {
            mf: self,
            w,
            of,
            rows,
            explicit,
        });
    }
}

#[cfg(test)]
impl MatrixFree {
    /// The sphere pass sphere by sphere in plain scalar code (the reference of the SIMD
    /// pass: the same sums in the same order).
    pub(super) fn gather_reference(&self, gamma: &[f64], w: &mut [f64]) {
        for s in 0..self.n_bodies() {
            let (mut f, mut t) = ([0.0f64; 3], [0.0f64; 3]);
            for j in self.b_ptr[s] as usize..self.b_ptr[s + 1] as usize {
                let (i, side) = ((self.s_row[j] >> 1) as usize, self.s_row[j] & 1);
                let n = [self.s_n[0][j], self.s_n[1][j], self.s_n[2][j]];
                let r = [self.s_r[0][j], self.s_r[1][j], self.s_r[2][j]];
                let (u, v) = super::frames::frame_from(&n, self.s_rc[j]);
                let g = &gamma[i..i + 3];
                let sg = if side == 0 {
                    [-g[0], -g[1], -g[2]]
                } else {
                    [g[0], g[1], g[2]]
                };
                let fc: [f64; 3] =
                    std::array::from_fn(|k| n[k] * sg[0] + u[k] * sg[1] + v[k] * sg[2]);
                let tc = [
                    r[1] * fc[2] - r[2] * fc[1],
                    r[2] * fc[0] - r[0] * fc[2],
                    r[0] * fc[1] - r[1] * fc[0],
                ];
                for k in 0..3 {
                    f[k] += fc[k];
                    t[k] += tc[k];
                }
            }
            let [im, ij] = self.b_inv[s];
            for k in 0..3 {
                w[6 * s + k] = im * f[k];
                w[6 * s + 3 + k] = ij * t[k];
            }
        }
    }

    /// The sphere pass with one lane ([`pulp::Scalar`]), in tasks of `task` spheres.
    pub(super) fn gather_one_lane(&self, gamma: &[f64], w: &mut [f64], task: usize) {
        let n = 6 * self.n_bodies();
        for (t, o) in w[..n].chunks_mut(6 * task).enumerate() {
            let op = GatherOp {
                mf: self,
                gamma,
                s0: t * task,
                out: o,
            };
            op.with_simd(pulp::Scalar::new());
        }
    }

    /// The rows of the consecutive contacts `c0..` ([`triplet_run`]) with one lane
    /// ([`pulp::Scalar`]).
    pub(super) fn triplet_one_lane(&self, w: &[f64], c0: usize, rows: RowData<'_>) {
        triplet_run(pulp::Scalar::new(), self, w, c0, rows);
    }
}
