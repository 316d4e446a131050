//! Tetrahedral meshes: patch tests, a cantilever against beam theory, loads, bad input.

use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::rng::Rng;
use chrono_fea::analytic::{rectangle_shear_coefficient, timoshenko_tip_deflection};
use chrono_fea::{
    BoxMesh, HexSplit, NodeId, SolidMaterial, SolidModel, StaticSettings, TetMesh, solve_static,
};
use nalgebra::{Matrix3, Vector3};

fn steel() -> SolidMaterial {
    SolidMaterial::new(2.0e11, 0.3, 7850.0, 0.0).unwrap()
}

/// A node displacement in `[-1/2, 1/2)^3` (cell units) from the seeded generator.
fn jitter(rng: &mut Rng) -> Vector3<f64> {
    Vector3::new(
        rng.range(-0.5, 0.5),
        rng.range(-0.5, 0.5),
        rng.range(-0.5, 0.5),
    )
}

/// A unit cube of 3x3x3 cells with the interior nodes moved by up to 30 % of a cell.
fn distorted_patch(split: HexSplit, model: SolidModel) -> (BoxMesh, TetMesh) {
    let mut b = BoxMesh::new(Vector3::zeros(), Vector3::repeat(1.0), [3, 3, 3], split).unwrap();
    let mut s = Rng::xorshift64(0x9e37_79b9_7f4a_7c15);
    for n in 0..b.positions.len() {
        if !b.is_boundary(NodeId(n)) {
            let d = jitter(&mut s);
            b.positions[n] += d * (0.6 / 3.0);
        }
    }
    let mesh = b.into_mesh(steel().with_model(model)).unwrap();
    (b, mesh)
}

#[test]
fn displacement_patch_test_is_exact() {
    // x = (I + H) X + c on the boundary, interior free: Newton must find the same linear
    // field inside, every element with the strain E = (F'F - I)/2, F = I + H.
    let h = Matrix3::new(2e-3, 5e-4, -3e-4, 1e-4, -1e-3, 6e-4, -2e-4, 3e-4, 1.5e-3);
    let c = Vector3::new(0.1, -0.2, 0.05);
    for (split, model) in [
        (HexSplit::Six, SolidModel::StVenantKirchhoff),
        (HexSplit::Five, SolidModel::StVenantKirchhoff),
        (HexSplit::Six, SolidModel::Corotational),
    ] {
        let (b, mut mesh) = distorted_patch(split, model);
        for n in 0..b.positions.len() {
            if b.is_boundary(NodeId(n)) {
                let x = b.positions[n];
                mesh.set_position(NodeId(n), x + h * x + c).unwrap();
                mesh.fix_node(NodeId(n)).unwrap();
            }
        }
        solve_static(
            &mut mesh,
            &StaticSettings {
                load_steps: 1,
                ..Default::default()
            },
        )
        .unwrap();
        let f = Matrix3::identity() + h;
        let e_exact = 0.5 * (f.transpose() * f - Matrix3::identity());
        let p_exact = mesh.elements()[0].first_piola_of(&f);
        let mut max_u: f64 = 0.0;
        for node in mesh.nodes() {
            let x = node.reference_position;
            max_u = max_u.max((node.position - (x + h * x + c)).norm());
        }
        assert!(max_u < 1e-13, "{split:?}: displacement error {max_u:e} m");
        for e in 0..mesh.elements().len() {
            let x = mesh.current_element_coordinates(e);
            let err = (mesh.elements()[e].green_strain(&x) - e_exact).amax() / e_exact.amax();
            assert!(err < 1e-10, "{split:?}: element {e} strain error {err:e}");
            let p = mesh.elements()[e].first_piola_stress(&x);
            let err = (p - p_exact).amax() / p_exact.amax();
            assert!(err < 1e-10, "{model:?}: element {e} stress error {err:e}");
        }
    }
}

#[test]
fn traction_patch_test_gives_uniform_stress() {
    // A bar (2 x 1 x 1 m, distorted interior) on rollers at x = 0, pulled by a uniform
    // nominal traction t on x = 2: uniaxial stress, P_xx = t in every element.
    let mut b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(2.0, 1.0, 1.0),
        [4, 2, 2],
        HexSplit::Six,
    )
    .unwrap();
    let mut s = Rng::xorshift64(7);
    for n in 0..b.positions.len() {
        if !b.is_boundary(NodeId(n)) {
            let d = jitter(&mut s);
            b.positions[n] += d * 0.15;
        }
    }
    let m = SolidMaterial::new(1.0e7, 0.25, 1000.0, 0.0).unwrap();
    let mut mesh = b.into_mesh(m).unwrap();
    for &n in &b.faces.x_min {
        mesh.fix_coordinate(n, 0).unwrap();
    }
    // Remove the rigid motions in y, z and about x with two more rollers.
    let origin = b.grid_node(0, 0, 0).unwrap();
    mesh.fix_coordinate(origin, 1).unwrap();
    mesh.fix_coordinate(origin, 2).unwrap();
    mesh.fix_coordinate(b.grid_node(0, 2, 0).unwrap(), 2)
        .unwrap();
    let t = 2.0e5; // 2 % strain: a nonlinear (large-strain) SVK check
    mesh.add_traction(&b.faces.x_max, Vector3::new(t, 0.0, 0.0))
        .unwrap();
    solve_static(&mut mesh, &StaticSettings::default()).unwrap();
    for e in 0..mesh.elements().len() {
        let x = mesh.current_element_coordinates(e);
        let el = &mesh.elements()[e];
        let p = el.deformation_gradient(&x) * el.pk2_stress(&x);
        let mut expected = Matrix3::zeros();
        expected[(0, 0)] = t;
        let err = (p - expected).amax() / t;
        assert!(err < 1e-9, "element {e}: first Piola stress error {err:e}");
    }
}

#[test]
fn cantilever_converges_towards_timoshenko() {
    // 1 m x 0.1 m x 0.1 m steel cantilever, tip shear load: linear tets are too stiff on
    // coarse meshes (shear locking) and the error falls under refinement.
    let (l, w): (f64, f64) = (1.0, 0.1);
    let m = steel();
    let p = 1.0e3;
    let ei = m.young * w.powi(4) / 12.0;
    let kga = rectangle_shear_coefficient(m.poisson) * m.shear_modulus() * w * w;
    let reference = timoshenko_tip_deflection(p, l, ei, kga);
    let mut errors = Vec::new();
    for n in [1usize, 2, 3] {
        let b = BoxMesh::new(
            Vector3::zeros(),
            Vector3::new(l, w, w),
            [10 * n, n, n],
            HexSplit::Six,
        )
        .unwrap();
        let mut mesh = b.into_mesh(m).unwrap();
        for &node in &b.faces.x_min {
            mesh.fix_node(node).unwrap();
        }
        let area = mesh
            .add_traction(&b.faces.x_max, Vector3::new(0.0, 0.0, -p / (w * w)))
            .unwrap();
        assert!((area - w * w).abs() < 1e-15);
        solve_static(
            &mut mesh,
            &StaticSettings {
                load_steps: 1,
                ..Default::default()
            },
        )
        .unwrap();
        let tip: f64 = b
            .faces
            .x_max
            .iter()
            .map(|&n| -mesh.node(n).unwrap().displacement().z)
            .sum::<f64>()
            / b.faces.x_max.len() as f64;
        errors.push((tip / reference - 1.0).abs());
        assert!(
            tip < reference,
            "linear tets are stiff: {tip} vs {reference}"
        );
    }
    assert!(
        errors[0] > errors[1] && errors[1] > errors[2],
        "error must fall: {errors:?}"
    );
    // The coarse mesh locks badly (tens of %); two refinements must halve it at least.
    assert!(errors[2] < 0.5 * errors[0], "{errors:?}");
}

#[test]
fn gravity_loads_the_mass() {
    let b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(0.3, 0.2, 0.1),
        [3, 2, 1],
        HexSplit::Five,
    )
    .unwrap();
    let mut mesh = b.into_mesh(steel()).unwrap();
    mesh.set_gravity(Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE))
        .unwrap();
    let mass = 7850.0 * 0.3 * 0.2 * 0.1;
    assert!((mesh.total_mass() / mass - 1.0).abs() < 1e-14);
    let f = mesh.external_force(1.0);
    let fz: f64 = f.iter().skip(2).step_by(3).sum();
    assert!((fz / (-GRAVITY_MAGNITUDE * mass) - 1.0).abs() < 1e-14);
    // Consistent mass: u' M u = m for a unit rigid translation.
    let map = mesh.dof_map();
    let mm = mesh.mass_matrix(&map).unwrap();
    let ones: Vec<f64> = (0..map.nfree())
        .map(|i| (i % 3 == 0) as u8 as f64)
        .collect();
    let mut total = 0.0;
    for j in 0..mm.ncols() {
        for idx in mm.symbolic().col_range(j) {
            total += ones[mm.symbolic().row_idx()[idx]] * mm.val()[idx] * ones[j];
        }
    }
    assert!((total / mass - 1.0).abs() < 1e-13, "{total} vs {mass}");
}

#[test]
fn bad_input_names_the_field() {
    let mut mesh = TetMesh::new();
    let a = mesh.add_node(Vector3::zeros()).unwrap();
    let b = mesh.add_node(Vector3::x()).unwrap();
    let c = mesh.add_node(Vector3::y()).unwrap();
    let d = mesh.add_node(Vector3::z()).unwrap();
    let e = mesh
        .add_tet([a, b, c, NodeId(9)], steel())
        .unwrap_err()
        .to_string();
    assert!(e.contains("element 0.node[3]") && e.contains('9'), "{e}");
    let e = mesh.add_tet([a, b, b, d], steel()).unwrap_err().to_string();
    assert!(e.contains("element 0.node[2]"), "{e}");
    let e = mesh.add_tet([a, c, b, d], steel()).unwrap_err().to_string();
    assert!(e.contains("element 0") && e.contains("inverted"), "{e}");
    let bad = SolidMaterial {
        poisson: 0.5,
        ..steel()
    };
    let e = mesh.add_tet([a, b, c, d], bad).unwrap_err().to_string();
    assert!(e.contains("material.poisson") && e.contains("0.5"), "{e}");
    assert_eq!(mesh.add_tet([a, b, c, d], steel()).unwrap(), 0);
    let e = mesh
        .add_traction(&[a, b], Vector3::x())
        .unwrap_err()
        .to_string();
    assert!(e.contains("traction.set"), "{e}");
    let e = mesh
        .set_force(a, Vector3::new(f64::NAN, 0.0, 0.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("node.force"), "{e}");
    // An unsupported mesh under load is a mechanism.
    mesh.set_force(d, Vector3::new(0.0, 0.0, 1.0)).unwrap();
    let e = solve_static(&mut mesh, &StaticSettings::default()).unwrap_err();
    assert!(matches!(e, chrono_fea::FeaError::Singular { .. }), "{e}");
}
