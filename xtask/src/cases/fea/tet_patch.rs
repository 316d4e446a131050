//! `fea-tet-patch`: the displacement patch test of the linear tetrahedron.
//!
//! A cube of side `size`, `divisions^3` cells split into tetrahedra, the interior nodes
//! moved at random (seeded) by up to `distortion` of a cell in each direction, so the
//! elements are irregular. The boundary nodes are moved to the linear field
//! `x = (I + H) X + c` and held; the interior nodes start at their reference positions
//! (not translated by `c`, so the first Newton iterates see large strains next to the
//! boundary) and are free, no load. The exact solution is the same linear field everywhere: every
//! element has `F = I + H`, the Green strain `E = (F^T F - I) / 2`, the stress of the
//! material model at that `F` (St. Venant–Kirchhoff `P = F S`, `S = lambda tr(E) I +
//! 2 mu E`; or corotational `P = R T`, `model = corotational`) and the Cauchy stress
//! `sigma = P F^T / det F`. (The sum over the elements around an interior node of
//! `V P G_a` vanishes for a constant stress, so the linear field is in equilibrium.) The
//! static solver (Newton, one load step) must find it to round-off: the checks are the
//! largest relative errors of the interior displacement, the strain and the Cauchy stress
//! over all elements, below `tolerance` (1e-10). On meshes with slivers the error at the
//! solver's default residual tolerance can approach 1e-10 (`--full`: 8e-11);
//! `newton_tolerance` tightens the Newton stop towards the round-off floor.

use chrono_core::math::{Matrix3, Vector3};
use chrono_core::rng::Rng;
use chrono_fea::{BoxMesh, NodeId, SolidMaterial, StaticSettings, solve_static};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `fea-tet-patch`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TetPatchParams {
    /// Cells along each side of the cube.
    pub divisions: usize,
    /// Side of the cube, m.
    pub size: f64,
    /// Hexahedron split: `six` or `five`.
    pub split: chrono_fea::HexSplit,
    /// Material model: `svk` (St. Venant–Kirchhoff) or `corotational`.
    pub model: chrono_fea::SolidModel,
    /// Largest random move of an interior node along each axis, in cells (< 0.5).
    pub distortion: f64,
    /// Seed of the node distortion.
    pub seed: u64,
    /// Displacement gradient `H` (row-major, 9 values): `x = (I + H) X + c`.
    pub gradient: Vec<f64>,
    /// Rigid translation `c`, m.
    pub translation: Vec<f64>,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Largest relative error allowed (displacement, strain, stress).
    pub tolerance: f64,
    /// Absolute Newton residual tolerance, N (`null`: the solver's default).
    pub newton_tolerance: Option<f64>,
}

impl Default for TetPatchParams {
    fn default() -> Self {
        Self {
            divisions: 3,
            size: 1.0,
            split: chrono_fea::HexSplit::Six,
            model: chrono_fea::SolidModel::StVenantKirchhoff,
            distortion: 0.3,
            seed: 12345,
            // Stretch, shear and a small rotation, all ~1e-3 .. 1e-2.
            gradient: vec![
                4e-3, 2e-3, -1e-3, //
                -1e-3, -2e-3, 3e-3, //
                1e-3, 5e-3, 1e-2,
            ],
            translation: vec![0.1, -0.05, 0.02],
            young: 2.0e11,
            poisson: 0.3,
            tolerance: 1e-10,
            newton_tolerance: None,
        }
    }
}

impl CaseParams for TetPatchParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("divisions", "-", "cells along each side of the cube"),
        ParamInfo::new("size", "m", "side of the cube"),
        ParamInfo::new("split", "-", "hexahedron split: six or five tetrahedra"),
        ParamInfo::new("model", "-", "material model: svk or corotational"),
        ParamInfo::new(
            "distortion",
            "cells",
            "largest random move of an interior node per axis (< 0.5)",
        ),
        ParamInfo::new("seed", "-", "seed of the node distortion"),
        ParamInfo::new(
            "gradient",
            "-",
            "displacement gradient H, row-major (9 values)",
        ),
        ParamInfo::new("translation", "m", "rigid translation c (3 values)"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("poisson", "-", "Poisson's ratio"),
        ParamInfo::new(
            "tolerance",
            "-",
            "largest relative error (displacement, strain, stress)",
        ),
        ParamInfo::new(
            "newton_tolerance",
            "N",
            "absolute Newton residual tolerance (null: solver default)",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Full {
            self.divisions = 6;
        }
    }
}

fn run(p: &TetPatchParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let split = p.split;
    anyhow::ensure!(
        p.divisions >= 2,
        "parameter `divisions` must be >= 2 (an interior node), got {}",
        p.divisions
    );
    anyhow::ensure!(
        p.distortion.is_finite() && (0.0..0.5).contains(&p.distortion),
        "parameter `distortion` must be in [0, 0.5), got {}",
        p.distortion
    );
    anyhow::ensure!(
        p.gradient.len() == 9 && p.gradient.iter().all(|x| x.is_finite()),
        "parameter `gradient` must hold 9 finite values, got {:?}",
        p.gradient
    );
    anyhow::ensure!(
        p.translation.len() == 3 && p.translation.iter().all(|x| x.is_finite()),
        "parameter `translation` must hold 3 finite values, got {:?}",
        p.translation
    );
    let h = Matrix3::from_row_slice(&p.gradient);
    let c = Vector3::from_column_slice(&p.translation);
    let f = Matrix3::identity() + h;
    anyhow::ensure!(
        f.determinant() > 0.0,
        "parameter `gradient`: det(I + H) = {} must be > 0",
        f.determinant()
    );
    let material = SolidMaterial::new(p.young, p.poisson, 1000.0, 0.0)?.with_model(p.model);
    let n = p.divisions;
    let mut b = BoxMesh::new(Vector3::zeros(), Vector3::repeat(p.size), [n, n, n], split)?;
    let cell = p.size / n as f64;
    // xorshift64: the case's stream since its first version (a zero seed would stick).
    let mut rng = Rng::xorshift64(p.seed.max(1));
    for k in 0..b.positions.len() {
        if !b.is_boundary(NodeId(k)) {
            let d = Vector3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
            );
            b.positions[k] += d * (2.0 * p.distortion * cell);
        }
    }
    let mut mesh = b.into_mesh(material)?;
    let exact = |x: &Vector3<f64>| x + h * x + c;
    for k in 0..b.positions.len() {
        if b.is_boundary(NodeId(k)) {
            mesh.set_position(NodeId(k), exact(&b.positions[k]))?;
            mesh.fix_node(NodeId(k))?;
        }
    }
    ctx.progress(0.2);
    let report = solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 1,
            absolute_tolerance: p.newton_tolerance,
            ..Default::default()
        },
    )?;
    ctx.progress(0.8);
    let e_exact = 0.5 * (f.transpose() * f - Matrix3::identity());
    let p_exact = mesh.elements()[0].first_piola_of(&f);
    let sigma_exact = p_exact * f.transpose() / f.determinant();
    let u_scale = b
        .positions
        .iter()
        .map(|x| (h * x).norm())
        .fold(0.0, f64::max);
    let mut max_u: f64 = 0.0;
    for node in mesh.nodes() {
        let x = node.reference_position;
        max_u = max_u.max((node.position - exact(&x)).norm() / u_scale);
    }
    let mut series = Series::new([
        "element",
        "volume_ratio",
        "strain_error",
        "stress_error",
        "von_mises",
    ]);
    let (mut max_e, mut max_s): (f64, f64) = (0.0, 0.0);
    let (mut v_min, mut v_max) = (f64::INFINITY, 0.0f64);
    let v_regular = cell.powi(3)
        / if split == chrono_fea::HexSplit::Six {
            6.0
        } else {
            5.0
        };
    for (e, el) in mesh.elements().iter().enumerate() {
        let x = mesh.current_element_coordinates(e);
        let err_e = (el.green_strain(&x) - e_exact).amax() / e_exact.amax();
        let sigma = el.cauchy_stress(&x);
        let err_s = (sigma - sigma_exact).amax() / sigma_exact.amax();
        max_e = max_e.max(err_e);
        max_s = max_s.max(err_s);
        let ratio = el.volume() / v_regular;
        v_min = v_min.min(ratio);
        v_max = v_max.max(ratio);
        series.push(&[e as f64, ratio, err_e, err_s, chrono_fea::von_mises(&sigma)]);
    }
    let mut out = CaseOutput::new();
    out.check(Check::below("max_displacement_error", max_u, p.tolerance));
    out.check(Check::below("max_strain_error", max_e, p.tolerance));
    out.check(Check::below("max_stress_error", max_s, p.tolerance));
    out.metric("elements", mesh.elements().len() as f64);
    out.metric("free_dof", mesh.dof_map().nfree() as f64);
    out.metric("newton_iterations", report.total_iterations() as f64);
    out.metric("final_residual_N", report.residual);
    out.metric("volume_ratio_min", v_min);
    out.metric("volume_ratio_max", v_max);
    out.metric("von_mises_exact_Pa", chrono_fea::von_mises(&sigma_exact));
    if let Some(dir) = ctx.vtk_dir() {
        chrono_fea::vtk::write_tet_vtu(&mesh, dir.join("patch.vtu"))?;
    }
    out.series = series;
    out.plot = PlotSpec::new(
        "Tetrahedron patch test: relative error per element",
        "element [-]",
        "relative error [-]",
        &["strain_error", "stress_error"],
    );
    out.steps = report.total_iterations() as u64;
    ctx.progress(1.0);
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<TetPatchParams>::boxed(
        "fea-tet-patch",
        "fea",
        "Patch test of the linear tetrahedron (St. Venant-Kirchhoff) on a distorted cube mesh: boundary nodes on a linear displacement field, Newton must reproduce it inside; strain and stress constant and exact to 1e-10.",
        run,
    )
}
