//! VTK output of deformed meshes with strain and stress fields, for ParaView.
//!
//! Each writer produces one unstructured grid (`.vtu`, ASCII) of the current
//! configuration through chrono-core's writer
//! ([`write_cells_vtu`]; series of frames with
//! [`write_pvd`](chrono_core::io::write_pvd)). Point data: `displacement` (m, current
//! minus reference position). Cell data, per cell type:
//!
//! - Cables ([`write_cable_vtu`]): each element drawn as `subdivisions` line segments
//!   (`VTK_LINE`) through its Hermite centre line `r(xi)`; per segment, at its
//!   midpoint: `axial_strain` `eps = (r_x . r_x - 1)/2` (Green, -), `curvature`
//!   `kappa = |r_x x r_xx| / |r_x|^3` (1/m), `axial_force` `E A eps` (N) and
//!   `bending_moment` `E I kappa` (N m) — the element's own strain measures and their
//!   conjugate section forces ([`AncfCable::strain_and_curvature`]).
//! - Fully parameterized beams ([`write_beam_vtu`]): the same segments; `axial_strain`
//!   `eps`, `twist` `K_x`, `curvature_y` `K_y`, `curvature_z` `K_z` (1/m, changes from
//!   the reference, [`AncfBeam::strains_at`]), `axial_force` `E A eps`,
//!   `bending_moment` `E sqrt((I_y K_y)^2 + (I_z K_z)^2)` (N m) and `torque` `G J K_x`.
//! - ANCF shells ([`write_shell_vtu`]): one quad (`VTK_QUAD`) per element; the
//!   membrane Green–Lagrange strain in the element's local frame (`e_1` along the
//!   reference `X_xi`, `e_3` the normal; [`AncfShell::strains`]) at the mid surface,
//!   averaged over the four in-plane integration points: `E11`, `E22`, `E12` (tensor
//!   component, -), the second Piola–Kirchhoff stress `S = C E` of those strains
//!   (`S11`, `S22`, `S12`, Pa, all six strain components in `C`), its von Mises value
//!   `von_mises_membrane` (Pa) and `von_mises_max`, the largest von Mises value of
//!   `C E` over all integration points (bending included; at the outer Gauss points of
//!   the thickness, `zeta = ±sqrt(3/5)`).
//! - Tetrahedra ([`write_tet_vtu`]): one `VTK_TETRA` per element; the Green–Lagrange
//!   strain `E = (F' F - I)/2` (`E_xx`, `E_yy`, `E_zz`, `E_yz`, `E_xz`, `E_xy`, tensor
//!   components), the Cauchy stress `sigma = F S F' / det F` (`sigma_xx` ...), its
//!   von Mises value `von_mises` (Pa) and `det_F` (constant in the linear element).
//!
//! Von Mises: `sqrt(((s11 - s22)^2 + (s22 - s33)^2 + (s33 - s11)^2)/2
//! + 3 (s12^2 + s23^2 + s13^2))` ([`von_mises`]).

use std::path::Path;

use chrono_core::Result as CoreResult;
use chrono_core::io::vtk::{CellGrid, VTK_LINE, VTK_QUAD, VTK_TETRA, write_cells_vtu};
use nalgebra::{Matrix3, Vector3, Vector6};

use crate::beam_mesh::BeamMesh;
use crate::element::{AncfBeam, AncfCable, AncfShell, BeamVector, ElementVector, von_mises};
use crate::mesh::CableMesh;
use crate::shell_mesh::ShellMesh;
use crate::tet_mesh::TetMesh;

/// Named cell scalars being collected.
struct Fields {
    names: Vec<&'static str>,
    values: Vec<Vec<f64>>,
}

impl Fields {
    fn new(names: &[&'static str]) -> Self {
        Self {
            names: names.to_vec(),
            values: vec![Vec::new(); names.len()],
        }
    }

    fn push(&mut self, row: &[f64]) {
        for (v, x) in self.values.iter_mut().zip(row) {
            v.push(*x);
        }
    }

    fn as_slices(&self) -> Vec<(&str, &[f64])> {
        self.names
            .iter()
            .zip(&self.values)
            .map(|(n, v)| (*n, v.as_slice()))
            .collect()
    }
}

/// The line segments of a 1-D mesh: nodes first (points `0..n_nodes`), then the interior
/// points of each element's `subdivisions` segments. `place(e, xi)` gives the current
/// and reference positions, `cell(e, xi)` the cell data of the segment centred at `xi`.
fn write_lines(
    path: &Path,
    nodes: &[(Vector3<f64>, Vector3<f64>)],
    elements: &[[usize; 2]],
    subdivisions: usize,
    place: impl Fn(usize, f64) -> (Vector3<f64>, Vector3<f64>),
    mut fields: Fields,
    cell: impl Fn(usize, f64) -> Vec<f64>,
) -> CoreResult<()> {
    let k = subdivisions.max(1);
    let mut points: Vec<Vector3<f64>> = nodes.iter().map(|n| n.0).collect();
    let mut disp: Vec<Vector3<f64>> = nodes.iter().map(|n| n.0 - n.1).collect();
    let mut conn = Vec::with_capacity(2 * k * elements.len());
    for (e, &[a, b]) in elements.iter().enumerate() {
        let mut prev = a;
        for s in 1..=k {
            let next = if s == k {
                b
            } else {
                let (x, x0) = place(e, s as f64 / k as f64);
                points.push(x);
                disp.push(x - x0);
                points.len() - 1
            };
            conn.extend([prev, next]);
            prev = next;
            fields.push(&cell(e, (s as f64 - 0.5) / k as f64));
        }
    }
    write_cells_vtu(
        path,
        &CellGrid {
            points: &points,
            cell_type: VTK_LINE,
            nodes_per_cell: 2,
            connectivity: &conn,
            point_scalars: &[],
            point_vectors: &[("displacement", &disp)],
            cell_scalars: &fields.as_slices(),
        },
    )
}

/// Write a cable mesh (module docs): `subdivisions` line segments per element (>= 1; 0
/// is taken as 1). Errors: the file cannot be written, a non-finite value (named).
pub fn write_cable_vtu(
    mesh: &CableMesh,
    path: impl AsRef<Path>,
    subdivisions: usize,
) -> CoreResult<()> {
    let q = mesh.coordinates();
    let q0: Vec<f64> = mesh
        .nodes()
        .iter()
        .flat_map(|n| {
            let (p, s) = (n.reference_position, n.reference_slope);
            [p.x, p.y, p.z, s.x, s.y, s.z]
        })
        .collect();
    let els = mesh.elements();
    let coords: Vec<(ElementVector, ElementVector)> = els
        .iter()
        .map(|el| {
            (
                mesh.element_coordinates(el, &q),
                mesh.element_coordinates(el, &q0),
            )
        })
        .collect();
    let nodes: Vec<_> = mesh
        .nodes()
        .iter()
        .map(|n| (n.position, n.reference_position))
        .collect();
    let conn: Vec<[usize; 2]> = els.iter().map(|el| el.nodes).collect();
    let cable = |e: usize| -> &AncfCable { &els[e] };
    write_lines(
        path.as_ref(),
        &nodes,
        &conn,
        subdivisions,
        |e, xi| {
            (
                cable(e).position_at(&coords[e].0, xi),
                cable(e).position_at(&coords[e].1, xi),
            )
        },
        Fields::new(&["axial_strain", "curvature", "axial_force", "bending_moment"]),
        |e, xi| {
            let (eps, kappa) = cable(e).strain_and_curvature(&coords[e].0, xi);
            let m = cable(e).material();
            vec![
                eps,
                kappa,
                m.axial_stiffness() * eps,
                m.bending_stiffness() * kappa,
            ]
        },
    )
}

/// Write a fully parameterized beam mesh (module docs), `subdivisions` segments per
/// element (>= 1). Errors as [`write_cable_vtu`].
pub fn write_beam_vtu(
    mesh: &BeamMesh,
    path: impl AsRef<Path>,
    subdivisions: usize,
) -> CoreResult<()> {
    let q = mesh.coordinates();
    let q0: Vec<f64> = mesh
        .nodes()
        .iter()
        .flat_map(|n| {
            let g = n.reference_gradients;
            let p = n.reference_position;
            [p, g[0], g[1], g[2]]
                .into_iter()
                .flat_map(|v| [v.x, v.y, v.z])
        })
        .collect();
    let els = mesh.elements();
    let coords: Vec<(BeamVector, BeamVector)> = els
        .iter()
        .map(|el| {
            (
                BeamMesh::element_coordinates(el, &q),
                BeamMesh::element_coordinates(el, &q0),
            )
        })
        .collect();
    let nodes: Vec<_> = mesh
        .nodes()
        .iter()
        .map(|n| (n.position, n.reference_position))
        .collect();
    let conn: Vec<[usize; 2]> = els.iter().map(|el| el.nodes).collect();
    let beam = |e: usize| -> &AncfBeam { &els[e] };
    write_lines(
        path.as_ref(),
        &nodes,
        &conn,
        subdivisions,
        |e, xi| {
            (
                beam(e).position_at(&coords[e].0, xi),
                beam(e).position_at(&coords[e].1, xi),
            )
        },
        Fields::new(&[
            "axial_strain",
            "twist",
            "curvature_y",
            "curvature_z",
            "axial_force",
            "bending_moment",
            "torque",
        ]),
        |e, xi| {
            let [eps, kx, ky, kz] = beam(e).strains_at(&coords[e].0, &coords[e].1, xi);
            let s = beam(e).section();
            vec![
                eps,
                kx,
                ky,
                kz,
                s.young * s.area * eps,
                s.young * (s.iy * ky).hypot(s.iz * kz),
                s.shear_modulus * s.torsion * kx,
            ]
        },
    )
}

/// A symmetric tensor from Voigt `[11, 22, 33, 23, 13, 12]` with tensor shears.
fn tensor(v: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(v[0], v[5], v[4], v[5], v[1], v[3], v[4], v[3], v[2])
}

/// The shell fields of one element (module docs): `[E11, E22, E12, S11, S22, S12,
/// von_mises_membrane, von_mises_max]`.
fn shell_fields(el: &AncfShell, e: &crate::element::ShellVector) -> [f64; 8] {
    let strains = el.strains(e);
    let c = el.material().elasticity();
    // Engineering shears in the Voigt strain: C maps them to tensor stresses.
    let stress = |eps: &Vector6<f64>| c * eps;
    let vm_max = strains
        .iter()
        .map(|eps| von_mises(&tensor(&stress(eps))))
        .fold(0.0, f64::max);
    // Points ordered eta, xi, zeta (outermost first), 3 through the thickness: the middle
    // one is on the mid surface.
    let mid: Vec<&Vector6<f64>> = strains.iter().skip(1).step_by(3).collect();
    let membrane = mid.iter().copied().sum::<Vector6<f64>>() / mid.len() as f64;
    let s = stress(&membrane);
    [
        membrane[0],
        membrane[1],
        0.5 * membrane[5],
        s[0],
        s[1],
        s[5],
        von_mises(&tensor(&s)),
        vm_max,
    ]
}

/// Write a shell mesh (module docs): quads on the four nodes of each element. Errors as
/// [`write_cable_vtu`].
pub fn write_shell_vtu(mesh: &ShellMesh, path: impl AsRef<Path>) -> CoreResult<()> {
    let q = mesh.coordinates();
    let points: Vec<Vector3<f64>> = mesh.nodes().iter().map(|n| n.position).collect();
    let disp: Vec<Vector3<f64>> = mesh.nodes().iter().map(|n| n.displacement()).collect();
    let conn: Vec<usize> = mesh.elements().iter().flat_map(|el| el.nodes).collect();
    let mut fields = Fields::new(&[
        "E11",
        "E22",
        "E12",
        "S11",
        "S22",
        "S12",
        "von_mises_membrane",
        "von_mises_max",
    ]);
    for el in mesh.elements() {
        fields.push(&shell_fields(el, &ShellMesh::element_coordinates(el, &q)));
    }
    write_cells_vtu(
        path,
        &CellGrid {
            points: &points,
            cell_type: VTK_QUAD,
            nodes_per_cell: 4,
            connectivity: &conn,
            point_scalars: &[],
            point_vectors: &[("displacement", &disp)],
            cell_scalars: &fields.as_slices(),
        },
    )
}

/// Write a tetrahedral mesh (module docs). Errors as [`write_cable_vtu`].
pub fn write_tet_vtu(mesh: &TetMesh, path: impl AsRef<Path>) -> CoreResult<()> {
    let points: Vec<Vector3<f64>> = mesh.nodes().iter().map(|n| n.position).collect();
    let disp: Vec<Vector3<f64>> = mesh.nodes().iter().map(|n| n.displacement()).collect();
    let conn: Vec<usize> = mesh.elements().iter().flat_map(|e| e.nodes).collect();
    let mut fields = Fields::new(&[
        "E_xx",
        "E_yy",
        "E_zz",
        "E_yz",
        "E_xz",
        "E_xy",
        "sigma_xx",
        "sigma_yy",
        "sigma_zz",
        "sigma_yz",
        "sigma_xz",
        "sigma_xy",
        "von_mises",
        "det_F",
    ]);
    for (e, el) in mesh.elements().iter().enumerate() {
        let x = mesh.current_element_coordinates(e);
        let g = el.green_strain(&x);
        let s = el.cauchy_stress(&x);
        fields.push(&[
            g[(0, 0)],
            g[(1, 1)],
            g[(2, 2)],
            g[(1, 2)],
            g[(0, 2)],
            g[(0, 1)],
            s[(0, 0)],
            s[(1, 1)],
            s[(2, 2)],
            s[(1, 2)],
            s[(0, 2)],
            s[(0, 1)],
            von_mises(&s),
            el.jacobian(&x),
        ]);
    }
    write_cells_vtu(
        path,
        &CellGrid {
            points: &points,
            cell_type: VTK_TETRA,
            nodes_per_cell: 4,
            connectivity: &conn,
            point_scalars: &[],
            point_vectors: &[("displacement", &disp)],
            cell_scalars: &fields.as_slices(),
        },
    )
}

#[cfg(test)]
#[path = "vtk_tests.rs"]
mod tests;
