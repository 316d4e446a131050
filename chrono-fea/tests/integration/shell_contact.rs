//! Contact through a shell's faces (`ShellItem::set_contact_faces`): a ball smaller than
//! an element rests on the element's face, where the node spheres let it through.

use chrono_ccp::{Schur, SolverSettings};
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fea::{AttachTarget, NodeId, ShellItem, ShellMaterial, ShellMesh};
use nalgebra::{Isometry3, Vector3};

const BALL_RADIUS: f64 = 0.05;
const BALL_MASS: f64 = 2.0;
const T: f64 = 0.01;

/// One 0.4 x 0.4 m element with its corners pinned at `z = 0`, a ball of radius 5 cm above
/// its middle; returns the system, the ball and the plate's item index.
fn ball_over_one_element(faces: bool) -> (System, BodyHandle, chrono_core::item::ItemHandle) {
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE),
        ..SystemSettings::default()
    };
    let solver = Schur::new(SolverSettings {
        tolerance: 1e-10,
        max_iterations: 2000,
        record_history: false,
    });
    let mut sys = System::new(settings, Box::new(solver)).unwrap();
    let m = ShellMaterial::isotropic(1.0e9, 0.3, 1000.0).unwrap();
    let mesh = ShellMesh::plate(0.4, 0.4, 1, 1, T, m).unwrap();
    let centre = mesh
        .nodes()
        .iter()
        .map(|n| n.position)
        .sum::<Vector3<f64>>()
        / 4.0;
    let corners: Vec<_> = mesh.nodes().iter().map(|n| n.position).collect();
    let mut item = ShellItem::new("plate", mesh).unwrap();
    item.set_damping(1e-3).unwrap();
    let material = ContactMaterial::with_friction(0.3);
    if faces {
        item.set_contact_faces(0.5 * T, material).unwrap();
    } else {
        item.set_contact_spheres(0.5 * T, material).unwrap();
    }
    for (k, x) in corners.into_iter().enumerate() {
        item.attach(NodeId(k), AttachTarget::Point(x)).unwrap();
    }
    let plate = sys.add_item(Box::new(item));
    let r = BALL_RADIUS;
    let inertia = 0.4 * BALL_MASS * r * r;
    let ball = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .name("ball")
                .mass(BALL_MASS)
                .inertia_diagonal(Vector3::repeat(inertia))
                .position(centre + Vector3::new(0.0, 0.0, 0.5 * T + r + 0.02))
                .collider(Shape::Sphere { radius: r }, Isometry3::identity(), material),
        )
        .unwrap();
    (sys, ball, plate)
}

#[test]
fn a_ball_smaller_than_an_element_rests_on_its_face() {
    let h = 1e-3;
    let (mut sys, ball, plate) = ball_over_one_element(true);
    let z_plate = 0.0;
    for _ in 0..600 {
        sys.step(h).unwrap();
    }
    let b = sys.body(ball).unwrap();
    let (z, vz) = (b.position().z, b.linear_velocity().z);
    // The ball rests on the plate's upper face, which sags a little under it.
    let item = sys.item::<ShellItem>(plate).unwrap();
    assert_eq!(item.mesh().nodes().len(), 4);
    assert!(z > z_plate + BALL_RADIUS, "the ball went through: z = {z}");
    assert!(z < z_plate + 0.5 * T + BALL_RADIUS + 1e-3, "z = {z}");
    assert!(vz.abs() < 1e-3, "still moving at {vz} m/s");
    // The face contacts carry the ball's weight.
    let (p, g) = (sys.last_problem(), sys.last_gamma());
    let force: f64 = (sys.proxy_contacts().iter())
        .map(|c| g[p.row_index(c.row)])
        .sum::<f64>()
        / h;
    let weight = BALL_MASS * GRAVITY_MAGNITUDE;
    assert!((force / weight - 1.0).abs() < 0.01, "{force} vs {weight}");
}

#[test]
fn node_spheres_let_a_ball_smaller_than_an_element_through() {
    // The contrast that motivates the faces: the same drop on node spheres.
    let (mut sys, ball, _) = ball_over_one_element(false);
    for _ in 0..300 {
        sys.step(1e-3).unwrap();
    }
    let z = sys.body(ball).unwrap().position().z;
    assert!(z < -BALL_RADIUS, "the ball was held at z = {z}");
}
