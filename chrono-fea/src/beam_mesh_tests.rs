//! Tests of [`BeamMesh`](super::BeamMesh): small-deflection cantilever in both bending
//! planes against Euler–Bernoulli, torsion against `T L / (G J)`, the stress-free arc,
//! loads and bad input.

use super::*;
use crate::statics::{StaticSettings, solve_static};
use chrono_core::math::GRAVITY_MAGNITUDE;

fn rect() -> BeamSection {
    // 20 mm (y) x 10 mm (z) steel: I_y = w h^3 / 12 (deflection along z) < I_z.
    BeamSection::rectangle(2e11, 0.3, 7850.0, 0.02, 0.01).unwrap()
}

fn one_step() -> StaticSettings {
    StaticSettings {
        load_steps: 1,
        ..StaticSettings::default()
    }
}

/// Tip deflection of a 1 m cantilever of `n` elements under a small tip force `force`.
fn cantilever_tip(n: usize, force: Vector3<f64>, quad: BeamQuadrature) -> Vector3<f64> {
    let mut mesh =
        BeamMesh::straight(Vector3::zeros(), Vector3::x(), n, Vector3::y(), rect()).unwrap();
    mesh.set_quadrature(quad).unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    mesh.set_force(NodeId(n), force).unwrap();
    solve_static(&mut mesh, &one_step()).unwrap();
    mesh.node(NodeId(n)).unwrap().displacement()
}

#[test]
fn cantilever_bends_like_euler_bernoulli_in_both_planes() {
    let s = rect();
    for n in [8, 16] {
        // Deflection along z: E I_y; along y: E I_z (twice the width: 4 times stiffer).
        let w = cantilever_tip(n, Vector3::new(0.0, 0.0, -1.0), BeamQuadrature::default());
        let exact_z = 1.0 / (3.0 * s.young * s.iy);
        assert!(
            (-w.z / exact_z - 1.0).abs() < 0.01,
            "n {n}: w_z {} vs {exact_z}",
            w.z
        );
        assert!(w.y.abs() < 1e-6 * exact_z);
        let v = cantilever_tip(n, Vector3::new(0.0, 1.0, 0.0), BeamQuadrature::default());
        let exact_y = 1.0 / (3.0 * s.young * s.iz);
        assert!(
            (v.y / exact_y - 1.0).abs() < 0.01,
            "n {n}: w_y {} vs {exact_y}",
            v.y
        );
        assert!(v.z.abs() < 1e-6 * exact_y);
    }
}

#[test]
fn shear_sampling_at_gauss_points_is_too_stiff() {
    // One element, L / h = 100. Shear and section strains at the nodes (default): the
    // cubic centre line bends freely, the Euler–Bernoulli tip deflection. At 3 Gauss
    // points the centre line is tied to the linear section vectors: constant curvature
    // in the element, 3/4 of the deflection; at 2 Gauss points the clamp (`r_x` and
    // `r_y` held) contradicts the 2-point shear field of the first element.
    let s = rect();
    let exact = 1.0 / (3.0 * s.young * s.iy);
    let force = Vector3::new(0.0, 0.0, -1.0);
    let tip = |shear| {
        -cantilever_tip(
            1,
            force,
            BeamQuadrature {
                shear,
                ..Default::default()
            },
        )
        .z / exact
    };
    let (nodes, gauss2, gauss3) = (tip(0), tip(2), tip(3));
    assert!((nodes - 1.0).abs() < 1e-3, "nodes: {nodes}");
    assert!((gauss3 - 0.75).abs() < 0.01, "3 Gauss points: {gauss3}");
    assert!(gauss2 < 0.8, "2 Gauss points: {gauss2}");
}

#[test]
fn torsion_of_a_straight_bar() {
    // Square 20 mm bar, G J with the St. Venant constant J = 0.1406 a^4.
    let s = BeamSection::rectangle(2e11, 0.3, 7850.0, 0.02, 0.02).unwrap();
    assert!(
        (s.torsion / 0.02f64.powi(4) - 0.1406).abs() < 1e-4,
        "J = {}",
        s.torsion
    );
    for n in [1, 4] {
        let mut mesh =
            BeamMesh::straight(Vector3::zeros(), Vector3::x(), n, Vector3::y(), s).unwrap();
        mesh.clamp(NodeId(0)).unwrap();
        mesh.set_torque(NodeId(n), Vector3::new(1.0, 0.0, 0.0))
            .unwrap();
        solve_static(&mut mesh, &one_step()).unwrap();
        let exact = 1.0 / (s.shear_modulus * s.torsion);
        let tip = mesh.node(NodeId(n)).unwrap();
        assert!(
            (tip.twist() / exact - 1.0).abs() < 0.01,
            "n {n}: {} vs {exact}",
            tip.twist()
        );
        // Twist linear along the bar.
        let mid = mesh.node(NodeId(n / 2)).unwrap().twist();
        if n > 1 {
            assert!((mid / (0.5 * exact) - 1.0).abs() < 0.01);
        }
        assert!(tip.displacement().norm() < 1e-6 * exact);
    }
}

#[test]
fn arc_reference_is_stress_free() {
    let s = BeamSection::rectangle(1e7, 0.0, 1.0, 1.0, 1.0).unwrap();
    let angle = std::f64::consts::FRAC_PI_4;
    let mut mesh = BeamMesh::arc(
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        100.0,
        angle,
        8,
        s,
    )
    .unwrap();
    let tip = mesh.node(NodeId(8)).unwrap().position;
    let exact = Vector3::new(100.0 * angle.sin(), 100.0 * (1.0 - angle.cos()), 0.0);
    assert!((tip - exact).norm() < 1e-12 * 100.0);
    assert!((mesh.total_mass() / (100.0 * angle) - 1.0).abs() < 1e-5);
    let map = mesh.dof_map();
    let (f, _) = mesh
        .internal_force(&mesh.coordinates(), &map, false)
        .unwrap();
    let fmax = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(fmax < 1e-12 * s.young * s.area, "reference force {fmax}");
    assert_eq!(mesh.strain_energy(), 0.0);
    mesh.clamp(NodeId(0)).unwrap();
    let report = solve_static(&mut mesh, &one_step()).unwrap();
    assert_eq!(report.total_iterations(), 0);
    // A small in-plane load moves the tip (the support works, the arc is not rigid).
    mesh.set_force(NodeId(8), Vector3::new(0.0, 0.0, 1.0))
        .unwrap();
    solve_static(&mut mesh, &one_step()).unwrap();
    assert!(mesh.node(NodeId(8)).unwrap().displacement().z > 0.0);
}

#[test]
fn gravity_load_of_a_cantilever() {
    // Distributed load q = rho A g: tip deflection q L^4 / (8 E I).
    let s = rect();
    let mut mesh = BeamMesh::straight(Vector3::zeros(), Vector3::x(), 8, Vector3::y(), s).unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    mesh.set_gravity(Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE))
        .unwrap();
    let f = mesh.external_force(1.0);
    let fz: f64 = (0..mesh.nodes().len()).map(|n| f[12 * n + 2]).sum();
    assert!((fz / (-GRAVITY_MAGNITUDE * s.mass_per_length()) - 1.0).abs() < 1e-12);
    solve_static(&mut mesh, &one_step()).unwrap();
    let exact = GRAVITY_MAGNITUDE * s.mass_per_length() / (8.0 * s.young * s.iy);
    let w = -mesh.node(NodeId(8)).unwrap().displacement().z;
    assert!((w / exact - 1.0).abs() < 0.01, "{w} vs {exact}");
}

#[test]
fn bad_input_names_the_field() {
    let s = rect();
    let mut mesh = BeamMesh::new();
    let err = mesh
        .add_node(
            Vector3::zeros(),
            [2.0 * Vector3::x(), Vector3::y(), Vector3::z()],
        )
        .unwrap_err();
    assert!(err.to_string().contains("node.gradient[0]"), "{err}");
    let err = mesh
        .add_node(Vector3::zeros(), [Vector3::x(), Vector3::x(), Vector3::z()])
        .unwrap_err();
    assert!(err.to_string().contains("orthogonal"), "{err}");
    let err = BeamMesh::straight(Vector3::zeros(), Vector3::x(), 2, Vector3::x(), s).unwrap_err();
    assert!(err.to_string().contains("y_axis"), "{err}");
    let err =
        BeamMesh::arc(Vector3::zeros(), Vector3::x(), Vector3::y(), 1.0, 0.0, 4, s).unwrap_err();
    assert!(err.to_string().contains("angle"), "{err}");
    let err = BeamMesh::arc(
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        -1.0,
        1.0,
        4,
        s,
    )
    .unwrap_err();
    assert!(err.to_string().contains("radius"), "{err}");
    let mut mesh = BeamMesh::straight(Vector3::zeros(), Vector3::x(), 2, Vector3::y(), s).unwrap();
    assert!(
        mesh.clamp(NodeId(5))
            .unwrap_err()
            .to_string()
            .contains("node")
    );
    assert!(mesh.fix_coordinate(NodeId(0), 12).is_err());
    let err = mesh
        .set_force(NodeId(1), Vector3::new(f64::NAN, 0.0, 0.0))
        .unwrap_err();
    assert!(err.to_string().contains("node.force"), "{err}");
    let err = BeamSection::rectangle(1e7, 0.0, 1.0, 1.0, 1.0)
        .unwrap()
        .with_torsion(-1.0)
        .unwrap_err();
    assert!(err.to_string().contains("section.torsion"), "{err}");
    // An unsupported mesh is a mechanism: a clear error, no NaN.
    mesh.set_force(NodeId(2), Vector3::z()).unwrap();
    assert!(solve_static(&mut mesh, &one_step()).is_err());
}

#[test]
fn cantilever_frequencies_bending_and_torsion() {
    // 1 m steel cantilever 20 x 10 mm, 16 elements: first bending (along z, I_y)
    // f = 1.8751^2 sqrt(E I_y / (rho A L^4)) / (2 pi); the first torsion mode of a
    // clamped-free bar f = sqrt(G J / (rho I_p)) / (4 L) with I_p = I_y + I_z (the
    // rotary inertia of r_y, r_z in the consistent mass).
    let s = rect();
    let mut mesh = BeamMesh::straight(Vector3::zeros(), Vector3::x(), 16, Vector3::y(), s).unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    let f = crate::modal::natural_frequencies(&mesh).unwrap();
    let pi2 = 2.0 * std::f64::consts::PI;
    let bend = 1.875_104_f64.powi(2) * (s.young * s.iy / (s.mass_per_length())).sqrt() / pi2;
    assert!((f[0] / bend - 1.0).abs() < 1e-3, "{} vs {bend}", f[0]);
    let torsion = (s.shear_modulus * s.torsion / (s.density * (s.iy + s.iz))).sqrt() / 4.0;
    let closest = f
        .iter()
        .map(|x| (x / torsion - 1.0).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        closest < 1e-2,
        "no mode near the torsion frequency {torsion}: {f:?}"
    );
}
