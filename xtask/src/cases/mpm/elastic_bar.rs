//! `mpm-elastic-bar`: the first axial mode of an elastic bar fixed at one end.
//!
//! A slender bar of square section (free sides, 3-D, the fixed end a sticky wall of the
//! grid; `chrono_mpm::bar`) starts in its first axial mode's velocity field and is run for
//! `periods` periods by explicit APIC MPM with fixed-corotated elasticity. Checked: the
//! frequency from the zero crossings of the free end's displacement against
//! `sqrt(E/rho)/(4L)` (exact for `poisson` = 0; the Rayleigh–Love correction of the
//! default section is below 1e-4), within 3 %, and the drift of the total energy over the
//! run (mean over the last period against the first) below 1 %. Reported: the error
//! under grid refinement (`cells_along` halved and doubled, the sweep).

use chrono_mpm::bar::{BarSpec, ElasticBar};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `mpm-elastic-bar`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ElasticBarParams {
    /// Bar length, m.
    pub length: f64,
    /// Side of the square section, m.
    pub width: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Grid cells along the bar.
    pub cells_along: usize,
    /// Markers per cell per axis.
    pub markers_per_cell: usize,
    /// Strain amplitude of the mode.
    pub strain_amplitude: f64,
    /// CFL number of the time step.
    pub cfl: f64,
    /// F-bar: off, increment or total (`chrono_mpm::fbar`).
    pub f_bar: String,
    /// Periods simulated.
    pub periods: f64,
    /// Refinement levels of the sweep: 1 = `cells_along` only, 2 = / 2 and x 1,
    /// 3 = / 4, / 2, x 1, 4 adds x 2, 5 adds x 4.
    pub sweep_levels: usize,
    /// Relative tolerance on the frequency.
    pub frequency_tolerance: f64,
    /// Limit of the energy drift over the run.
    pub drift_tolerance: f64,
}

impl Default for ElasticBarParams {
    fn default() -> Self {
        let b = BarSpec::default();
        Self {
            length: b.length,
            width: b.width,
            young: b.young,
            density: b.density,
            poisson: b.poisson,
            cells_along: b.cells_along,
            markers_per_cell: b.markers_per_cell,
            strain_amplitude: b.strain_amplitude,
            cfl: b.cfl,
            f_bar: "off".into(),
            periods: 10.0,
            sweep_levels: 3,
            frequency_tolerance: 0.03,
            drift_tolerance: 0.01,
        }
    }
}

impl CaseParams for ElasticBarParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("length", "m", "bar length L"),
        ParamInfo::new("width", "m", "side of the square section"),
        ParamInfo::new("young", "Pa", "Young's modulus E"),
        ParamInfo::new("density", "kg/m^3", "density rho"),
        ParamInfo::new(
            "poisson",
            "-",
            "Poisson's ratio (the reference is exact for 0)",
        ),
        ParamInfo::new(
            "cells_along",
            "-",
            "grid cells along the bar (dx = L / cells_along)",
        ),
        ParamInfo::new("markers_per_cell", "-", "markers per cell per axis"),
        ParamInfo::new("strain_amplitude", "-", "strain amplitude of the mode"),
        ParamInfo::new("cfl", "-", "CFL number of the time step (dt = cfl dx / c)"),
        ParamInfo::new(
            "f_bar",
            "-",
            "F-bar volume averaging: off, increment or total (chrono_mpm::fbar)",
        ),
        ParamInfo::new("periods", "-", "periods simulated"),
        ParamInfo::new(
            "sweep_levels",
            "-",
            "refinement sweep: 1 = cells_along, 2 = /2 and x1, 3 = /4 /2 x1, 4 adds x2, 5 adds x4",
        ),
        ParamInfo::new(
            "frequency_tolerance",
            "-",
            "relative tolerance on the frequency",
        ),
        ParamInfo::new(
            "drift_tolerance",
            "-",
            "limit of |energy drift| over the run",
        ),
    ];

    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.cells_along = 16;
                self.sweep_levels = 2;
            }
            Mode::Default => {}
            Mode::Full => self.sweep_levels = 4,
        }
    }
}

fn spec(p: &ElasticBarParams, cells_along: usize) -> anyhow::Result<BarSpec> {
    Ok(BarSpec {
        length: p.length,
        width: p.width,
        young: p.young,
        density: p.density,
        poisson: p.poisson,
        cells_along,
        markers_per_cell: p.markers_per_cell,
        strain_amplitude: p.strain_amplitude,
        cfl: p.cfl,
        f_bar: p.f_bar.parse()?,
    })
}

fn run(p: &ElasticBarParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        (1..=5).contains(&p.sweep_levels),
        "sweep_levels must lie in [1, 5], got {}",
        p.sweep_levels
    );
    // The sweep: 1 level = cells_along only, 2 = / 2 and x 1, 3 = / 4, / 2, x 1, then
    // x 2 and x 4.
    let n0 = p.cells_along;
    let scaled = |k: i32| ((n0 as f64 * 2f64.powi(k)).round() as usize).max(2);
    let levels: Vec<usize> = match p.sweep_levels {
        1 => vec![n0],
        2 => vec![scaled(-1), n0],
        k => (0..k as i32).map(|i| scaled(i - 2)).collect(),
    };
    let total_work: f64 = levels.iter().map(|&n| (n * n) as f64).sum();
    let mut done = 0.0;
    let mut out = CaseOutput::new();
    let mut main = None;
    for &n in &levels {
        let start = std::time::Instant::now();
        let mut bar = ElasticBar::new(spec(p, n)?)?;
        let reference = bar.reference_frequency();
        let work = (n * n) as f64;
        let r = bar.run(p.periods, |f| ctx.progress((done + f * work) / total_work))?;
        done += work;
        let err = (r.frequency / reference - 1.0).abs();
        out.sweep.push(SweepPoint {
            label: format!("{n} cells along"),
            error: err,
            wall_s: start.elapsed().as_secs_f64().max(1e-9),
        });
        out.metric(format!("frequency_error_{n}_cells"), err);
        out.metric(format!("energy_drift_{n}_cells"), r.energy_drift);
        if n == p.cells_along {
            main = Some((bar, r, reference));
        }
    }
    let (bar, r, reference) = main.expect("the sweep includes cells_along");
    out.check(Check::relative(
        "frequency",
        r.frequency,
        reference,
        p.frequency_tolerance,
    ));
    out.check(Check::below(
        "energy_drift",
        r.energy_drift.abs(),
        p.drift_tolerance,
    ));
    out.metric("frequency_reference", reference);
    out.metric("energy_drift_signed", r.energy_drift);
    out.metric("energy_excursion", r.energy_excursion);
    out.metric("markers", bar.body.markers.len() as f64);
    out.metric("dt", bar.dt);
    out.metric("active_blocks", bar.body.grid().active_blocks() as f64);
    ctx.note(format!(
        "{} markers, dt {:.3e} s, {} steps; frequency {:.5} Hz vs {:.5} Hz",
        bar.body.markers.len(),
        bar.dt,
        r.steps,
        r.frequency,
        reference
    ));

    let mut series = Series::new(["t", "tip_mm", "kinetic_mJ", "total_mJ"]);
    let stride = (r.samples.len() / 2000).max(1);
    for s in r.samples.iter().step_by(stride) {
        series.push(&[
            s.t,
            s.tip * 1e3,
            s.kinetic * 1e3,
            (s.kinetic + s.elastic) * 1e3,
        ]);
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "MPM elastic bar: free-end displacement and energy",
        "t [s]",
        "tip [mm], energy [mJ]",
        &["tip_mm", "kinetic_mJ", "total_mJ"],
    );
    out.steps = r.steps;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<ElasticBarParams>::boxed(
        "mpm-elastic-bar",
        "mpm",
        "Elastic bar fixed at one end, first axial mode by explicit APIC MPM: frequency against sqrt(E/rho)/(4L) within 3 %, energy drift over 10 periods below 1 %; error under grid refinement in the sweep.",
        run,
    )
}
