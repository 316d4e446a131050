//! `fea-cantilever`: an ANCF cantilever under a dead tip force normal to its axis.
//!
//! A straight beam of length `L` along +X, clamped at `x = 0`, a vertical (-Z) tip force
//! `P` given by the load parameter `alpha = P L^2 / (E I)`. The loads of the list are
//! applied in ascending order, each from the previous equilibrium in `load_steps` equal
//! increments of the force, one Newton solve each. The density does not enter (statics). References:
//! - small loads (`alpha < 0.1`): Euler–Bernoulli `v = P L^3 / (3 E I)`, within 1 %;
//! - every load: the inextensible elastica, `v / L` and `u / L` from
//!   [`elastica_tip_load`] (shooting; checked against Mattiasson 1981 in chrono-fea's
//!   tests), within 2 % for `alpha >= 1` (the acceptance). For `alpha < 1` the
//!   axial displacement is of second order (`u / L ~ -alpha^2 / 15`) and checked in
//!   absolute terms, to 1 % of the tip deflection.
//!
//! The elastica is inextensible; the finite element is not: the default slenderness
//! `L / h = 100` makes the axial strain `P / (E A) <= alpha h^2 / (12 L^2) ~ 1e-4`.
//!
//! `element`: `cable` (the gradient-deficient ANCF cable, default) or `beam` (the fully
//! parameterized ANCF beam with shear and torsion, `nu = 0`, clamped in all 12
//! coordinates).

use chrono_core::math::Vector3;
use chrono_fea::analytic::{cantilever_tip_deflection, elastica_tip_load};
use chrono_fea::{NodeId, StaticModel, StaticSettings, solve_static};
use serde::{Deserialize, Serialize};

use super::Element;
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};
use chrono_fea::{beam_cantilever, cable_cantilever};

/// Parameters of `fea-cantilever`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CantileverParams {
    /// Number of elements.
    pub n_elements: usize,
    /// Beam length, m.
    pub length: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Section width, m.
    pub width: f64,
    /// Section height (the bending direction), m.
    pub height: f64,
    /// Load parameters `P L^2 / (E I)`, ascending.
    pub load: Vec<f64>,
    /// Element type: `cable` (gradient-deficient ANCF) or `beam` (fully parameterized).
    pub element: Element,
    /// Newton load increments from one load of the list to the next.
    pub load_steps: usize,
    /// Relative tolerance against Euler–Bernoulli at small loads.
    pub tolerance_small: f64,
    /// Relative tolerance against the elastica for `alpha >= 1`.
    pub tolerance_large: f64,
}

impl Default for CantileverParams {
    fn default() -> Self {
        Self {
            n_elements: 8,
            length: 1.0,
            young: 2.0e11,
            width: 0.01,
            height: 0.01,
            load: vec![0.01, 1.0, 2.0, 3.0, 4.0, 5.0, 7.5, 10.0],
            element: Element::Cable,
            load_steps: 4,
            tolerance_small: 0.01,
            tolerance_large: 0.02,
        }
    }
}

impl CaseParams for CantileverParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n_elements", "-", "number of elements"),
        ParamInfo::new("length", "m", "beam length"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("width", "m", "section width"),
        ParamInfo::new("height", "m", "section height (bending direction)"),
        ParamInfo::new("load", "-", "load parameters P L^2 / (E I), ascending"),
        ParamInfo::new("element", "-", "element type: cable or beam"),
        ParamInfo::new("load_steps", "-", "Newton load increments between loads"),
        ParamInfo::new(
            "tolerance_small",
            "-",
            "relative tolerance vs Euler-Bernoulli (alpha < 0.1)",
        ),
        ParamInfo::new(
            "tolerance_large",
            "-",
            "relative tolerance vs the elastica (alpha >= 1)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        // Full: a finer mesh as well; the default is already the setup.
        if mode == Mode::Full {
            self.n_elements = 32;
        }
    }
}

/// Tip displacements `(v / L, u / L)` for each load of `p.load`, and Newton iterations.
fn solve(p: &CantileverParams, n_elements: usize) -> anyhow::Result<(Vec<(f64, f64)>, usize)> {
    let ei = p.young * p.width * p.height.powi(3) / 12.0;
    let tip = NodeId(n_elements);
    if p.element == Element::Beam {
        let mut mesh = beam_cantilever(n_elements, p.length, p.young, 1000.0, p.width, p.height)?;
        load_path(
            p,
            ei,
            &mut mesh,
            |m, f| m.set_force(tip, f),
            |m| m.node(tip).map(|n| n.displacement()),
        )
    } else {
        let mut mesh = cable_cantilever(n_elements, p.length, p.young, 1000.0, p.width, p.height)?;
        load_path(
            p,
            ei,
            &mut mesh,
            |m, f| m.set_force(tip, f),
            |m| m.node(tip).map(|n| n.displacement()),
        )
    }
}

/// Walk the loads of `p.load` on `mesh` (`set_tip` applies the tip force, `tip` reads
/// the tip displacement).
fn load_path<M: StaticModel>(
    p: &CantileverParams,
    ei: f64,
    mesh: &mut M,
    set_tip: impl Fn(&mut M, Vector3<f64>) -> chrono_fea::Result<()>,
    tip: impl Fn(&M) -> chrono_fea::Result<Vector3<f64>>,
) -> anyhow::Result<(Vec<(f64, f64)>, usize)> {
    // One Newton solve per increment: the load factor of each solve is 1 (the full
    // current force), the increments walk from the previous load of the list to the next.
    let settings = StaticSettings {
        load_steps: 1,
        ..StaticSettings::default()
    };
    let mut out = Vec::with_capacity(p.load.len());
    let mut iterations = 0;
    let mut previous = 0.0;
    for &alpha in &p.load {
        for k in 1..=p.load_steps {
            let a = previous + (alpha - previous) * k as f64 / p.load_steps as f64;
            let force = a * ei / (p.length * p.length);
            set_tip(mesh, Vector3::new(0.0, 0.0, -force))?;
            let report = solve_static(mesh, &settings)
                .map_err(|e| anyhow::anyhow!("load parameter {a} (towards {alpha}): {e}"))?;
            iterations += report.total_iterations();
        }
        previous = alpha;
        let d = tip(mesh)?;
        out.push((-d.z / p.length, d.x / p.length));
    }
    Ok((out, iterations))
}

fn run(p: &CantileverParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(!p.load.is_empty(), "parameter `load` must not be empty");
    for (i, &a) in p.load.iter().enumerate() {
        anyhow::ensure!(
            a.is_finite() && a > 0.0 && a <= 10.0,
            "parameter `load[{i}]` must be in (0, 10] (the elastica reference), got {a}"
        );
        anyhow::ensure!(
            i == 0 || a > p.load[i - 1],
            "parameter `load` must be ascending, got {} after {}",
            a,
            p.load[i - 1]
        );
    }
    anyhow::ensure!(
        p.load_steps >= 1,
        "parameter `load_steps` must be >= 1, got {}",
        p.load_steps
    );
    let (tips, iterations) = solve(p, p.n_elements)?;
    let ei = p.young * p.width * p.height.powi(3) / 12.0;
    let mut out = CaseOutput::new();
    let mut series = Series::new([
        "load_parameter",
        "v_over_L",
        "u_over_L",
        "v_elastica",
        "u_elastica",
    ]);
    for (&alpha, &(v, u)) in p.load.iter().zip(&tips) {
        let r = elastica_tip_load(alpha)?;
        series.push(&[alpha, v, u, r.deflection, r.axial]);
        let (v_m, u_m) = (v * p.length, u * p.length);
        if alpha < 0.1 {
            let eb = cantilever_tip_deflection(alpha * ei / p.length.powi(2), p.length, ei);
            out.check(Check::relative(
                format!("tip_deflection_{alpha}"),
                v_m,
                eb,
                p.tolerance_small,
            ));
        } else {
            out.check(Check::relative(
                format!("tip_deflection_{alpha}"),
                v_m,
                r.deflection * p.length,
                p.tolerance_large,
            ));
        }
        if alpha < 1.0 {
            out.check(Check::absolute(
                format!("tip_axial_{alpha}"),
                u_m,
                r.axial * p.length,
                0.01 * r.deflection * p.length,
            ));
        } else {
            out.check(Check::relative(
                format!("tip_axial_{alpha}"),
                u_m,
                r.axial * p.length,
                p.tolerance_large,
            ));
        }
        out.metric(
            format!("elastica_deflection_{alpha}"),
            r.deflection * p.length,
        );
        out.metric(format!("elastica_axial_{alpha}"), r.axial * p.length);
    }
    ctx.progress(0.5);
    // Mesh convergence at the largest load: relative error of the tip deflection.
    let top = *p.load.last().unwrap_or(&1.0);
    let r_top = elastica_tip_load(top)?;
    let meshes: &[usize] = if ctx.mode == Mode::Quick {
        &[2, 4, 8]
    } else {
        &[2, 4, 8, 16, 32]
    };
    for (i, &n) in meshes.iter().enumerate() {
        let start = std::time::Instant::now();
        let (t, _) = solve(p, n)?;
        let (v, _) = t[t.len() - 1];
        out.sweep.push(SweepPoint {
            label: format!("{n} elements"),
            error: (v / r_top.deflection - 1.0).abs(),
            wall_s: start.elapsed().as_secs_f64().max(1e-9),
        });
        ctx.progress(0.5 + 0.5 * (i + 1) as f64 / meshes.len() as f64);
    }
    let mut reference = Series::new(["load_parameter", "v_elastica", "u_elastica"]);
    for k in 0..=40 {
        let alpha = top * k as f64 / 40.0;
        let r = elastica_tip_load(alpha)?;
        reference.push(&[alpha, r.deflection, r.axial]);
    }
    out.metric("newton_iterations", iterations as f64);
    out.series = series;
    out.reference_series = Some(reference);
    out.plot = PlotSpec::new(
        "ANCF cantilever, tip force: tip displacement / L",
        "P L^2 / (E I) [-]",
        "tip displacement / L [-]",
        &["v_over_L", "u_over_L"],
    )
    .with_reference(&["v_elastica", "u_elastica"]);
    out.steps = iterations as u64;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<CantileverParams>::boxed(
        "fea-cantilever",
        "fea",
        "ANCF cable (or beam: element=beam) cantilever under a dead tip force, P L^2/(E I) from 0.01 to 10: tip deflection against Euler-Bernoulli (small load, 1 %) and the elastica (2 %).",
        run,
    )
}
