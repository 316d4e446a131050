//! Least-squares fits shared by the cases (flow rates, slopes of heaps, exponents,
//! convergence orders), and the mean and spread of repeated runs.

/// Least-squares line `y = a x + b` (the library's, re-exported for the cases).
pub use chrono_core::granular::probe::line_fit;

/// Standard error of the least-squares slope of the points `(x, y)`:
/// `sqrt(sum r^2 / (n - 2) / sum (x - x_mean)^2)` with `r` the residuals (None below 3
/// points or without spread in `x`).
pub fn slope_standard_error(pts: &[(f64, f64)]) -> Option<f64> {
    let (slope, icept) = line_fit(pts)?;
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let ssr: f64 = pts
        .iter()
        .map(|p| (p.1 - slope * p.0 - icept).powi(2))
        .sum();
    (pts.len() >= 3 && sxx > 0.0).then(|| (ssr / (n - 2.0) / sxx).sqrt())
}

/// Mean and sample standard deviation `sqrt(sum (x - mean)^2 / (n - 1))` of `xs` (the
/// spread 0 for one value; NaN for none).
pub fn mean_std(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = if xs.len() > 1 {
        xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

#[cfg(test)]
mod tests {
    use super::{line_fit, mean_std, slope_standard_error};

    #[test]
    fn mean_and_sample_std() {
        let (m, s) = mean_std(&[1.0, 2.0, 6.0]);
        assert!((m - 3.0).abs() < 1e-15);
        // ((4 + 1 + 9) / 2)^(1/2)
        assert!((s - 7f64.sqrt()).abs() < 1e-15);
        assert_eq!(mean_std(&[2.5]), (2.5, 0.0));
    }

    #[test]
    fn recovers_a_line_and_rejects_degenerate_input() {
        let pts: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, 3.0 * i as f64 - 2.0)).collect();
        let (a, b) = line_fit(&pts).unwrap();
        assert!((a - 3.0).abs() < 1e-12 && (b + 2.0).abs() < 1e-12);
        assert!(line_fit(&pts[..1]).is_none());
        assert!(line_fit(&[(1.0, 2.0), (1.0, 3.0)]).is_none());
    }

    #[test]
    fn slope_error_of_scattered_points() {
        // y = x +- 0.1 alternating at x = 0, 0, 1, 1: residuals all 0.1, slope 1,
        // SE = sqrt(4 * 0.01 / 2 / 1) = 0.1414.
        let pts = [(0.0, 0.1), (0.0, -0.1), (1.0, 1.1), (1.0, 0.9)];
        let se = slope_standard_error(&pts).unwrap();
        assert!((se - 0.02f64.sqrt()).abs() < 1e-12, "{se}");
        let exact = [(0.0, 0.0), (1.0, 1.0), (2.0, 2.0)];
        assert!(slope_standard_error(&exact).unwrap() < 1e-12);
        assert!(slope_standard_error(&pts[..2]).is_none());
    }
}
