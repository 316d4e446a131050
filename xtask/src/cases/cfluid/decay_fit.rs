//! Frequency and damping of a free decay: the least-squares fit of a damped sinusoid and
//! the logarithmic decrement of its extrema (the measurement of `cfluid-sloshing-decay`).
//!
//! Model: `y(t) = c + exp(-sigma t) (A cos(omega_d t) + B sin(omega_d t))`. For fixed
//! `(sigma, omega_d)` the model is linear in `(c, A, B)` (least squares); the two
//! nonlinear parameters minimize the residual (variable projection: a grid, then
//! Nelder-Mead). The damping ratio is `zeta = sigma / omega_n`,
//! `omega_n = sqrt(omega_d^2 + sigma^2)` (a linear oscillator
//! `y'' + 2 zeta omega_n y' + omega_n^2 y = 0`).

use nalgebra::{DMatrix, DVector};

/// The fitted damped sinusoid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DampedFit {
    /// Damped angular frequency `omega_d`, rad/s.
    pub omega_d: f64,
    /// Decay rate `sigma`, 1/s.
    pub sigma: f64,
    /// Offset `c` (the signal's units).
    pub offset: f64,
    /// Amplitude `sqrt(A^2 + B^2)` at `t = 0`.
    pub amplitude: f64,
    /// RMS residual over the RMS of the oscillating part (0 for an exact fit).
    pub rel_residual: f64,
}

impl DampedFit {
    /// Undamped natural frequency `omega_n = sqrt(omega_d^2 + sigma^2)`, rad/s.
    pub fn omega_n(&self) -> f64 {
        self.omega_d.hypot(self.sigma)
    }

    /// Damping ratio `zeta = sigma / omega_n`.
    pub fn zeta(&self) -> f64 {
        self.sigma / self.omega_n()
    }
}

/// Residual sum of squares and linear coefficients `(c, A, B)` at `(sigma, omega)`.
fn linear(samples: &[(f64, f64)], sigma: f64, omega: f64) -> Option<(f64, [f64; 3])> {
    let n = samples.len();
    let mut m = DMatrix::<f64>::zeros(n, 3);
    let mut y = DVector::<f64>::zeros(n);
    for (i, &(t, v)) in samples.iter().enumerate() {
        let e = (-sigma * t).exp();
        let (s, c) = (omega * t).sin_cos();
        m[(i, 0)] = 1.0;
        m[(i, 1)] = e * c;
        m[(i, 2)] = e * s;
        y[i] = v;
    }
    let coef = m.clone().svd(true, true).solve(&y, 1e-12).ok()?;
    let r = &y - &m * &coef;
    let rss = r.norm_squared();
    rss.is_finite()
        .then_some((rss, [coef[0], coef[1], coef[2]]))
}

/// Nelder-Mead on `f` from `x0` with initial steps `step`; `iters` iterations.
fn nelder_mead(
    f: impl Fn([f64; 2]) -> f64,
    x0: [f64; 2],
    step: [f64; 2],
    iters: usize,
) -> [f64; 2] {
    let mut s = [x0, [x0[0] + step[0], x0[1]], [x0[0], x0[1] + step[1]]];
    let mut v = s.map(&f);
    for _ in 0..iters {
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&i, &j| v[i].total_cmp(&v[j]));
        s = idx.map(|i| s[i]);
        v = idx.map(|i| v[i]);
        let c = [(s[0][0] + s[1][0]) / 2.0, (s[0][1] + s[1][1]) / 2.0];
        let at = |t: f64| [c[0] + t * (s[2][0] - c[0]), c[1] + t * (s[2][1] - c[1])];
        let xr = at(-1.0);
        let fr = f(xr);
        if fr < v[0] {
            let xe = at(-2.0);
            let fe = f(xe);
            if fe < fr {
                (s[2], v[2]) = (xe, fe);
            } else {
                (s[2], v[2]) = (xr, fr);
            }
        } else if fr < v[1] {
            (s[2], v[2]) = (xr, fr);
        } else {
            let xc = at(0.5);
            let fc = f(xc);
            if fc < v[2] {
                (s[2], v[2]) = (xc, fc);
            } else {
                for k in 1..3 {
                    s[k] = [(s[0][0] + s[k][0]) / 2.0, (s[0][1] + s[k][1]) / 2.0];
                    v[k] = f(s[k]);
                }
            }
        }
    }
    let best = (0..3).min_by(|&i, &j| v[i].total_cmp(&v[j])).unwrap_or(0);
    s[best]
}

/// Fits the damped sinusoid to `samples` (`(t, y)`, at least 8), the frequency searched
/// in `[0.6, 1.4] omega_guess` and the damping ratio in `[0, 0.6]`. Errors when the fit
/// is singular or the samples are too few.
pub fn fit_damped(samples: &[(f64, f64)], omega_guess: f64) -> anyhow::Result<DampedFit> {
    anyhow::ensure!(
        samples.len() >= 8,
        "decay fit: {} samples, need at least 8",
        samples.len()
    );
    anyhow::ensure!(
        omega_guess > 0.0 && omega_guess.is_finite(),
        "decay fit: omega_guess must be > 0, got {omega_guess}"
    );
    let t0 = samples[0].0;
    let shifted: Vec<(f64, f64)> = samples.iter().map(|&(t, y)| (t - t0, y)).collect();
    let rss = |x: [f64; 2]| {
        let (sigma, omega) = (x[0], x[1]);
        if omega <= 0.0 {
            return f64::INFINITY;
        }
        linear(&shifted, sigma, omega).map_or(f64::INFINITY, |r| r.0)
    };
    let mut best = (f64::INFINITY, [0.0, omega_guess]);
    for i in 0..=80 {
        let omega = omega_guess * (0.6 + 0.8 * i as f64 / 80.0);
        for j in 0..=30 {
            let zeta = 0.6 * (j as f64 / 30.0).powi(2);
            let x = [zeta * omega, omega];
            let r = rss(x);
            if r < best.0 {
                best = (r, x);
            }
        }
    }
    anyhow::ensure!(best.0.is_finite(), "decay fit: singular least squares");
    let step = [0.02 * omega_guess, 0.01 * omega_guess];
    let mut x = best.1;
    for _ in 0..3 {
        x = nelder_mead(rss, x, step, 200);
    }
    let (rss_best, coef) =
        linear(&shifted, x[0], x[1]).ok_or_else(|| anyhow::anyhow!("decay fit: singular"))?;
    let amplitude = coef[1].hypot(coef[2]);
    let mean = shifted.iter().map(|s| s.1).sum::<f64>() / shifted.len() as f64;
    let var = shifted.iter().map(|s| (s.1 - mean).powi(2)).sum::<f64>();
    Ok(DampedFit {
        omega_d: x[1],
        sigma: x[0],
        offset: coef[0],
        // the amplitude at the first sample's time; referred to t = 0 of the signal
        amplitude: amplitude * (x[0] * t0).exp(),
        rel_residual: (rss_best / var.max(f64::MIN_POSITIVE)).sqrt(),
    })
}

/// The logarithmic decrement of the extrema of `y - offset`: the damping ratio from a
/// straight line through `ln |e_i|` against `i` (successive extrema, half a period
/// apart: `|e_{i+1}| / |e_i| = exp(-pi zeta / sqrt(1 - zeta^2))`), and the number of
/// extrema used. `None` with fewer than 3 extrema. An extremum is a sample larger (or
/// smaller) than every sample within `window` samples on either side; the extrema after
/// the first one below 5 % of the largest are left out (noise).
pub fn log_decrement(samples: &[(f64, f64)], offset: f64, window: usize) -> Option<(f64, usize)> {
    let w = window.max(1);
    let y: Vec<f64> = samples.iter().map(|s| s.1 - offset).collect();
    let mut ext = Vec::new();
    for i in w..y.len().saturating_sub(w) {
        let nb = &y[i - w..=i + w];
        let is_max = nb.iter().all(|&v| v <= y[i]) && y[i] > 0.0;
        let is_min = nb.iter().all(|&v| v >= y[i]) && y[i] < 0.0;
        if (is_max || is_min)
            && ext
                .last()
                .is_none_or(|&(_, s): &(usize, f64)| s * y[i] < 0.0)
        {
            ext.push((i, y[i]));
        }
    }
    // the extrema that stand out of the noise: from the largest down to 5 % of it
    let top = ext.iter().fold(0.0f64, |m, e| m.max(e.1.abs()));
    if let Some(k) = ext.iter().position(|e| e.1.abs() < 0.05 * top) {
        ext.truncate(k);
    }
    if ext.len() < 3 {
        return None;
    }
    let n = ext.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for (k, &(_, e)) in ext.iter().enumerate() {
        let (x, l) = (k as f64, e.abs().ln());
        sx += x;
        sy += l;
        sxx += x * x;
        sxy += x * l;
    }
    let slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let d = -slope;
    Some((d / (std::f64::consts::PI.powi(2) + d * d).sqrt(), ext.len()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn synthetic(omega_n: f64, zeta: f64, noise: f64) -> Vec<(f64, f64)> {
        let sigma = zeta * omega_n;
        let wd = omega_n * (1.0 - zeta * zeta).sqrt();
        (0..1500)
            .map(|i| {
                let t = 0.1 + i as f64 * 0.004;
                // a deterministic "noise" that is not a sinusoid of the fitted frequency
                let n = noise * ((37.0 * t).sin() * (91.0 * t).cos());
                (
                    t,
                    0.02 + (-sigma * t).exp() * (0.5 * (wd * t).cos() - 0.2 * (wd * t).sin()) + n,
                )
            })
            .collect()
    }

    /// The fit recovers frequency and damping of a synthetic damped sinusoid (light and
    /// heavy damping, with an offset and a small perturbation), and the decrement agrees.
    #[test]
    fn fit_recovers_frequency_and_damping() {
        for &(omega_n, zeta) in &[(5.64, 0.002), (5.64, 0.05), (8.7, 0.2)] {
            let s = synthetic(omega_n, zeta, 1e-3);
            let f = fit_damped(&s, 0.9 * omega_n).unwrap();
            assert!((f.omega_n() / omega_n - 1.0).abs() < 2e-3, "{f:?}");
            assert!((f.zeta() - zeta).abs() < 0.02 * zeta + 2e-4, "{zeta} {f:?}");
            assert!((f.offset - 0.02).abs() < 1e-3, "{f:?}");
            assert!((f.amplitude / 0.5385 - 1.0).abs() < 0.02, "{f:?}");
            let (zd, n) = log_decrement(&s, f.offset, 5).unwrap();
            assert!(n >= 4, "{n}");
            assert!((zd - zeta).abs() < 0.05 * zeta + 1e-3, "{zeta} {zd}");
        }
    }

    /// The fit can fail the check: a damping twice as large is not found where it is not.
    #[test]
    fn fit_tells_damping_apart() {
        let a = fit_damped(&synthetic(6.0, 0.03, 0.0), 6.0).unwrap();
        let b = fit_damped(&synthetic(6.0, 0.06, 0.0), 6.0).unwrap();
        assert!((b.zeta() / a.zeta() - 2.0).abs() < 0.01, "{a:?} {b:?}");
        assert!(fit_damped(&[(0.0, 1.0); 3], 6.0).is_err());
        assert!(fit_damped(&synthetic(6.0, 0.03, 0.0), -1.0).is_err());
    }
}
