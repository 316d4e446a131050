//! `fea-shell-cantilever`: the cantilever plate strip under end shear of Sze, Liu & Lo
//! (2004), test 3.1, with the ANCF shell (Yamashita et al. 2015).
//!
//! Sze, K. Y., Liu, X. H., Lo, S. H. (2004), "Popular benchmark problems for geometric
//! nonlinear analysis of shells", Finite Elem. Anal. Des. 40: 1551–1569. A plate strip
//! `L = 10`, width `b = 1`, thickness `h = 0.1`, `E = 1.2e6`, `nu = 0`, clamped at
//! `x = 0` (positions and directors of the root nodes held), a vertical (+Z, dead) shear
//! force `P` at the free end, split equally over the tip nodes (the consistent load of a
//! uniform edge load on the bilinear element), up to `P_max = 4`. The reference is the
//! tabulated load–displacement curve of the paper (S4R 16 x 1),
//! `data/reference/shell_sze2004_3-1_cantilever_end_shear.csv`: tip vertical
//! `w` and tip horizontal `-u` against `P / P_max` at 20 load points.
//!
//! The loads of the reference are applied in ascending order, each from the previous
//! equilibrium in `load_steps` increments, one Newton solve each. Metrics: `w` and `-u`
//! (mean of the tip nodes) at `P_max` and their largest relative error over the
//! published points with a reference value `>= 0.1` (smaller values, the first points
//! of `-u`, are given to 3 decimals only: their rounding alone is up to 2 %).
//! Acceptance: 5 %, in every mode (the quick mode uses 8 elements, which still pass).

use chrono_core::math::Vector3;
use chrono_fea::{NodeId, ShellMaterial, ShellMesh, StaticSettings, solve_static};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// The reference data file.
pub const REFERENCE: &str = "shell_sze2004_3-1_cantilever_end_shear.csv";

/// Parameters of `fea-shell-cantilever`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShellCantileverParams {
    /// Elements along the length.
    pub n_elements: usize,
    /// Elements across the width.
    pub n_width: usize,
    /// Length, m.
    pub length: f64,
    /// Width, m.
    pub width: f64,
    /// Thickness, m.
    pub thickness: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Largest end shear (total), N.
    pub p_max: f64,
    /// Fraction of the reference load points applied (1: up to `P_max`).
    pub load: f64,
    /// Newton solves (load increments) per reference load interval.
    pub load_steps: usize,
    /// Locking remedies: `ans+eas` (default), `ans`, `eas` or `none`.
    pub locking: super::Locking,
    /// Relative tolerance against the reference.
    pub tolerance: f64,
}

impl Default for ShellCantileverParams {
    fn default() -> Self {
        Self {
            n_elements: 16,
            n_width: 1,
            length: 10.0,
            width: 1.0,
            thickness: 0.1,
            young: 1.2e6,
            poisson: 0.0,
            p_max: 4.0,
            load: 1.0,
            load_steps: 1,
            locking: super::Locking::AnsEas,
            tolerance: 0.05,
        }
    }
}

impl CaseParams for ShellCantileverParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("n_elements", "-", "elements along the length"),
        ParamInfo::new("n_width", "-", "elements across the width"),
        ParamInfo::new("length", "m", "plate length"),
        ParamInfo::new("width", "m", "plate width"),
        ParamInfo::new("thickness", "m", "plate thickness"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("poisson", "-", "Poisson's ratio"),
        ParamInfo::new("p_max", "N", "largest end shear force (total)"),
        ParamInfo::new(
            "load",
            "-",
            "fraction of the load curve applied (last load point P / P_max)",
        ),
        ParamInfo::new(
            "load_steps",
            "-",
            "Newton solves per reference load interval",
        ),
        ParamInfo::new(
            "locking",
            "-",
            "locking remedies: ans+eas, ans, eas or none (the last two lock)",
        ),
        ParamInfo::new("tolerance", "-", "relative tolerance against the reference"),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.n_elements = 8,
            Mode::Full => self.n_elements = 32,
            Mode::Default => {}
        }
    }
}

fn run(p: &ShellCantileverParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.n_elements >= 1 && p.n_width >= 1,
        "parameters `n_elements` and `n_width` must be >= 1, got {} and {}",
        p.n_elements,
        p.n_width
    );
    anyhow::ensure!(
        p.load_steps >= 1,
        "parameter `load_steps` must be >= 1, got {}",
        p.load_steps
    );
    anyhow::ensure!(
        p.load.is_finite() && p.load > 0.0 && p.load <= 1.0,
        "parameter `load` must be in (0, 1], got {}",
        p.load
    );
    anyhow::ensure!(
        p.p_max.is_finite() && p.p_max > 0.0,
        "parameter `p_max` must be > 0, got {}",
        p.p_max
    );
    let reference = crate::reference::csv(REFERENCE)?;
    let material = ShellMaterial::isotropic(p.young, p.poisson, 1.0)?;
    let (nx, ny) = (p.n_elements, p.n_width);
    let mut mesh = ShellMesh::plate(p.length, p.width, nx, ny, p.thickness, material)?;
    mesh.set_locking(p.locking.remedies())?;
    let tip: Vec<NodeId> = (0..=ny).map(|j| ShellMesh::grid_node(nx, nx, j)).collect();
    for j in 0..=ny {
        mesh.fix_node(ShellMesh::grid_node(nx, 0, j))?;
    }
    let settings = StaticSettings {
        load_steps: 1,
        ..StaticSettings::default()
    };
    let mut series = Series::new([
        "load_fraction",
        "w_tip",
        "minus_u_tip",
        "w_ref",
        "minus_u_ref",
    ]);
    series.push(&[0.0, 0.0, 0.0, 0.0, 0.0]);
    let (mut err_w, mut err_u): (f64, f64) = (0.0, 0.0);
    let (mut w, mut u) = (0.0, 0.0);
    let mut iterations = Vec::new();
    let mut previous = 0.0;
    let points: Vec<&Vec<f64>> = reference
        .iter()
        .filter(|r| r[0] > 0.0 && r[0] <= p.load + 1e-12)
        .collect();
    anyhow::ensure!(
        !points.is_empty(),
        "no reference load point up to `load` = {}",
        p.load
    );
    for (k, row) in points.iter().enumerate() {
        let (frac, u_ref, w_ref) = (row[0], row[1], row[2]);
        for s in 1..=p.load_steps {
            let f = previous + (frac - previous) * s as f64 / p.load_steps as f64;
            // Consistent nodal loads of a uniform edge load: 1/2 at the corners.
            for (j, n) in tip.iter().enumerate() {
                let share = if j == 0 || j == ny { 0.5 } else { 1.0 } / ny as f64;
                mesh.set_force(*n, Vector3::new(0.0, 0.0, f * p.p_max * share))?;
            }
            let report = solve_static(&mut mesh, &settings)
                .map_err(|e| anyhow::anyhow!("P / P_max = {f:.4}: {e}"))?;
            iterations.push(report.total_iterations());
        }
        previous = frac;
        let d: Vector3<f64> = tip
            .iter()
            .map(|n| mesh.node(*n).map(|x| x.displacement()))
            .sum::<Result<Vector3<f64>, _>>()?
            / tip.len() as f64;
        (w, u) = (d.z, -d.x);
        if w_ref >= 0.1 {
            err_w = err_w.max((w / w_ref - 1.0).abs());
        }
        if u_ref >= 0.1 {
            err_u = err_u.max((u / u_ref - 1.0).abs());
        }
        series.push(&[frac, w, u, w_ref, u_ref]);
        ctx.progress_steps(k as u64 + 1, points.len() as u64);
    }
    let last = points[points.len() - 1];
    let mut out = CaseOutput::new();
    out.check(Check::relative("w_tip", w, last[2], p.tolerance));
    out.check(Check::relative("minus_u_tip", u, last[1], p.tolerance));
    out.check(Check::below("max_error_w", err_w, p.tolerance));
    out.check(Check::below("max_error_u", err_u, p.tolerance));
    out.metric("load_fraction", last[0]);
    out.metric("elements", mesh.elements().len() as f64);
    out.metric("free_dof", mesh.dof_map().nfree() as f64);
    out.metric("newton_iterations", iterations.iter().sum::<usize>() as f64);
    out.metric(
        "max_newton_iterations_per_solve",
        iterations.iter().copied().max().unwrap_or(0) as f64,
    );
    out.series = series;
    out.plot = PlotSpec::new(
        "ANCF shell cantilever under end shear (Sze et al. 2004, test 3.1)",
        "P / P_max [-]",
        "tip displacement [m]",
        &["w_tip", "minus_u_tip", "w_ref", "minus_u_ref"],
    );
    out.steps = iterations.len() as u64;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<ShellCantileverParams>::boxed(
        "fea-shell-cantilever",
        "fea",
        "ANCF 4-node shell (ANS + EAS) cantilever plate strip under end shear (Sze, Liu & Lo 2004, test 3.1): tip w and -u along the load path within 5 % of the published curve.",
        run,
    )
}
