//! Slope attachments of a cable node to a rigid body (CCP rows): a cantilever clamped to
//! a fixed body matches the clamped static solution and the clamp couple is the moment of
//! the load; a clamped tangent follows a body that rotates (kinematic, and dynamic driven
//! by a motor); a body on a revolute joint receives the bending moment.

use chrono_ccp::{Cg, Schur, SolverSettings};
use chrono_core::joint::{Drive, JointBuilder, JointKind};
use chrono_core::{BodyHandle, RigidBodyBuilder, System, SystemSettings};
use chrono_fea::{
    AttachTarget, BeamMaterial, CableItem, CableMesh, CableQuadrature, NodeId, SlopeTarget,
    StaticSettings, solve_static,
};
use nalgebra::{Matrix3, Point3, UnitQuaternion, Vector3};

fn system() -> System {
    let solver = Cg::new(SolverSettings {
        tolerance: 1e-12,
        max_iterations: 1000,
        record_history: false,
    });
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    System::new(settings, Box::new(solver)).unwrap()
}

fn steel() -> BeamMaterial {
    BeamMaterial::rectangle(2e11, 7850.0, 0.01, 0.01, 0.0).unwrap()
}

const N: usize = 8;

/// A free straight cable from the origin along x, length 1 m.
fn cable() -> CableMesh {
    CableMesh::straight(
        Vector3::zeros(),
        Vector3::x(),
        N,
        steel(),
        CableQuadrature::default(),
    )
    .unwrap()
}

/// Clamp node 0 of `mesh` to `body` at world point 0 with the slope along world x, given
/// the body's pose now.
fn clamped(sys: &System, body: BodyHandle, mesh: CableMesh) -> CableItem {
    let b = sys.body(body).unwrap();
    let local = b.pose().inverse() * Point3::origin();
    let dir = b.rotation().inverse() * Vector3::x();
    let mut item = CableItem::new("cable", mesh).unwrap();
    item.attach(
        NodeId(0),
        AttachTarget::Body {
            body,
            local: local.coords,
        },
    )
    .unwrap();
    item.attach_slope(NodeId(0), SlopeTarget::Body { body, local: dir })
        .unwrap();
    item
}

/// Angle between the slope of node 0 and the body's direction `R x_B` (the clamp's
/// world x at creation), rad.
fn tangent_error(
    sys: &System,
    body: BodyHandle,
    item: chrono_core::item::ItemHandle,
    r0: &UnitQuaternion<f64>,
) -> f64 {
    let b = sys.body(body).unwrap();
    let want = b.rotation() * (r0.inverse() * Vector3::x());
    let s = sys.item::<CableItem>(item).unwrap().mesh().nodes()[0].slope;
    s.normalize().cross(&want).norm().asin()
}

/// A cantilever clamped (position and slope rows) to a fixed, rotated and offset body
/// under a small tip load settles at the static solution of the supported clamp
/// (`CableMesh::clamp`), within 1 % of Euler–Bernoulli, and the clamp couple is the
/// moment of the load about the clamp.
#[test]
fn clamp_to_a_fixed_body_matches_the_static_cantilever() {
    let ei = steel().bending_stiffness();
    let p = 3.0 * ei * 1e-3; // 1 mm tip deflection: P L^3 / (3 E I)
    let load = Vector3::new(0.0, 0.0, -p);
    let mut reference = cable();
    reference.clamp(NodeId(0)).unwrap();
    reference.set_force(NodeId(N), load).unwrap();
    solve_static(&mut reference, &StaticSettings::default()).unwrap();
    let tip_static = reference.nodes()[N].displacement();

    let mut sys = system();
    let rot = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.5, 0.4));
    let body = sys
        .add_body(
            RigidBodyBuilder::fixed()
                .position(Vector3::new(-0.2, 0.1, 0.05))
                .rotation(rot),
        )
        .unwrap();
    let mut mesh = cable();
    mesh.set_force(NodeId(N), load).unwrap();
    let idx = sys.add_item(Box::new(clamped(&sys, body, mesh)));
    for _ in 0..200 {
        sys.step(0.02).unwrap();
    }
    let item = sys.item::<CableItem>(idx).unwrap();
    let nodes = item.mesh().nodes();
    let tip = nodes[N].displacement();
    let eb = p / (3.0 * ei);
    eprintln!(
        "clamp to a fixed body: tip {tip:?}, static clamp {tip_static:?}, EB {eb:e}; couple {:?}",
        item.slope_reaction(0)
    );
    assert!(
        (tip - tip_static).norm() < 1e-6 * tip_static.norm(),
        "{tip:?} vs {tip_static:?}"
    );
    assert!((-tip.z / eb - 1.0).abs() < 0.01, "{} vs {eb}", -tip.z);
    // Equilibrium of the whole cable: clamp force -F, clamp couple -(r_tip - r_0) x F.
    let couple = item.slope_reaction(0).unwrap();
    let expect = -(nodes[N].position - nodes[0].position).cross(&load);
    assert!(
        (couple - expect).norm() < 1e-6 * expect.norm(),
        "{couple:?} vs {expect:?}"
    );
    assert!((expect.norm() / p - 1.0).abs() < 1e-5, "moment arm ~ L");
    let force = item.reaction(0).unwrap();
    assert!((force + load).norm() < 1e-6 * p, "{force:?}");
}

/// Spin `body` for a quarter turn at `omega` about z and return the largest tangent
/// error over the steps.
fn spin(
    sys: &mut System,
    body: BodyHandle,
    idx: chrono_core::item::ItemHandle,
    omega: f64,
    h: f64,
) -> f64 {
    let r0 = sys.body(body).unwrap().rotation();
    let steps = (0.5 * std::f64::consts::PI / omega / h).round() as usize;
    let mut worst: f64 = 0.0;
    for _ in 0..steps {
        sys.step(h).unwrap();
        worst = worst.max(tangent_error(sys, body, idx, &r0));
    }
    let turned = sys.body(body).unwrap().rotation().angle_to(&r0);
    assert!(
        (turned - 0.5 * std::f64::consts::PI).abs() < 0.01,
        "{turned}"
    );
    worst
}

/// The clamped tangent follows a kinematic body spinning at a constant rate to the
/// linearization error of the rows, `~ (omega h)^2`; without the slope rows (a pin at
/// the rotation centre) the cable does not turn at all.
#[test]
fn clamped_tangent_follows_a_spinning_kinematic_body() {
    let (omega, h) = (2.0, 1e-3);
    let build = |slope: bool| {
        let mut sys = system();
        let body = sys
            .add_body(RigidBodyBuilder::kinematic().angular_velocity(Vector3::new(0.0, 0.0, omega)))
            .unwrap();
        let item = if slope {
            clamped(&sys, body, cable())
        } else {
            let mut it = CableItem::new("pinned", cable()).unwrap();
            it.attach(
                NodeId(0),
                AttachTarget::Body {
                    body,
                    local: Vector3::zeros(),
                },
            )
            .unwrap();
            it
        };
        let idx = sys.add_item(Box::new(item));
        (sys, body, idx)
    };
    let (mut sys, body, idx) = build(true);
    let worst = spin(&mut sys, body, idx, omega, h);
    eprintln!("kinematic spin: max tangent error {worst:e} rad");
    assert!(worst < 1e-5, "{worst}");
    let tip = sys.item::<CableItem>(idx).unwrap().mesh().nodes()[N].position;
    assert!(
        tip.y > 0.9 && tip.x.abs() < 0.1,
        "the cable turned: {tip:?}"
    );
    let (mut sys, body, idx) = build(false);
    let worst = spin(&mut sys, body, idx, omega, h);
    assert!(worst > 1.0, "a pinned cable does not turn: {worst}");
}

/// The same with a dynamic body driven by a speed motor on a revolute joint: the rows
/// act on the body's block and the motor supplies the torque that spins the cable up.
/// (The motor's row is a box row: the Schur solver, not conjugate gradients.)
#[test]
fn clamped_tangent_follows_a_motor_driven_body() {
    let (omega, h) = (2.0, 1e-3);
    let mut sys = system();
    sys.set_solver(Box::new(Schur::new(SolverSettings {
        tolerance: 1e-12,
        max_iterations: 1000,
        record_history: false,
    })));
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let body = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(1.0)
                .inertia(Matrix3::from_diagonal_element(1e-3))
                .angular_velocity(Vector3::new(0.0, 0.0, omega)),
        )
        .unwrap();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::RotationalMotor {
            drive: Drive::Speed(omega),
            max_torque: f64::INFINITY,
            limits: None,
        },
        ground,
        body,
        Vector3::zeros(),
        Vector3::z(),
    ))
    .unwrap();
    let idx = sys.add_item(Box::new(clamped(&sys, body, cable())));
    let worst = spin(&mut sys, body, idx, omega, h);
    let w = sys.body(body).unwrap().angular_velocity();
    eprintln!("motor spin: max tangent error {worst:e} rad, body omega {w:?}");
    assert!(worst < 1e-5, "{worst}");
    assert!((w.z - omega).abs() < 1e-6, "{w:?}");
}

/// A body on a revolute joint (axis y through its centre) with a cantilever clamped to
/// it under a tip load `P`: the rows pass the bending moment `P L` to the body, so an
/// opposite applied torque `-P L` holds it still; without it body and cable turn
/// together as one rigid body, `theta = P L t^2 / (2 (J + rho A L^3 / 3))` (the cable's
/// inertia about the hinge counts: the rows carry its angular acceleration too).
#[test]
fn body_on_a_revolute_joint_receives_the_bending_moment() {
    let ei = steel().bending_stiffness();
    let p = 3.0 * ei * 1e-3;
    let run = |torque: f64| {
        let mut sys = system();
        let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
        let body = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(1.0)
                    .inertia(Matrix3::from_diagonal_element(10.0)),
            )
            .unwrap();
        sys.add_joint(JointBuilder::at_axis(
            JointKind::Revolute,
            ground,
            body,
            Vector3::zeros(),
            Vector3::y(),
        ))
        .unwrap();
        sys.body_mut(body)
            .unwrap()
            .set_applied_torque(Vector3::new(0.0, torque, 0.0))
            .unwrap();
        let mut mesh = cable();
        mesh.set_force(NodeId(N), Vector3::new(0.0, 0.0, -p))
            .unwrap();
        let idx = sys.add_item(Box::new(clamped(&sys, body, mesh)));
        for _ in 0..100 {
            sys.step(0.01).unwrap();
        }
        let angle = sys.body(body).unwrap().rotation().scaled_axis().y;
        let couple = sys
            .item::<CableItem>(idx)
            .unwrap()
            .slope_reaction(0)
            .unwrap();
        (angle, couple)
    };
    let (held, couple) = run(-p);
    let (free, _) = run(0.0);
    let inertia = 10.0 + steel().mass_per_length() / 3.0;
    let rigid = p * 0.5 / inertia; // t = 1 s
    eprintln!(
        "revolute: angle with -P L {held:e} rad, without {free:e} rad (rigid {rigid:e}); couple {couple:?}"
    );
    assert!(held.abs() < 1e-3 * free, "{held}");
    // Within 1.5 %: the cable is not quite rigid (1 mm static deflection); without its
    // inertia the estimate would be 2.6 % higher.
    assert!((free / rigid - 1.0).abs() < 0.015, "{free} vs {rigid}");
    assert!((couple.y / -p - 1.0).abs() < 1e-3, "{couple:?}");
}
