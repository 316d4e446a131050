//! SPH validation cases and benches (chrono-sph): hydrostatic tank, start-up Poiseuille
//! flow, dam break against Martin and Moyce (1952), sloshing against linear theory, and
//! the 3D dam-break throughput bench. See `docs/validation-sph.md`.
//!
//! Quasi-2D cases are 3D slabs, periodic along y, `slab_layers` particles thick (at least
//! twice the kernel support, so the minimum image is exact).

pub mod bench;
pub mod dam_break;
pub mod hydrostatic;
pub mod poiseuille;
pub mod sloshing;

use chrono_sph::SphSystem;

use crate::case::{RunContext, SweepPoint};
use crate::fit::line_fit;

/// Particles across a periodic slab: the smallest count with `n dp >= 4 h (1 + skin)`
/// (twice the neighbour-list radius with the default 10 % Verlet skin, which
/// [`chrono_sph::SphSettings::validate`] requires of a period).
pub fn slab_layers(h_over_dp: f64) -> usize {
    ((4.4 * h_over_dp) - 1e-9).ceil().max(1.0) as usize
}

/// Wall layers covering the kernel support `2 h`.
pub fn wall_layers(h_over_dp: f64) -> usize {
    ((2.0 * h_over_dp) - 1e-9).ceil().max(1.0) as usize
}

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

/// VTK frames of an SPH system (or, by [`record_with`](Self::record_with), of any particle
/// system) when the run asked for them (`--vtk`), every `every_s` seconds of simulated
/// time, plus the `.pvd` collection.
pub struct SphFrames {
    dir: Option<std::path::PathBuf>,
    every_s: f64,
    next: f64,
    frames: Vec<(f64, String)>,
}

impl SphFrames {
    /// Frames every `every_s` seconds into the case's VTK directory, if any.
    pub fn new(ctx: &RunContext, every_s: f64) -> Self {
        Self {
            dir: ctx.vtk_dir(),
            every_s,
            next: 0.0,
            frames: Vec::new(),
        }
    }

    /// Writes a frame when due.
    pub fn record(&mut self, sys: &SphSystem) -> anyhow::Result<()> {
        self.record_with(sys.time(), |path| Ok(sys.write_vtk(path, true)?))
    }

    /// Writes a frame at simulated time `time` (s) with `write` when due (any particle
    /// system: `write` gets the frame's path).
    pub fn record_with(
        &mut self,
        time: f64,
        write: impl FnOnce(&std::path::Path) -> anyhow::Result<()>,
    ) -> anyhow::Result<()> {
        let Some(dir) = &self.dir else { return Ok(()) };
        if time + 1e-12 < self.next {
            return Ok(());
        }
        self.next += self.every_s;
        let name = format!("frame_{:05}.vtp", self.frames.len());
        write(&dir.join(&name))?;
        self.frames.push((time, name));
        Ok(())
    }

    /// Writes the `.pvd` collection.
    pub fn finish(&self) -> anyhow::Result<()> {
        let Some(dir) = &self.dir else { return Ok(()) };
        let frames: Vec<(f64, &str)> = self.frames.iter().map(|(t, n)| (*t, n.as_str())).collect();
        chrono_core::io::vtk::write_pvd(dir.join("frames.pvd"), &frames)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helpers() {
        assert_eq!(slab_layers(1.3), 6);
        assert_eq!(slab_layers(1.5), 7);
        assert_eq!(wall_layers(1.3), 3);
        assert_eq!(wall_layers(1.5), 3);
        assert!((rel_l2(&[1.1, 2.2], &[1.0, 2.0]) - 0.1).abs() < 1e-12);
        let o = convergence_order(&[(0.1, 0.04), (0.05, 0.01), (0.025, 0.0025)]);
        assert!((o - 2.0).abs() < 1e-9);
        assert_eq!(sweep_spacings(1.0, 2), vec![2.25, 1.5]);
    }
}
