//! Finite-element validation cases (chrono-fea):
//!
//! - `fea-bend-45`: the 45-degree bend of Bathe & Bolourchi (1979), a curved cantilever
//!   under an out-of-plane tip load, with the fully parameterized ANCF beam;
//! - `fea-cantilever`: an ANCF cantilever under a dead tip force, from the small-load
//!   Euler–Bernoulli regime to the large-deflection elastica (`P L^2 / (E I)` up to 10);
//! - `fea-cantilever-frequency`: its first bending frequency against the Euler–Bernoulli
//!   value `1.875^2 sqrt(E I / (rho A L^4)) / (2 pi)`;
//! - `fea-pendulum`: an undamped flexible pendulum stepped in the system's CCP (implicit
//!   Euler) keeps its energy; the numerical damping against the step size;
//! - `fea-tet-patch`: the patch test of the linear tetrahedron on a distorted mesh;
//! - `fea-tet-cantilever`: a tetrahedral box cantilever under a tip shear load, mesh
//!   convergence of the tip deflection against beam theory;
//! - `fea-shell-cantilever`: the ANCF shell plate strip under end shear against the
//!   load–displacement curve of Sze, Liu & Lo (2004);
//! - `fea-shell-pressure`: an ANCF shell sphere under internal follower pressure against
//!   the membrane solution;
//! - `fea-tire-drop`: a pressurized ANCF shell tire on a rigid rim dropped on rigid
//!   ground comes to rest: static deflection against the membrane estimate.

pub mod bend45;
pub mod cantilever;
pub mod frequency;
pub mod pendulum;
pub mod shell_cantilever;
pub mod shell_pressure;
pub mod tet_cantilever;
pub mod tet_patch;
pub mod tire_drop;

use chrono_core::math::Vector3;
use chrono_fea::{
    BeamMaterial, BeamMesh, BeamSection, CableMesh, CableQuadrature, HexSplit, NodeId, SolidModel,
};

/// The beam element of a case parameter for the cases that only run the cable
/// (`fea-cantilever-frequency`, `fea-pendulum`): `cable`; `beam` (the fully
/// parameterized ANCF beam) is rejected here with a clear error — it runs in
/// `fea-cantilever` and `fea-bend-45`.
pub fn check_element(element: &str) -> anyhow::Result<()> {
    match element {
        "cable" => Ok(()),
        "beam" => anyhow::bail!(
            "parameter `element` = `beam`: this case runs the cable only (the fully parameterized ANCF beam runs in fea-cantilever and fea-bend-45); use `cable`"
        ),
        other => anyhow::bail!("parameter `element` must be `cable` or `beam`, got `{other}`"),
    }
}

/// Whether a case parameter selects the fully parameterized beam (`beam`) rather than
/// the cable (`cable`); anything else is an error naming the value.
pub fn is_beam(element: &str) -> anyhow::Result<bool> {
    match element {
        "cable" => Ok(false),
        "beam" => Ok(true),
        other => anyhow::bail!("parameter `element` must be `cable` or `beam`, got `{other}`"),
    }
}

/// The straight cantilever of [`cantilever_mesh`] with the fully parameterized ANCF
/// beam: section `width` (along Y) x `height` (along Z), `nu = 0` (the references are
/// shear-rigid; the beam's shear flexibility adds `~ 3 E I / (k G A L^2) ~ 1e-4`
/// relative at `L / h = 100`), clamped at node 0 (all 12 coordinates).
pub fn beam_cantilever_mesh(
    n_elements: usize,
    length: f64,
    young: f64,
    density: f64,
    width: f64,
    height: f64,
) -> anyhow::Result<BeamMesh> {
    anyhow::ensure!(
        n_elements >= 1,
        "parameter `n_elements` must be >= 1, got {n_elements}"
    );
    anyhow::ensure!(
        length.is_finite() && length > 0.0,
        "parameter `length` must be > 0, got {length}"
    );
    let section = BeamSection::rectangle(young, 0.0, density, width, height)?;
    let mut mesh = BeamMesh::straight(
        Vector3::zeros(),
        Vector3::new(length, 0.0, 0.0),
        n_elements,
        Vector3::y(),
        section,
    )?;
    mesh.clamp(NodeId(0))?;
    Ok(mesh)
}

/// A straight cantilever along +X from the origin, clamped at node 0 (position and slope direction),
/// `n_elements` cable elements of a rectangular `width` x `height` section (bending
/// across the height, which lies along Z).
pub fn cantilever_mesh(
    n_elements: usize,
    length: f64,
    young: f64,
    density: f64,
    width: f64,
    height: f64,
) -> anyhow::Result<CableMesh> {
    anyhow::ensure!(
        n_elements >= 1,
        "parameter `n_elements` must be >= 1, got {n_elements}"
    );
    anyhow::ensure!(
        length.is_finite() && length > 0.0,
        "parameter `length` must be > 0, got {length}"
    );
    let material = BeamMaterial::rectangle(young, density, width, height, 0.0)?;
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::new(length, 0.0, 0.0),
        n_elements,
        material,
        CableQuadrature::default(),
    )?;
    mesh.clamp(NodeId(0))?;
    Ok(mesh)
}

/// The hexahedron split of a case parameter: `six` or `five` tetrahedra per cell.
pub fn parse_split(split: &str) -> anyhow::Result<HexSplit> {
    match split {
        "six" => Ok(HexSplit::Six),
        "five" => Ok(HexSplit::Five),
        other => anyhow::bail!("parameter `split` must be `six` or `five`, got `{other}`"),
    }
}

/// The solid model of a case parameter: `svk` (St. Venant–Kirchhoff) or `corotational`.
pub fn parse_model(model: &str) -> anyhow::Result<SolidModel> {
    match model {
        "svk" => Ok(SolidModel::StVenantKirchhoff),
        "corotational" => Ok(SolidModel::Corotational),
        other => anyhow::bail!("parameter `model` must be `svk` or `corotational`, got `{other}`"),
    }
}

/// Write the deformed tetrahedral mesh as a `.vtu`: current positions, the displacement
/// (point vectors), the von Mises (Cauchy) stress and the volume ratio `det F` per element.
pub fn write_tet_vtu(mesh: &chrono_fea::TetMesh, path: &std::path::Path) -> anyhow::Result<()> {
    use chrono_core::io::vtk::{CellGrid, VTK_TETRA, write_cells_vtu};
    let points: Vec<Vector3<f64>> = mesh.nodes().iter().map(|n| n.position).collect();
    let displacement: Vec<Vector3<f64>> = mesh.nodes().iter().map(|n| n.displacement()).collect();
    let connectivity: Vec<usize> = mesh.elements().iter().flat_map(|e| e.nodes).collect();
    let von_mises = mesh.von_mises_stresses();
    let jacobian: Vec<f64> = (0..mesh.elements().len())
        .map(|e| mesh.elements()[e].jacobian(&mesh.current_element_coordinates(e)))
        .collect();
    write_cells_vtu(
        path,
        &CellGrid {
            points: &points,
            cell_type: VTK_TETRA,
            nodes_per_cell: 4,
            connectivity: &connectivity,
            point_scalars: &[],
            point_vectors: &[("displacement", &displacement)],
            cell_scalars: &[("von_mises", &von_mises), ("det_F", &jacobian)],
        },
    )?;
    Ok(())
}
