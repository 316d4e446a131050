//! `fsi-floating-body`: a box, a horizontal cylinder and a sphere float in a tank of
//! WCSPH water, coupled two-way through BCE markers inside one chrono-core `System`
//! (chrono-fsi).
//!
//! Scene ([`chrono_fsi::scene::floating`]): the box (height `body_size`, width
//! `2 body_size`, so it floats upright at every density ratio) and the cylinder (diameter
//! `body_size`) span a quasi-2-D slab periodic along y, in a tank `length` body widths
//! long; the sphere (diameter `body_size`) floats in a 3-D tank `width` diameters long
//! and periodic along y with period `width` diameters (a row of spheres: the draft is
//! static and local, so the shorter tank is enough for it, not for a heave period). Walls at
//! both ends and the floor. The body starts `offset` above its Archimedes position and
//! settles; the fluid is damped (`damping`, a velocity relaxation that leaves the static
//! equilibrium unchanged) so the run reaches it within `t_end`.
//!
//! Reference (Archimedes): the draft `d` at which the displaced fluid weighs as much as
//! the body ([`chrono_fsi::scene::archimedes_draft`]). The measured draft is the
//! still-water level minus the body's lowest point, averaged over the last `window`
//! fraction of the run; the level is where the fluid's actual volume `sum m/rho` fills
//! the tank around the body ([`chrono_fsi::scene::FloatingScene::draft`]).
//! Checked (acceptance of issue 24): `|d - d_A| <= max(2 % d_A, dp / 4)` per shape where
//! the body is resolved, `body_size / dp >= 10` (`RESOLVED_SPACINGS`; coarser set-ups
//! report the error and the tolerance); `drift`, the horizontal displacement at the end,
//! below `dp` (the scene is symmetric) at every resolution; reported: `jitter` (RMS
//! vertical speed over the window), `substeps` (fluid sub-steps per system step) and the
//! wall time.
//!
//! Defaults: `dp = 0.02 m`, 5 spacings per body size, 0.5 s (the ~40 s budget): the drafts
//! are reported (box -9 %, cylinder -16 %, still settling at 0.5 s, sphere -6 %: 0.2-0.4
//! dp high). `--full` is the checked set-up: `dp = body_size / 10`, 1 s (about 250 s):
//! box -0.43 %, cylinder -3.0 % (1.5 mm against the 2.5 mm quarter spacing), sphere -2.6 %
//! (1.3 mm). A box twice the size at the default `dp` (10 spacings, 1 s) reads -0.41 %: the
//! error is the body's resolution and the settling, not an offset of the coupling
//! (docs/validation-fsi.md). `draft_pressure` (reported) reads the level from the far
//! fluid's pressure instead (`FloatingScene::draft_pressure`).
//!
//! `fluid = cfluid` runs the same scenes in a constraint fluid
//! ([`chrono_fsi::cfluid::floating_cfluid`]: the body's markers in the fluid's density
//! rows, one CCP per `coupling_step` for fluid and body, APGD at `tolerance` and
//! `max_iterations`, `damping` the same velocity relaxation), the draft read from the
//! fluid's particle count and checked the same way (docs/validation-fsi.md, "Constraint
//! fluids").
//!
//! The sphere's heave period against Hulme (1982) is the case `fsi-sphere-heave`
//! (`sphere_heave.rs`).

use std::time::Instant;

use chrono_core::descriptor::SolverSettings;
use chrono_fsi::cfluid::{CfluidFloat, floating_cfluid};
use chrono_fsi::scene::{FloatShape, FloatingParams, FloatingSystem, floating};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Spacings across the body size from which the draft is checked (below it is reported):
/// at 5 the kernel support spans half the body and the drafts read 0.2-0.4 spacings
/// high; at 10 (and 1 s to settle) box, cylinder and sphere are within the criterion
/// (docs/validation-fsi.md).
const RESOLVED_SPACINGS: f64 = 10.0;

/// Parameters of `fsi-floating-body`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FloatingBodyParams {
    /// `box`, `cylinder`, `sphere` or `all` (the three in turn).
    pub shape: String,
    /// Body density, kg/m^3.
    pub body_density: f64,
    /// Body size (box height, cylinder and sphere diameter), m.
    pub body_size: f64,
    /// Water depth, m.
    pub depth: f64,
    /// Fluid model: `sph` (WCSPH, sub-stepped) or `cfluid` (constraint fluid, one CCP
    /// per step with the body).
    pub fluid: String,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Tank length (box, cylinder), in body widths.
    pub length: f64,
    /// Sphere: period along y, in diameters.
    pub width: f64,
    /// Start above the Archimedes position, m.
    pub offset: f64,
    /// Fluid velocity relaxation rate during the run, 1/s.
    pub damping: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Multibody (coupling) step, s.
    pub coupling_step: f64,
    /// Fraction of the run the draft is averaged over.
    pub window: f64,
    /// Water density, kg/m^3.
    pub rho_water: f64,
    /// `fluid = cfluid`: the CCP solver's tolerance (chrono-ccp residual, m/s).
    pub tolerance: f64,
    /// `fluid = cfluid`: the CCP solver's iteration cap per step.
    pub max_iterations: usize,
    /// `fluid = cfluid`: the largest density deficit with a bilateral row
    /// (`CfluidSettings::surface_deficit`; 0: every deficit a free surface).
    pub surface_deficit: f64,
}

impl Default for FloatingBodyParams {
    fn default() -> Self {
        Self {
            shape: "all".into(),
            body_density: 500.0,
            body_size: 0.1,
            depth: 0.15,
            fluid: "sph".into(),
            spacing: 0.02,
            length: 10.0,
            width: 3.0,
            offset: 0.0,
            damping: 8.0,
            t_end: 0.5,
            coupling_step: 1e-3,
            window: 0.25,
            rho_water: 1000.0,
            tolerance: 1e-4,
            max_iterations: 300,
            surface_deficit: 0.0,
        }
    }
}

impl CaseParams for FloatingBodyParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("shape", "-", "box | cylinder | sphere | all"),
        ParamInfo::new("body_density", "kg/m^3", "body density"),
        ParamInfo::new("body_size", "m", "box height, cylinder and sphere diameter"),
        ParamInfo::new("depth", "m", "water depth"),
        ParamInfo::new(
            "fluid",
            "-",
            "sph (WCSPH + BCE markers) | cfluid (constraint fluid, body markers in its density rows)",
        ),
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new("length", "-", "tank length in body widths (box, cylinder)"),
        ParamInfo::new("width", "-", "sphere: period along y in diameters"),
        ParamInfo::new("offset", "m", "start above the Archimedes position"),
        ParamInfo::new("damping", "1/s", "fluid velocity relaxation rate"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new(
            "coupling_step",
            "s",
            "multibody step h (the fluid sub-steps inside it)",
        ),
        ParamInfo::new(
            "window",
            "-",
            "fraction of the run the draft is averaged over",
        ),
        ParamInfo::new("rho_water", "kg/m^3", "water density"),
        ParamInfo::new(
            "tolerance",
            "m/s",
            "fluid = cfluid: CCP solver tolerance (APGD residual)",
        ),
        ParamInfo::new(
            "max_iterations",
            "-",
            "fluid = cfluid: CCP solver iteration cap per step",
        ),
        ParamInfo::new(
            "surface_deficit",
            "-",
            "fluid = cfluid: largest density deficit with a bilateral row (0: all unilateral)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.spacing = 0.025;
                self.body_size = 0.1;
                self.length = 6.0;
                self.t_end = 0.4;
            }
            Mode::Default => {}
            // The checked set-up: the body resolved by RESOLVED_SPACINGS, settled over 1 s.
            Mode::Full => {
                self.spacing = self.body_size / RESOLVED_SPACINGS;
                self.t_end = self.t_end.max(1.0);
            }
        }
    }
}

struct Outcome {
    draft: f64,
    draft_pressure: f64,
    draft_archimedes: f64,
    drift: f64,
    jitter: f64,
    substeps: f64,
    steps: u64,
    wall: f64,
}

/// The scene's parameters for `shape` (the run's parameters checked first).
fn floating_params(p: &FloatingBodyParams, shape: FloatShape) -> anyhow::Result<FloatingParams> {
    anyhow::ensure!(
        p.coupling_step.is_finite() && p.coupling_step > 0.0,
        "parameter `coupling_step` must be > 0, got {}",
        p.coupling_step
    );
    anyhow::ensure!(
        p.t_end.is_finite() && p.t_end > 0.0,
        "parameter `t_end` must be > 0, got {}",
        p.t_end
    );
    anyhow::ensure!(
        p.window > 0.0 && p.window <= 1.0,
        "parameter `window` must be in (0, 1], got {}",
        p.window
    );
    // tank length in body sizes: `length` body widths for the slab shapes, a
    // `width`-square for the sphere (3-D, the costly one)
    let length = match shape {
        FloatShape::Box => p.length * chrono_fsi::scene::BOX_ASPECT,
        FloatShape::Cylinder => p.length,
        FloatShape::Sphere => p.width,
    };
    Ok(FloatingParams {
        shape,
        body_density: p.body_density,
        body_size: p.body_size,
        depth: p.depth,
        length,
        width: p.width,
        spacing: p.spacing,
        rho0: p.rho_water,
        offset: p.offset,
        ..FloatingParams::default()
    })
}

fn simulate(
    p: &FloatingBodyParams,
    shape: FloatShape,
    series: &mut Series,
    ctx: &RunContext,
) -> anyhow::Result<Outcome> {
    let fp = floating_params(p, shape)?;
    let solver = chrono_ccp::Psor::new(SolverSettings::default());
    let mut scene = floating(&fp, Box::new(solver))?;
    let fluid = scene.fluid;
    scene
        .system
        .item_mut::<chrono_fsi::SphFluid>(fluid)
        .expect("fluid")
        .sph_mut()
        .set_damping(p.damping)?;
    let r = record(p, &mut scene, series, ctx, |s| {
        [s.draft(&fp), s.draft_pressure(&fp), s.draft_archimedes]
    })?;
    let f = scene.fluid();
    Ok(Outcome {
        draft: r.draft,
        draft_pressure: r.draft_pressure,
        draft_archimedes: scene.draft_archimedes,
        drift: r.drift,
        jitter: r.jitter,
        substeps: f.substeps() as f64 / r.steps as f64,
        steps: f.substeps(),
        wall: r.wall,
    })
}

/// The window's means of a run of `scene`: `reading` gives the draft, the pressure-level
/// draft (NaN where there is none) and the Archimedes draft, m.
struct Record {
    draft: f64,
    draft_pressure: f64,
    drift: f64,
    jitter: f64,
    steps: u64,
    wall: f64,
}

/// Steps `scene` to `t_end` by `coupling_step`, averaging `reading`'s drafts and the
/// body's vertical speed over the last `window` of the run; the drift is the body's
/// horizontal displacement at the end.
fn record<S: FloatingSystem>(
    p: &FloatingBodyParams,
    scene: &mut S,
    series: &mut Series,
    ctx: &RunContext,
    reading: impl Fn(&S) -> [f64; 3],
) -> anyhow::Result<Record> {
    let body = scene.body();
    let x0 = scene.system().body(body)?.position();
    let start = Instant::now();
    let n = (p.t_end / p.coupling_step).round().max(1.0) as u64;
    let from = ((1.0 - p.window) * n as f64) as u64;
    let (mut sum, mut sum_p, mut vz2, mut cnt) = (0.0, 0.0, 0.0, 0usize);
    for i in 1..=n {
        scene.step(p.coupling_step)?;
        let t = scene.system().time();
        let [draft, draft_p, archimedes] = reading(scene);
        let vz = scene.system().body(body)?.linear_velocity().z;
        if i > from {
            sum += draft;
            sum_p += draft_p;
            vz2 += vz * vz;
            cnt += 1;
        }
        if i % 10 == 0 {
            series.push(&[t, draft, archimedes, vz]);
        }
        ctx.progress_steps(i, n);
    }
    let x1 = scene.system().body(body)?.position();
    Ok(Record {
        draft: sum / cnt as f64,
        draft_pressure: sum_p / cnt as f64,
        drift: ((x1.x - x0.x).powi(2) + (x1.y - x0.y).powi(2)).sqrt(),
        jitter: (vz2 / cnt as f64).sqrt(),
        steps: n,
        wall: start.elapsed().as_secs_f64(),
    })
}

/// The same scene in a constraint fluid (`chrono_fsi::cfluid::floating_cfluid`): one CCP
/// per step `coupling_step` for the fluid and the body, APGD at `tolerance` and
/// `max_iterations`; `damping` relaxes the fluid's velocities as in the SPH run.
fn simulate_cfluid(
    p: &FloatingBodyParams,
    shape: FloatShape,
    series: &mut Series,
    ctx: &RunContext,
) -> anyhow::Result<Outcome> {
    let fp = floating_params(p, shape)?;
    let solver = crate::cases::cfluid::solver_by_name("apgd", p.tolerance, p.max_iterations)?;
    let c = CfluidFloat {
        surface_deficit: p.surface_deficit,
        ..CfluidFloat::default()
    };
    let mut scene = floating_cfluid(&fp, &c, solver)?;
    scene.fluid_mut().set_damping(p.damping)?;
    let r = record(p, &mut scene, series, ctx, |s| {
        [s.draft(&fp), f64::NAN, s.draft_archimedes]
    })?;
    Ok(Outcome {
        draft: r.draft,
        draft_pressure: f64::NAN,
        draft_archimedes: scene.draft_archimedes,
        drift: r.drift,
        jitter: r.jitter,
        substeps: 1.0,
        steps: r.steps,
        wall: r.wall,
    })
}

fn run(p: &FloatingBodyParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let cfluid = match p.fluid.as_str() {
        "sph" => false,
        "cfluid" => true,
        other => anyhow::bail!("parameter `fluid` must be sph | cfluid, got `{other}`"),
    };
    let shapes: Vec<(FloatShape, &str)> = match p.shape.as_str() {
        "all" => vec![
            (FloatShape::Box, "box"),
            (FloatShape::Cylinder, "cylinder"),
            (FloatShape::Sphere, "sphere"),
        ],
        s => vec![(s.parse::<FloatShape>()?, s)],
    };
    let single = shapes.len() == 1;
    let mut out = CaseOutput::new();
    let mut series = Series::new(["t", "draft", "draft_archimedes", "vz"]);
    let mut steps = 0;
    for (shape, name) in shapes {
        let o = if cfluid {
            simulate_cfluid(p, shape, &mut series, ctx)?
        } else {
            simulate(p, shape, &mut series, ctx)?
        };
        steps += o.steps;
        let sfx = |m: &str| {
            if single {
                m.to_string()
            } else {
                format!("{m}_{name}")
            }
        };
        // acceptance: within max(2 %, dp / 4) of Archimedes, checked where the body is
        // resolved (RESOLVED_SPACINGS across); a coarser set-up reports it (module docs).
        let tol = (0.02 * o.draft_archimedes).max(0.25 * p.spacing);
        let err = (o.draft - o.draft_archimedes).abs();
        if p.body_size / p.spacing >= RESOLVED_SPACINGS - 1e-9 {
            out.check(Check::below(sfx("draft_abs_error"), err, tol));
        } else {
            out.metric(sfx("draft_abs_error"), err)
                .metric(sfx("draft_tolerance"), tol);
        }
        out.check(Check::below(sfx("drift"), o.drift, p.spacing));
        if o.draft_pressure.is_finite() {
            out.metric(sfx("draft_pressure"), o.draft_pressure).metric(
                sfx("draft_pressure_error"),
                o.draft_pressure / o.draft_archimedes - 1.0,
            );
        }
        out.metric(sfx("draft"), o.draft)
            .metric(sfx("draft_archimedes"), o.draft_archimedes)
            .metric(sfx("draft_error"), o.draft / o.draft_archimedes - 1.0)
            .metric(sfx("jitter"), o.jitter)
            .metric(sfx("substeps_per_step"), o.substeps)
            .metric(sfx("wall_s"), o.wall);
    }
    out.series = series;
    out.plot = PlotSpec::new(
        if cfluid {
            "floating bodies (constraint fluid, body markers in its rows): draft against Archimedes"
        } else {
            "floating bodies (WCSPH + BCE markers): draft against Archimedes"
        },
        "t [s]",
        "m",
        &["draft"],
    )
    .with_reference(&["draft_archimedes"]);
    out.steps = steps;
    Ok(out)
}

/// The `fsi-floating-body` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<FloatingBodyParams>::boxed(
        "fsi-floating-body",
        "fsi",
        "Box, horizontal cylinder and sphere floating in WCSPH water (BCE markers, fluid sub-stepped inside the multibody step): draft against Archimedes.",
        run,
    )
}
