//! PNG plots with plotters: a case's series against its reference (`plot.png`) and a
//! log-log speed-against-error plot of a sweep (`speed_vs_error.png`).

use std::path::Path;
use std::sync::Once;

use anyhow::{Context, anyhow, bail};
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use crate::case::{CaseOutput, Series, SweepPoint};

/// Plot size in pixels.
const SIZE: (u32, u32) = (1024, 640);

/// The font embedded in the binary (DejaVu Sans, see `xtask/assets/LICENSE-DejaVu.txt`).
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font as `"sans-serif"` (once per process).
pub fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            eprintln!("warning: the embedded plot font could not be loaded");
        }
    });
}

/// One curve: a label, its points split at non-finite values, dashed or not.
struct Curve {
    label: String,
    segments: Vec<Vec<(f64, f64)>>,
    dashed: bool,
    color: RGBColor,
}

fn color(i: usize) -> RGBColor {
    const COLORS: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
    ];
    COLORS[i % COLORS.len()]
}

/// The (x, y) points of two columns, split into runs of finite values.
fn segments(series: &Series, x: &str, y: &str) -> anyhow::Result<Vec<Vec<(f64, f64)>>> {
    let col = |name: &str| {
        series.column_index(name).ok_or_else(|| {
            anyhow!(
                "column `{name}` is not in the series ({})",
                series.columns.join(", ")
            )
        })
    };
    let (ix, iy) = (col(x)?, col(y)?);
    let mut out = vec![Vec::new()];
    for row in &series.rows {
        let p = (row[ix], row[iy]);
        if p.0.is_finite() && p.1.is_finite() {
            out.last_mut().expect("non-empty").push(p);
        } else if !out.last().expect("non-empty").is_empty() {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    Ok(out)
}

/// The curves described by the output's [`PlotSpec`](crate::case::PlotSpec).
fn curves(out: &CaseOutput) -> anyhow::Result<Vec<Curve>> {
    let series = &out.series;
    let spec = &out.plot;
    let first = |s: &Series| s.columns.first().cloned().unwrap_or_default();
    let x = if spec.x.is_empty() {
        first(series)
    } else {
        spec.x.clone()
    };
    let others = |s: &Series, x: &str| -> Vec<String> {
        s.columns.iter().filter(|c| *c != x).cloned().collect()
    };
    let ys = if spec.y.is_empty() {
        others(series, &x)
    } else {
        spec.y.clone()
    };
    let mut curves = Vec::new();
    for (i, y) in ys.iter().enumerate() {
        let segments = segments(series, &x, y)?;
        curves.push(Curve {
            label: y.clone(),
            segments,
            dashed: false,
            color: color(i),
        });
    }
    let ref_src = out.reference_series.as_ref().unwrap_or(series);
    let ref_x = if ref_src.column_index(&x).is_some() {
        x.clone()
    } else {
        first(ref_src)
    };
    let ref_ys = match (&out.reference_series, spec.reference_y.is_empty()) {
        (Some(r), true) => others(r, &ref_x),
        _ => spec.reference_y.clone(),
    };
    for (j, y) in ref_ys.iter().enumerate() {
        let segments = segments(ref_src, &ref_x, y).context("reference series")?;
        let label = format!("{y} (reference)");
        // Distinct colours: a reference drawn over a matching curve must stay visible.
        curves.push(Curve {
            label,
            segments,
            dashed: true,
            color: color(ys.len() + j),
        });
    }
    Ok(curves)
}

/// A range covering `values` with a small margin; `None` when there are none.
fn range(values: impl Iterator<Item = f64>, margin: f64) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() {
        return None;
    }
    if hi > lo {
        let pad = margin * (hi - lo);
        Some((lo - pad, hi + pad))
    } else {
        // A constant: centre it in a small band.
        let pad = (0.05 * lo.abs()).max(1e-9);
        Some((lo - pad, hi + pad))
    }
}

/// A compact tick label.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// Draws the series (solid) against the reference (dashed) into `path`. Returns
/// `Ok(false)` without writing anything when the series is empty.
pub fn plot_series(path: &Path, case_name: &str, out: &CaseOutput) -> anyhow::Result<bool> {
    if out.series.is_empty() || out.series.columns.len() < 2 {
        return Ok(false);
    }
    let curves = curves(out)?;
    let points = || curves.iter().flat_map(|c| c.segments.iter().flatten());
    let (Some(xr), Some(yr)) = (
        range(points().map(|p| p.0), 0.0),
        range(points().map(|p| p.1), 0.05),
    ) else {
        bail!("no finite values to plot");
    };
    register_fonts();
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let title = if out.plot.title.is_empty() {
        case_name
    } else {
        &out.plot.title
    };
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 26))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    let x_label = if out.plot.x_label.is_empty() {
        out.plot.x.clone()
    } else {
        out.plot.x_label.clone()
    };
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(out.plot.y_label.as_str())
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 14))
        .draw()?;
    for c in &curves {
        let style = c.color.stroke_width(2);
        let label = c.label.as_str();
        if c.dashed {
            let dashes = c
                .segments
                .iter()
                .flat_map(|s| DashedLineSeries::new(s.iter().copied(), 10, 6, style));
            chart
                .draw_series(dashes)?
                .label(label)
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (8, 0)], style)
                        + PathElement::new(vec![(12, 0), (20, 0)], style)
                });
        } else {
            let lines = c
                .segments
                .iter()
                .map(|s| PathElement::new(s.clone(), style));
            chart
                .draw_series(lines)?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(true)
}

/// Draws error against wall time (log-log, labelled points, in sweep order) into
/// `path`. Returns `Ok(false)` without writing when no point has positive finite values.
pub fn plot_sweep(path: &Path, case_name: &str, sweep: &[SweepPoint]) -> anyhow::Result<bool> {
    let pts: Vec<&SweepPoint> = sweep
        .iter()
        .filter(|p| p.error.is_finite() && p.error > 0.0 && p.wall_s.is_finite() && p.wall_s > 0.0)
        .collect();
    if pts.is_empty() {
        return Ok(false);
    }
    let log_range = |v: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = v.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
            (lo.min(x), hi.max(x))
        });
        (lo / 2.0, hi * 2.0)
    };
    let xr = log_range(&mut pts.iter().map(|p| p.wall_s));
    let yr = log_range(&mut pts.iter().map(|p| p.error));
    register_fonts();
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{case_name}: error against wall time"),
            ("sans-serif", 26),
        )
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d((xr.0..xr.1).log_scale(), (yr.0..yr.1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("wall time [s]")
        .y_desc("error")
        .x_labels(10)
        .y_labels(10)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 14))
        .draw()?;
    let c = color(0);
    chart.draw_series(LineSeries::new(
        pts.iter().map(|p| (p.wall_s, p.error)),
        c.stroke_width(1),
    ))?;
    chart.draw_series(pts.iter().map(|p| {
        EmptyElement::at((p.wall_s, p.error))
            + Circle::new((0, 0), 5, c.filled())
            + Text::new(p.label.clone(), (8, -16), ("sans-serif", 15))
    }))?;
    root.present()
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_ticks() {
        assert_eq!(range([1.0, 3.0].into_iter(), 0.0), Some((1.0, 3.0)));
        assert_eq!(range(std::iter::empty(), 0.1), None);
        let (lo, hi) = range([2.0, 2.0].into_iter(), 0.0).unwrap();
        assert!(lo < 2.0 && hi > 2.0);
        assert_eq!(tick(0.5), "0.5");
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(1e-6), "1.0e-6");
    }

    #[test]
    fn segments_split_at_non_finite_values() {
        let mut s = Series::new(["t", "x"]);
        for r in [[0.0, 1.0], [1.0, f64::NAN], [2.0, 2.0], [3.0, 3.0]] {
            s.push(&r);
        }
        let seg = segments(&s, "t", "x").unwrap();
        assert_eq!(seg, vec![vec![(0.0, 1.0)], vec![(2.0, 2.0), (3.0, 3.0)]]);
        assert!(
            segments(&s, "t", "y")
                .unwrap_err()
                .to_string()
                .contains("`y`")
        );
    }
}
