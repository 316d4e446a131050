//! Tests of the VTK writers: each file is parsed back (an independent reader of the
//! VTK XML format below: counts, connectivity, offsets, cell types, every named array)
//! and its fields compared with analytic values.

use std::collections::HashMap;

use nalgebra::{Matrix3, Rotation3, Vector3};

use super::*;
use crate::material::{BeamMaterial, BeamSection, SolidMaterial};
use crate::node::NodeId;
use crate::statics::{StaticSettings, solve_static};
use crate::tet_box::{BoxMesh, HexSplit};
use crate::{CableQuadrature, ShellMaterial};

/// A parsed `.vtu`: counts and the arrays by name (values, components).
struct Vtu {
    points: usize,
    cells: usize,
    arrays: HashMap<String, (Vec<f64>, usize)>,
}

impl Vtu {
    fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path).unwrap();
        assert!(text.starts_with("<?xml") && text.trim_end().ends_with("</VTKFile>"));
        assert!(text.contains("<VTKFile type=\"UnstructuredGrid\""));
        let attr = |s: &str, name: &str| -> Option<String> {
            let key = format!(" {name}=\"");
            let at = s.find(&key)? + key.len();
            Some(s[at..].split('"').next()?.to_string())
        };
        let piece = &text[text.find("<Piece").unwrap()..];
        let points = attr(piece, "NumberOfPoints").unwrap().parse().unwrap();
        let cells = attr(piece, "NumberOfCells").unwrap().parse().unwrap();
        let mut arrays = HashMap::new();
        for chunk in text.split("<DataArray").skip(1) {
            let head = &chunk[..chunk.find('>').unwrap()];
            let name = attr(head, "Name").unwrap();
            let comps = attr(head, "NumberOfComponents").map_or(1, |c| c.parse().unwrap());
            let body = &chunk[chunk.find('>').unwrap() + 1..chunk.find("</DataArray>").unwrap()];
            let values: Vec<f64> = body
                .split_whitespace()
                .map(|s| s.parse().unwrap())
                .collect();
            assert!(values.iter().all(|x| x.is_finite()), "{name}");
            assert!(
                arrays.insert(name.clone(), (values, comps)).is_none(),
                "{name}"
            );
        }
        let vtu = Self {
            points,
            cells,
            arrays,
        };
        vtu.check_topology();
        vtu
    }

    fn get(&self, name: &str) -> &[f64] {
        &self
            .arrays
            .get(name)
            .unwrap_or_else(|| panic!("no {name}"))
            .0
    }

    /// Points, offsets, types and connectivity agree; every point and cell array has one
    /// entry per point or cell.
    fn check_topology(&self) {
        assert_eq!(self.get("Points").len(), 3 * self.points);
        let offsets = self.get("offsets");
        let conn = self.get("connectivity");
        assert_eq!(offsets.len(), self.cells);
        assert_eq!(self.get("types").len(), self.cells);
        assert_eq!(offsets.last().copied(), Some(conn.len() as f64));
        assert!(conn.iter().all(|&i| i >= 0.0 && (i as usize) < self.points));
        for (name, (v, c)) in &self.arrays {
            if ["Points", "offsets", "connectivity", "types"].contains(&name.as_str()) {
                continue;
            }
            assert!(
                v.len() == c * self.points || v.len() == c * self.cells,
                "{name}: {} values",
                v.len()
            );
        }
    }
}

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("chrono-fea-vtk-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A tetrahedral box under the homogeneous deformation `x = F X`: every cell holds the
/// analytic Green strain `(F'F - I)/2` and the St. Venant–Kirchhoff Cauchy stress
/// `F (lambda tr E I + 2 mu E) F' / det F`, every point the displacement `(F - I) X`.
#[test]
fn tet_under_homogeneous_stretch_writes_the_analytic_strain_and_stress() {
    let (young, nu) = (2.0e9, 0.3);
    let mat = SolidMaterial::new(young, nu, 1000.0, 0.0).unwrap();
    let b = BoxMesh::new(
        Vector3::new(0.1, -0.2, 0.3),
        Vector3::new(1.0, 0.5, 0.4),
        [3, 2, 2],
        HexSplit::Six,
    )
    .unwrap();
    let mut mesh = b.into_mesh(mat).unwrap();
    let f = Matrix3::new(1.02, 0.01, 0.0, -0.005, 0.97, 0.015, 0.0, 0.02, 1.03);
    let q: Vec<f64> = mesh
        .nodes()
        .iter()
        .flat_map(|n| {
            let x = f * n.reference_position;
            [x.x, x.y, x.z]
        })
        .collect();
    mesh.set_coordinates(&q).unwrap();
    let path = temp("tets.vtu");
    write_tet_vtu(&mesh, &path).unwrap();
    let v = Vtu::read(&path);
    assert_eq!(
        (v.points, v.cells),
        (mesh.nodes().len(), mesh.elements().len())
    );
    assert!(v.get("types").iter().all(|&t| t == 10.0));

    let e = 0.5 * (f.transpose() * f - Matrix3::identity());
    let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = young / (2.0 * (1.0 + nu));
    let s = lambda * e.trace() * Matrix3::identity() + 2.0 * mu * e;
    let sigma = f * s * f.transpose() / f.determinant();
    let ij = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];
    let names = ["xx", "yy", "zz", "yz", "xz", "xy"];
    for (k, &(i, j)) in ij.iter().enumerate() {
        for &x in v.get(&format!("E_{}", names[k])) {
            assert!(
                (x - e[(i, j)]).abs() < 1e-13,
                "E_{}: {x} vs {}",
                names[k],
                e[(i, j)]
            );
        }
        for &x in v.get(&format!("sigma_{}", names[k])) {
            assert!(
                (x - sigma[(i, j)]).abs() < 1e-9 * sigma.norm(),
                "sigma_{}: {x} vs {}",
                names[k],
                sigma[(i, j)]
            );
        }
    }
    let s = sigma;
    let vm = (0.5
        * ((s[(0, 0)] - s[(1, 1)]).powi(2)
            + (s[(1, 1)] - s[(2, 2)]).powi(2)
            + (s[(2, 2)] - s[(0, 0)]).powi(2))
        + 3.0 * (s[(0, 1)].powi(2) + s[(1, 2)].powi(2) + s[(0, 2)].powi(2)))
    .sqrt();
    for &x in v.get("von_mises") {
        assert!((x - vm).abs() < 1e-9 * vm, "{x} vs {vm}");
    }
    for &x in v.get("det_F") {
        assert!((x - f.determinant()).abs() < 1e-13);
    }
    let pts = v.get("Points");
    let disp = v.get("displacement");
    for (k, n) in mesh.nodes().iter().enumerate() {
        let u = (f - Matrix3::identity()) * n.reference_position;
        for c in 0..3 {
            assert!((disp[3 * k + c] - u[c]).abs() < 1e-14);
            assert!((pts[3 * k + c] - n.position[c]).abs() < 1e-15);
        }
    }
}

/// A cantilever cable under a pure axial tip pull `F`: the stretch `lambda` solves
/// `E A (lambda^2 - 1)/2 lambda = F` and every segment holds `eps = (lambda^2 - 1)/2`,
/// no curvature, `axial_force lambda = F`.
#[test]
fn cable_under_axial_pull_writes_the_analytic_strain() {
    let mat = BeamMaterial::rectangle(2e11, 7850.0, 0.01, 0.01, 0.0).unwrap();
    let l = 2.0;
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::new(l, 0.0, 0.0),
        4,
        mat,
        CableQuadrature::default(),
    )
    .unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    let ea = mat.axial_stiffness();
    let f = 0.02 * ea;
    mesh.set_force(NodeId(4), Vector3::new(f, 0.0, 0.0))
        .unwrap();
    solve_static(&mut mesh, &StaticSettings::default()).unwrap();
    // Newton on g(lambda) = E A (lambda^3 - lambda)/2 - F.
    let mut lam: f64 = 1.0;
    for _ in 0..50 {
        lam -= (0.5 * ea * (lam.powi(3) - lam) - f) / (0.5 * ea * (3.0 * lam * lam - 1.0));
    }
    let eps = 0.5 * (lam * lam - 1.0);
    let path = temp("cable.vtu");
    write_cable_vtu(&mesh, &path, 3).unwrap();
    let v = Vtu::read(&path);
    assert_eq!((v.points, v.cells), (5 + 4 * 2, 4 * 3));
    assert!(v.get("types").iter().all(|&t| t == 3.0));
    for &x in v.get("axial_strain") {
        assert!((x - eps).abs() < 1e-9 * eps, "{x} vs {eps}");
    }
    for &x in v.get("curvature") {
        assert!(x.abs() < 1e-9, "{x}");
    }
    for &x in v.get("axial_force") {
        assert!((x * lam - f).abs() < 1e-9 * f, "{x}");
    }
    // Points along the line at x = lambda X, displacement (lambda - 1) X.
    let (pts, disp) = (v.get("Points"), v.get("displacement"));
    for k in 0..v.points {
        assert!((disp[3 * k] - (lam - 1.0) / lam * pts[3 * k]).abs() < 1e-9);
    }
}

/// A small tip load `P` on a clamped cable: the written bending moment at each segment
/// centre is `P (L - x)` (Euler–Bernoulli; the cubic elements hold it exactly up to the
/// geometric nonlinearity of a 1 mm deflection).
#[test]
fn cable_cantilever_writes_the_bending_moment() {
    let mat = BeamMaterial::rectangle(2e11, 7850.0, 0.01, 0.01, 0.0).unwrap();
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::x(),
        8,
        mat,
        CableQuadrature::default(),
    )
    .unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    let p = 3.0 * mat.bending_stiffness() * 1e-3;
    mesh.set_force(NodeId(8), Vector3::new(0.0, 0.0, -p))
        .unwrap();
    solve_static(&mut mesh, &StaticSettings::default()).unwrap();
    let path = temp("cantilever.vtu");
    write_cable_vtu(&mesh, &path, 2).unwrap();
    let v = Vtu::read(&path);
    let m = v.get("bending_moment");
    for (c, &x) in m.iter().enumerate() {
        let xs = (c as f64 + 0.5) / 16.0;
        let want = p * (1.0 - xs);
        assert!((x - want).abs() < 1e-3 * p, "cell {c}: {x} vs {want}");
    }
}

/// A plate under the homogeneous in-plane stretch `x' = (1 + a) x`, `y' = (1 - b) y`
/// (directors unchanged): the membrane strains are `E11 = ((1 + a)^2 - 1)/2`,
/// `E22 = ((1 - b)^2 - 1)/2`, `E12 = 0`, the stresses those of the 3-D isotropic law
/// with `E33 = 0`, `S11 = (lambda + 2 mu) E11 + lambda E22`; no bending, so the largest
/// von Mises value is the membrane one.
#[test]
fn shell_under_homogeneous_stretch_writes_the_analytic_membrane_strain() {
    let (young, nu) = (1e7, 0.3);
    let mut mesh = ShellMesh::plate(
        1.0,
        0.5,
        3,
        2,
        0.01,
        ShellMaterial::isotropic(young, nu, 1000.0).unwrap(),
    )
    .unwrap();
    let (a, b) = (0.01, 0.004);
    let q: Vec<f64> = mesh
        .nodes()
        .iter()
        .flat_map(|n| {
            let x = n.reference_position;
            let d = n.reference_slope;
            [(1.0 + a) * x.x, (1.0 - b) * x.y, x.z, d.x, d.y, d.z]
        })
        .collect();
    mesh.set_coordinates(&q).unwrap();
    let path = temp("plate.vtu");
    write_shell_vtu(&mesh, &path).unwrap();
    let v = Vtu::read(&path);
    assert_eq!((v.points, v.cells), (12, 6));
    assert!(v.get("types").iter().all(|&t| t == 9.0));
    let (e11, e22) = (
        0.5 * ((1.0 + a) * (1.0 + a) - 1.0),
        0.5 * ((1.0 - b) * (1.0 - b) - 1.0),
    );
    let lambda = young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = young / (2.0 * (1.0 + nu));
    let s11 = (lambda + 2.0 * mu) * e11 + lambda * e22;
    let s22 = (lambda + 2.0 * mu) * e22 + lambda * e11;
    let s33 = lambda * (e11 + e22);
    let vm = (0.5 * ((s11 - s22).powi(2) + (s22 - s33).powi(2) + (s33 - s11).powi(2))).sqrt();
    let close = |name: &str, want: f64, scale: f64| {
        for &x in v.get(name) {
            assert!((x - want).abs() < 1e-10 * scale, "{name}: {x} vs {want}");
        }
    };
    close("E11", e11, e11);
    close("E22", e22, e11);
    close("E12", 0.0, e11);
    close("S11", s11, s11);
    close("S22", s22, s11);
    close("S12", 0.0, s11);
    close("von_mises_membrane", vm, vm);
    close("von_mises_max", vm, vm);
}

/// A straight beam stretched uniformly by `lambda` and rotated rigidly: axial strain
/// `(lambda^2 - 1)/2`, no curvature, no twist (the strains are frame invariant).
#[test]
fn beam_under_stretch_and_rotation_writes_the_axial_strain_only() {
    let section = BeamSection::rectangle(2e11, 0.3, 7850.0, 0.02, 0.01).unwrap();
    let mut mesh =
        BeamMesh::straight(Vector3::zeros(), Vector3::x(), 3, Vector3::y(), section).unwrap();
    let lam = 1.003;
    let rot = Rotation3::from_scaled_axis(Vector3::new(0.2, 0.7, -0.4));
    let q: Vec<f64> = mesh
        .nodes()
        .iter()
        .flat_map(|n| {
            let g = n.reference_gradients;
            [
                rot * (lam * n.reference_position),
                rot * (lam * g[0]),
                rot * g[1],
                rot * g[2],
            ]
            .into_iter()
            .flat_map(|v| [v.x, v.y, v.z])
        })
        .collect();
    mesh.set_coordinates(&q).unwrap();
    let path = temp("beam.vtu");
    write_beam_vtu(&mesh, &path, 2).unwrap();
    let v = Vtu::read(&path);
    assert_eq!((v.points, v.cells), (4 + 3, 6));
    let eps = 0.5 * (lam * lam - 1.0);
    for &x in v.get("axial_strain") {
        assert!((x - eps).abs() < 1e-12, "{x} vs {eps}");
    }
    for name in [
        "twist",
        "curvature_y",
        "curvature_z",
        "bending_moment",
        "torque",
    ] {
        for &x in v.get(name) {
            assert!(x.abs() < 1e-9, "{name}: {x}");
        }
    }
}

/// A clamped beam with a small tip load `P` along `-z`: the written bending moment at each
/// segment centre is `P (L - x)`, the torque zero.
#[test]
fn beam_cantilever_writes_the_bending_moment() {
    let section = BeamSection::rectangle(2e11, 0.3, 7850.0, 0.02, 0.01).unwrap();
    let n = 6;
    let mut mesh =
        BeamMesh::straight(Vector3::zeros(), Vector3::x(), n, Vector3::y(), section).unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    let p = 3.0 * section.young * section.iy.min(section.iz) * 1e-4;
    mesh.set_force(NodeId(n), Vector3::new(0.0, 0.0, -p))
        .unwrap();
    solve_static(&mut mesh, &StaticSettings::default()).unwrap();
    let path = temp("beam_cantilever.vtu");
    write_beam_vtu(&mesh, &path, 2).unwrap();
    let v = Vtu::read(&path);
    for (c, &x) in v.get("bending_moment").iter().enumerate() {
        let xs = (c as f64 + 0.5) / (2 * n) as f64;
        let want = p * (1.0 - xs);
        assert!((x - want).abs() < 2e-3 * p, "cell {c}: {x} vs {want}");
    }
    for &x in v.get("torque") {
        assert!(x.abs() < 1e-9 * p, "{x}");
    }
}
