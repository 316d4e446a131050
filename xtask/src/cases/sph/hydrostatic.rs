//! `sph-hydrostatic`: a tank of still water (quasi-2D slab).
//!
//! Reference: hydrostatics, `p = rho_0 g (H - z)`; the fluid should stay at rest. Starts
//! from the compressible hydrostatic density (`Tait::hydrostatic_density`) on a cubic
//! lattice, walls by marker layers with extrapolated pressure (Adami et al. 2012); the
//! solver defaults (`h = 1.5 dp`, delta-SPH with the hydrostatic correction,
//! `alpha = 0.02`) are the ones that keep it still (`docs/validation-sph.md`). `--quick`
//! is the coarse lattice (dp = H/10) over the same 2 s. Metrics after `t_end`: `pressure_error`
//! (relative L2 in the bulk, i.e. fluid farther than the kernel support from walls and
//! surface), `max_speed` (spurious currents, against `1 % sqrt(g H)`),
//! `density_variation` (max `|rho/rho_0 - 1|`) and `left_tank` (fluid particles outside
//! the tank). The 20 s long-run stability check is `--full` (or `--set t_end=20`).

use std::time::Instant;

use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::particles::KernelKind;
use chrono_core::particles::lattice::SlabTank;
use chrono_sph::{SphSettings, SphSystem};
use serde::{Deserialize, Serialize};

use super::{convergence_order, particle_frames, rel_l2, sweep_point, sweep_spacings};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// `g` = [`GRAVITY_MAGNITUDE`], m/s^2.
const G: f64 = GRAVITY_MAGNITUDE;

/// Parameters of `sph-hydrostatic`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct HydrostaticParams {
    /// Water depth `H`, m.
    pub depth: f64,
    /// Tank length (x), m.
    pub tank_length: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// `h / dp`.
    pub h_over_dp: f64,
    /// Kernel: `wendland_c2` or `cubic_spline`.
    pub kernel: KernelKind,
    /// Monaghan artificial viscosity alpha.
    pub alpha: f64,
    /// Density diffusion coefficient delta (Fourtakas et al. 2019 form; 0 = off).
    pub delta: f64,
    /// Extra coarser runs for the speed-against-error sweep (spacing x 1.5^k).
    pub sweep: u32,
}

impl Default for HydrostaticParams {
    fn default() -> Self {
        Self {
            depth: 0.4,
            tank_length: 0.4,
            spacing: 0.02,
            t_end: 2.0,
            h_over_dp: 1.5,
            kernel: KernelKind::WendlandC2,
            alpha: 0.02,
            delta: 0.1,
            sweep: 0,
        }
    }
}

impl CaseParams for HydrostaticParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("depth", "m", "water depth H"),
        ParamInfo::new("tank_length", "m", "tank length (x)"),
        ParamInfo::new("spacing", "m", "particle spacing dp"),
        ParamInfo::new(
            "t_end",
            "s",
            "simulated time (20 s in --full: long-run stability)",
        ),
        ParamInfo::new("h_over_dp", "-", "smoothing length over spacing"),
        ParamInfo::new("kernel", "-", "wendland_c2 | cubic_spline"),
        ParamInfo::new("alpha", "-", "Monaghan artificial viscosity"),
        ParamInfo::new(
            "delta",
            "-",
            "delta-SPH density diffusion (hydrostatic form)",
        ),
        ParamInfo::new(
            "sweep",
            "-",
            "extra coarser runs (spacing x 1.5^k) for the sweep",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                // coarse, but the full 2 s: the start-up transient must have decayed
                self.spacing = 0.04;
            }
            // dp = 0.03 m, the full 2 s, for the 20-minute budget of the default run
            // (`xtask/src/budget.rs`); the earlier default, dp = 0.02 m (~110 s), is
            // `--set spacing=0.02`, which `--full` keeps.
            Mode::Default => self.spacing = 0.03,
            Mode::Full => {
                self.t_end = 20.0;
                self.sweep = 2;
            }
        }
    }
}

struct Outcome {
    pressure_error: f64,
    max_speed: f64,
    density_variation: f64,
    left_tank: usize,
    steps: u64,
    series: Series,
}

fn build(p: &HydrostaticParams, dp: f64) -> anyhow::Result<(SphSystem, [f64; 3])> {
    anyhow::ensure!(
        p.depth > 0.0,
        "parameter `depth` must be > 0, got {}",
        p.depth
    );
    anyhow::ensure!(
        dp > 0.0 && dp < p.depth / 4.0,
        "parameter `spacing` must be in (0, depth/4), got {dp}"
    );
    let top = 1.25 * p.depth;
    let tank = SlabTank::sloshing(dp, p.h_over_dp, p.tank_length, p.depth, top);
    let settings = SphSettings {
        kernel: p.kernel,
        sound_speed: 10.0 * (2.0 * G * p.depth).sqrt(),
        artificial_viscosity: p.alpha,
        diffusion_delta: p.delta,
        ..SphSettings::default()
    };
    let sys = chrono_sph::scene::slab_tank(settings, &tank)?;
    Ok((sys, [p.tank_length, tank.thickness(), top]))
}

fn simulate(p: &HydrostaticParams, dp: f64, ctx: Option<&RunContext>) -> anyhow::Result<Outcome> {
    let (mut sys, upper) = build(p, dp)?;
    // The reference is the water actually in the tank: the lattice holds a whole number of
    // layers, `depth` rounded to a multiple of `dp` (13 layers of 0.03 m for 0.4 m). The
    // top layer's centres sit `dp / 2` below the free surface.
    let d = sys.data();
    let depth = (0..d.len())
        .filter(|&i| d.kind[i] == chrono_sph::data::FLUID)
        .map(|i| d.z[i])
        .fold(f64::NEG_INFINITY, f64::max)
        + 0.5 * dp;
    anyhow::ensure!(
        depth.is_finite(),
        "no fluid particle: `depth` {} is below one layer of `spacing` {dp}",
        p.depth
    );
    let v_ref = (G * p.depth).sqrt();
    let mut series = Series::new(["t", "max_speed_over_sqrt_gH", "p_bottom", "p_bottom_exact"]);
    let probe = [0.5 * p.tank_length, 0.5 * upper[1], 2.0 * dp];
    let p_exact = 1000.0 * G * (depth - probe[2]);
    let mut frames = particle_frames(ctx, p.t_end / 50.0)?;
    let mut next_row = 0.0;
    let mut max_speed_late = 0.0f64;
    while sys.time() < p.t_end - 1e-12 {
        sys.step()?;
        let t = sys.time();
        if t >= 0.5 * p.t_end {
            max_speed_late = max_speed_late.max(sys.stats().max_speed);
        }
        if t >= next_row {
            next_row += p.t_end / 400.0;
            let pb = sys.pressure_at(probe)?.unwrap_or(f64::NAN);
            series.push(&[t, sys.stats().max_speed / v_ref, pb, p_exact]);
            frames.record(0, t, |path| sys.write_vtk(path, true))?;
            if let Some(c) = ctx {
                c.progress(t / p.t_end);
            }
        }
    }
    frames.finish()?;
    let d = sys.data();
    let support = sys.kernel().support();
    let (mut num, mut refs) = (Vec::new(), Vec::new());
    let mut dvar = 0.0f64;
    for i in 0..d.len() {
        if d.kind[i] != chrono_sph::data::FLUID {
            continue;
        }
        dvar = dvar.max((d.rho[i] / 1000.0 - 1.0).abs());
        let (x, z) = (d.x[i], d.z[i]);
        if x > support && x < p.tank_length - support && z > support && z < depth - support {
            num.push(d.p[i]);
            refs.push(1000.0 * G * (depth - z));
        }
    }
    anyhow::ensure!(
        !refs.is_empty(),
        "no bulk particle: the tank is too small for the kernel support"
    );
    let tol = 0.5 * dp;
    let left_tank = sys.fluid_outside(
        [-tol, -1.0, -tol],
        [upper[0] + tol, upper[1] + 1.0, upper[2]],
    );
    Ok(Outcome {
        pressure_error: rel_l2(&num, &refs),
        max_speed: max_speed_late.max(sys.stats().max_speed),
        density_variation: dvar,
        left_tank,
        steps: sys.steps(),
        series,
    })
}

fn run(p: &HydrostaticParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let mut out = CaseOutput::new();
    let mut conv = Vec::new();
    for dp in sweep_spacings(p.spacing, p.sweep) {
        let start = Instant::now();
        let o = simulate(p, dp, None)?;
        out.sweep.push(sweep_point(
            dp,
            o.pressure_error,
            start.elapsed().as_secs_f64(),
        ));
        conv.push((dp, o.pressure_error));
    }
    let start = Instant::now();
    let o = simulate(p, p.spacing, Some(ctx))?;
    if p.sweep > 0 {
        out.sweep.push(sweep_point(
            p.spacing,
            o.pressure_error,
            start.elapsed().as_secs_f64(),
        ));
        conv.push((p.spacing, o.pressure_error));
        out.metric("convergence_order", convergence_order(&conv));
    }
    let v_ref = (G * p.depth).sqrt();
    out.check(Check::below("pressure_error", o.pressure_error, 0.02))
        .check(Check::below("max_speed", o.max_speed, 0.01 * v_ref))
        .check(Check::below("density_variation", o.density_variation, 0.01))
        .check(Check::below("left_tank", o.left_tank as f64, 0.0));
    out.series = o.series;
    out.plot = PlotSpec::new("SPH hydrostatic tank", "t [s]", "p [Pa]", &["p_bottom"])
        .with_reference(&["p_bottom_exact"]);
    out.steps = o.steps;
    Ok(out)
}

/// The `sph-hydrostatic` case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<HydrostaticParams>::boxed(
        "sph-hydrostatic",
        "sph",
        "Still water in a tank (quasi-2D WCSPH): pressure against rho g (H - z), spurious currents, density variation; 20 s stability in --full.",
        run,
    )
}
