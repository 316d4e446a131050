//! `granular-shear`'s reduction of a measured curve: the peak and residual of the force
//! ratio `S / N` sampled in bins of shear displacement, and the load plate's dilation rate
//! at the peak (Taylor's stress–dilatancy balance; see [`super::shear`]).

/// Index of the middle bin of the peak: the 3-bin window of bins `(s, ratio)` (increasing
/// displacement) with the largest mean ratio among those centred at `s <= peak_window s_max`.
pub fn peak_bin(bins: &[(f64, f64)], peak_window: f64) -> Option<usize> {
    let s_max = bins.last().map(|b| b.0).unwrap_or(0.0);
    let mut best: Option<(usize, f64)> = None;
    for (i, w) in bins.windows(3).enumerate() {
        let mean = (w[0].1 + w[1].1 + w[2].1) / 3.0;
        if w[1].0 <= peak_window * s_max && best.is_none_or(|(_, m)| mean > m) {
            best = Some((i + 1, mean));
        }
    }
    best.map(|(i, _)| i)
}

/// Peak (largest 3-bin running mean over the bins with `s <= peak_window s_max`, see
/// [`peak_bin`]) and residual (mean over `s >= (1 - residual_window) s_max`) of a ratio
/// sampled in bins `(s, ratio)` of increasing displacement.
pub fn peak_and_residual(
    bins: &[(f64, f64)],
    peak_window: f64,
    residual_window: f64,
) -> anyhow::Result<(f64, f64)> {
    anyhow::ensure!(
        bins.len() >= 6,
        "granular-shear: {} bins are too few for a peak and a residual (make `displacement` larger or `bin` smaller)",
        bins.len()
    );
    let s_max = bins.last().map(|b| b.0).unwrap_or(0.0);
    let peak = peak_bin(bins, peak_window)
        .map(|i| (bins[i - 1].1 + bins[i].1 + bins[i + 1].1) / 3.0)
        .unwrap_or(f64::NAN);
    let late: Vec<f64> = bins
        .iter()
        .filter(|b| b.0 >= (1.0 - residual_window) * s_max)
        .map(|b| b.1)
        .collect();
    anyhow::ensure!(
        peak.is_finite() && !late.is_empty(),
        "granular-shear: `peak_window` = {peak_window} or `residual_window` = {residual_window} selects no bins"
    );
    Ok((peak, late.iter().sum::<f64>() / late.len() as f64))
}

/// Dilation rate `dy/dx` at bin `center`: the least-squares slope of the load plate's rise
/// `y` against the shear displacement `x` over the bins `(x, y)` within `half_width` of
/// displacement either side (same units for both, e.g. grain diameters).
///
/// Taylor's energy balance for the direct shear box (D. W. Taylor, *Fundamentals of Soil
/// Mechanics*, Wiley 1948, ch. 14; M. D. Bolton, "The strength and dilatancy of sands",
/// Géotechnique 36 (1986) 65–78): the shear work `S dx` is spent in friction at the
/// critical-state ratio `mu_cv` and in lifting the normal load, `S dx = mu_cv N dx + N dy`,
/// so the peak ratio is `S / N = mu_cv + dy/dx` at the peak's dilation rate.
pub fn dilation_rate(bins: &[(f64, f64)], center: usize, half_width: f64) -> f64 {
    let Some(&(x0, _)) = bins.get(center) else {
        return f64::NAN;
    };
    let pts: Vec<(f64, f64)> = bins
        .iter()
        .copied()
        .filter(|(x, _)| (x - x0).abs() <= half_width + 1e-12)
        .collect();
    crate::fit::line_fit(&pts).map_or(f64::NAN, |(slope, _)| slope)
}

/// Taylor's balance along the whole curve: the mean of `S/N - dy/dx` over the bins at
/// displacement `x >= from`, with `dy/dx` the [`dilation_rate`] over `half_width` around
/// each bin. `ratio` and `rise` are bins `(x, S/N)` and `(x, y)` at the same displacements.
/// Where the energy balance `S dx = mu_cv N dx + N dy` holds, this is `mu_cv` whether the
/// sample dilates or contracts. NaN if no bin is at `x >= from`.
pub fn dilatancy_corrected_ratio(
    ratio: &[(f64, f64)],
    rise: &[(f64, f64)],
    from: f64,
    half_width: f64,
) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (i, &(x, r)) in ratio.iter().enumerate() {
        if x >= from {
            sum += r - dilation_rate(rise, i, half_width);
            n += 1;
        }
    }
    if n == 0 { f64::NAN } else { sum / n as f64 }
}

/// Dilation rate `dy/dx` over the residual window: the least-squares slope of the rise bins
/// `(x, y)` with `x >= (1 - residual_window) x_max`. Zero where the sample has reached its
/// critical state (steady volume); NaN with fewer than two bins there.
pub fn residual_dilation_rate(rise: &[(f64, f64)], residual_window: f64) -> f64 {
    let x_max = rise.last().map_or(0.0, |b| b.0);
    let late: Vec<(f64, f64)> = rise
        .iter()
        .copied()
        .filter(|b| b.0 >= (1.0 - residual_window) * x_max)
        .collect();
    crate::fit::line_fit(&late).map_or(f64::NAN, |(slope, _)| slope)
}
