//! `granular-settle` (validation) and the `granular-settle` bench: grains settling in an
//! open box under gravity, by NSC (DEM-C) or SMC (DEM-P).
//!
//! Validation (the "hard case that must stay stable"): after the grains have
//! fallen from a loose jittered lattice and settled, the kinetic energy per grain decays
//! below `ke_bound * m g d` (a grain's kinetic energy small against the energy of lifting it
//! by one diameter) and stays there over the last quarter of the run, no grain leaves the
//! box, and (NSC) the deepest penetration is below 1 % of the radius. `--full`: 10 000
//! grains for 10 s at `h = 1e-3` s.
//!
//! Bench: steps/s, contacts/s and the share of the wall time spent in the broad phase,
//! the narrow phase, assembly (NSC: variables, rows, problem; SMC: contact forces) plus
//! integration, and the CCP solve.

use crate::cases::timed_solver::TimedSolver;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use chrono_core::granular::probe::max_penetration;
use chrono_core::granular::{GrainBed, Region, add_box_container};
use chrono_core::math::Vector3;
use chrono_core::system::{ContactMethod, SmcModel, SmcSettings};
use chrono_core::{BodyHandle, ContactMaterial, System, SystemSettings};
use serde::{Deserialize, Serialize};

use super::{grain_frames, make_system, record_grains};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `granular-settle`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SettleParams {
    /// Number of grains.
    pub n: usize,
    /// Contact method: `nsc` or `smc`.
    pub method: ContactMethod,
    /// SMC force law: `hooke` or `hertz`.
    pub model: SmcModel,
    /// Largest grain radius, m (radii uniform in [0.8 r, r]).
    pub radius: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Young's modulus (SMC), Pa.
    pub young: f64,
    /// Restitution (SMC).
    pub restitution: f64,
    /// Time step, s (0: 1e-3 for NSC, the SMC limit for SMC).
    pub h: f64,
    /// Simulated time, s (validation).
    pub t_end: f64,
    /// Steps to time (bench; 0 = use `t_end`).
    pub steps: u64,
    /// Bound on the kinetic energy per grain, in units of `m g d`.
    pub ke_bound: f64,
    /// CCP solver of the NSC step, by name (`chrono_ccp::SOLVER_NAMES`).
    pub solver: String,
    /// Solver tolerance (NSC), m/s.
    pub tolerance: f64,
    /// Solver iteration cap (NSC).
    pub max_iterations: usize,
    /// Seed of the packing.
    pub seed: u64,
}

impl Default for SettleParams {
    fn default() -> Self {
        Self {
            n: 1000,
            method: ContactMethod::Nsc,
            model: SmcModel::Hertz,
            radius: 0.005,
            density: 2500.0,
            mu: 0.5,
            young: 1e7,
            restitution: 0.5,
            h: 0.0,
            t_end: 1.0,
            steps: 0,
            ke_bound: 1e-3,
            solver: "apgd".into(),
            tolerance: 1e-5,
            max_iterations: 100,
            seed: 1,
        }
    }
}

const INFO: &[ParamInfo] = &[
    ParamInfo::new("n", "-", "number of grains"),
    ParamInfo::new("method", "-", "contact method: nsc | smc"),
    ParamInfo::new("model", "-", "SMC force law: hooke | hertz"),
    ParamInfo::new("radius", "m", "largest grain radius (radii in [0.8 r, r])"),
    ParamInfo::new("density", "kg/m^3", "grain density"),
    ParamInfo::new("mu", "-", "friction coefficient"),
    ParamInfo::new("young", "Pa", "Young's modulus (SMC)"),
    ParamInfo::new("restitution", "-", "restitution (SMC)"),
    ParamInfo::new("h", "s", "time step (0: 1e-3 NSC, the SMC limit SMC)"),
    ParamInfo::new("t_end", "s", "simulated time"),
    ParamInfo::new("steps", "-", "steps to run (bench; 0 = t_end / h)"),
    ParamInfo::new("ke_bound", "m g d", "bound on the kinetic energy per grain"),
    ParamInfo::new(
        "solver",
        "-",
        "CCP solver (NSC): apgd | apsor (12 iterations suffice) | chrono_ccp::SOLVER_NAMES",
    ),
    ParamInfo::new("tolerance", "m/s", "solver tolerance (NSC)"),
    ParamInfo::new("max_iterations", "-", "solver iteration cap (NSC)"),
    ParamInfo::new("seed", "-", "seed of the packing"),
];

impl CaseParams for SettleParams {
    const INFO: &'static [ParamInfo] = INFO;
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            // 400 grains for 1 s (~18 s; the default run's too, for its 20-minute budget;
            // the earlier default, 1000 grains, ~55 s, is `--set n=1000`).
            Mode::Quick | Mode::Default => {
                self.n = 400;
                self.t_end = 1.0;
            }
            Mode::Full => {
                self.n = 10_000;
                self.t_end = 10.0;
            }
        }
    }
}

/// Bench parameters: the same scene, timed over a fixed number of steps.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SettleBenchParams(SettleParams);

impl Default for SettleBenchParams {
    fn default() -> Self {
        Self(SettleParams {
            n: 10_000,
            steps: 100,
            ..SettleParams::default()
        })
    }
}

impl CaseParams for SettleBenchParams {
    const INFO: &'static [ParamInfo] = INFO;
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.0.n = 2000;
            self.0.steps = 20;
        }
    }
}

/// The scene: grains on a jittered lattice in an open box (also the scene of
/// `granular-vs-rapier`).
pub(super) struct Scene {
    pub(super) sys: System,
    pub(super) grains: Vec<BodyHandle>,
    pub(super) lower: Vector3<f64>,
    pub(super) upper: Vector3<f64>,
    pub(super) h: f64,
    solve_nanos: Arc<AtomicU64>,
}

pub(super) fn scene(p: &SettleParams) -> anyhow::Result<Scene> {
    anyhow::ensure!(p.n > 0, "parameter `n` must be > 0");
    let method = p.method;
    let settings = SystemSettings {
        envelope: 0.1 * p.radius,
        smc: SmcSettings {
            model: p.model,
            ..SmcSettings::default()
        },
        ..SystemSettings::default()
    };
    let mut sys = make_system(method, settings, p.tolerance, p.max_iterations)?;
    let nanos = Arc::new(AtomicU64::new(0));
    let inner = crate::cases::rigid::make_solver(&p.solver, p.tolerance, p.max_iterations)?;
    sys.set_solver(Box::new(TimedSolver {
        inner,
        nanos: nanos.clone(),
    }));
    let mat = ContactMaterial::smc(p.young, 0.3, p.restitution, p.mu);
    let pitch = 2.2 * p.radius;
    let side = ((p.n as f64).cbrt() * 1.3).ceil();
    let layers = (p.n as f64 / (side * side)).ceil() + 1.0;
    let lower = Vector3::zeros();
    let upper = Vector3::new(side * pitch, side * pitch, (layers + 1.0) * pitch);
    // No kick, no settling here: the case is the settling.
    let bed = GrainBed {
        gap: 0.2 * p.radius,
        count: Some(p.n),
        kick: None,
        seed: p.seed,
        ..GrainBed::new(
            Region::Box { lower, upper },
            0.8 * p.radius,
            p.radius,
            p.density,
            mat,
        )
    };
    add_box_container(&mut sys, "box", lower, upper, mat)?;
    let grains = bed.pour(&mut sys)?.handles;
    let h = super::step_size(p.h, method, &sys);
    Ok(Scene {
        sys,
        grains,
        lower,
        upper,
        h,
        solve_nanos: nanos,
    })
}

fn run(p: &SettleParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let mut s = scene(p)?;
    let g = s.sys.settings().gravity.norm();
    let m_grain = p.density * 4.0 / 3.0 * std::f64::consts::PI * (0.9 * p.radius).powi(3);
    let unit = m_grain * g * 2.0 * p.radius;
    let n = (p.t_end / s.h).round().max(1.0) as u64;
    let mut series = Series::new(["t", "ke_per_grain_over_mgd", "max_penetration_over_r"]);
    let mut vtk = grain_frames(ctx, (0.05 / s.h).round() as u64)?;
    let (mut ke_late_max, mut pen_late_max) = (0.0f64, 0.0f64);
    for i in 1..=n {
        s.sys.step(s.h)?;
        record_grains(&mut vtk, i, &s.sys)?;
        let ke = s.sys.kinetic_energy() / p.n as f64 / unit;
        let pen = max_penetration(&s.sys) / (0.8 * p.radius);
        if i * 4 >= 3 * n {
            ke_late_max = ke_late_max.max(ke);
            pen_late_max = pen_late_max.max(pen);
        }
        if i % 10 == 0 || i == n {
            series.push(&[s.sys.time(), ke, pen]);
        }
        ctx.progress_steps(i, n);
    }
    vtk.finish()?;
    let escaped = s
        .grains
        .iter()
        .filter(|&&b| {
            let x = s.sys.body(b).map(|b| b.position()).unwrap_or_default();
            (0..3).any(|a| x[a] < s.lower[a]) || x.x > s.upper.x || x.y > s.upper.y
        })
        .count();
    let mut out = CaseOutput::new();
    out.check(Check::below(
        "ke_per_grain_late_max",
        ke_late_max,
        p.ke_bound,
    ))
    .check(Check::below("escaped_grains", escaped as f64, 0.0));
    if p.method == ContactMethod::Nsc {
        out.check(Check::below("max_penetration_over_r", pen_late_max, 0.01));
    } else {
        out.metric("max_penetration_over_r", pen_late_max);
    }
    out.metric("h", s.h);
    out.series = series;
    out.plot = PlotSpec::new(
        "grains settling in a box",
        "t [s]",
        "KE per grain / (m g d)",
        &["ke_per_grain_over_mgd"],
    );
    out.steps = n;
    Ok(out)
}

fn run_bench(p: &SettleBenchParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let p = &p.0;
    let mut s = scene(p)?;
    let steps = if p.steps > 0 {
        p.steps
    } else {
        (p.t_end / s.h).round().max(1.0) as u64
    };
    let (mut broad, mut narrow, mut total, mut contacts) = (0.0, 0.0, 0.0, 0u64);
    s.solve_nanos.store(0, Ordering::Relaxed);
    for i in 1..=steps {
        let t = std::time::Instant::now();
        let r = s.sys.step(s.h)?;
        total += t.elapsed().as_secs_f64();
        let (b, nphase) = s.sys.collision().last_timing();
        broad += b;
        narrow += nphase;
        contacts += r.contacts as u64;
        ctx.progress_steps(i, steps);
    }
    let solve = s.solve_nanos.load(Ordering::Relaxed) as f64 * 1e-9;
    let mut out = CaseOutput::new();
    out.metric("grains", p.n as f64)
        .metric("h", s.h)
        .metric("threads", rayon::current_num_threads() as f64)
        .metric("step_s_mean", total / steps as f64)
        .metric("steps_per_s", steps as f64 / total)
        .metric("contacts_per_step", contacts as f64 / steps as f64)
        .metric("contacts_per_s", contacts as f64 / total)
        .metric("share_broad_phase", broad / total)
        .metric("share_narrow_phase", narrow / total)
        .metric(
            "share_assembly_and_integration",
            (total - broad - narrow - solve) / total,
        )
        .metric("share_solve", solve / total);
    out.steps = steps;
    Ok(out)
}

/// The validation case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<SettleParams>::boxed(
        "granular-settle",
        "granular",
        "Grains settle in an open box (NSC or SMC): kinetic energy per grain below a bound over the last quarter, no grain escapes, NSC penetration < 1 % of the radius.",
        run,
    )
}

/// The bench.
pub fn bench() -> Box<dyn Case> {
    ParamCase::<SettleBenchParams>::boxed(
        "granular-settle",
        "granular",
        "Grains settling in a box: steps/s, contacts/s, shares of broad phase, narrow phase, assembly + integration, solve.",
        run_bench,
    )
}
