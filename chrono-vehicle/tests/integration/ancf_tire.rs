//! The ANCF shell tire as a vehicle tire: mounted on a spindle at any pose, moved with it
//! by `set_forward_speed`, carrying the vehicle's weight (`TireKind::Ancf`).

use std::sync::Arc;

use chrono_ccp::{Schur, SolverSettings};
use chrono_core::math::{Isometry3, UnitQuaternion, Vector3};
use chrono_core::{ContactMaterial, RigidBodyBuilder, System, SystemSettings};
use chrono_fea::ShellItem;
use chrono_vehicle::hmmwv::{TireKind, hmmwv_data_with};
use chrono_vehicle::terrain::{FlatTerrain, Terrain};
use chrono_vehicle::tire::{AncfTireData, Tire};
use chrono_vehicle::{VehicleData, WheeledVehicle};

fn schur() -> Box<Schur> {
    Box::new(Schur::new(SolverSettings {
        tolerance: 1e-10,
        max_iterations: 2000,
        record_history: false,
    }))
}

fn coarse() -> AncfTireData {
    AncfTireData {
        n_around: 12,
        n_across: 3,
        ..AncfTireData::hmmwv()
    }
}

/// The largest speed of any node of `item`, m/s.
fn max_node_speed(item: &ShellItem) -> f64 {
    (0..item.mesh().nodes().len())
        .map(|k| item.node_velocity(chrono_fea::NodeId(k)).unwrap().0.norm())
        .fold(0.0, f64::max)
}

#[test]
fn a_tire_mounted_on_a_turned_spindle_stays_in_equilibrium() {
    // No gravity: the inflated carcass is in equilibrium with its beads where the rim holds
    // them. Bead targets taken in the wrong frame would be centimetres off and the
    // attachment rows would fling the nodes at (offset / h) m/s.
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, schur()).unwrap();
    let turn = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7);
    let spindle = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .name("spindle")
                .mass(18.8)
                .inertia_diagonal(Vector3::new(0.46, 0.62, 0.46))
                .position(Vector3::new(1.0, -2.0, 3.0))
                .rotation(turn),
        )
        .unwrap();
    let model = coarse().inflate().unwrap();
    let h = model.mount(&mut sys, "tire", spindle).unwrap();
    let h_step = 2e-3;
    for _ in 0..5 {
        sys.step(h_step).unwrap();
    }
    let item = sys.item::<ShellItem>(h).unwrap();
    let v = max_node_speed(item);
    assert!(v < 1e-3, "largest node speed {v} m/s");
    // The carcass sits around the spindle's turned axle: every bead node at the rim radius
    // from the axle line.
    let axle = turn * Vector3::y();
    let x = sys.body(spindle).unwrap().position();
    for &n in model.tire().beads.iter().flatten() {
        let r = item.mesh().node(n).unwrap().position - x;
        let radial = (r - axle * axle.dot(&r)).norm();
        assert!((radial - coarse().rim_radius).abs() < 1e-4, "{radial}");
    }
}

fn hmmwv_on_flat(data: &VehicleData) -> (System, WheeledVehicle) {
    let mut sys = System::new(SystemSettings::default(), schur()).unwrap();
    let terrain = Arc::new(FlatTerrain::new(0.0, 0.9).unwrap());
    terrain
        .add_to_system(&mut sys, ContactMaterial::with_friction(0.9))
        .unwrap();
    let z0 = chrono_vehicle::scene::start_height(data, 0.0, 0.02);
    let v = WheeledVehicle::build(
        &mut sys,
        data,
        &Isometry3::translation(0.0, 0.0, z0),
        terrain,
    )
    .unwrap();
    (sys, v)
}

#[test]
fn set_forward_speed_moves_each_carcass_with_its_spindle() {
    let mut data = hmmwv_data_with(TireKind::Ancf).unwrap();
    data.wheel.tire = Tire::Ancf(coarse());
    let (mut sys, v) = hmmwv_on_flat(&data);
    assert!(v.wheels().iter().all(|w| w.shell.is_some()));
    let speed = 3.0;
    v.set_forward_speed(&mut sys, speed).unwrap();
    for w in v.wheels() {
        let b = sys.body(w.spindle).unwrap();
        let (x, vs, omega) = (b.position(), b.linear_velocity(), b.angular_velocity());
        assert!(omega.norm() > speed / 0.5, "spindle spin {omega}");
        let item = sys.item::<ShellItem>(w.shell.unwrap()).unwrap();
        for (k, node) in item.mesh().nodes().iter().enumerate() {
            let (got, rate) = item.node_velocity(chrono_fea::NodeId(k)).unwrap();
            let rigid = vs + omega.cross(&(node.position - x));
            assert!((got - rigid).norm() < 1e-12, "node {k}: {got} vs {rigid}");
            assert!((rate - omega.cross(&node.slope)).norm() < 1e-12, "node {k}");
        }
    }
    // One step in the air: the spindles drop as the springs extend (a few 0.1 m/s), the
    // carcasses go on rolling forward with them; a carcass left at rest would read ~0.
    sys.step(1e-3).unwrap();
    for w in v.wheels() {
        let item = sys.item::<ShellItem>(w.shell.unwrap()).unwrap();
        let n = item.mesh().nodes().len();
        let mean_vx = (0..n)
            .map(|k| item.node_velocity(chrono_fea::NodeId(k)).unwrap().0.x)
            .sum::<f64>()
            / n as f64;
        assert!((mean_vx - speed).abs() < 0.02 * speed, "{mean_vx}");
    }
}

#[test]
fn the_carcass_mass_is_part_of_the_vehicle_and_not_of_its_spindles() {
    let rigid = hmmwv_data_with(TireKind::Rigid).unwrap();
    let ancf = hmmwv_data_with(TireKind::Ancf).unwrap();
    // Both tires weigh 37.6 kg: the vehicle's mass is the same, but the ANCF carcass' mass
    // is in its nodes, not on the spindle.
    assert!((rigid.total_mass() - ancf.total_mass()).abs() < 1e-9);
    assert!((ancf.wheel.spindle_mass().mass - ancf.wheel.rim.mass).abs() < 1e-12);
    assert!((rigid.wheel.spindle_mass().mass - rigid.wheel.rim.mass - 37.6).abs() < 1e-9);
}

#[test]
fn bad_ancf_tire_data_names_the_field() {
    let mut data = hmmwv_data_with(TireKind::Ancf).unwrap();
    let Tire::Ancf(t) = &mut data.wheel.tire else {
        panic!("an ANCF tire")
    };
    t.pressure = -2e5;
    let e = data.validate().unwrap_err().to_string();
    assert!(e.contains("ancf_tire.pressure"), "{e}");
    let json = serde_json::to_string(&data).unwrap();
    let e = VehicleData::from_json(&json, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("ancf_tire.pressure"), "{e}");
}

#[test]
fn inside_ancf_tire_tells_the_cavity_from_the_outside() {
    let mut data = hmmwv_data_with(TireKind::Ancf).unwrap();
    data.wheel.tire = Tire::Ancf(coarse());
    let (sys, v) = hmmwv_on_flat(&data);
    let g = coarse().geometry(Vector3::zeros()).unwrap();
    let r_mid = g.ring_radius + g.section_radius;
    for (i, w) in v.wheels().iter().enumerate() {
        let x = sys.body(w.spindle).unwrap().position();
        // Down, forward, and between two rings of nodes (15 degrees off a ring).
        let a = 15f64.to_radians();
        for dir in [
            Vector3::new(0.0, 0.0, -1.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(a.cos(), 0.0, -a.sin()),
        ] {
            let inside = |q: Vector3<f64>| v.inside_ancf_tire(&sys, i, &q).unwrap();
            // The section's centre; just inside and outside the tread's mid surface (the
            // chord between rings lies up to 1.4 cm inside the circle at 12 around).
            assert!(inside(x + dir * g.ring_radius));
            assert!(inside(x + dir * (r_mid - 0.03)));
            assert!(!inside(x + dir * (r_mid + 0.01)));
            // Beside the sidewall, outside; the hub (inside the rim), outside.
            let out = Vector3::new(0.0, g.section_radius + 0.02, 0.0);
            assert!(!inside(x + dir * g.ring_radius + out));
            assert!(!inside(x + dir * g.ring_radius - out));
            assert!(!inside(x + dir * (0.5 * g.bead_radius())));
        }
        assert!(
            !v.inside_ancf_tire(&sys, i, &(x + Vector3::new(0.0, 0.0, -3.0)))
                .unwrap()
        );
    }
}
