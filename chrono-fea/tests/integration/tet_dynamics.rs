//! A tetrahedral mesh stepping in a `System` (implicit Euler in the CCP): free vibration
//! against the modal frequency of the same mesh, momentum of a free block, a damped
//! block settling at its static solution, a block hanging from attachment rows, a block
//! resting on the ground through its surface-node contact spheres.

use chrono_ccp::{Apgd, Cg, SolverSettings};
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::math::Isometry3;
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fea::{
    AttachTarget, BoxMesh, FeaError, HexSplit, NodeId, SolidMaterial, StaticSettings, TetItem,
    natural_frequencies, solve_static,
};
use nalgebra::Vector3;

fn system(gravity: Vector3<f64>) -> System {
    let settings = SystemSettings {
        gravity,
        ..SystemSettings::default()
    };
    let solver = Cg::new(SolverSettings {
        tolerance: 1e-12,
        max_iterations: 500,
        record_history: false,
    });
    System::new(settings, Box::new(solver)).unwrap()
}

/// Released from a static tip deflection, the clamped tetrahedral cantilever (a section
/// twice as wide as high, so the first mode is the bending along the load and the
/// sideways one is far above it) vibrates at the first natural frequency of the same mesh (`K v = w^2 M v`), within 1 %; the
/// energy never grows (backward Euler only dissipates).
#[test]
fn cantilever_free_vibration_matches_the_modal_frequency() {
    let m = SolidMaterial::new(2.0e11, 0.3, 7850.0, 0.0).unwrap();
    let b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(1.0, 0.2, 0.1),
        [10, 2, 1],
        HexSplit::Five,
    )
    .unwrap();
    let mut mesh = b.into_mesh(m).unwrap();
    for &n in &b.faces.x_min {
        mesh.fix_node(n).unwrap();
    }
    let modes = natural_frequencies(&mesh).unwrap();
    let f_modal = modes[0];
    mesh.add_traction(&b.faces.x_max, Vector3::new(0.0, 0.0, -5e4))
        .unwrap();
    solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 1,
            ..Default::default()
        },
    )
    .unwrap();
    for &n in &b.faces.x_max {
        mesh.set_force(n, Vector3::zeros()).unwrap();
    }
    let tip = b.faces.x_max[0];
    let z0 = mesh.node(tip).unwrap().displacement().z;
    assert!(z0 < 0.0);
    let strain0 = mesh.strain_energy();
    let mut sys = system(Vector3::zeros());
    let idx = sys.add_item(Box::new(TetItem::new("bar", mesh).unwrap()));
    let h = 2e-5;
    let mut prev = z0;
    let mut crossings = Vec::new();
    for s in 0..2000 {
        sys.step(h).unwrap();
        let item = sys.item::<TetItem>(idx).unwrap();
        let z = item.mesh().node(tip).unwrap().displacement().z;
        if prev < 0.0 && z >= 0.0 {
            crossings.push((s as f64 + prev / (prev - z)) * h);
        }
        prev = z;
        let energy = item.kinetic_energy() + item.strain_energy();
        assert!(
            energy <= strain0 * (1.0 + 1e-9),
            "step {s}: {energy} > {strain0}"
        );
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let f = (crossings.len() - 1) as f64 / (crossings.last().unwrap() - crossings[0]);
    let err = f / f_modal - 1.0;
    eprintln!("tet free vibration: {f} Hz, modal {f_modal} Hz, error {err:e}");
    assert!(err.abs() < 0.01, "f = {f} Hz, modal {f_modal} Hz");
}

/// A free block (no supports, no gravity) hit at one node keeps its linear momentum to
/// round-off (internal forces cancel, `K` annihilates translations), and its centre of
/// mass moves uniformly.
#[test]
fn free_block_conserves_momentum() {
    let m = SolidMaterial::new(1.0e6, 0.3, 1000.0, 0.0).unwrap();
    let b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(0.2, 0.1, 0.1),
        [2, 1, 1],
        HexSplit::Six,
    )
    .unwrap();
    let mesh = b.into_mesh(m).unwrap();
    let mass = mesh.total_mass();
    let mut item = TetItem::new("block", mesh).unwrap();
    item.set_node_velocity(NodeId(0), Vector3::new(1.0, -0.5, 2.0))
        .unwrap();
    let p0 = item.linear_momentum();
    let centre = |it: &TetItem| -> Vector3<f64> {
        // Centre of mass = consistent-mass weighted mean = rho V-weighted element centroids.
        let nodes = it.mesh().nodes();
        it.mesh()
            .elements()
            .iter()
            .map(|e| {
                e.nodes
                    .iter()
                    .map(|&n| nodes[n].position)
                    .sum::<Vector3<f64>>()
                    * (e.mass() / 4.0)
            })
            .sum::<Vector3<f64>>()
            / mass
    };
    let c0 = centre(&item);
    let mut sys = system(Vector3::zeros());
    let idx = sys.add_item(Box::new(item));
    let h = 1e-4;
    let steps = 300;
    for _ in 0..steps {
        sys.step(h).unwrap();
    }
    let item = sys.item::<TetItem>(idx).unwrap();
    let p = item.linear_momentum();
    assert!((p - p0).norm() < 1e-13 * p0.norm(), "{p:?} vs {p0:?}");
    let moved = centre(item) - c0;
    let expected = p0 / mass * (h * steps as f64);
    assert!(
        (moved - expected).norm() < 1e-12,
        "{moved:?} vs {expected:?}"
    );
}

/// A damped block hanging from its top face under gravity comes to rest at the static
/// solution of the same mesh (St. Venant–Kirchhoff, Newton).
#[test]
fn damped_block_settles_at_the_static_solution() {
    let m = SolidMaterial::new(1.0e6, 0.3, 1000.0, 2e-3).unwrap();
    let b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(0.1, 0.1, 0.2),
        [2, 2, 4],
        HexSplit::Six,
    )
    .unwrap();
    let mut mesh = b.into_mesh(m).unwrap();
    for &n in &b.faces.z_max {
        mesh.fix_node(n).unwrap();
    }
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let mut reference = mesh.clone();
    reference.set_gravity(g).unwrap();
    solve_static(&mut reference, &StaticSettings::default()).unwrap();
    let mut sys = system(g);
    let idx = sys.add_item(Box::new(TetItem::new("block", mesh).unwrap()));
    for _ in 0..1500 {
        sys.step(1e-3).unwrap();
    }
    let item = sys.item::<TetItem>(idx).unwrap();
    let bottom = b.faces.z_min[4];
    let u_dyn = item.mesh().node(bottom).unwrap().displacement();
    let u_static = reference.node(bottom).unwrap().displacement();
    assert!(u_static.z < -1e-4, "{u_static:?}");
    let err = (u_dyn - u_static).norm() / u_static.norm();
    eprintln!(
        "settled {:e} m vs static {:e} m: {err:e}",
        u_dyn.z, u_static.z
    );
    assert!(err < 1e-6, "dynamic {u_dyn:?} vs static {u_static:?}");
}

/// The soft block of the settling test, hanging from its top face by attachment rows to
/// fixed points instead of supports: at rest, the attachment forces carry the weight and
/// the shape is the supported static solution.
#[test]
fn block_hangs_from_attachment_rows() {
    let m = SolidMaterial::new(1.0e6, 0.3, 1000.0, 2e-3).unwrap();
    let b = BoxMesh::new(
        Vector3::zeros(),
        Vector3::new(0.1, 0.1, 0.2),
        [2, 2, 4],
        HexSplit::Six,
    )
    .unwrap();
    let mesh = b.into_mesh(m).unwrap();
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let weight = mesh.total_mass() * GRAVITY_MAGNITUDE;
    let mut reference = mesh.clone();
    for &n in &b.faces.z_max {
        reference.fix_node(n).unwrap();
    }
    reference.set_gravity(g).unwrap();
    solve_static(&mut reference, &StaticSettings::default()).unwrap();
    let mut item = TetItem::new("block", mesh).unwrap();
    for &n in &b.faces.z_max {
        let p = item.mesh().node(n).unwrap().position;
        item.attach(n, AttachTarget::Point(p)).unwrap();
    }
    let e = item
        .attach(
            NodeId(0),
            AttachTarget::Point(Vector3::new(f64::NAN, 0.0, 0.0)),
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("attachment.point"), "{e}");
    let mut sys = system(g);
    let idx = sys.add_item(Box::new(item));
    for _ in 0..1500 {
        sys.step(1e-3).unwrap();
    }
    let item = sys.item::<TetItem>(idx).unwrap();
    let total: Vector3<f64> = (0..b.faces.z_max.len())
        .map(|i| item.reaction(i).unwrap())
        .sum();
    // The rows pull the nodes up: the force on the nodes is +z.
    let err = total.z / weight - 1.0;
    eprintln!(
        "attachment force {:.9} N, weight {weight:.9} N, error {err:e}",
        total.z
    );
    assert!(
        err.abs() < 1e-9,
        "attachment force {total:?}, weight {weight}"
    );
    let bottom = b.faces.z_min[4];
    let u = item.mesh().node(bottom).unwrap().displacement();
    let u_ref = reference.node(bottom).unwrap().displacement();
    let err = (u - u_ref).norm() / u_ref.norm();
    assert!(err < 1e-6, "{u:?} vs {u_ref:?}");
}

/// A block dropped on a fixed half-space comes to rest on its bottom-face spheres: the
/// contact force equals the weight, the nodes stop, the spheres do not sink.
#[test]
fn dropped_block_rests_on_the_ground() {
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
    let m = SolidMaterial::new(1.0e6, 0.3, 1000.0, 2e-3).unwrap();
    let r = 0.005;
    let b = BoxMesh::new(
        Vector3::new(0.0, 0.0, r + 0.02),
        Vector3::new(0.2, 0.1, 0.05),
        [4, 2, 1],
        HexSplit::Six,
    )
    .unwrap();
    let mesh = b.into_mesh(m).unwrap();
    let weight = mesh.total_mass() * GRAVITY_MAGNITUDE;
    let mut item = TetItem::new("block", mesh).unwrap();
    assert_eq!(item.surface_nodes().len(), item.mesh().nodes().len());
    let e = item
        .set_contact_spheres(-1.0, ContactMaterial::default())
        .unwrap_err();
    assert!(matches!(e, FeaError::InvalidParameter { ref field, .. } if field == "contact.radius"));
    item.set_contact_spheres(r, ContactMaterial::with_friction(0.5))
        .unwrap();
    let idx = sys.add_item(Box::new(item));
    let h = 1e-3;
    for _ in 0..800 {
        sys.step(h).unwrap();
    }
    let (p, g) = (sys.last_problem(), sys.last_gamma());
    let force: f64 = sys
        .proxy_contacts()
        .iter()
        .map(|c| g[p.row_index(c.row)])
        .sum::<f64>()
        / h;
    let item = sys.item::<TetItem>(idx).unwrap();
    let speed = (0..item.mesh().nodes().len())
        .map(|n| item.node_velocity(NodeId(n)).unwrap().norm())
        .fold(0.0, f64::max);
    let pen = item
        .mesh()
        .nodes()
        .iter()
        .map(|n| r - n.position.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let err = force / weight - 1.0;
    eprintln!(
        "block on ground: force {force:.6} N, weight {weight:.6} N, error {err:e}, speed {speed:e} m/s, penetration {pen:e} m"
    );
    assert!(
        err.abs() < 0.01,
        "contact force {force} N, weight {weight} N"
    );
    assert!(speed < 1e-4, "still moving at {speed} m/s");
    assert!(pen < 0.01 * r, "penetration {pen} m");
}
