//! `fea-bend-45`: the 45-degree bend of Bathe & Bolourchi (1979), a curved cantilever
//! under an out-of-plane dead tip load, with the fully parameterized ANCF beam.
//!
//! Bathe, K.-J., Bolourchi, S. (1979), "Large displacement analysis of three-dimensional
//! beam structures", Int. J. Numer. Meth. Eng. 14: 961–986. An eighth of a circle of
//! radius `R = 100` in the horizontal plane, square section `1 x 1`, `E = 1e7`, `nu = 0`
//! (`G = E / 2`), clamped at one end, a vertical dead force `P` at the other. Frame (the
//! one of the published tables): the clamp at the origin with the tangent along +X, the
//! arc bending towards +Y (centre `(0, R, 0)`), the tip at
//! `(R sin 45°, R (1 - cos 45°), 0) = (70.711, 29.289, 0)`, the load along +Z.
//!
//! Reference: the tip positions of Simo & Vu-Quoc (1986, "A three-dimensional
//! finite-strain rod model. Part II: computational aspects", Comput. Methods Appl. Mech.
//! Eng. 58: 79–116), 8 elements: `P = 300: (58.84, 22.33, 40.08)`,
//! `450: (52.32, 18.62, 48.39)`, `600: (47.23, 15.79, 53.37)` (Bathe & Bolourchi give
//! `(47.2, 15.9, 53.4)` at 600). Loads are applied in ascending order, each from the
//! previous equilibrium in `load_steps` increments (one Newton solve each).
//!
//! Metrics at each load: the tip position and displacement, the relative error of each
//! displacement component against the reference displacement (reference position minus
//! the initial tip), and the vector error `|u - u_ref| / |u_ref|`. Checks (the issue's
//! acceptance, 3 %): every displacement component and the vector error. A refinement
//! study (`refine`) solves to the largest load with other meshes (sweep points: the
//! vector error).
//!
//! Section: the stiffnesses of the published problem, `E A = 1e7`, `k G A = 4.1667e6`
//! (`k = 5/6`), `E I = 8.333e5` in both planes and `G J = 8.333e5`, i.e. `J = 1/6`, the
//! polar moment `I_y + I_z` (as listed for this problem in the BeamDyn verification of
//! Wang, Sprague, Jonkman & Johnson 2015, NREL/CP-5000-63165, and used by GXBeam's
//! example), not the St. Venant value of the square `0.1406` (`torsion` sets it: the
//! converged tip then moves by up to 3 % of the small `u_y`, see docs/validation-fea.md).

use chrono_core::math::Vector3;
use chrono_fea::{BeamMesh, BeamQuadrature, BeamSection, NodeId, StaticSettings, solve_static};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Radius of the bend.
pub const RADIUS: f64 = 100.0;
/// Young's modulus.
pub const YOUNG: f64 = 1e7;

/// The reference tip positions (Simo & Vu-Quoc 1986, 8 elements) at the published loads.
pub const REFERENCE: [(f64, [f64; 3]); 3] = [
    (300.0, [58.84, 22.33, 40.08]),
    (450.0, [52.32, 18.62, 48.39]),
    (600.0, [47.23, 15.79, 53.37]),
];

/// Parameters of `fea-bend-45`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Bend45Params {
    /// Number of elements.
    pub n_elements: usize,
    /// Tip loads, ascending, each one of the published levels 300, 450, 600.
    pub load: Vec<f64>,
    /// Newton load increments from one load of the list to the next.
    pub load_steps: usize,
    /// Torsion constant `J` (1/6, the published problem's `G J = 8.333e5`).
    pub torsion: f64,
    /// Shear correction factor `k`.
    pub shear_factor: f64,
    /// Sampling of the shear and cross-section strains: 0 at the nodes (the element's
    /// default), 1..=5 Gauss points (to show the locking the nodes avoid).
    pub shear_points: usize,
    /// Meshes of the refinement study at the largest load (empty: none).
    pub refine: Vec<usize>,
    /// Relative tolerance against the reference.
    pub tolerance: f64,
}

impl Default for Bend45Params {
    fn default() -> Self {
        Self {
            n_elements: 8,
            load: vec![300.0, 450.0, 600.0],
            load_steps: 10,
            torsion: 1.0 / 6.0,
            shear_factor: 5.0 / 6.0,
            shear_points: 0,
            refine: vec![4, 8, 16],
            tolerance: 0.03,
        }
    }
}

impl CaseParams for Bend45Params {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n_elements", "-", "number of elements"),
        ParamInfo::new("load", "N", "tip loads, ascending, of 300, 450, 600"),
        ParamInfo::new("load_steps", "-", "Newton load increments between loads"),
        ParamInfo::new(
            "torsion",
            "m^4",
            "torsion constant J (1/6 as published; 0.1406: St. Venant)",
        ),
        ParamInfo::new("shear_factor", "-", "shear correction factor k"),
        ParamInfo::new(
            "shear_points",
            "-",
            "shear/section strain sampling: 0 nodes (default), 1..=5 Gauss points",
        ),
        ParamInfo::new(
            "refine",
            "-",
            "meshes of the refinement study (largest load)",
        ),
        ParamInfo::new("tolerance", "-", "relative tolerance against the reference"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.load_steps = 5;
                self.refine = vec![4];
            }
            Mode::Full => self.refine = vec![4, 8, 16, 32],
            Mode::Default => {}
        }
    }
}

/// The initial tip position.
pub fn initial_tip() -> Vector3<f64> {
    let phi = std::f64::consts::FRAC_PI_4;
    Vector3::new(RADIUS * phi.sin(), RADIUS * (1.0 - phi.cos()), 0.0)
}

/// Tip positions at each load of `p.load` with `n` elements, and Newton iterations.
fn solve(p: &Bend45Params, n: usize) -> anyhow::Result<(Vec<Vector3<f64>>, usize)> {
    let section = BeamSection::rectangle(YOUNG, 0.0, 1.0, 1.0, 1.0)?
        .with_torsion(p.torsion)?
        .with_shear_factor(p.shear_factor)?;
    let mut mesh = BeamMesh::arc(
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        RADIUS,
        std::f64::consts::FRAC_PI_4,
        n,
        section,
    )?;
    mesh.set_quadrature(BeamQuadrature {
        shear: p.shear_points,
        ..BeamQuadrature::default()
    })?;
    mesh.clamp(NodeId(0))?;
    let tip = NodeId(n);
    let settings = StaticSettings {
        load_steps: 1,
        ..StaticSettings::default()
    };
    let mut out = Vec::with_capacity(p.load.len());
    let mut iterations = 0;
    let mut previous = 0.0;
    for &load in &p.load {
        for k in 1..=p.load_steps {
            let f = previous + (load - previous) * k as f64 / p.load_steps as f64;
            mesh.set_force(tip, Vector3::new(0.0, 0.0, f))?;
            let report = solve_static(&mut mesh, &settings)
                .map_err(|e| anyhow::anyhow!("{n} elements, P = {f} (towards {load}): {e}"))?;
            iterations += report.total_iterations();
        }
        previous = load;
        out.push(mesh.node(tip)?.position);
    }
    Ok((out, iterations))
}

fn reference(load: f64) -> Option<Vector3<f64>> {
    REFERENCE
        .iter()
        .find(|(p, _)| *p == load)
        .map(|(_, x)| Vector3::from(*x))
}

fn run(p: &Bend45Params, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.n_elements >= 1,
        "parameter `n_elements` must be >= 1, got {}",
        p.n_elements
    );
    anyhow::ensure!(
        p.load_steps >= 1,
        "parameter `load_steps` must be >= 1, got {}",
        p.load_steps
    );
    anyhow::ensure!(!p.load.is_empty(), "parameter `load` must not be empty");
    for (i, &load) in p.load.iter().enumerate() {
        anyhow::ensure!(
            reference(load).is_some(),
            "parameter `load[{i}]` must be one of the published levels 300, 450, 600, got {load}"
        );
        anyhow::ensure!(
            i == 0 || load > p.load[i - 1],
            "parameter `load` must be ascending, got {load} after {}",
            p.load[i - 1]
        );
    }
    for (i, &n) in p.refine.iter().enumerate() {
        anyhow::ensure!(n >= 1, "parameter `refine[{i}]` must be >= 1, got {n}");
    }
    anyhow::ensure!(
        p.tolerance.is_finite() && p.tolerance > 0.0,
        "parameter `tolerance` must be > 0, got {}",
        p.tolerance
    );
    let x0 = initial_tip();
    let (tips, iterations) = solve(p, p.n_elements)?;
    let mut out = CaseOutput::new();
    let mut series = Series::new(["load", "x", "y", "z", "x_ref", "y_ref", "z_ref"]);
    series.push(&[0.0, x0.x, x0.y, x0.z, x0.x, x0.y, x0.z]);
    for (&load, tip) in p.load.iter().zip(&tips) {
        let r = reference(load).expect("checked");
        let (u, u_ref) = (tip - x0, r - x0);
        let tag = format!("{load:.0}");
        for (c, name) in ["x", "y", "z"].iter().enumerate() {
            out.metric(format!("tip_{name}_{tag}"), tip[c]);
            out.metric(format!("tip_{name}_ref_{tag}"), r[c]);
            out.metric(
                format!("error_u{name}_{tag}"),
                (u[c] / u_ref[c] - 1.0).abs(),
            );
            out.check(Check::relative(
                format!("u{name}_{tag}"),
                u[c],
                u_ref[c],
                p.tolerance,
            ));
        }
        out.check(Check::below(
            format!("error_vector_{tag}"),
            (u - u_ref).norm() / u_ref.norm(),
            p.tolerance,
        ));
        series.push(&[load, tip.x, tip.y, tip.z, r.x, r.y, r.z]);
    }
    ctx.progress(0.5);
    let top = *p.load.last().expect("non-empty");
    let r_top = reference(top).expect("checked") - x0;
    for (i, &n) in p.refine.iter().enumerate() {
        let start = std::time::Instant::now();
        let (t, _) = solve(p, n)?;
        let u = t[t.len() - 1] - x0;
        out.metric(format!("refine_{n}_tip_x"), t[t.len() - 1].x);
        out.metric(format!("refine_{n}_tip_y"), t[t.len() - 1].y);
        out.metric(format!("refine_{n}_tip_z"), t[t.len() - 1].z);
        out.sweep.push(SweepPoint {
            label: format!("{n} elements"),
            error: (u - r_top).norm() / r_top.norm(),
            wall_s: start.elapsed().as_secs_f64().max(1e-9),
        });
        ctx.progress(0.5 + 0.5 * (i + 1) as f64 / p.refine.len() as f64);
    }
    out.metric("elements", p.n_elements as f64);
    out.metric("newton_iterations", iterations as f64);
    out.series = series;
    out.plot = PlotSpec::new(
        "45-degree bend (Bathe & Bolourchi 1979), ANCF beam: tip position",
        "tip load P [-]",
        "tip position [-]",
        &["x", "y", "z"],
    )
    .with_reference(&["x_ref", "y_ref", "z_ref"]);
    out.steps = iterations as u64;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<Bend45Params>::boxed(
        "fea-bend-45",
        "fea",
        "45-degree bend (Bathe & Bolourchi 1979) with the fully parameterized ANCF beam: tip displacements at P = 300, 450, 600 within 3 % of Simo & Vu-Quoc (1986).",
        run,
    )
}
