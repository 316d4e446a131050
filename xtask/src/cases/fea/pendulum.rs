//! `fea-pendulum`: an undamped flexible pendulum keeps its energy.
//!
//! A straight ANCF cable beam of length `L` along +X, pinned at `x = 0` to the ground (its
//! position tied to the origin by three bilateral rows in the CCP, `pin = rows`, or the
//! position coordinates removed, `pin = support`; the slope is free, so the pin is a
//! revolute joint for planar motion), released from rest horizontally under gravity
//! `GRAVITY` (`-9.81 Z`). The system steps it with chrono-fea's linearized implicit Euler (iteration
//! matrix `M + h^2 K` as the coupled mass operator of the CCP, see
//! `chrono_fea::dynamics`).
//!
//! Energy `E = T + U + V`: kinetic `v' M v / 2` (consistent mass), strain, and the gravity
//! potential `-∫ rho A g . r dx`; `E(0) = 0`. The metric is the drift relative to the
//! energy scale of the swing `m g L / 2` (the potential the rigid pendulum releases from
//! horizontal to vertical): `energy_drift_max = max_t |E(t) - E(0)| / (m g L / 2)` and
//! `energy_drift_end` (signed, at `t_end`). Linearized implicit Euler dissipates: the
//! drift is negative and shrinks with `h` (first order), which the step-size sweep
//! documents (`h_sweep`: drift and wall time per step size). Checks: the drift at `h`
//! within `tolerance` (the "within a few percent over 10 s"), and the ratio of the
//! drifts at the two smallest sweep steps `h1 < h2` at most `(h1 / h2)^min_order` (the
//! energy converges as `h` decreases, at an observed order of at least `min_order`).

use chrono_ccp::{Cg, SolverSettings};
use chrono_core::math::Vector3;
use chrono_core::{System, SystemSettings};
use chrono_fea::{AttachTarget, BeamMaterial, CableItem, CableMesh, CableQuadrature, NodeId};
use serde::{Deserialize, Serialize};

use super::{Element, check_cable_only};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// How the pendulum is pinned (`--set pin=support`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Pin {
    /// Three bilateral rows in the CCP tie node 0 to the origin.
    Rows,
    /// Node 0's position coordinates removed (a support).
    Support,
}

/// Parameters of `fea-pendulum`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PendulumParams {
    /// Number of elements.
    pub n_elements: usize,
    /// Beam length, m.
    pub length: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Section width, m.
    pub width: f64,
    /// Section height, m (bending in the swing plane is across the height).
    pub height: f64,
    /// Stiffness-proportional (Rayleigh) damping, s (0: undamped, the benchmark).
    pub damping: f64,
    /// Element type: `cable` (`beam`: not yet available).
    pub element: Element,
    /// The pin: `rows` (bilateral rows in the CCP) or `support` (removed coordinates).
    pub pin: Pin,
    /// Step size of the main run, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Step sizes of the numerical-damping sweep, s (empty: no sweep).
    pub h_sweep: Vec<f64>,
    /// Bound on `energy_drift_max` at `h`.
    pub tolerance: f64,
    /// Least observed order of the drift between the two smallest sweep steps.
    pub min_order: f64,
}

impl Default for PendulumParams {
    fn default() -> Self {
        Self {
            n_elements: 8,
            length: 1.0,
            young: 2.0e9,
            density: 7850.0,
            width: 0.02,
            height: 0.02,
            damping: 0.0,
            element: Element::Cable,
            pin: Pin::Rows,
            h: 1e-4,
            t_end: 10.0,
            h_sweep: vec![1e-3, 5e-4, 2.5e-4, 1e-4],
            tolerance: 0.05,
            min_order: 0.7,
        }
    }
}

impl CaseParams for PendulumParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n_elements", "-", "number of elements"),
        ParamInfo::new("length", "m", "beam length"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("density", "kg/m^3", "density"),
        ParamInfo::new("width", "m", "section width"),
        ParamInfo::new("height", "m", "section height (swing-plane bending)"),
        ParamInfo::new("damping", "s", "Rayleigh stiffness-proportional damping"),
        ParamInfo::new("element", "-", "element type: cable (beam: not yet)"),
        ParamInfo::new("pin", "-", "rows (CCP bilateral rows) or support"),
        ParamInfo::new("h", "s", "step size of the main run"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new("h_sweep", "s", "step sizes of the numerical-damping sweep"),
        ParamInfo::new("tolerance", "-", "bound on the relative energy drift at h"),
        ParamInfo::new(
            "min_order",
            "-",
            "least observed order of the drift in h (two smallest sweep steps)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            // A shorter horizon and a coarser sweep: seconds on a loaded machine.
            Mode::Quick => {
                self.t_end = 4.0;
                self.h_sweep = vec![4e-4, 2e-4];
            }
            Mode::Full => self.h_sweep = vec![2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4, 5e-5],
            Mode::Default => {}
        }
    }
}

/// What one simulation gives.
struct Run {
    drift_max: f64,
    drift_end: f64,
    steps: u64,
    wall_s: f64,
    /// Lowest tip height reached, m.
    tip_min_z: f64,
    max_pin_gap: f64,
}

/// Simulate to `t_end` with step `h`; record the energy every `record` s into `series`.
fn simulate(
    p: &PendulumParams,
    h: f64,
    mut series: Option<&mut Series>,
    ctx: Option<&RunContext>,
) -> anyhow::Result<Run> {
    anyhow::ensure!(
        h.is_finite() && h > 0.0,
        "parameter `h` must be > 0, got {h}"
    );
    anyhow::ensure!(
        p.t_end.is_finite() && p.t_end > 0.0,
        "parameter `t_end` must be > 0, got {}",
        p.t_end
    );
    anyhow::ensure!(
        p.length.is_finite() && p.length > 0.0,
        "parameter `length` must be > 0, got {}",
        p.length
    );
    anyhow::ensure!(
        p.n_elements >= 1,
        "parameter `n_elements` must be >= 1, got {}",
        p.n_elements
    );
    let mat = BeamMaterial::rectangle(p.young, p.density, p.width, p.height, p.damping)?;
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::new(p.length, 0.0, 0.0),
        p.n_elements,
        mat,
        CableQuadrature::default(),
    )?;
    let rows = match p.pin {
        Pin::Rows => true,
        Pin::Support => {
            mesh.fix_position(NodeId(0))?;
            false
        }
    };
    let g = chrono_core::math::GRAVITY;
    let scale = 0.5 * mesh.total_mass() * -g.z * p.length;
    let mut item = CableItem::new("pendulum", mesh)?;
    if rows {
        item.attach(NodeId(0), AttachTarget::Point(Vector3::zeros()))?;
    }
    let settings = SystemSettings {
        gravity: g,
        ..SystemSettings::default()
    };
    // Bilateral rows only: CG solves the (3-row) problem exactly.
    let solver = Cg::new(SolverSettings {
        tolerance: 1e-12,
        max_iterations: 100,
        record_history: false,
    });
    let mut sys = System::new(settings, Box::new(solver))?;
    let idx = sys.add_item(Box::new(item));
    let energy = |sys: &System| -> (f64, f64, f64) {
        let it = sys.item::<CableItem>(idx).expect("the pendulum item");
        (
            it.kinetic_energy(),
            it.strain_energy(),
            it.gravity_potential(&g),
        )
    };
    let (t0, u0, v0) = energy(&sys);
    let e0 = t0 + u0 + v0;
    let n = (p.t_end / h).round().max(1.0) as u64;
    let every = ((0.01 / h).round() as u64).max(1);
    let start = std::time::Instant::now();
    let (mut drift_max, mut drift_end, mut tip_min_z, mut max_pin_gap) =
        (0.0f64, 0.0, 0.0f64, 0.0f64);
    for s in 1..=n {
        sys.step(h)?;
        let (t, u, v) = energy(&sys);
        let d = (t + u + v - e0) / scale;
        drift_max = drift_max.max(d.abs());
        drift_end = d;
        let it = sys.item::<CableItem>(idx).expect("the pendulum item");
        let nodes = it.mesh().nodes();
        tip_min_z = tip_min_z.min(nodes[p.n_elements].position.z);
        max_pin_gap = max_pin_gap.max(nodes[0].position.norm());
        if s % every == 0 {
            if let Some(out) = series.as_deref_mut() {
                out.push(&[s as f64 * h, t / scale, u / scale, v / scale, d]);
            }
            if let Some(c) = ctx {
                c.progress(0.5 * s as f64 / n as f64);
            }
        }
    }
    Ok(Run {
        drift_max,
        drift_end,
        steps: n,
        wall_s: start.elapsed().as_secs_f64().max(1e-9),
        tip_min_z,
        max_pin_gap,
    })
}

fn run(p: &PendulumParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    check_cable_only(p.element)?;
    let mut out = CaseOutput::new();
    let mut series = Series::new(["t", "kinetic", "strain", "potential", "drift"]);
    let main = simulate(p, p.h, Some(&mut series), Some(ctx))?;
    out.check(Check::below(
        "energy_drift_max",
        main.drift_max,
        p.tolerance,
    ));
    out.metric("energy_drift_end", main.drift_end);
    out.metric("tip_min_z", main.tip_min_z);
    out.metric("pin_gap_max", main.max_pin_gap);
    out.metric("wall_per_step_us", 1e6 * main.wall_s / main.steps as f64);
    let mut sweep = Vec::new();
    for (i, &h) in p.h_sweep.iter().enumerate() {
        let r = simulate(p, h, None, None)?;
        out.metric(format!("energy_drift_max_h{h:e}"), r.drift_max);
        out.metric(format!("energy_drift_end_h{h:e}"), r.drift_end);
        out.sweep.push(SweepPoint {
            label: format!("h = {h:e} s"),
            error: r.drift_max,
            wall_s: r.wall_s,
        });
        sweep.push((h, r.drift_max));
        ctx.progress(0.5 + 0.5 * (i + 1) as f64 / p.h_sweep.len() as f64);
    }
    sweep.sort_by(|a, b| a.0.total_cmp(&b.0));
    if sweep.len() >= 2 {
        let ((h1, d1), (h2, d2)) = (sweep[0], sweep[1]);
        // First order in h: the drift ratio of the two smallest steps is (h1 / h2)^order;
        // it must not exceed (h1 / h2)^min_order.
        out.metric("drift_order", (d2 / d1).ln() / (h2 / h1).ln());
        out.check(Check::below(
            "drift_ratio_smallest_steps",
            d1 / d2,
            (h1 / h2).powf(p.min_order),
        ));
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "ANCF flexible pendulum: energies / (m g L / 2)",
        "t [s]",
        "energy / (m g L / 2) [-]",
        &["kinetic", "strain", "potential", "drift"],
    );
    out.steps = main.steps;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<PendulumParams>::boxed(
        "fea-pendulum",
        "fea",
        "Undamped flexible ANCF pendulum pinned by CCP rows, released horizontally: energy drift over t_end against a few percent of m g L/2, and its first-order decrease with h (implicit Euler's numerical damping).",
        run,
    )
}
