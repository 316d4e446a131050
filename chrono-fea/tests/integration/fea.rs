//! Tests of the ANCF cable element, the mesh assembly, the static solver and the modal
//! analysis against exact and analytic solutions.

use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_fea::analytic::{
    cantilever_first_frequency, cantilever_tip_deflection, elastica_tip_load,
};
use chrono_fea::element::{AncfCable, ElementVector};
use chrono_fea::{
    BeamMaterial, CableMesh, CableQuadrature, FeaError, NodeId, StaticSettings,
    natural_frequencies, solve_static,
};
use nalgebra::{Rotation3, Vector3};

const E: f64 = 2.0e11;
const RHO: f64 = 7850.0;

fn material(h: f64) -> BeamMaterial {
    BeamMaterial::rectangle(E, RHO, h, h, 0.0).unwrap()
}

/// Element coordinates of a straight element of length `l` along `t`, moved rigidly by
/// rotation `rot` and translation `c`, and stretched by `stretch` (1: none).
fn placed(l: f64, rot: &Rotation3<f64>, c: Vector3<f64>, stretch: f64) -> ElementVector {
    let t = rot * Vector3::x();
    let mut e = ElementVector::zeros();
    let parts = [c, stretch * t, c + stretch * l * t, stretch * t];
    for (k, p) in parts.iter().enumerate() {
        e.fixed_rows_mut::<3>(3 * k).copy_from(p);
    }
    e
}

fn element(l: f64, h: f64) -> AncfCable {
    AncfCable::new([0, 1], l, material(h), CableQuadrature::default()).unwrap()
}

/// A deterministic, strongly deformed configuration (large rotation, stretch, bending
/// in two planes, twisted slopes).
fn deformed(l: f64) -> ElementVector {
    let rot = Rotation3::from_euler_angles(0.3, -0.7, 1.1);
    let mut e = placed(l, &rot, Vector3::new(0.1, -0.2, 0.3), 1.02);
    let bumps = [
        0.0,
        0.0,
        0.0,
        0.1,
        -0.2,
        0.15,
        0.03 * l,
        -0.02 * l,
        0.05 * l,
        -0.3,
        0.1,
        0.25,
    ];
    for i in 0..12 {
        e[i] += bumps[i];
    }
    e
}

#[test]
fn rigid_motion_gives_zero_internal_force() {
    let (l, h) = (0.25, 0.01);
    let el = element(l, h);
    let scale = el.material().axial_stiffness();
    for (i, angles) in [(0.0, 0.0, 0.0), (0.4, -1.2, 2.5), (3.0, 0.2, -0.9)]
        .iter()
        .enumerate()
    {
        let rot = Rotation3::from_euler_angles(angles.0, angles.1, angles.2);
        let e = placed(l, &rot, Vector3::new(1.0, -2.0, 0.5 * i as f64), 1.0);
        let q = el.internal_force(&e);
        assert!(
            q.amax() < 1e-13 * scale,
            "rotation {angles:?}: |Q| = {}",
            q.amax()
        );
        assert!(el.strain_energy(&e).abs() < 1e-20 * scale);
    }
}

#[test]
fn uniform_stretch_gives_the_exact_axial_force() {
    let (l, h) = (0.3, 0.02);
    let el = element(l, h);
    let ea = el.material().axial_stiffness();
    let rot = Rotation3::from_euler_angles(0.5, 0.2, -0.3);
    let t = rot * Vector3::x();
    for stretch in [1.001, 1.05, 0.97] {
        let e = placed(l, &rot, Vector3::zeros(), stretch);
        let q = el.internal_force(&e);
        // Green strain and the nominal force E A eps lambda along the axis at B, minus at A;
        // no moment-like slope forces and no bending in a straight stretched element.
        let eps = 0.5 * (stretch * stretch - 1.0);
        let n = ea * eps * stretch;
        let qb = Vector3::new(q[6], q[7], q[8]);
        let qa = Vector3::new(q[0], q[1], q[2]);
        assert!(
            (qb - n * t).norm() < 1e-9 * n.abs(),
            "stretch {stretch}: {qb:?} vs {}",
            n
        );
        assert!((qa + n * t).norm() < 1e-9 * n.abs());
        for i in [3, 4, 5, 9, 10, 11] {
            assert!(q[i].abs() < 1e-9 * n.abs() * l, "slope row {i}: {}", q[i]);
        }
        for xi in [0.0, 0.3, 1.0] {
            let (strain, kappa) = el.strain_and_curvature(&e, xi);
            assert!((strain - eps).abs() < 1e-14);
            assert!(kappa.abs() < 1e-7, "kappa {kappa}");
        }
    }
}

#[test]
fn internal_force_is_the_energy_gradient() {
    let l = 0.2;
    for quad in [
        CableQuadrature::default(),
        CableQuadrature {
            axial: 3,
            bending: 2,
        },
    ] {
        let el = AncfCable::new([0, 1], l, material(0.01), quad).unwrap();
        let e = deformed(l);
        let q = el.internal_force(&e);
        let d = 1e-6;
        for i in 0..12 {
            let (mut ep, mut em) = (e, e);
            ep[i] += d;
            em[i] -= d;
            let fd = (el.strain_energy(&ep) - el.strain_energy(&em)) / (2.0 * d);
            assert!(
                (fd - q[i]).abs() < 1e-6 * q.amax(),
                "row {i}: fd {fd} vs {}",
                q[i]
            );
        }
    }
}

#[test]
fn tangent_matches_central_differences_of_the_force() {
    let l = 0.2;
    let el = element(l, 0.01);
    for e in [
        deformed(l),
        placed(l, &Rotation3::identity(), Vector3::zeros(), 1.0),
    ] {
        let k = el.tangent_stiffness(&e);
        assert!(
            (k - k.transpose()).amax() < 1e-10 * k.amax(),
            "tangent not symmetric"
        );
        let d = 1e-7;
        let mut worst: f64 = 0.0;
        for j in 0..12 {
            let (mut ep, mut em) = (e, e);
            ep[j] += d;
            em[j] -= d;
            let col = (el.internal_force(&ep) - el.internal_force(&em)) / (2.0 * d);
            worst = worst.max((col - k.column(j)).amax());
        }
        assert!(
            worst < 1e-6 * k.amax(),
            "max |K - K_fd| = {worst:e} vs |K| = {:e}",
            k.amax()
        );
    }
}

#[test]
fn consistent_mass_and_gravity_integrate_to_the_total() {
    let (l, h) = (0.4, 0.02);
    let el = element(l, h);
    let m = el.mass_matrix();
    let total = RHO * h * h * l;
    for dir in 0..3 {
        // a unit rigid translation: velocity [u, 0, u, 0]
        let mut u = ElementVector::zeros();
        u[dir] = 1.0;
        u[6 + dir] = 1.0;
        let mass = (u.transpose() * m * u)[(0, 0)];
        assert!((mass - total).abs() < 1e-14 * total, "{mass} vs {total}");
    }
    assert!((m - m.transpose()).amax() < 1e-15 * m.amax());
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let qg = el.gravity_force(&g);
    assert!((qg[2] + qg[8] - total * g.z).abs() < 1e-12 * total);
    // the gravity force is M applied to the rigid "acceleration" [g, 0, g, 0]
    let mut acc = ElementVector::zeros();
    acc[2] = g.z;
    acc[8] = g.z;
    assert!((m * acc - qg).amax() < 1e-12 * total);
    let mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::new(1.2, 0.0, 0.0),
        6,
        material(h),
        CableQuadrature::default(),
    )
    .unwrap();
    assert!((mesh.total_mass() - RHO * h * h * 1.2).abs() < 1e-12);
}

fn cantilever(n: usize, l: f64, h: f64) -> CableMesh {
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::new(l, 0.0, 0.0),
        n,
        material(h),
        CableQuadrature::default(),
    )
    .unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    mesh
}

#[test]
fn small_load_cantilever_tip_is_euler_bernoulli() {
    let (l, h) = (1.0, 0.01);
    let mut mesh = cantilever(8, l, h);
    let ei = material(h).bending_stiffness();
    let p = 1e-3 * ei / (l * l);
    mesh.set_force(NodeId(8), Vector3::new(0.0, 0.0, -p))
        .unwrap();
    let report = solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 1,
            ..Default::default()
        },
    )
    .unwrap();
    let tip = mesh.node(NodeId(8)).unwrap().displacement();
    let exact = cantilever_tip_deflection(p, l, ei);
    let err = (-tip.z / exact - 1.0).abs();
    assert!(err < 0.01, "tip {} vs {exact}: {err:e}", -tip.z);
    // cubic Hermite interpolation is exact for the cubic deflection line; what is left is
    // the geometric nonlinearity at this load (~alpha^2)
    assert!(err < 1e-5, "relative error {err:e}");
    assert!(report.total_iterations() <= 5, "{:?}", report.iterations);
    assert!(tip.y.abs() < 1e-15);
}

#[test]
fn axial_pull_matches_the_green_strain_law() {
    let (l, h) = (2.0, 0.01);
    let mut mesh = cantilever(4, l, h);
    let ea = material(h).axial_stiffness();
    let f = 0.02 * ea;
    mesh.set_force(NodeId(4), Vector3::new(f, 0.0, 0.0))
        .unwrap();
    solve_static(&mut mesh, &StaticSettings::default()).unwrap();
    let lambda = 1.0 + mesh.node(NodeId(4)).unwrap().displacement().x / l;
    // E A (lambda^2 - 1) / 2 * lambda = F
    let residual = ea * 0.5 * (lambda * lambda - 1.0) * lambda - f;
    assert!(
        residual.abs() < 1e-9 * f,
        "lambda {lambda}: residual {residual}"
    );
    for node in mesh.nodes() {
        assert!((node.slope - Vector3::new(lambda, 0.0, 0.0)).norm() < 1e-10);
    }
}

#[test]
fn large_deflection_tip_follows_the_elastica() {
    let (l, h) = (1.0, 0.01);
    let mut mesh = cantilever(8, l, h);
    let ei = material(h).bending_stiffness();
    let settings = StaticSettings {
        load_steps: 5,
        ..Default::default()
    };
    for alpha in [1.0, 5.0, 10.0] {
        mesh.set_force(NodeId(8), Vector3::new(0.0, 0.0, -alpha * ei / (l * l)))
            .unwrap();
        solve_static(&mut mesh, &settings).unwrap();
        let tip = mesh.node(NodeId(8)).unwrap().displacement();
        let r = elastica_tip_load(alpha).unwrap();
        let (ev, eu) = (
            (-tip.z / l) / r.deflection - 1.0,
            (tip.x / l) / r.axial - 1.0,
        );
        assert!(
            ev.abs() < 0.02 && eu.abs() < 0.02,
            "alpha {alpha}: v {ev:e}, u {eu:e}"
        );
    }
}

#[test]
fn first_bending_frequency_of_a_cantilever() {
    let (l, h) = (1.0, 0.01);
    let mesh = cantilever(8, l, h);
    let m = material(h);
    let f = natural_frequencies(&mesh).unwrap();
    let exact = cantilever_first_frequency(m.bending_stiffness(), m.mass_per_length(), l);
    // two equal bending modes (the cable's bending stiffness is isotropic)
    assert!((f[0] / exact - 1.0).abs() < 0.02, "{} vs {exact}", f[0]);
    assert!((f[1] / f[0] - 1.0).abs() < 1e-8);
}

#[test]
fn bad_input_names_the_field() {
    let err = BeamMaterial::new(-1.0, RHO, 1e-4, 1e-9, 0.0)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("material.young") && err.contains("-1"),
        "{err}"
    );
    let err = BeamMaterial::new(E, RHO, 1e-4, f64::NAN, 0.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("material.second_moment"), "{err}");
    let err = BeamMaterial::rectangle(E, RHO, 0.0, 0.01, 0.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("section.width"), "{err}");
    let mut mesh = CableMesh::new();
    let err = mesh
        .add_node(Vector3::zeros(), Vector3::new(2.0, 0.0, 0.0))
        .unwrap_err()
        .to_string();
    assert!(err.contains("node.slope"), "{err}");
    let a = mesh.add_node(Vector3::zeros(), Vector3::x()).unwrap();
    let b = mesh
        .add_node(Vector3::new(0.0, 1.0, 0.0), Vector3::x())
        .unwrap();
    let err = mesh
        .add_cable(a, b, material(0.01), CableQuadrature::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("reference slope of node 0"), "{err}");
    let err = mesh
        .add_cable(a, NodeId(7), material(0.01), CableQuadrature::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("no such node"), "{err}");
    let err = CableMesh::straight(
        Vector3::zeros(),
        Vector3::x(),
        0,
        material(0.01),
        CableQuadrature::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("n_elements"), "{err}");
    let err = AncfCable::new(
        [0, 1],
        1.0,
        material(0.01),
        CableQuadrature {
            axial: 0,
            bending: 3,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("quadrature.axial"), "{err}");
    let mut mesh = cantilever(2, 1.0, 0.01);
    let err = mesh
        .set_force(NodeId(2), Vector3::new(f64::INFINITY, 0.0, 0.0))
        .unwrap_err()
        .to_string();
    assert!(err.contains("node.force"), "{err}");
    let err = solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 0,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("statics.load_steps"), "{err}");
}

#[test]
fn newton_failure_names_the_load_step() {
    let (l, h) = (1.0, 0.01);
    let mut mesh = cantilever(4, l, h);
    let ei = material(h).bending_stiffness();
    mesh.set_force(NodeId(4), Vector3::new(0.0, 0.0, -10.0 * ei))
        .unwrap();
    let err = solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 2,
            max_iterations: 2,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            FeaError::NotConverged {
                step: 1,
                steps: 2,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("load step 1 of 2"), "{err}");
}

#[test]
fn unsupported_mesh_is_reported_singular() {
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::x(),
        2,
        material(0.01),
        CableQuadrature::default(),
    )
    .unwrap();
    mesh.set_force(NodeId(2), Vector3::new(0.0, 0.0, -1.0))
        .unwrap();
    let err = solve_static(&mut mesh, &StaticSettings::default()).unwrap_err();
    assert!(
        matches!(
            err,
            FeaError::Singular { step: 1, .. } | FeaError::NonFinite { .. }
        ),
        "{err}"
    );
}

/// A generalized load on the coordinates acts as the nodal forces and end moments it
/// stands for: a tip force on the position entries gives the same solution as
/// `set_force`, and a uniform load `q` as consistent nodal loads (`q l / 2` on positions,
/// `+-q l^2 / 12` on slopes) gives the Euler–Bernoulli tip deflection `q L^4 / (8 E I)`.
/// A load of the wrong length is an error naming the field.
#[test]
fn coordinate_load_acts_as_the_nodal_forces_it_stands_for() {
    let (l, h, n) = (1.0, 0.01, 8);
    let ei = material(h).bending_stiffness();
    let settings = StaticSettings {
        load_steps: 1,
        ..Default::default()
    };
    let p = 1e-3 * ei / (l * l);
    let mut a = cantilever(n, l, h);
    a.set_force(NodeId(n), Vector3::new(0.0, 0.0, -p)).unwrap();
    solve_static(&mut a, &settings).unwrap();
    let mut b = cantilever(n, l, h);
    let mut q = vec![0.0; b.ndof()];
    q[6 * n + 2] = -p;
    b.set_coordinate_load(&q).unwrap();
    solve_static(&mut b, &settings).unwrap();
    let (ta, tb) = (
        a.node(NodeId(n)).unwrap().displacement(),
        b.node(NodeId(n)).unwrap().displacement(),
    );
    assert!((ta - tb).norm() < 1e-12 * ta.norm(), "{ta} vs {tb}");
    // a uniform load, consistent nodal loads of the Hermite shape functions
    let w = 1e-3 * ei / l.powi(3);
    let le = l / n as f64;
    let mut c = cantilever(n, l, h);
    let mut q = vec![0.0; c.ndof()];
    for e in 0..n {
        q[6 * e + 2] -= 0.5 * w * le;
        q[6 * e + 5] -= w * le * le / 12.0;
        q[6 * (e + 1) + 2] -= 0.5 * w * le;
        q[6 * (e + 1) + 5] += w * le * le / 12.0;
    }
    c.set_coordinate_load(&q).unwrap();
    solve_static(&mut c, &settings).unwrap();
    let tip = -c.node(NodeId(n)).unwrap().displacement().z;
    let exact = w * l.powi(4) / (8.0 * ei);
    assert!((tip / exact - 1.0).abs() < 1e-3, "tip {tip} vs {exact}");
    let e = c.set_coordinate_load(&[0.0; 5]).unwrap_err();
    assert!(e.to_string().contains("coordinate_load"), "{e}");
}
