//! SPH validation cases and benches (chrono-sph): hydrostatic tank, start-up Poiseuille
//! flow, dam break against Martin and Moyce (1952), sloshing against linear theory, and
//! the 3D dam-break throughput bench. See `docs/validation-sph.md`.
//!
//! Quasi-2D cases are 3D slabs, periodic along y,
//! [`slab_layers`](chrono_core::particles::lattice::slab_layers) particles thick (at least
//! twice the kernel support, so the minimum image is exact); the tanks and fluid blocks
//! come from [`chrono_core::particles::lattice`].

pub mod bench;
pub mod dam_break;
pub mod hydrostatic;
pub mod poiseuille;
pub mod sloshing;

use chrono_core::io::{Every, FrameSeries};

use crate::case::{RunContext, SweepPoint};
use crate::fit::line_fit;

/// Relative L2 error `sqrt(sum (a - b)^2 / sum b^2)`.
pub fn rel_l2(values: &[f64], reference: &[f64]) -> f64 {
    let num: f64 = values
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b) * (a - b))
        .sum();
    let den: f64 = reference.iter().map(|b| b * b).sum();
    (num / den).sqrt()
}

/// Least-squares slope of `log(error)` against `log(spacing)` over the sweep (the
/// observed convergence order); NaN with fewer than two usable points.
pub fn convergence_order(points: &[(f64, f64)]) -> f64 {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(dp, e)| *dp > 0.0 && *e > 0.0 && e.is_finite())
        .map(|(dp, e)| (dp.ln(), e.ln()))
        .collect();
    line_fit(&pts).map_or(f64::NAN, |(a, _)| a)
}

/// Spacings of a sweep of `levels` extra runs, coarse to fine, ending with `dp`:
/// `dp * 1.5^k`, `k = levels, ..., 1` (the run at `dp` itself is the main run).
pub fn sweep_spacings(dp: f64, levels: u32) -> Vec<f64> {
    (1..=levels)
        .rev()
        .map(|k| dp * 1.5f64.powi(k as i32))
        .collect()
}

/// A sweep point labelled by spacing.
pub fn sweep_point(dp: f64, error: f64, wall_s: f64) -> SweepPoint {
    SweepPoint {
        label: format!("dp={dp:.3e}"),
        error,
        wall_s: wall_s.max(1e-9),
    }
}

/// The VTK frame series of a particle case (`particles_NNNNNN.vtp` and `particles.pvd`
/// in the case's VTK directory, every `every_s` seconds of simulated time): disabled
/// unless the run asked for frames (`--vtk`).
pub fn particle_frames(ctx: Option<&RunContext>, every_s: f64) -> anyhow::Result<FrameSeries> {
    Ok(FrameSeries::new(
        ctx.and_then(RunContext::vtk_dir),
        "particles",
        "vtp",
        Every::Seconds(every_s),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helpers() {
        assert!((rel_l2(&[1.1, 2.2], &[1.0, 2.0]) - 0.1).abs() < 1e-12);
        let o = convergence_order(&[(0.1, 0.04), (0.05, 0.01), (0.025, 0.0025)]);
        assert!((o - 2.0).abs() < 1e-9);
        assert_eq!(sweep_spacings(1.0, 2), vec![2.25, 1.5]);
    }
}
