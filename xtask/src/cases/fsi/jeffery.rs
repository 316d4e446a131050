//! `fsi-jeffery`: a neutrally buoyant prolate spheroid in simple shear between two
//! moving-belt walls (WCSPH, chrono-fsi); its rotation period against Jeffery (1922),
//! `T = (2 pi / gamma) (r + 1 / r)` (issue 24).
//!
//! Scene ([`chrono_fsi::jeffery::jeffery_scene`]): fluid periodic along the flow (x, cell
//! `length` major axes) and across it (y, `width` major axes), walls `gap` major axes
//! apart (at least 5) at `z = 0` and `z = H` carrying `-U` and `+U` (belts: markers at
//! rest with the wall's velocity, [`chrono_sph::WallBelt`]), `gamma = 2 U / H`; the
//! spheroid (largest semi-axis `semi_axis`, aspect ratio `aspect_ratio`, the fluid's
//! density, no gravity) at the centre with its symmetry axis along the flow, at rest; the
//! fluid starts on the developed Couette profile. Particle Reynolds number
//! `Re = gamma a^2 / nu`.
//!
//! Measured: the axis angle in the shear plane over `duration` Jeffery periods, fitted by
//! Jeffery's orbit ([`chrono_fsi::jeffery::fit_jeffery_orbit`]): the period `T`, the
//! orbit's aspect ratio and the start time free when the record spans at least 0.4 pi
//! (a quarter orbit is 0.5 pi), else `T` and the start time with `r` held (the starting
//! rate `gamma / (r^2 + 1)` then gives `T`). `period` is checked within 5 % of Jeffery's
//! (the criterion) where the spheroid is resolved (`RESOLVED_SPACINGS` on its
//! largest semi-axis), the record spans a quarter orbit with the aspect ratio fitted and
//! `Re <= 0.1`; otherwise reported. Also reported: the fit's residual, the fitted aspect
//! ratio, the largest out-of-plane component of the axis and the centre's drift (both 0
//! on Jeffery's orbit here), the walls' shear stress over `mu gamma`, particles, fluid
//! steps and wall time; `sweep` adds runs at `1.5^k` times the spacing.
//!
//! Defaults (the main run has about 12 s left in its budget): 4 spacings on the largest
//! semi-axis (2 on the smallest), 0.05 periods, reported; `--full` 6 spacings and 0.3
//! periods, checked, with 4 reported.

use std::f64::consts::PI;
use std::time::Instant;

use chrono_core::descriptor::SolverSettings;
use chrono_fsi::jeffery::{JefferyParams, fit_jeffery_orbit, jeffery_angle, jeffery_scene};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo, ensure_positive};

/// Spacings on the largest semi-axis from which the period is checked: over 0.3
/// periods the error reads +0.86 % at 4 spacings (2 on the smallest semi-axis) and
/// -0.18 % at 6 (docs/validation-fsi.md, `fsi-jeffery`); 4 is the fewest the markers
/// accept at `r = 2` (4 spacings across the minor axis), so the default reports.
const RESOLVED_SPACINGS: f64 = 6.0;

/// The orbit's span needed for the check: a quarter period takes the axis from the flow
/// to the gradient direction (`pi / 2`); the fit then fixes `T` and `r` apart.
const CHECKED_DURATION: f64 = 0.25;

/// Parameters of `fsi-jeffery`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct JefferyCaseParams {
    /// Aspect ratio `r` (symmetry over equatorial semi-axis).
    pub aspect_ratio: f64,
    /// Shear rate `gamma`, 1/s.
    pub shear_rate: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Fluid and spheroid density, kg/m^3.
    pub rho: f64,
    /// The spheroid's largest semi-axis `a`, m.
    pub semi_axis: f64,
    /// Wall gap in major axes (at least 5).
    pub gap: f64,
    /// Cell period along the flow in major axes.
    pub length: f64,
    /// Cell period across the flow in major axes.
    pub width: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Smoothing length over spacing.
    pub h_over_dp: f64,
    /// Run length in Jeffery periods.
    pub duration: f64,
    /// Extra runs at `1.5^k` times the spacing, `k = 1..=sweep` (error against resolution).
    pub sweep: u32,
}

impl Default for JefferyCaseParams {
    fn default() -> Self {
        let p = JefferyParams::default();
        Self {
            aspect_ratio: p.aspect_ratio,
            shear_rate: p.shear_rate,
            viscosity: p.viscosity,
            rho: p.rho,
            semi_axis: p.semi_axis,
            gap: p.gap,
            length: p.length,
            width: p.width,
            spacing: p.spacing,
            h_over_dp: p.h_over_dp,
            duration: 0.05,
            sweep: 0,
        }
    }
}

impl CaseParams for JefferyCaseParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "aspect_ratio",
            "-",
            "spheroid aspect ratio r (symmetry over equatorial semi-axis)",
        ),
        ParamInfo::new("shear_rate", "1/s", "shear rate gamma = 2 U / H"),
        ParamInfo::new("viscosity", "Pa s", "dynamic viscosity"),
        ParamInfo::new("rho", "kg/m^3", "fluid and spheroid density"),
        ParamInfo::new("semi_axis", "m", "the spheroid's largest semi-axis a"),
        ParamInfo::new("gap", "-", "wall gap in major axes 2 a (at least 5)"),
        ParamInfo::new("length", "-", "cell period along the flow in major axes"),
        ParamInfo::new("width", "-", "cell period across the flow in major axes"),
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new("h_over_dp", "-", "smoothing length over spacing"),
        ParamInfo::new("duration", "-", "run length in Jeffery periods"),
        ParamInfo::new(
            "sweep",
            "-",
            "coarser runs at 1.5^k the spacing, k = 1..=sweep",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.duration = 0.03,
            Mode::Default => {}
            Mode::Full => {
                self.spacing = self.semi_axis / RESOLVED_SPACINGS;
                self.duration = 0.3;
                self.sweep = self.sweep.max(1);
            }
        }
    }
}

/// One run's results.
struct RunResult {
    period: f64,
    fitted_r: f64,
    residual: f64,
    span: f64,
    parameters: usize,
    out_of_plane: f64,
    drift: f64,
    wall_stress: f64,
    particles: usize,
    steps: u64,
    wall: f64,
    series: Series,
}

fn scene_params(p: &JefferyCaseParams, spacing: f64) -> JefferyParams {
    JefferyParams {
        aspect_ratio: p.aspect_ratio,
        shear_rate: p.shear_rate,
        viscosity: p.viscosity,
        rho: p.rho,
        semi_axis: p.semi_axis,
        gap: p.gap,
        length: p.length,
        width: p.width,
        spacing,
        h_over_dp: p.h_over_dp,
    }
}

fn run_once(p: &JefferyCaseParams, spacing: f64, ctx: &RunContext) -> anyhow::Result<RunResult> {
    let sp = scene_params(p, spacing);
    let solver = chrono_ccp::Psor::new(SolverSettings::default());
    let mut scene = jeffery_scene(&sp, Box::new(solver))?;
    let t_j = sp.period();
    let t_end = p.duration * t_j;
    let n = (t_end / sp.coupling_step()?).ceil().max(20.0) as u64;
    let h = t_end / n as f64;
    let (mut t, mut theta) = (vec![0.0], vec![scene.angle()]);
    let (mut out_of_plane, mut drift): (f64, f64) = (0.0, 0.0);
    let mut series = Series::new(["t", "angle", "jeffery_angle", "spin"]);
    let start = Instant::now();
    for i in 1..=n {
        scene.system.step(h)?;
        let a = scene.angle();
        let last = theta[theta.len() - 1];
        // unwrap: the axis turns less than pi per step
        theta.push(last + (a - last + PI).rem_euclid(2.0 * PI) - PI);
        t.push(scene.system.time());
        out_of_plane = out_of_plane.max(scene.out_of_plane().abs());
        drift = drift.max((scene.centre() - scene.centre0).norm());
        if i % (n / 200).max(1) == 0 || i == n {
            series.push(&[
                t[t.len() - 1],
                theta[theta.len() - 1],
                jeffery_angle(t[t.len() - 1], t_j, p.aspect_ratio),
                scene.angular_velocity().y,
            ]);
            ctx.progress_steps(i, n);
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let fit = fit_jeffery_orbit(&t, &theta, t_j, p.aspect_ratio, true)?;
    Ok(RunResult {
        period: fit.period,
        fitted_r: fit.aspect_ratio,
        residual: fit.residual,
        span: fit.span,
        parameters: fit.parameters,
        out_of_plane,
        drift,
        wall_stress: scene.wall_shear_stress() / (p.viscosity * p.shear_rate),
        particles: scene.fluid().sph().num_fluid(),
        steps: scene.fluid().substeps(),
        wall,
        series,
    })
}

fn run(p: &JefferyCaseParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    ensure_positive("duration", p.duration)?;
    let sp = scene_params(p, p.spacing);
    sp.validate()?;
    let t_j = sp.period();
    let reynolds = sp.reynolds();
    let r = run_once(p, p.spacing, ctx)?;
    let resolved = p.semi_axis / p.spacing >= RESOLVED_SPACINGS - 1e-9;
    let mut out = CaseOutput::new();
    if resolved && p.duration >= CHECKED_DURATION && r.parameters == 3 && reynolds <= 0.1 {
        out.check(Check::relative("period", r.period, t_j, 0.05));
    } else {
        out.metric("period", r.period);
    }
    let cell = sp.cell();
    out.metric("period_jeffery", t_j)
        .metric("period_error", r.period / t_j - 1.0)
        .metric("reynolds", reynolds)
        .metric("aspect_ratio", p.aspect_ratio)
        .metric("aspect_ratio_fitted", r.fitted_r)
        .metric("fit_residual", r.residual)
        .metric("fit_parameters", r.parameters as f64)
        .metric("angle_span", r.span)
        .metric("out_of_plane_max", r.out_of_plane)
        .metric("centre_drift_over_spacing", r.drift / p.spacing)
        .metric("wall_stress_over_mu_gamma", r.wall_stress)
        .metric("gap_major_axes", cell[2] / (2.0 * p.semi_axis))
        .metric("spacings_on_semi_axis", p.semi_axis / p.spacing)
        .metric("particles", r.particles as f64)
        .metric("fluid_steps", r.steps as f64)
        .metric("wall_s", r.wall);
    let mut lines = vec![format!(
        "a/dp {:.1}: T {:.4} s (Jeffery {:.4} s, {:+.2} %), r fitted {:.3} ({} parameters, span {:.2} rad), residual {:.1e} rad, {} particles, {} steps, {:.1} s",
        p.semi_axis / p.spacing,
        r.period,
        t_j,
        100.0 * (r.period / t_j - 1.0),
        r.fitted_r,
        r.parameters,
        r.span,
        r.residual,
        r.particles,
        r.steps,
        r.wall
    )];
    for k in 1..=p.sweep {
        let dp = p.spacing * 1.5f64.powi(k as i32);
        match run_once(p, dp, ctx) {
            Ok(s) => {
                let err = s.period / t_j - 1.0;
                out.metric(format!("sweep{k}_period_error"), err)
                    .metric(format!("sweep{k}_spacings_on_semi_axis"), p.semi_axis / dp);
                lines.push(format!(
                    "a/dp {:.1}: T {:.4} s, error {:+.2} %, r fitted {:.3}, residual {:.1e} rad, {} particles, {:.1} s",
                    p.semi_axis / dp,
                    s.period,
                    100.0 * err,
                    s.fitted_r,
                    s.residual,
                    s.particles,
                    s.wall
                ));
            }
            Err(e) => lines.push(format!("a/dp {:.1}: not run ({e})", p.semi_axis / dp)),
        }
    }
    for l in &lines {
        ctx.note(l);
    }
    out.series = r.series;
    out.plot = PlotSpec::new(
        "Spheroid in simple shear: axis angle against Jeffery's orbit",
        "t [s]",
        "rad, rad/s",
        &["angle", "jeffery_angle", "spin"],
    );
    out.steps = r.steps;
    Ok(out)
}

/// The `fsi-jeffery` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<JefferyCaseParams>::boxed(
        "fsi-jeffery",
        "fsi",
        "A neutrally buoyant spheroid in simple shear between moving-belt walls (WCSPH with BCE markers): rotation period against Jeffery (1922), T = (2 pi / gamma)(r + 1/r).",
        run,
    )
}
