//! `fea-shell-pressure`: a closed thin sphere under internal pressure, the ANCF shell
//! with a curved reference configuration and a follower pressure.
//!
//! One octant of a sphere of mid-surface radius `R` (three `n x n` patches, the radial
//! projection of the cube corner, [`ShellMesh::sphere_octant`]), directors the outward
//! normals, symmetry on the three coordinate planes (a node on the plane `x = 0` holds
//! its `x` position and the `x` component of its director; likewise `y`, `z`). The
//! pressure `p` acts on the mid surface along the current normal (follower load, with its
//! load stiffness in Newton). The membrane solution of a thin sphere,
//!
//! ```text
//! u = p R^2 (1 - nu) / (2 E t)
//! ```
//!
//! is the reference for the radial expansion: the metric is the mean over the nodes of
//! `|r| - R`, within 2 %; the spread (max - min) over the nodes shows how uniform the
//! discrete solution is. The 3-D material sees a through-thickness stress of order `p`
//! against the membrane stress `p R / (2 t)`: a relative effect `~ t / R` (1 % at the
//! default `R / t = 100`) that thin-shell theory neglects.

use chrono_fea::{NodeId, ShellMaterial, ShellMesh, StaticSettings, solve_static};
use serde::{Deserialize, Serialize};

use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `fea-shell-pressure`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ShellPressureParams {
    /// Internal pressure, Pa.
    pub pressure: f64,
    /// Elements along each edge of the three patches (3 n^2 elements in the octant).
    pub n_elements: usize,
    /// Mid-surface radius, m.
    pub radius: f64,
    /// Thickness, m.
    pub thickness: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Load increments (Newton solves of the follower load).
    pub load_steps: usize,
    /// Locking remedies: `ans+eas` (default), `ans`, `eas` or `none`.
    pub locking: super::Locking,
    /// Relative tolerance against the membrane solution.
    pub tolerance: f64,
}

impl Default for ShellPressureParams {
    fn default() -> Self {
        Self {
            pressure: 1.0e6,
            n_elements: 6,
            radius: 1.0,
            thickness: 0.01,
            young: 2.0e11,
            poisson: 0.3,
            load_steps: 1,
            locking: super::Locking::AnsEas,
            tolerance: 0.02,
        }
    }
}

impl CaseParams for ShellPressureParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("pressure", "Pa", "internal pressure (follower load)"),
        ParamInfo::new(
            "n_elements",
            "-",
            "elements along each patch edge (3 n^2 in the octant)",
        ),
        ParamInfo::new("radius", "m", "mid-surface radius"),
        ParamInfo::new("thickness", "m", "shell thickness"),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("poisson", "-", "Poisson's ratio"),
        ParamInfo::new("load_steps", "-", "load increments"),
        ParamInfo::new(
            "locking",
            "-",
            "locking remedies: ans+eas, ans, eas or none",
        ),
        ParamInfo::new(
            "tolerance",
            "-",
            "relative tolerance against the membrane solution",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => self.n_elements = 4,
            Mode::Full => self.n_elements = 12,
            Mode::Default => {}
        }
    }
}

fn run(p: &ShellPressureParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(
        p.load_steps >= 1,
        "parameter `load_steps` must be >= 1, got {}",
        p.load_steps
    );
    anyhow::ensure!(
        p.pressure.is_finite(),
        "parameter `pressure` must be finite, got {}",
        p.pressure
    );
    let material = ShellMaterial::isotropic(p.young, p.poisson, 1000.0)?;
    let mut mesh = ShellMesh::sphere_octant(p.radius, p.n_elements, p.thickness, material)?;
    mesh.set_locking(p.locking.remedies())?;
    let r = p.radius;
    for k in 0..mesh.nodes().len() {
        let x = mesh.nodes()[k].reference_position;
        for axis in 0..3 {
            if x[axis].abs() < 1e-9 * r {
                mesh.fix_symmetry(NodeId(k), axis)?;
            }
        }
    }
    mesh.set_pressure(p.pressure)?;
    ctx.progress(0.1);
    let report = solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: p.load_steps,
            ..StaticSettings::default()
        },
    )?;
    ctx.progress(0.9);
    if let Some(dir) = ctx.vtk_dir() {
        chrono_fea::vtk::write_shell_vtu(&mesh, dir.join("sphere_octant.vtu"))?;
    }
    let exact = p.pressure * r * r * (1.0 - p.poisson) / (2.0 * p.young * p.thickness);
    let mut series = Series::new(["node", "polar_angle_deg", "radial_displacement", "membrane"]);
    let (mut sum, mut lo, mut hi) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
    for (k, n) in mesh.nodes().iter().enumerate() {
        let ur = n.position.norm() - r;
        sum += ur;
        lo = lo.min(ur);
        hi = hi.max(ur);
        let polar = (n.reference_position.z / r)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        series.push(&[k as f64, polar, ur, exact]);
    }
    let mean = sum / mesh.nodes().len() as f64;
    let mut out = CaseOutput::new();
    out.check(Check::relative(
        "radial_displacement_m",
        mean,
        exact,
        p.tolerance,
    ));
    out.metric("radial_displacement_min_m", lo);
    out.metric("radial_displacement_max_m", hi);
    out.metric("spread_relative", (hi - lo) / exact.abs());
    out.metric("elements", mesh.elements().len() as f64);
    out.metric("free_dof", mesh.dof_map().nfree() as f64);
    out.metric("newton_iterations", report.total_iterations() as f64);
    out.metric("octant_area_m2", mesh.area());
    out.series = series;
    out.plot = PlotSpec::new(
        "ANCF shell sphere under internal pressure: radial displacement per node",
        "polar angle [deg]",
        "radial displacement [m]",
        &["radial_displacement", "membrane"],
    );
    out.steps = report.total_iterations() as u64;
    ctx.progress(1.0);
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<ShellPressureParams>::boxed(
        "fea-shell-pressure",
        "fea",
        "ANCF 4-node shell sphere octant (curved reference, symmetry planes) under internal follower pressure: radial expansion within 2 % of the membrane solution p R^2 (1 - nu) / (2 E t).",
        run,
    )
}
