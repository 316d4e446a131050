//! ANCF shells stepping in a `System` (implicit Euler in the CCP): free fall under
//! gravity, a pressurized closed sphere against the static solver, free vibration of an
//! undamped plate against its modal frequency, a plate hanging from attachment rows to a
//! rigid body, a plate resting on the ground through its node spheres.

use chrono_ccp::{Apgd, Cg, SolverSettings};
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::math::{Isometry3, UnitQuaternion};
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fea::{
    AttachTarget, DirectorTarget, FeaError, NodeId, ShellItem, ShellMaterial, ShellMesh,
    StaticSettings, natural_frequencies, solve_static,
};
use nalgebra::Vector3;

fn system(gravity: Vector3<f64>) -> System {
    let settings = SystemSettings {
        gravity,
        ..SystemSettings::default()
    };
    let solver = Cg::new(SolverSettings {
        tolerance: 1e-13,
        max_iterations: 1000,
        record_history: false,
    });
    System::new(settings, Box::new(solver)).unwrap()
}

fn steel() -> ShellMaterial {
    ShellMaterial::isotropic(2.0e11, 0.3, 7850.0).unwrap()
}

/// A free plate (no support) falls with the free-fall acceleration: the consistent
/// gravity load is `M` times the uniform field, `K` annihilates a translation, so the
/// implicit Euler velocities are `v_n = n h g` and the positions
/// `z_n = z_0 - g h^2 n (n + 1) / 2` exactly; the directors do not turn; the momentum is
/// `m g t`.
#[test]
fn free_plate_falls_at_the_free_fall_acceleration() {
    let mesh = ShellMesh::plate(0.4, 0.2, 4, 2, 0.01, steel()).unwrap();
    let mass = mesh.total_mass();
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let mut sys = system(g);
    let idx = sys.add_item(Box::new(ShellItem::new("plate", mesh).unwrap()));
    let (h, n) = (1e-3, 200);
    for _ in 0..n {
        sys.step(h).unwrap();
    }
    let item = sys.item::<ShellItem>(idx).unwrap();
    let t = h * n as f64;
    let drop = GRAVITY_MAGNITUDE * h * h * (n * (n + 1)) as f64 / 2.0;
    for (k, node) in item.mesh().nodes().iter().enumerate() {
        let (v, dd) = item.node_velocity(NodeId(k)).unwrap();
        assert!((v - g * t).norm() < 1e-10, "node {k}: {v:?}");
        assert!(dd.norm() < 1e-10, "node {k}: director rate {dd:?}");
        let dz = node.position.z - node.reference_position.z;
        assert!((dz + drop).abs() < 1e-10, "node {k}: {dz} vs {}", -drop);
    }
    let p = item.linear_momentum();
    assert!(
        (p - mass * g * t).norm() < 1e-9 * mass * GRAVITY_MAGNITUDE * t,
        "{p:?}"
    );
}

/// The octant of a closed sphere (symmetry planes) under internal follower pressure:
/// started at the static solution it stays there, and started from the unloaded sphere
/// with damping it settles at it (the follower load and its symmetrized load stiffness
/// in the step, against the static Newton solver with the exact one).
#[test]
fn pressurized_sphere_settles_at_the_static_solution() {
    let (r, p) = (1.0, 1.0e6);
    let mut mesh = ShellMesh::sphere_octant(r, 3, 0.01, steel()).unwrap();
    for k in 0..mesh.nodes().len() {
        let x = mesh.nodes()[k].reference_position;
        for axis in 0..3 {
            if x[axis].abs() < 1e-9 * r {
                mesh.fix_symmetry(NodeId(k), axis).unwrap();
            }
        }
    }
    mesh.set_pressure(p).unwrap();
    let mut reference = mesh.clone();
    solve_static(&mut reference, &StaticSettings::default()).unwrap();
    let q_static = reference.coordinates();
    let u_static = reference.nodes()[0].position.norm() - r;
    assert!(u_static > 1e-5, "{u_static}");
    let mut at_rest = ShellItem::new("sphere", reference.clone()).unwrap();
    at_rest.set_damping(1e-4).unwrap();
    let mut settling = ShellItem::new("sphere", mesh).unwrap();
    settling.set_damping(1e-4).unwrap();
    let mut sys = system(Vector3::zeros());
    let a = sys.add_item(Box::new(at_rest));
    let b = sys.add_item(Box::new(settling));
    for _ in 0..400 {
        sys.step(2e-4).unwrap();
    }
    for (idx, tol) in [(a, 1e-9), (b, 1e-6)] {
        let q = sys.item::<ShellItem>(idx).unwrap().mesh().coordinates();
        let err = q
            .iter()
            .zip(&q_static)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        eprintln!("sphere item {idx}: max |q - q_static| = {err:e} (u = {u_static:e} m)");
        assert!(err < tol * u_static, "item {idx}: {err:e}");
    }
}

/// An undamped clamped plate strip released from a static tip deflection vibrates at the
/// first natural frequency of the same mesh (within 1 %); its energy never grows and
/// loses only the implicit Euler's `exp(-omega^2 h t)` (bounded below here).
#[test]
fn undamped_plate_vibrates_at_the_modal_frequency_with_bounded_energy() {
    let (l, w, t) = (1.0, 0.1, 0.01);
    let mut mesh = ShellMesh::plate(l, w, 8, 1, t, steel()).unwrap();
    let tip: Vec<NodeId> = (0..2).map(|j| ShellMesh::grid_node(8, 8, j)).collect();
    for j in 0..2 {
        mesh.fix_node(ShellMesh::grid_node(8, 0, j)).unwrap();
    }
    let f_modal = natural_frequencies(&mesh).unwrap()[0];
    for &n in &tip {
        mesh.set_force(n, Vector3::new(0.0, 0.0, -20.0)).unwrap();
    }
    solve_static(&mut mesh, &StaticSettings::default()).unwrap();
    for &n in &tip {
        mesh.set_force(n, Vector3::zeros()).unwrap();
    }
    let z0 = mesh.node(tip[0]).unwrap().displacement().z;
    let e0 = mesh.strain_energy();
    let mut sys = system(Vector3::zeros());
    let idx = sys.add_item(Box::new(ShellItem::new("strip", mesh).unwrap()));
    let h = 1e-4;
    let (mut prev, mut crossings, mut e_min) = (z0, Vec::new(), e0);
    for s in 0..4000 {
        sys.step(h).unwrap();
        let item = sys.item::<ShellItem>(idx).unwrap();
        let z = item.mesh().node(tip[0]).unwrap().displacement().z;
        if prev < 0.0 && z >= 0.0 {
            crossings.push((s as f64 + prev / (prev - z)) * h);
        }
        prev = z;
        let e = item.kinetic_energy() + item.strain_energy();
        assert!(e <= e0 * (1.0 + 1e-9), "step {s}: {e} > {e0}");
        e_min = e_min.min(e);
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let f = (crossings.len() - 1) as f64 / (crossings.last().unwrap() - crossings[0]);
    let omega = std::f64::consts::TAU * f_modal;
    let t_end = 4000.0 * h;
    eprintln!(
        "plate: {f} Hz vs modal {f_modal} Hz; energy min {:.6} E0 (backward Euler {:.6})",
        e_min / e0,
        (-omega * omega * h * t_end).exp()
    );
    assert!((f / f_modal - 1.0).abs() < 0.01, "{f} Hz vs {f_modal} Hz");
    assert!(e_min > 0.8 * e0, "energy fell to {e_min} of {e0}");
}

/// A soft vertical plate hanging from its top edge by attachment rows to points of a
/// fixed rigid body: at rest the rows carry the weight, the attached nodes stay at their
/// points, and the shape is the static solution of the same mesh with those positions
/// supported and gravity as a dead load.
#[test]
fn plate_hangs_from_a_rigid_body_by_attachment_rows() {
    let m = ShellMaterial::isotropic(1.0e7, 0.3, 1000.0).unwrap();
    let (lx, lz, nx, nz) = (0.2, 0.3, 2, 3);
    let mesh = ShellMesh::grid(
        nx,
        nz,
        |u, v| (Vector3::new(u * lx, 0.0, -v * lz), Vector3::y()),
        0.005,
        m,
    )
    .unwrap();
    let weight = mesh.total_mass() * GRAVITY_MAGNITUDE;
    let top: Vec<NodeId> = (0..=nx).map(|i| ShellMesh::grid_node(nx, i, 0)).collect();
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let mut reference = mesh.clone();
    for &n in &top {
        reference.fix_position(n).unwrap();
    }
    reference.set_gravity(g).unwrap();
    solve_static(&mut reference, &StaticSettings::default()).unwrap();
    let mut sys = system(g);
    let body_at = Vector3::new(0.1, 0.0, 0.05);
    let body = sys
        .add_body(RigidBodyBuilder::fixed().position(body_at))
        .unwrap();
    let mut item = ShellItem::new("sheet", mesh).unwrap();
    item.set_damping(2e-3).unwrap();
    for &n in &top {
        let p = item.mesh().node(n).unwrap().position;
        item.attach(
            n,
            AttachTarget::Body {
                body,
                local: p - body_at,
            },
        )
        .unwrap();
    }
    let e = item.set_damping(-1.0).unwrap_err();
    assert!(matches!(e, FeaError::InvalidParameter { ref field, .. } if field == "damping"));
    let idx = sys.add_item(Box::new(item));
    for _ in 0..1500 {
        sys.step(1e-3).unwrap();
    }
    let item = sys.item::<ShellItem>(idx).unwrap();
    let total: Vector3<f64> = (0..top.len()).map(|i| item.reaction(i).unwrap()).sum();
    let err = total.z / weight - 1.0;
    eprintln!("hanging plate: rows carry {} N, weight {weight} N", total.z);
    assert!(err.abs() < 1e-6, "{total:?} vs {weight}");
    for &n in &top {
        let node = item.mesh().node(n).unwrap();
        assert!(
            node.displacement().norm() < 1e-9,
            "{:?}",
            node.displacement()
        );
    }
    let bottom = ShellMesh::grid_node(nx, 1, nz);
    let u = item.mesh().node(bottom).unwrap().displacement();
    let u_ref = reference.node(bottom).unwrap().displacement();
    assert!(u_ref.z < -1e-5, "{u_ref:?}");
    let err = (u - u_ref).norm() / u_ref.norm();
    eprintln!("hanging plate: bottom {u:?} vs static {u_ref:?}: {err:e}");
    assert!(err < 1e-5, "{u:?} vs {u_ref:?}");
}

/// A plate dropped flat on a half-space rests on its node spheres (radius t/2): the
/// contact force is the weight, the nodes stop, the spheres do not sink.
#[test]
fn dropped_plate_rests_on_the_ground() {
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE),
        ..SystemSettings::default()
    };
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-12,
        max_iterations: 3000,
        record_history: false,
    });
    let mut sys = System::new(settings, Box::new(solver)).unwrap();
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        ContactMaterial::with_friction(0.5),
    ))
    .unwrap();
    let t = 0.01;
    let m = ShellMaterial::isotropic(1.0e8, 0.3, 1000.0).unwrap();
    let mut mesh = ShellMesh::plate(0.2, 0.2, 2, 2, t, m).unwrap();
    let mut q = mesh.coordinates();
    for k in 0..mesh.nodes().len() {
        q[6 * k + 2] += 0.5 * t + 0.01;
    }
    mesh.set_coordinates(&q).unwrap();
    let weight = mesh.total_mass() * GRAVITY_MAGNITUDE;
    let mut item = ShellItem::new("plate", mesh).unwrap();
    item.set_damping(1e-3).unwrap();
    let e = item
        .set_contact_spheres(0.0, ContactMaterial::default())
        .unwrap_err();
    assert!(matches!(e, FeaError::InvalidParameter { ref field, .. } if field == "contact.radius"));
    item.set_contact_spheres(0.5 * t, ContactMaterial::with_friction(0.5))
        .unwrap();
    let idx = sys.add_item(Box::new(item));
    let h = 1e-3;
    for _ in 0..600 {
        sys.step(h).unwrap();
    }
    let (p, g) = (sys.last_problem(), sys.last_gamma());
    let force: f64 = sys
        .proxy_contacts()
        .iter()
        .map(|c| g[p.row_index(c.row)])
        .sum::<f64>()
        / h;
    let item = sys.item::<ShellItem>(idx).unwrap();
    let speed = (0..item.mesh().nodes().len())
        .map(|n| item.node_velocity(NodeId(n)).unwrap().0.norm())
        .fold(0.0, f64::max);
    let pen = item
        .mesh()
        .nodes()
        .iter()
        .map(|n| 0.5 * t - n.position.z)
        .fold(f64::NEG_INFINITY, f64::max);
    eprintln!("plate on ground: force {force} N, weight {weight} N, speed {speed:e}, pen {pen:e}");
    assert!((force / weight - 1.0).abs() < 0.01, "{force} vs {weight}");
    assert!(speed < 1e-4, "still moving at {speed} m/s");
    assert!(pen < 0.01 * 0.5 * t, "penetration {pen} m");
}

/// A steel strip clamped by attachment rows (positions and directors) to a fixed, rotated
/// rigid body sags under gravity to the static solution of the same mesh with its root
/// nodes supported (`fix_node`): the director rows hold the slope at the root.
#[test]
fn strip_clamped_by_director_rows_matches_the_supported_static_solution() {
    let (l, w, t, n) = (1.0, 0.1, 0.01, 8);
    let mesh = ShellMesh::plate(l, w, n, 1, t, steel()).unwrap();
    let root: Vec<NodeId> = (0..2).map(|j| ShellMesh::grid_node(n, 0, j)).collect();
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let mut reference = mesh.clone();
    for &r in &root {
        reference.fix_node(r).unwrap();
    }
    reference.set_gravity(g).unwrap();
    solve_static(&mut reference, &StaticSettings::default()).unwrap();
    let mut sys = system(g);
    let at = Vector3::new(-0.2, 0.05, 0.1);
    let rot = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7);
    let body = sys
        .add_body(RigidBodyBuilder::fixed().position(at).rotation(rot))
        .unwrap();
    let mut item = ShellItem::new("strip", mesh).unwrap();
    item.set_damping(0.02).unwrap();
    for &r in &root {
        let node = *item.mesh().node(r).unwrap();
        item.attach(
            r,
            AttachTarget::Body {
                body,
                local: rot.inverse() * (node.position - at),
            },
        )
        .unwrap();
        item.attach_director(
            r,
            DirectorTarget::Body {
                body,
                local: rot.inverse() * node.slope,
            },
        )
        .unwrap();
    }
    let e = item
        .attach_director(
            root[0],
            DirectorTarget::Fixed(Vector3::new(f64::NAN, 0.0, 1.0)),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("director.target"), "{e}");
    let idx = sys.add_item(Box::new(item));
    for _ in 0..1500 {
        sys.step(1e-3).unwrap();
    }
    let item = sys.item::<ShellItem>(idx).unwrap();
    let tip = ShellMesh::grid_node(n, n, 0);
    let u = item.mesh().node(tip).unwrap().displacement();
    let u_ref = reference.node(tip).unwrap().displacement();
    let err = (u - u_ref).norm() / u_ref.norm();
    eprintln!(
        "clamped strip: tip {:e} m vs static {:e} m: {err:e}",
        u.z, u_ref.z
    );
    assert!(u_ref.z < -1e-3, "{u_ref:?}");
    assert!(err < 1e-5, "{u:?} vs {u_ref:?}");
    for &r in &root {
        let node = item.mesh().node(r).unwrap();
        assert!(
            (node.slope - node.reference_slope).norm() < 1e-9,
            "{:?}",
            node.slope
        );
    }
}
