//! The cable mesh stepping in a `System`: free vibration against the modal frequency, a
//! hanging cable at rest at its static solution (attached by CCP rows), momentum exchange
//! with a rigid body through an attachment.

use chrono_ccp::{Cg, SolverSettings};
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::{RigidBodyBuilder, System, SystemSettings};
use chrono_fea::{
    AttachTarget, BeamMaterial, CableItem, CableMesh, CableQuadrature, NodeId, StaticSettings,
    natural_frequencies, solve_static,
};
use nalgebra::{Matrix3, Vector3};

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

fn steel() -> BeamMaterial {
    BeamMaterial::rectangle(2e11, 7850.0, 0.01, 0.01, 0.0).unwrap()
}

/// Released from a small static tip deflection, the clamped cantilever vibrates at its
/// first natural frequency (modal analysis of the same mesh) within 2 %.
#[test]
fn cantilever_free_vibration_matches_the_modal_frequency() {
    let n = 8;
    let mut mesh = CableMesh::straight(
        Vector3::zeros(),
        Vector3::x(),
        n,
        steel(),
        CableQuadrature::default(),
    )
    .unwrap();
    mesh.clamp(NodeId(0)).unwrap();
    let f_modal = natural_frequencies(&mesh).unwrap()[0];
    let ei = steel().bending_stiffness();
    let p = 3.0 * ei * 1e-3; // 1 mm static tip deflection: P L^3 / (3 E I)
    mesh.set_force(NodeId(n), Vector3::new(0.0, 0.0, -p))
        .unwrap();
    solve_static(
        &mut mesh,
        &StaticSettings {
            load_steps: 1,
            ..Default::default()
        },
    )
    .unwrap();
    mesh.set_force(NodeId(n), Vector3::zeros()).unwrap();
    let mut sys = system(Vector3::zeros());
    let idx = sys.add_item(Box::new(CableItem::new("cantilever", mesh).unwrap()));
    let h = 2e-4;
    let mut prev = -1e-3;
    let mut crossings = Vec::new();
    for s in 0..2500 {
        sys.step(h).unwrap();
        let z = sys.item::<CableItem>(idx).unwrap().mesh().nodes()[n]
            .position
            .z;
        if prev < 0.0 && z >= 0.0 {
            crossings.push((s as f64 + prev / (prev - z)) * h);
        }
        prev = z;
    }
    assert!(crossings.len() >= 3, "{crossings:?}");
    let periods = (crossings.len() - 1) as f64;
    let f = periods / (crossings.last().unwrap() - crossings[0]);
    let err = f / f_modal - 1.0;
    eprintln!("free vibration: {f} Hz, modal {f_modal} Hz, error {err:e}");
    assert!(
        err.abs() < 0.02,
        "f = {f} Hz, modal {f_modal} Hz, err {err}"
    );
}

/// A vertical cable pinned at the top by CCP rows (slope direction supported) starts at
/// its static solution under gravity and stays there; the attachment carries its weight.
#[test]
fn hanging_cable_stays_at_the_static_solution() {
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let build = || {
        CableMesh::straight(
            Vector3::zeros(),
            Vector3::new(0.0, 0.0, -1.0),
            6,
            steel(),
            CableQuadrature::default(),
        )
        .unwrap()
    };
    let mut stat = build();
    stat.clamp(NodeId(0)).unwrap();
    stat.set_gravity(g).unwrap();
    solve_static(&mut stat, &StaticSettings::default()).unwrap();
    let q_static = stat.coordinates();
    assert!(q_static[6 * 6 + 2] < -1.0, "stretched by its weight");

    let mut mesh = build();
    mesh.set_coordinates(&q_static).unwrap();
    mesh.fix_slope_direction(NodeId(0)).unwrap();
    let mut item = CableItem::new("hanging", mesh).unwrap();
    item.attach(NodeId(0), AttachTarget::Point(Vector3::zeros()))
        .unwrap();
    let weight = item.mesh().total_mass() * GRAVITY_MAGNITUDE;
    let mut sys = system(g);
    let idx = sys.add_item(Box::new(item));
    for _ in 0..200 {
        sys.step(1e-3).unwrap();
    }
    let item = sys.item::<CableItem>(idx).unwrap();
    let q = item.mesh().coordinates();
    let drift = q
        .iter()
        .zip(&q_static)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let r = item.reaction(0).unwrap();
    eprintln!("hanging cable: drift {drift:e} m, reaction {r:?}, weight {weight} N");
    assert!(drift < 1e-9, "drift {drift} m");
    assert!((r.z / weight - 1.0).abs() < 1e-6, "{r:?} vs {weight}");
    assert!(r.x.abs() + r.y.abs() < 1e-9 * weight);
}

/// Linear momentum of the uniform straight-element cable, `sum_e rho A L (v_A/2 +
/// L rx_A/12 + v_B/2 - L rx_B/12)` (the weights of the consistent mass), kg m/s.
fn cable_momentum(item: &CableItem) -> Vector3<f64> {
    let mut p = Vector3::zeros();
    for el in item.mesh().elements() {
        let (l, ra) = (el.length(), el.material().mass_per_length());
        let (va, sa) = item.node_velocity(NodeId(el.nodes[0])).unwrap();
        let (vb, sb) = item.node_velocity(NodeId(el.nodes[1])).unwrap();
        p += ra * l * (0.5 * va + l / 12.0 * sa + 0.5 * vb - l / 12.0 * sb);
    }
    p
}

/// A free cable attached to a moving rigid body (no gravity): the body drags it along,
/// total linear momentum is conserved, and the attachment holds.
#[test]
fn attachment_to_a_rigid_body_conserves_momentum() {
    let mesh = CableMesh::straight(
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::new(1.1, 0.0, 0.0),
        4,
        BeamMaterial::rectangle(1e9, 1000.0, 0.01, 0.01, 0.0).unwrap(),
        CableQuadrature::default(),
    )
    .unwrap();
    let mut sys = system(Vector3::zeros());
    let m_body = 2.0;
    let v0 = Vector3::new(0.0, 0.5, 0.2);
    let body = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(m_body)
                .inertia(Matrix3::from_diagonal_element(0.01))
                .linear_velocity(v0),
        )
        .unwrap();
    let mut item = CableItem::new("towed", mesh).unwrap();
    item.attach(
        NodeId(0),
        AttachTarget::Body {
            body,
            local: Vector3::new(0.1, 0.0, 0.0),
        },
    )
    .unwrap();
    let idx = sys.add_item(Box::new(item));
    let p0 = m_body * v0;
    for _ in 0..300 {
        sys.step(1e-3).unwrap();
    }
    let b = sys.body(body).unwrap();
    let item = sys.item::<CableItem>(idx).unwrap();
    let p = m_body * b.linear_velocity() + cable_momentum(item);
    eprintln!(
        "towed cable: momentum error {:e}, body at {:?}",
        (p - p0).norm(),
        b.position()
    );
    assert!((p - p0).norm() < 1e-9 * p0.norm(), "{p:?} vs {p0:?}");
    let anchor = b.pose() * nalgebra::Point3::new(0.1, 0.0, 0.0);
    let gap = (item.mesh().nodes()[0].position - anchor.coords).norm();
    eprintln!("attachment gap {gap:e} m");
    assert!(gap < 1e-6, "attachment gap {gap} m");
    assert!(b.position().y > 0.05, "the body moved: {:?}", b.position());
}
