//! Shafts in the system's CCP (`chrono_vehicle::driveline::shafts`) with a real solver:
//! each test checks dynamics that fail if a row, its sign or its bound is wrong.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::math::{UnitQuaternion, Vector3};
use chrono_core::{RigidBodyBuilder, System, SystemSettings};
use chrono_vehicle::driveline::{ShaftId, ShaftSystem};

const H: f64 = 1e-3;

fn system() -> System {
    let s = SolverSettings {
        tolerance: 1e-12,
        max_iterations: 2000,
        record_history: false,
    };
    let settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    System::new(settings, Box::new(Apgd::new(s))).unwrap()
}

fn shafts(sys: &mut System, idx: chrono_core::item::ItemHandle) -> &mut ShaftSystem {
    sys.item_mut::<ShaftSystem>(idx).unwrap()
}

/// Gear `w_a = r w_b` with a torque on `a`. Eliminating the impulse from
/// `J_a w_a+ = J_a w_a + h T + g` and `J_b w_b+ = J_b w_b - r g` gives the invariant
/// `L = r J_a w_a + J_b w_b`, which changes by `r T h` per step (also through the first
/// step, which projects inconsistent initial speeds onto the gear). After it the pair is
/// one body of inertia `J_eff = r^2 J_a + J_b`, and the kinetic energy changes by the
/// trapezoidal work `T h (w_a + w_a+)/2` each step.
#[test]
fn gear_pair_holds_the_ratio_and_its_momentum() {
    let (ja, jb, r, t) = (0.7, 2.5, -0.3, 40.0);
    let mut s = ShaftSystem::new("gears");
    let a = s.add_shaft("a", ja).unwrap();
    let b = s.add_shaft("b", jb).unwrap();
    let gear = s.add_gear(a, b, r).unwrap();
    s.set_speed(a, 5.0).unwrap();
    s.set_speed(b, 3.0).unwrap();
    s.set_torque(a, t).unwrap();
    let mut l = r * ja * 5.0 + jb * 3.0;
    let mut sys = system();
    let i = sys.add_item(Box::new(s));
    let jeff = r * r * ja + jb;
    let mut prev: Option<(f64, f64)> = None;
    for n in 0..500 {
        sys.step(H).unwrap();
        l += r * t * H;
        let s = shafts(&mut sys, i);
        let (wa, wb) = (s.speed(a), s.speed(b));
        assert!((wa - r * wb).abs() < 1e-9, "ratio: {wa} vs {}", r * wb);
        let li = r * ja * wa + jb * wb;
        assert!((li - l).abs() < 1e-9 * l.abs().max(1.0), "L {li} vs {l}");
        assert!((wb - l / jeff).abs() < 1e-9);
        let ke = s.kinetic_energy();
        if let Some((ke0, wa0)) = prev {
            let work = t * H * 0.5 * (wa0 + wa);
            assert!((ke - ke0 - work).abs() < 1e-9 * ke.max(1.0), "energy");
        }
        prev = Some((ke, wa));
        // After the first (projecting) step: the torque on b, -r g/h, is J_b dw_b/dt
        // with dw_b/dt = r T / J_eff, so g/h = -J_b T / J_eff.
        if n > 0 {
            let g = s.reaction(gear);
            assert!((g + jb * t / jeff).abs() < 1e-6, "reaction {g}");
        }
    }
    // r T < 0: L and w_b decreased.
    assert!(shafts(&mut sys, i).speed(b) < 3.0 - 0.5);
}

/// Differential: carrier driven by a torque, the left output held by a brake. Willis with
/// `w_l = 0` gives `w_r = 2 w_c`: relative to the carrier the free output turns at `+w_c`,
/// the mirror of the held one's `-w_c`. The pair is one dof with `J_eff = J_c + 4 J_r`.
#[test]
fn differential_with_one_output_held_doubles_the_other() {
    let (jc, jl, jr, t) = (0.6, 0.5, 0.4, 30.0);
    let mut s = ShaftSystem::new("diff");
    let c = s.add_shaft("carrier", jc).unwrap();
    let l = s.add_shaft("left", jl).unwrap();
    let r = s.add_shaft("right", jr).unwrap();
    s.add_differential(c, l, r).unwrap();
    let brake = s.add_clutch(l, None, 1e6).unwrap();
    s.set_torque(c, t).unwrap();
    let mut sys = system();
    let i = sys.add_item(Box::new(s));
    for n in 1..=400 {
        sys.step(H).unwrap();
        let s = shafts(&mut sys, i);
        let (wc, wl, wr) = (s.speed(c), s.speed(l), s.speed(r));
        assert!(wl.abs() < 1e-9, "held output moves: {wl}");
        assert!((wr - 2.0 * wc).abs() < 1e-9, "{wr} vs 2 x {wc}");
        let want = t * n as f64 * H / (jc + 4.0 * jr);
        assert!((wc - want).abs() < 1e-9, "carrier {wc} vs {want}");
        // The brake holds half the carrier torque's share: T_l = -(reaction of diff)/2.
        let tb = s.reaction(brake);
        let tr = jr * 2.0 * t / (jc + 4.0 * jr); // torque on the right output, N m
        assert!((tb + tr).abs() < 1e-6, "brake {tb} vs {tr}");
    }
}

fn diff_with_load(
    lock: f64,
    load: f64,
) -> (
    System,
    chrono_core::item::ItemHandle,
    [ShaftId; 3],
    chrono_vehicle::driveline::LinkId,
) {
    let mut s = ShaftSystem::new("diff");
    let c = s.add_shaft("carrier", 0.6).unwrap();
    let l = s.add_shaft("left", 0.5).unwrap();
    let r = s.add_shaft("right", 0.5).unwrap();
    s.add_differential(c, l, r).unwrap();
    let lk = s.add_clutch(l, Some(r), lock).unwrap();
    s.set_torque(c, 200.0).unwrap();
    s.set_torque(r, -load).unwrap();
    let mut sys = system();
    let i = sys.add_item(Box::new(s));
    (sys, i, [c, l, r], lk)
}

/// An open differential splits torque equally, so a load on the right output makes the
/// outputs' speeds diverge; locked (limit well above the need) both outputs and the
/// carrier turn together; with a limit below the need the lock slips and transmits
/// exactly its limit (a limited-slip differential).
#[test]
fn locked_differential_turns_both_outputs_together() {
    let load = 150.0;
    // Open: d(w_l - w_r)/dt = (T_l - T_r)/J = (load)/0.5 (equal split of the carrier).
    let (mut sys, i, [_, l, r], _) = diff_with_load(0.0, load);
    for _ in 0..200 {
        sys.step(H).unwrap();
    }
    let s = shafts(&mut sys, i);
    let want = load / 0.5 * 200.0 * H;
    assert!(((s.speed(l) - s.speed(r)) - want).abs() < 1e-9);
    // Locked: the lock must carry load/2 = 75 N m; limit 1000.
    let (mut sys, i, [c, l, r], lk) = diff_with_load(1000.0, load);
    for n in 1..=200 {
        sys.step(H).unwrap();
        let s = shafts(&mut sys, i);
        assert!((s.speed(l) - s.speed(r)).abs() < 1e-9);
        assert!((s.speed(c) - s.speed(l)).abs() < 1e-9);
        let want = (200.0 - load) * n as f64 * H / (0.6 + 0.5 + 0.5);
        assert!((s.speed(c) - want).abs() < 1e-9, "{} vs {want}", s.speed(c));
        // The lock slows the (faster) left output: torque on it -load/2.
        assert!(
            (s.reaction(lk) + load / 2.0).abs() < 1e-6,
            "{}",
            s.reaction(lk)
        );
    }
    // Limited slip: limit 40 < 75, the lock transmits exactly 40 (against the left's
    // faster spin) and the outputs diverge at (load - 2 x 40) / J.
    let (mut sys, i, [_, l, r], lk) = diff_with_load(40.0, load);
    for _ in 0..200 {
        sys.step(H).unwrap();
        let s = shafts(&mut sys, i);
        assert!((s.reaction(lk) + 40.0).abs() < 1e-9, "{}", s.reaction(lk));
    }
    let s = shafts(&mut sys, i);
    let want = (load - 80.0) / 0.5 * 200.0 * H;
    assert!(((s.speed(l) - s.speed(r)) - want).abs() < 1e-9);
}

/// A brake (clutch to ground) with limit `T` on a spinning shaft: `w` falls by exactly
/// `T h / J` per step until it stops, then stays at rest (no reversal). Raising the
/// limit mid-way (the pedal pressed harder) changes the rate at once.
#[test]
fn brake_decelerates_at_exactly_t_over_j_and_stops() {
    let (j, w0, t) = (1.5, 20.0, 60.0);
    let mut s = ShaftSystem::new("brake");
    let a = s.add_shaft("axle", j).unwrap();
    let brake = s.add_clutch(a, None, t).unwrap();
    s.set_speed(a, w0).unwrap();
    let mut sys = system();
    let i = sys.add_item(Box::new(s));
    let mut w = w0;
    for n in 0..800 {
        if n == 200 {
            shafts(&mut sys, i)
                .set_clutch_torque(brake, 2.0 * t)
                .unwrap();
        }
        let tn = if n < 200 { t } else { 2.0 * t };
        sys.step(H).unwrap();
        w = (w - tn * H / j).max(0.0);
        let s = shafts(&mut sys, i);
        assert!(
            (s.speed(a) - w).abs() < 1e-9,
            "step {n}: {} vs {w}",
            s.speed(a)
        );
        if w > 0.0 {
            assert!((s.reaction(brake) + tn).abs() < 1e-9);
        }
    }
    assert_eq!(w, 0.0, "the test should reach the stop");
}

/// A shaft coupled to a body's spin about a tilted body axis: a torque on the shaft spins
/// up the pair as one inertia `J_shaft + I_axis` (the body's inertia about the axis), and
/// the body spins about that axis only (the row's world axis follows the body). With a
/// free reference body (the housing, inertia `I_c` about the axis) the coupling torque
/// `g` acts as `+g` on the body and `-g` on the housing about the same world axis, so
/// their angular momenta stay opposite; with `w_s = w_b - w_c` and the shaft's
/// `J_s dw_s/dt = T - g`: `g = T / (1 + J_s (1/I + 1/I_c))`.
#[test]
fn body_coupled_to_a_shaft_spins_up_with_the_combined_inertia() {
    let (js, t) = (0.5, 12.0);
    let inertia = Vector3::new(2.0, 3.0, 5.0);
    let rot = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.5);
    for with_reference in [false, true] {
        let mut sys = system();
        let wheel = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(20.0)
                    .inertia_diagonal(inertia)
                    .rotation(rot),
            )
            .unwrap();
        let chassis = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(100.0)
                    .inertia_diagonal(Vector3::new(40.0, 40.0, 40.0))
                    .position(Vector3::new(0.0, 3.0, 0.0)),
            )
            .unwrap();
        let mut s = ShaftSystem::new("axle");
        let a = s.add_shaft("axle", js).unwrap();
        let axis = Vector3::y(); // body frame: principal axis with I = 3
        let reference = with_reference.then_some(chassis);
        let link = s.couple_to_body(a, wheel, axis * 2.0, reference).unwrap();
        s.set_torque(a, t).unwrap();
        let i = sys.add_item(Box::new(s));
        let a_world = rot * axis;
        for n in 1..=300 {
            sys.step(H).unwrap();
            let time = n as f64 * H;
            let wb = sys.body(wheel).unwrap().angular_velocity();
            let wr = sys.body(chassis).unwrap().angular_velocity();
            let w_shaft = shafts(&mut sys, i).speed(a);
            let rel = a_world.dot(&(wb - wr));
            assert!((w_shaft - rel).abs() < 1e-9, "coupling {w_shaft} vs {rel}");
            assert!(
                (wb - a_world * a_world.dot(&wb)).norm() < 1e-9,
                "off-axis spin"
            );
            if with_reference {
                let (wb_ax, wc) = (a_world.dot(&wb), a_world.dot(&wr));
                assert!(
                    (3.0 * wb_ax + 40.0 * wc).abs() < 1e-8,
                    "momentum {wb_ax} {wc}"
                );
                assert!((wr - a_world * wc).norm() < 1e-9, "housing off-axis spin");
                let g = t / (1.0 + js * (1.0 / 3.0 + 1.0 / 40.0));
                assert!((wb_ax - g * time / 3.0).abs() < 1e-8, "{wb_ax}");
                let react = shafts(&mut sys, i).reaction(link);
                assert!((react + g).abs() < 1e-6, "{react} vs {}", -g);
            } else {
                let want = t * time / (js + 3.0);
                assert!((w_shaft - want).abs() < 1e-9, "{w_shaft} vs {want}");
                // The row's reaction is the torque on the shaft: J_s dw/dt - T.
                let react = shafts(&mut sys, i).reaction(link);
                assert!((react - (js * t / (js + 3.0) - t)).abs() < 1e-6, "{react}");
            }
        }
    }
}

/// A fixed body has no block: the coupling holds the shaft at the body's (zero) spin, and
/// a kinematic body drives the shaft at its prescribed spin through the right-hand side.
#[test]
fn coupling_to_fixed_and_kinematic_bodies_uses_their_known_spin() {
    let mut sys = system();
    let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
    let motor = sys
        .add_body(RigidBodyBuilder::kinematic().angular_velocity(Vector3::new(0.0, 0.0, 7.0)))
        .unwrap();
    let mut s = ShaftSystem::new("kin");
    let a = s.add_shaft("a", 1.0).unwrap();
    let b = s.add_shaft("b", 1.0).unwrap();
    s.couple_to_body(a, ground, Vector3::z(), None).unwrap();
    s.couple_to_body(b, motor, Vector3::z(), Some(ground))
        .unwrap();
    s.set_torque(a, 50.0).unwrap();
    s.set_speed(b, -3.0).unwrap();
    let i = sys.add_item(Box::new(s));
    for _ in 0..10 {
        sys.step(H).unwrap();
        let s = shafts(&mut sys, i);
        assert!(s.speed(a).abs() < 1e-10);
        assert!((s.speed(b) - 7.0).abs() < 1e-10);
    }
}

#[test]
fn bad_input_names_the_field_and_value() {
    let mut s = ShaftSystem::new("x");
    let e = s.add_shaft("crank", -1.1).unwrap_err().to_string();
    assert!(
        e.contains("shaft \"crank\".inertia") && e.contains("-1.1"),
        "{e}"
    );
    let a = s.add_shaft("a", 1.0).unwrap();
    let b = s.add_shaft("b", 1.0).unwrap();
    let e = s.add_gear(a, b, 0.0).unwrap_err().to_string();
    assert!(e.contains("gear.ratio") && e.contains('0'), "{e}");
    let e = s.add_gear(a, a, 2.0).unwrap_err().to_string();
    assert!(e.contains("distinct"), "{e}");
    let e = s.add_clutch(a, Some(b), -5.0).unwrap_err().to_string();
    assert!(e.contains("clutch.max_torque") && e.contains("-5"), "{e}");
    let e = s
        .add_planetary([a, b, a], [1.0, 1.0, 1.0])
        .unwrap_err()
        .to_string();
    assert!(e.contains("planetary"), "{e}");
    let e = s.set_torque(b, f64::NAN).unwrap_err().to_string();
    assert!(e.contains("shaft \"b\".torque") && e.contains("NaN"), "{e}");
    // Handles of bodies outside any system (slot 5 exists in no system of this test).
    let set = chrono_core::Bodies::from_bodies(vec![RigidBodyBuilder::fixed().build().unwrap(); 6]);
    let body = set.handle(0);
    let e = s
        .couple_to_body(a, body, Vector3::zeros(), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("body coupling.axis"), "{e}");
    let g = s.add_gear(a, b, 2.0).unwrap();
    let e = s.set_clutch_torque(g, 10.0).unwrap_err().to_string();
    assert!(e.contains("not a clutch"), "{e}");
    // A coupling to a body that is not in the system fails at the step, naming the link.
    s.couple_to_body(b, set.handle(5), Vector3::z(), None)
        .unwrap();
    let mut sys = system();
    sys.add_item(Box::new(s));
    let e = sys.step(H).unwrap_err().to_string();
    assert!(
        e.contains("shaft system \"x\"") && e.contains("body"),
        "{e}"
    );
}

/// The vehicle case: a spindle on a revolute joint (about Y) on a free-floating chassis,
/// its axle shaft coupled to the spindle's spin relative to the chassis, a torque on the
/// shaft. The joint and the coupling act in the same CCP: the shaft turns at the spindle's
/// spin relative to the chassis, and, the coupling's torques on the two bodies being equal
/// and opposite about the same axis (and the joint's forces internal), the bodies' total
/// angular momentum about the origin stays zero while the spindle spins up forwards and
/// the chassis pitches back. The hub is in the chassis' XZ plane so that every rotation
/// stays about the principal Y axes: off them (hub at y = 0.9) the total drifts as about
/// 2e-10 n^2 N m s after n steps, the same with any joint: the step applies impulses in
/// the body frame of `q(l)` and then rotates by `exp(h w+)`, which conserves `R J w`
/// exactly only for the free part (see `RigidBody::free_momentum`).
#[test]
fn spindle_on_a_revolute_joint_of_a_floating_chassis() {
    use chrono_core::{JointBuilder, JointKind};
    let mut sys = system();
    let chassis = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(100.0)
                .inertia_diagonal(Vector3::new(40.0, 60.0, 70.0)),
        )
        .unwrap();
    let hub = Vector3::new(1.5, 0.0, -0.2);
    let spindle = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(15.0)
                .inertia_diagonal(Vector3::new(0.5, 1.0, 0.5))
                .position(hub),
        )
        .unwrap();
    sys.add_joint(JointBuilder::at_axis(
        JointKind::Revolute,
        chassis,
        spindle,
        hub,
        Vector3::y(),
    ))
    .unwrap();
    let mut s = ShaftSystem::new("axle");
    let a = s.add_shaft("axle", 0.5).unwrap();
    s.couple_to_body(a, spindle, Vector3::y(), Some(chassis))
        .unwrap();
    s.set_torque(a, 20.0).unwrap();
    let i = sys.add_item(Box::new(s));
    for _ in 0..500 {
        sys.step(H).unwrap();
        let (c, sp) = (sys.body(chassis).unwrap(), sys.body(spindle).unwrap());
        let axis = sp.rotation() * Vector3::y();
        let rel = axis.dot(&(sp.angular_velocity() - c.angular_velocity()));
        let w = sys.item::<ShaftSystem>(i).unwrap().speed(a);
        assert!((w - rel).abs() < 1e-9, "shaft {w} vs relative spin {rel}");
        let total: Vector3<f64> = [c, sp]
            .iter()
            .map(|b| b.position().cross(&(b.mass() * b.linear_velocity())) + b.angular_momentum())
            .sum();
        assert!(total.norm() < 1e-8, "angular momentum {total:?}");
    }
    let w = shafts(&mut sys, i).speed(a);
    assert!(w > 1.0, "spun up: {w}");
    assert!(sys.body(chassis).unwrap().angular_velocity().y < 0.0);
    assert!(sys.max_joint_violation() < 1e-6);
}
