//! Least-squares fits shared by the cases (flow rates, slopes of heaps, exponents,
//! convergence orders).

/// Least-squares line `y = a x + b` through `pts`: `Some((a, b))`, or `None` with fewer
/// than two points or no spread in `x`.
pub fn line_fit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in pts {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
    }
    (sxx > 0.0).then(|| {
        let a = sxy / sxx;
        (a, my - a * mx)
    })
}

#[cfg(test)]
mod tests {
    use super::line_fit;

    #[test]
    fn recovers_a_line_and_rejects_degenerate_input() {
        let pts: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, 3.0 * i as f64 - 2.0)).collect();
        let (a, b) = line_fit(&pts).unwrap();
        assert!((a - 3.0).abs() < 1e-12 && (b + 2.0).abs() < 1e-12);
        assert!(line_fit(&pts[..1]).is_none());
        assert!(line_fit(&[(1.0, 2.0), (1.0, 3.0)]).is_none());
    }
}
