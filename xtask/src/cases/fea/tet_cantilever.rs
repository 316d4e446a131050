//! `fea-tet-cantilever`: a box cantilever of linear tetrahedra under a tip shear load.
//!
//! A steel bar `length x width x height` along +X, the face `x = 0` clamped (all nodes
//! fixed), a uniform shear traction on the face `x = length` adding up to the tip force
//! `P` along -Z (`P` small: `v / L ~ 2e-4`, so the St. Venant–Kirchhoff solution is the
//! linear one to ~1e-8). Meshed with `n` cells through the height and width and
//! `n round(length / height)` along the length, each cell split into tetrahedra
//! (`split`), for each `n` of `refinements`.
//!
//! Metric: the tip deflection, the mean of `-u_z` over the tip face nodes, against the
//! Timoshenko beam `v = P L^3 / (3 E I) + P L / (k G A)` with Cowper's shear coefficient
//! of a rectangle `k = 10 (1 + nu) / (12 + 11 nu)` (0.85 at `nu = 0.3`; the shear term is
//! 0.77 % of the deflection for `L / h = 10`). The Euler–Bernoulli value
//! `P L^3 / (3 E I)` is reported too. The 3D solution also differs from the beam by the
//! clamp (the fully fixed face restrains the Poisson contraction: a local effect of
//! relative size ~`(h / L)^2`).
//!
//! Linear (constant-strain) tetrahedra lock in bending: a bent element must also shear,
//! so coarse meshes are much too stiff. The error falls under refinement towards the
//! asymptotic second order of the displacement. The checks: the error falls at every
//! refinement (`max_error_ratio < 1`), the observed order between the two finest meshes
//! is within `order_tolerance` of the asymptotic order 2, and the Richardson
//! extrapolation of the three finest meshes (with the order they show) is within
//! `tolerance` (2 %) of the Timoshenko value: the 3D solution is not the beam's (clamp,
//! shear distribution), and a pre-asymptotic extrapolation carries an error of its own;
//! the measured figures are in `docs/validation-fea.md`.

use chrono_core::math::Vector3;
use chrono_fea::analytic::{
    cantilever_tip_deflection, rectangle_shear_coefficient, timoshenko_tip_deflection,
};
use chrono_fea::{BoxMesh, SolidMaterial, StaticSettings, solve_static};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `fea-tet-cantilever`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TetCantileverParams {
    /// Cells through the height (and width) of each mesh, ascending (>= 3 meshes).
    pub refinements: Vec<usize>,
    /// Bar length, m.
    pub length: f64,
    /// Section width (Y), m.
    pub width: f64,
    /// Section height (Z, the load direction), m.
    pub height: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Tip force along -Z, N.
    pub force: f64,
    /// Hexahedron split: `six` or `five`.
    pub split: chrono_fea::HexSplit,
    /// Material model: `svk` (St. Venant–Kirchhoff) or `corotational`.
    pub model: chrono_fea::SolidModel,
    /// Accepted distance of the observed order (two finest meshes) from 2.
    pub order_tolerance: f64,
    /// Relative tolerance of the extrapolated tip deflection against Timoshenko.
    pub tolerance: f64,
}

impl Default for TetCantileverParams {
    fn default() -> Self {
        Self {
            refinements: vec![1, 2, 4, 6, 8, 10],
            length: 1.0,
            width: 0.1,
            height: 0.1,
            young: 2.0e11,
            poisson: 0.3,
            force: 1.0e3,
            split: chrono_fea::HexSplit::Six,
            model: chrono_fea::SolidModel::StVenantKirchhoff,
            order_tolerance: 1.0,
            tolerance: 0.02,
        }
    }
}

impl CaseParams for TetCantileverParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "refinements",
            "-",
            "cells through the height of each mesh, ascending (>= 3 meshes)",
        ),
        ParamInfo::new("length", "m", "bar length"),
        ParamInfo::new("width", "m", "section width (Y)"),
        ParamInfo::new("height", "m", "section height (Z, load direction)"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("poisson", "-", "Poisson's ratio"),
        ParamInfo::new("force", "N", "tip force along -Z"),
        ParamInfo::new("split", "-", "hexahedron split: six or five tetrahedra"),
        ParamInfo::new("model", "-", "material model: svk or corotational"),
        ParamInfo::new(
            "order_tolerance",
            "-",
            "accepted distance of the observed order (two finest meshes) from 2",
        ),
        ParamInfo::new(
            "tolerance",
            "-",
            "relative tolerance of the extrapolated deflection vs Timoshenko",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.refinements = vec![1, 2, 4, 6, 8],
            Mode::Default => {}
            Mode::Full => self.refinements = vec![1, 2, 4, 6, 8, 10, 12],
        }
    }
}

/// One mesh: tip deflection (m), elements, free dof, Newton iterations.
struct Solution {
    tip: f64,
    elements: usize,
    free_dof: usize,
    iterations: usize,
}

fn solve(
    p: &TetCantileverParams,
    n: usize,
    ctx: &RunContext,
    last: bool,
) -> anyhow::Result<Solution> {
    let split = p.split;
    let along = ((p.length / p.height).round() as usize).max(1) * n;
    let b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(p.length, p.width, p.height),
        [along, n, n],
        split,
    )?;
    let material = SolidMaterial::new(p.young, p.poisson, 7850.0, 0.0)?.with_model(p.model);
    let mut mesh = b.into_mesh(material)?;
    for &node in &b.faces.x_min {
        mesh.fix_node(node)?;
    }
    mesh.add_traction(
        &b.faces.x_max,
        Vector3::new(0.0, 0.0, -p.force / (p.width * p.height)),
    )?;
    let report = solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 1,
            ..Default::default()
        },
    )
    .map_err(|e| anyhow::anyhow!("mesh with {n} cells through the height: {e}"))?;
    let tip = b
        .faces
        .x_max
        .iter()
        .map(|&k| mesh.node(k).map(|node| -node.displacement().z))
        .sum::<Result<f64, _>>()?
        / b.faces.x_max.len() as f64;
    if last && let Some(dir) = ctx.vtk_dir() {
        chrono_fea::vtk::write_tet_vtu(&mesh, dir.join("cantilever.vtu"))?;
    }
    Ok(Solution {
        tip,
        elements: mesh.elements().len(),
        free_dof: mesh.dof_map().nfree(),
        iterations: report.total_iterations(),
    })
}

fn run(p: &TetCantileverParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.refinements.len() >= 3,
        "parameter `refinements` needs at least 3 meshes (for the observed order and the extrapolation), got {:?}",
        p.refinements
    );
    for (i, &n) in p.refinements.iter().enumerate() {
        anyhow::ensure!(
            n >= 1 && (i == 0 || n > p.refinements[i - 1]),
            "parameter `refinements` must be ascending and >= 1, got {:?}",
            p.refinements
        );
    }
    for (name, v) in [
        ("length", p.length),
        ("width", p.width),
        ("height", p.height),
        ("force", p.force),
    ] {
        anyhow::ensure!(
            v.is_finite() && v > 0.0,
            "parameter `{name}` must be > 0, got {v}"
        );
    }
    let material = SolidMaterial::new(p.young, p.poisson, 7850.0, 0.0)?.with_model(p.model);
    let area = p.width * p.height;
    let ei = p.young * p.width * p.height.powi(3) / 12.0;
    let kga = rectangle_shear_coefficient(p.poisson) * material.shear_modulus() * area;
    let timoshenko = timoshenko_tip_deflection(p.force, p.length, ei, kga);
    let euler = cantilever_tip_deflection(p.force, p.length, ei);

    let mut out = CaseOutput::new();
    let mut series = Series::new([
        "cells_through_height",
        "tip_deflection",
        "timoshenko",
        "relative_error",
    ]);
    let mut sols = Vec::with_capacity(p.refinements.len());
    let mut iterations = 0;
    for (i, &n) in p.refinements.iter().enumerate() {
        let start = std::time::Instant::now();
        let s = solve(p, n, ctx, i + 1 == p.refinements.len())?;
        let wall = start.elapsed().as_secs_f64();
        let err = (s.tip / timoshenko - 1.0).abs();
        series.push(&[n as f64, s.tip, timoshenko, err]);
        out.sweep.push(SweepPoint {
            label: format!("n={n} ({} tets)", s.elements),
            error: err,
            wall_s: wall.max(1e-9),
        });
        out.metric(format!("tip_deflection_n{n}"), s.tip);
        out.metric(format!("relative_error_n{n}"), err);
        out.metric(format!("elements_n{n}"), s.elements as f64);
        out.metric(format!("free_dof_n{n}"), s.free_dof as f64);
        iterations += s.iterations;
        sols.push((n as f64, s.tip, err));
        ctx.note(format!(
            "fea-tet-cantilever: n = {n}: {} tets, {} dof, tip {:.6e} m, error {:.3e}, {:.2} s",
            s.elements, s.free_dof, s.tip, err, wall
        ));
        ctx.progress((i + 1) as f64 / p.refinements.len() as f64);
    }
    // Observed orders between successive meshes (mesh size ~ 1/n).
    let mut max_ratio: f64 = 0.0;
    let mut last_order = f64::NAN;
    for w in sols.windows(2) {
        let ((n0, _, e0), (n1, _, e1)) = (w[0], w[1]);
        max_ratio = max_ratio.max(e1 / e0);
        last_order = (e0 / e1).ln() / (n1 / n0).ln();
        out.metric(format!("observed_order_n{}_n{}", n0, n1), last_order);
    }
    // Richardson extrapolation from the three finest meshes: v = v_inf - C n^-r, with r
    // from the deflections themselves (not from the reference).
    let k = sols.len();
    let ((na, va, _), (nb, vb, _), (nc, vc, _)) = (sols[k - 3], sols[k - 2], sols[k - 1]);
    let (r, v_inf) = richardson(na, va, nb, vb, nc, vc)?;
    let finest = sols[k - 1].1;
    out.metric("tip_deflection", finest);
    out.metric("tip_deflection_timoshenko", timoshenko);
    out.metric("tip_deflection_euler_bernoulli", euler);
    out.metric("relative_error_finest", sols[k - 1].2);
    out.metric("extrapolation_order", r);
    out.check(Check::below("max_error_ratio", max_ratio, 1.0 - 1e-9));
    out.check(Check::absolute(
        "observed_order_finest",
        last_order,
        2.0,
        p.order_tolerance,
    ));
    out.check(Check::relative(
        "tip_deflection_extrapolated",
        v_inf,
        timoshenko,
        p.tolerance,
    ));
    out.metric("newton_iterations", iterations as f64);
    out.series = series;
    out.plot = PlotSpec::new(
        "Tetrahedral cantilever: tip deflection vs Timoshenko",
        "cells through the height [-]",
        "tip deflection [m]",
        &["tip_deflection", "timoshenko"],
    );
    out.steps = iterations as u64;
    Ok(out)
}

/// The limit `v_inf` and order `r` of `v(n) = v_inf - C n^-r` through three meshes
/// `n_a < n_b < n_c`: `r` from the root of
/// `(v_b - v_a) / (v_c - v_b) = (n_a^-r - n_b^-r) / (n_b^-r - n_c^-r)` (bisection on
/// `r` in [0.05, 8]), then `v_inf = v_c + (v_c - v_b) n_c^-r / (n_b^-r - n_c^-r)`.
fn richardson(na: f64, va: f64, nb: f64, vb: f64, nc: f64, vc: f64) -> anyhow::Result<(f64, f64)> {
    let target = (vb - va) / (vc - vb);
    anyhow::ensure!(
        target.is_finite() && target > 0.0,
        "extrapolation: the three finest deflections {va:e}, {vb:e}, {vc:e} are not monotone"
    );
    let g = |r: f64| {
        let (a, b, c) = (na.powf(-r), nb.powf(-r), nc.powf(-r));
        (a - b) / (b - c) - target
    };
    let (mut lo, mut hi) = (0.05, 8.0);
    anyhow::ensure!(
        g(lo) * g(hi) < 0.0,
        "extrapolation: no order in [0.05, 8] fits the deflections {va:e}, {vb:e}, {vc:e}"
    );
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(lo) * g(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let r = 0.5 * (lo + hi);
    let (b, c) = (nb.powf(-r), nc.powf(-r));
    Ok((r, vc + (vc - vb) * c / (b - c)))
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<TetCantileverParams>::boxed(
        "fea-tet-cantilever",
        "fea",
        "Box cantilever of linear tetrahedra (clamped face, tip shear traction), several refinements: the tip deflection converges (error falls, observed order, Richardson limit within 2 % of Timoshenko).",
        run,
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn richardson_recovers_a_known_sequence() {
        let v = |n: f64| 3.0 - 2.0 * n.powf(-1.7);
        let (r, v_inf) = super::richardson(2.0, v(2.0), 3.0, v(3.0), 4.0, v(4.0)).unwrap();
        assert!((r - 1.7).abs() < 1e-9, "{r}");
        assert!((v_inf - 3.0).abs() < 1e-9, "{v_inf}");
        assert!(super::richardson(1.0, 1.0, 2.0, 2.0, 3.0, 1.5).is_err());
    }
}
