//! SPH smoothing kernels with gradients: the cubic B-spline (Monaghan and Lattanzio 1985)
//! and the Wendland C2 function (Wendland 1995), both with compact support `2 h`.
//!
//! With `q = r / h` and `d` the number of space dimensions (2 or 3):
//!
//! ```text
//! cubic spline:  W(r) = sigma_d / h^d * { 1 - 3/2 q^2 + 3/4 q^3      0 <= q < 1
//!                                        { 1/4 (2 - q)^3              1 <= q < 2
//!                                        { 0                          q >= 2
//!                sigma_2 = 10 / (7 pi),  sigma_3 = 1 / pi
//! Wendland C2:   W(r) = sigma_d / h^d * (1 - q/2)^4 (2 q + 1)         0 <= q < 2
//!                sigma_2 = 7 / (4 pi),   sigma_3 = 21 / (16 pi)
//! ```
//!
//! Both are normalized, `int W dV = 1` (units 1/m^d). The gradient with respect to the
//! first particle is `grad_a W_ab = (dW/dr)(r_ab) x_ab / r_ab` with `x_ab = x_a - x_b`;
//! [`Kernel::grad_factor`] returns `F(r) = (dW/dr) / r` (finite at `r = 0` for both
//! kernels), so `grad_a W_ab = F(r_ab) x_ab`.
//!
//! References: J. J. Monaghan, J. C. Lattanzio, "A refined particle method for
//! astrophysical problems", Astron. Astrophys. 149 (1985) 135-143; H. Wendland,
//! "Piecewise polynomial, positive definite and compactly supported radial functions of
//! minimal degree", Adv. Comput. Math. 4 (1995) 389-396; W. Dehnen, H. Aly, "Improving
//! convergence in smoothed particle hydrodynamics simulations without pairing
//! instability", MNRAS 425 (2012) 1068-1082 (the normalizations above).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use crate::error::{ChronoError, Result};

/// Which kernel function.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum KernelKind {
    /// The cubic B-spline of Monaghan and Lattanzio (1985), support `2 h`.
    #[serde(alias = "cubic")]
    CubicSpline,
    /// The Wendland C2 function (Wendland 1995), support `2 h`; free of the pairing
    /// instability (Dehnen and Aly 2012).
    #[default]
    #[serde(alias = "wendland")]
    WendlandC2,
}

impl KernelKind {
    /// Parses `cubic_spline` / `cubic` or `wendland_c2` / `wendland`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "cubic_spline" | "cubic" => Ok(Self::CubicSpline),
            "wendland_c2" | "wendland" => Ok(Self::WendlandC2),
            other => Err(ChronoError::invalid(
                "kernel",
                other,
                "must be `cubic_spline` or `wendland_c2`",
            )),
        }
    }
}

/// A smoothing kernel of a given kind, smoothing length `h` (m) and dimension (2 or 3).
///
/// The constants are precomputed, so [`w`](Kernel::w) and
/// [`grad_factor`](Kernel::grad_factor) are a few multiplications each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kernel {
    kind: KernelKind,
    h: f64,
    dim: u32,
    inv_h: f64,
    /// `sigma_d / h^d`, 1/m^d.
    norm: f64,
}

impl Kernel {
    /// A kernel of `kind` with smoothing length `h > 0` (m) in `dim` = 2 or 3 dimensions.
    pub fn new(kind: KernelKind, h: f64, dim: u32) -> Result<Self> {
        crate::error::check_positive("kernel.h", h)?;
        let sigma = match (kind, dim) {
            (KernelKind::CubicSpline, 2) => 10.0 / (7.0 * PI),
            (KernelKind::CubicSpline, 3) => 1.0 / PI,
            (KernelKind::WendlandC2, 2) => 7.0 / (4.0 * PI),
            (KernelKind::WendlandC2, 3) => 21.0 / (16.0 * PI),
            _ => return Err(ChronoError::invalid("kernel.dim", dim, "must be 2 or 3")),
        };
        Ok(Self {
            kind,
            h,
            dim,
            inv_h: 1.0 / h,
            norm: sigma / h.powi(dim as i32),
        })
    }

    /// The kernel kind.
    pub fn kind(&self) -> KernelKind {
        self.kind
    }

    /// The smoothing length `h`, m.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The number of space dimensions (2 or 3).
    pub fn dim(&self) -> u32 {
        self.dim
    }

    /// The support radius `2 h`, m: `W(r) = 0` for `r >= 2 h`.
    pub fn support(&self) -> f64 {
        2.0 * self.h
    }

    /// `W(r)`, 1/m^d.
    #[inline]
    pub fn w(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        match self.kind {
            KernelKind::CubicSpline => {
                if q < 1.0 {
                    self.norm * (1.0 - 1.5 * q * q + 0.75 * q * q * q)
                } else if q < 2.0 {
                    let t = 2.0 - q;
                    self.norm * 0.25 * t * t * t
                } else {
                    0.0
                }
            }
            KernelKind::WendlandC2 => {
                if q < 2.0 {
                    let t = 1.0 - 0.5 * q;
                    let t2 = t * t;
                    self.norm * t2 * t2 * (2.0 * q + 1.0)
                } else {
                    0.0
                }
            }
        }
    }

    /// `dW/dr`, 1/m^(d+1) (<= 0 for both kernels).
    #[inline]
    pub fn dw_dr(&self, r: f64) -> f64 {
        self.grad_factor(r) * r
    }

    /// `F(r) = (dW/dr) / r`, 1/m^(d+2), finite at `r = 0`; `grad_a W_ab = F(r_ab) x_ab`.
    #[inline]
    pub fn grad_factor(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        let c = self.norm * self.inv_h * self.inv_h;
        match self.kind {
            KernelKind::CubicSpline => {
                if q < 1.0 {
                    // d/dq (1 - 1.5 q^2 + 0.75 q^3) / q = -3 + 2.25 q
                    c * (-3.0 + 2.25 * q)
                } else if q < 2.0 {
                    let t = 2.0 - q;
                    // d/dq 0.25 (2-q)^3 / q = -0.75 (2-q)^2 / q
                    -0.75 * c * t * t / q
                } else {
                    0.0
                }
            }
            KernelKind::WendlandC2 => {
                if q < 2.0 {
                    // d/dq (1-q/2)^4 (2q+1) / q = -5 (1-q/2)^3
                    let t = 1.0 - 0.5 * q;
                    -5.0 * c * t * t * t
                } else {
                    0.0
                }
            }
        }
    }

    /// `W` and `F = (dW/dr)/r` at once (one branch), see [`grad_factor`](Self::grad_factor).
    #[inline]
    pub fn w_and_grad_factor(&self, r: f64) -> (f64, f64) {
        (self.w(r), self.grad_factor(r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds() -> [KernelKind; 2] {
        [KernelKind::CubicSpline, KernelKind::WendlandC2]
    }

    /// Radial quadrature of `int W dV` (Simpson, fine).
    fn radial_integral(k: &Kernel) -> f64 {
        let n = 20_000;
        let r_max = k.support();
        let dr = r_max / n as f64;
        let mut s = 0.0;
        for i in 0..=n {
            let r = i as f64 * dr;
            let shell = if k.dim() == 3 {
                4.0 * PI * r * r
            } else {
                2.0 * PI * r
            };
            let wgt = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            s += wgt * k.w(r) * shell;
        }
        s * dr / 3.0
    }

    #[test]
    fn kernels_are_normalized_in_2d_and_3d() {
        for kind in kinds() {
            for dim in [2, 3] {
                for h in [0.013, 1.0, 7.5] {
                    let k = Kernel::new(kind, h, dim).unwrap();
                    let s = radial_integral(&k);
                    assert!((s - 1.0).abs() < 1e-9, "{kind:?} d={dim} h={h}: {s}");
                }
            }
        }
    }

    #[test]
    fn lattice_sum_is_close_to_one() {
        // On a cubic lattice of spacing dp with h = 1.3 dp, sum_b W_ab dp^3 ~ 1.
        for kind in kinds() {
            let dp = 0.01;
            let k = Kernel::new(kind, 1.3 * dp, 3).unwrap();
            let mut s = 0.0;
            for i in -4i32..=4 {
                for j in -4i32..=4 {
                    for l in -4i32..=4 {
                        let r = dp * ((i * i + j * j + l * l) as f64).sqrt();
                        s += k.w(r) * dp * dp * dp;
                    }
                }
            }
            assert!((s - 1.0).abs() < 0.01, "{kind:?}: {s}");
        }
    }

    #[test]
    fn gradient_matches_finite_differences() {
        for kind in kinds() {
            for dim in [2, 3] {
                let h = 0.2;
                let k = Kernel::new(kind, h, dim).unwrap();
                for i in 1..80 {
                    let r = i as f64 * 0.005;
                    let e = 1e-7;
                    let fd = (k.w(r + e) - k.w(r - e)) / (2.0 * e);
                    let an = k.dw_dr(r);
                    let scale = k.w(0.0) / h;
                    assert!(
                        (fd - an).abs() < 1e-6 * scale,
                        "{kind:?} d={dim} r={r}: fd {fd} analytic {an}"
                    );
                    assert!(an <= 0.0);
                }
                assert_eq!(k.w(2.0 * h), 0.0);
                assert_eq!(k.grad_factor(2.0 * h + 1e-9), 0.0);
                assert!(k.grad_factor(0.0).is_finite());
            }
        }
    }

    #[test]
    fn gradient_first_moment_is_minus_identity() {
        // int x_ab (x) grad_a W dV = -I (consistency of the gradient): in 3D the trace
        // is int r dW/dr 4 pi r^2 dr = -3.
        for kind in kinds() {
            let k = Kernel::new(kind, 0.5, 3).unwrap();
            let n = 20_000;
            let dr = k.support() / n as f64;
            let mut s = 0.0;
            for i in 0..n {
                let r = (i as f64 + 0.5) * dr;
                s += r * k.dw_dr(r) * 4.0 * PI * r * r * dr;
            }
            assert!((s + 3.0).abs() < 1e-6, "{kind:?}: {s}");
        }
    }

    #[test]
    fn bad_input_is_rejected_with_the_field() {
        let e = Kernel::new(KernelKind::CubicSpline, -1.0, 3).unwrap_err();
        assert!(e.to_string().contains("kernel.h"), "{e}");
        let e = Kernel::new(KernelKind::WendlandC2, 1.0, 1).unwrap_err();
        assert!(e.to_string().contains("kernel.dim"), "{e}");
        assert!(KernelKind::parse("gauss").is_err());
        assert_eq!(KernelKind::parse("cubic").unwrap(), KernelKind::CubicSpline);
    }
}
