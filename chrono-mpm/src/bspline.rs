//! Quadratic B-spline interpolation between markers and grid nodes.
//!
//! The 1-D kernel (Steffen, Kirby & Berzins, "Analysis and reduction of quadrature errors
//! in the material point method", IJNME 76, 2008), with `s = |x - x_i| / dx`:
//!
//! ```text
//! N(s) = 3/4 - s^2            for s < 1/2
//!      = (3/2 - s)^2 / 2      for 1/2 <= s < 3/2
//!      = 0                    otherwise
//! ```
//!
//! Why quadratic and not the seed's cubic: the quadratic spline is C1 (gradients continuous,
//! no cell-crossing noise of linear hat functions) with a support of 3 nodes per axis, so a
//! marker touches 27 nodes instead of the cubic's 64 (2.4 x less transfer work), and its
//! APIC inertia tensor is the constant `D = dx^2/4 I` (Jiang et al. 2015, sec. 5.3); the
//! cubic's would be `dx^2/3 I`. Both reproduce affine fields exactly, which is what the
//! APIC transfers need. The accuracy of the two on the elastic bar is measured in
//! `docs/mpm.md` (quadratic here; the cubic is for a later comparison).
//!
//! A marker at `x` has the *base node* `b = floor((x - origin)/dx - 1/2)` per axis and
//! weights on the nodes `b, b+1, b+2`, with `f = (x - origin)/dx - b` in `[1/2, 3/2)`.

/// Per-axis weights and their derivatives for one marker.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stencil {
    /// Base node per axis (grid index, may be negative relative to the box origin).
    pub base: [i64; 3],
    /// Fractional offset `f = (x - origin)/dx - base` per axis, in `[1/2, 3/2)`.
    pub frac: [f64; 3],
    /// `w[a][o]`: weight of node `base + o` along axis `a`.
    pub w: [[f64; 3]; 3],
    /// `dw[a][o]`: derivative of `w[a][o]` with respect to the marker position along
    /// axis `a`, 1/m.
    pub dw: [[f64; 3]; 3],
}

/// 1-D quadratic weights of nodes `b, b+1, b+2` for a marker at fractional offset `f`.
#[inline]
pub fn weights_1d(f: f64) -> [f64; 3] {
    let a = 1.5 - f;
    let c = f - 1.0;
    let d = f - 0.5;
    [0.5 * a * a, 0.75 - c * c, 0.5 * d * d]
}

/// Derivatives of [`weights_1d`] with respect to `f` (so `d/dx_p = (1/dx) d/df`).
#[inline]
pub fn dweights_1d(f: f64) -> [f64; 3] {
    [f - 1.5, -2.0 * (f - 1.0), f - 0.5]
}

impl Stencil {
    /// The stencil of a marker at `x` on a grid with `origin` and spacing `dx`.
    #[inline]
    pub fn new(x: [f64; 3], origin: [f64; 3], dx: f64) -> Self {
        let mut s = Stencil::default();
        let inv = 1.0 / dx;
        for a in 0..3 {
            let g = (x[a] - origin[a]) * inv;
            let b = (g - 0.5).floor();
            let f = g - b;
            s.base[a] = b as i64;
            s.frac[a] = f;
            s.w[a] = weights_1d(f);
            let d = dweights_1d(f);
            s.dw[a] = [d[0] * inv, d[1] * inv, d[2] * inv];
        }
        s
    }

    /// Weight of node `base + o`.
    #[inline]
    pub fn weight(&self, o: [usize; 3]) -> f64 {
        self.w[0][o[0]] * self.w[1][o[1]] * self.w[2][o[2]]
    }

    /// Gradient of the weight of node `base + o` with respect to the marker position,
    /// `grad w_ip = d N_i(x_p) / d x_p`, 1/m.
    #[inline]
    pub fn grad(&self, o: [usize; 3]) -> [f64; 3] {
        let (wx, wy, wz) = (self.w[0][o[0]], self.w[1][o[1]], self.w[2][o[2]]);
        [
            self.dw[0][o[0]] * wy * wz,
            wx * self.dw[1][o[1]] * wz,
            wx * wy * self.dw[2][o[2]],
        ]
    }

    /// `x_i - x_p` for node `base + o`, m.
    #[inline]
    pub fn offset(&self, o: [usize; 3], dx: f64) -> [f64; 3] {
        [
            (o[0] as f64 - self.frac[0]) * dx,
            (o[1] as f64 - self.frac[1]) * dx,
            (o[2] as f64 - self.frac[2]) * dx,
        ]
    }
}

/// The APIC inertia tensor factor of the quadratic spline: `D = dx^2 / 4 I`, so
/// `C = B D^-1 = 4/dx^2 B`.
pub fn apic_d_inverse(dx: f64) -> f64 {
    4.0 / (dx * dx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_linear_reproduction_and_inertia() {
        // sum w = 1, sum w (x_i - x_p) = 0, sum w (x_i - x_p)^2 = dx^2/4 for any f.
        let dx = 0.3;
        for k in 0..=100 {
            let f = 0.5 + k as f64 / 100.0 * 0.999_999;
            let w = weights_1d(f);
            let s0: f64 = w.iter().sum();
            let s1: f64 = (0..3).map(|o| w[o] * (o as f64 - f) * dx).sum();
            let s2: f64 = (0..3).map(|o| w[o] * ((o as f64 - f) * dx).powi(2)).sum();
            assert!((s0 - 1.0).abs() < 1e-14, "f {f}: sum {s0}");
            assert!(s1.abs() < 1e-14, "f {f}: first moment {s1}");
            assert!(
                (s2 - dx * dx / 4.0).abs() < 1e-14,
                "f {f}: second moment {s2}"
            );
            // Gradients sum to zero, and sum of grad * (x_i - x_p) is -1 (d/dx_p of the
            // first moment identity).
            let d = dweights_1d(f);
            let g0: f64 = d.iter().sum();
            assert!(g0.abs() < 1e-14);
        }
    }

    #[test]
    fn derivative_matches_finite_difference() {
        for &f in &[0.5, 0.7, 1.0, 1.23, 1.49] {
            let e = 1e-6;
            let (a, b) = (weights_1d(f + e), weights_1d(f - e));
            let d = dweights_1d(f);
            for o in 0..3 {
                assert!(((a[o] - b[o]) / (2.0 * e) - d[o]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn stencil_gradient_matches_finite_difference() {
        let (origin, dx) = ([0.1, -0.2, 0.3], 0.05);
        let x = [0.2371, -0.1733, 0.3412];
        let s = Stencil::new(x, origin, dx);
        let e = 1e-7;
        for a in 0..3 {
            let mut xp = x;
            let mut xm = x;
            xp[a] += e;
            xm[a] -= e;
            let (sp, sm) = (Stencil::new(xp, origin, dx), Stencil::new(xm, origin, dx));
            assert_eq!(sp.base, s.base);
            assert_eq!(sm.base, s.base);
            for o0 in 0..3 {
                for o1 in 0..3 {
                    for o2 in 0..3 {
                        let o = [o0, o1, o2];
                        let fd = (sp.weight(o) - sm.weight(o)) / (2.0 * e);
                        assert!((fd - s.grad(o)[a]).abs() < 1e-5 * (1.0 + fd.abs()));
                    }
                }
            }
        }
    }
}
