//! Tests of the TMeasy tire and the rigid tire in real systems (APGD solver).

use chrono_core::math::GRAVITY_MAGNITUDE;
use std::sync::Arc;

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::math::Vector3;
use chrono_core::{
    BodyHandle, ContactMaterial, ForceHandle, RigidBodyBuilder, System, SystemSettings,
};
use chrono_vehicle::terrain::{FlatTerrain, HeightmapTerrain, Terrain};
use chrono_vehicle::tire::{RigidTire, TMeasyParams, TMeasyTire, Tire, TireOutput};

const H: f64 = 1e-3;
const G: f64 = GRAVITY_MAGNITUDE;

fn system() -> System {
    let s = SolverSettings {
        tolerance: 1e-10,
        max_iterations: 500,
        record_history: false,
    };
    System::new(SystemSettings::default(), Box::new(Apgd::new(s))).unwrap()
}

fn flat() -> Arc<dyn Terrain> {
    Arc::new(FlatTerrain::new(0.0, 0.9).unwrap())
}

fn add_tire(
    sys: &mut System,
    body: BodyHandle,
    p: &TMeasyParams,
    t: Arc<dyn Terrain>,
) -> ForceHandle {
    let tire = TMeasyTire::new("tire", body, Vector3::y(), p.clone(), t).unwrap();
    sys.add_force_element(Box::new(tire)).unwrap()
}

fn out(sys: &System, h: ForceHandle) -> TireOutput {
    *sys.force_element::<TMeasyTire>(h).unwrap().output()
}

/// A kinematic wheel at load `fz` rolling at `vx` with longitudinal slip `sx` (so
/// `r_D Omega = vx / (1 - sx)`) and lateral velocity `vy`; the output after 2 s (at least
/// 20 relaxation times `sigma / v`).
fn held_wheel(p: &TMeasyParams, fz: f64, vx: f64, sx: f64, vy: f64) -> TireOutput {
    let mut sys = system();
    let dz = fz / p.vertical_stiffness;
    let rd = p.radius - dz / 3.0;
    let omega = vx / (1.0 - sx) / rd;
    let b = sys
        .add_body(
            RigidBodyBuilder::kinematic()
                .position(Vector3::new(0.0, 0.0, p.radius - dz))
                .linear_velocity(Vector3::new(vx, vy, 0.0))
                .angular_velocity(Vector3::new(0.0, omega, 0.0)),
        )
        .unwrap();
    let f = add_tire(&mut sys, b, p, flat());
    for _ in 0..2000 {
        sys.step(H).unwrap();
    }
    out(&sys, f)
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

#[test]
fn held_slip_reproduces_the_tmeasy_curve_at_both_reference_loads() {
    let p = TMeasyParams::hmmwv();
    let c = p.longitudinal;
    for k in 0..2 {
        let fz = p.nominal_load * (k + 1) as f64;
        // initial slope: F/s at a tiny slip (the curve bends by 1 + q (a - 2) ~ 0.4 %)
        let s = 2e-4;
        let o = held_wheel(&p, fz, 10.0, s, 0.0);
        assert!(o.in_contact);
        assert!(
            rel(o.normal_force, fz) < 1e-9,
            "Fz {} vs {fz}",
            o.normal_force
        );
        assert!(rel(o.slip_long, s) < 1e-6, "slip {}", o.slip_long);
        assert!(
            rel(o.relaxed_slip_long, s) < 1e-3,
            "relaxed slip {}",
            o.relaxed_slip_long
        );
        assert!(
            rel(o.fx / s, c.df0[k]) < 1e-2,
            "slope {} vs {}",
            o.fx / s,
            c.df0[k]
        );
        assert!(o.fy.abs() < 1e-9 * fz);
        // the maximum at s_M
        let o = held_wheel(&p, fz, 10.0, c.s_max[k], 0.0);
        assert!(
            rel(o.fx, c.f_max[k]) < 1e-3,
            "F_M {} vs {}",
            o.fx,
            c.f_max[k]
        );
        // slightly off the maximum on both sides it is lower
        for ds in [-0.02, 0.02] {
            let o2 = held_wheel(&p, fz, 10.0, c.s_max[k] + ds, 0.0);
            assert!(o2.fx < o.fx, "F({}) = {} >= F_M", c.s_max[k] + ds, o2.fx);
        }
        // sliding beyond s_S; braking gives the opposite force
        let o = held_wheel(&p, fz, 10.0, c.s_slide[k] + 0.1, 0.0);
        assert!(
            rel(o.fx, c.f_slide[k]) < 1e-3,
            "F_S {} vs {}",
            o.fx,
            c.f_slide[k]
        );
        let o = held_wheel(&p, fz, 10.0, -c.s_max[k], 0.0);
        assert!(rel(-o.fx, c.f_max[k]) < 1e-3, "braking F_M {}", o.fx);
    }
}

#[test]
fn lateral_slide_to_plus_y_gives_force_to_minus_y_and_an_aligning_torque() {
    let p = TMeasyParams::hmmwv();
    let fz = p.nominal_load;
    let o = held_wheel(&p, fz, 5.0, 0.0, 0.5);
    assert!(o.fy < 0.0, "Fy = {}", o.fy);
    let (_, fy) = p.steady_force(fz, 0.0, o.slip_lat, 1.0);
    assert!(rel(o.fy, fy) < 1e-3, "Fy {} vs curve {fy}", o.fy);
    // slip 0.1 is in the rising part: well below the maximum, above the linear estimate/2
    assert!(-o.fy < p.lateral.f_max[0] && -o.fy > 0.5 * p.lateral.df0[0] * 0.1);
    assert!(o.fx.abs() < 1e-6 * fz, "Fx = {}", o.fx);
    // the trail is behind the contact point: the torque turns the wheel towards +Y
    assert!(o.mz > 0.0, "Mz = {}", o.mz);
    let o2 = held_wheel(&p, fz, 5.0, 0.0, -0.5);
    assert!((o2.fy + o.fy).abs() < 1e-9 * fz && (o2.mz + o.mz).abs() < 1e-9 * fz);
}

/// A dynamic wheel of `mass` and spin inertia `iy` resting on its static deflection.
fn wheel(sys: &mut System, p: &TMeasyParams, mass: f64, iy: f64, v: f64, omega: f64) -> BodyHandle {
    let dz = mass * G / p.vertical_stiffness;
    sys.add_body(
        RigidBodyBuilder::dynamic()
            .mass(mass)
            .inertia_diagonal(Vector3::new(p.inertia[0], iy, p.inertia[2]))
            .position(Vector3::new(0.0, 0.0, p.radius - dz))
            .linear_velocity(Vector3::new(v, 0.0, 0.0))
            .angular_velocity(Vector3::new(0.0, omega, 0.0)),
    )
    .unwrap()
}

#[test]
fn loaded_rolling_wheel_settles_at_mg_and_rolling_resistance_slows_it() {
    let p = TMeasyParams::hmmwv();
    let mut sys = system();
    let m = p.nominal_load / G;
    // dropped from 2 cm above the unloaded contact, rolling at 5 m/s
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(m)
                .inertia_diagonal(Vector3::from(p.inertia))
                .position(Vector3::new(0.0, 0.0, p.radius + 0.02))
                .linear_velocity(Vector3::new(5.0, 0.0, 0.0))
                .angular_velocity(Vector3::new(0.0, 5.0 / p.radius, 0.0)),
        )
        .unwrap();
    let f = add_tire(&mut sys, b, &p, flat());
    let mut v1 = 0.0;
    for k in 1..=3000 {
        sys.step(H).unwrap();
        if k == 1000 {
            v1 = sys.body(b).unwrap().linear_velocity().x;
        }
    }
    let o = out(&sys, f);
    let body = sys.body(b).unwrap();
    assert!(
        rel(o.normal_force, m * G) < 1e-3,
        "Fz {} vs mg {}",
        o.normal_force,
        m * G
    );
    assert!(rel(o.deflection, m * G / p.vertical_stiffness) < 1e-3);
    assert!(body.linear_velocity().z.abs() < 1e-3);
    // rolling without slip: v = r_D Omega
    let v2 = body.linear_velocity().x;
    assert!((v2 - o.rolling_radius * o.spin_rate).abs() < 1e-3 * v2);
    // d/dt (I Omega + m v r) = -f_r r_D F_z about the contact point, with v = r_D Omega
    let (rd, r) = (o.rolling_radius, p.radius - o.deflection);
    let expected = -p.rolling_resistance * rd * m * G * rd / (p.inertia[1] + m * rd * r);
    let a = (v2 - v1) / 2.0;
    assert!(rel(a, expected) < 0.02, "deceleration {a} vs {expected}");
}

#[test]
fn spinning_wheel_set_down_drives_itself_forward_conserving_angular_momentum() {
    let mut p = TMeasyParams::hmmwv();
    p.rolling_resistance = 0.0;
    let mut sys = system();
    let (m, iy, omega0) = (200.0, 20.0, 30.0);
    let b = wheel(&mut sys, &p, m, iy, 0.0, omega0);
    let f = add_tire(&mut sys, b, &p, flat());
    let mut early = 0.0;
    for k in 1..=3000 {
        sys.step(H).unwrap();
        if k == 50 {
            early = sys.body(b).unwrap().linear_velocity().x;
        }
    }
    let o = out(&sys, f);
    let v = sys.body(b).unwrap().linear_velocity().x;
    // angular momentum about the contact point is conserved: I w0 = I w + m v r, v = r_D w
    let (rd, r) = (o.rolling_radius, p.radius - o.deflection);
    let expected = rd * iy * omega0 / (iy + m * rd * r);
    assert!(rel(v, expected) < 5e-3, "v {v} vs {expected}");
    assert!((v - rd * o.spin_rate).abs() < 1e-3 * v, "still slipping");
    // while it spins up the force is the sliding force (about mu_S m g)
    let fs = p.longitudinal.at_load(m * G, p.nominal_load, 1.0).f_slide;
    let a = early / 0.05;
    assert!(
        a > 0.5 * fs / m && a <= 1.05 * fs / m,
        "a {a} vs F_S/m {}",
        fs / m
    );
}

#[test]
fn airborne_wheel_feels_no_tire_force() {
    let p = TMeasyParams::hmmwv();
    let mut sys = system();
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(50.0)
                .inertia_diagonal(Vector3::from(p.inertia))
                .position(Vector3::new(0.0, 0.0, p.radius + 0.1))
                .linear_velocity(Vector3::new(3.0, 1.0, 0.0))
                .angular_velocity(Vector3::new(0.0, 2.0, 0.0)),
        )
        .unwrap();
    let f = add_tire(&mut sys, b, &p, flat());
    for _ in 0..100 {
        sys.step(H).unwrap();
        assert!(!out(&sys, f).in_contact);
        let l = sys.element_loads().get(b);
        assert_eq!(l[0], Vector3::zeros());
        assert_eq!(l[1], Vector3::zeros());
    }
    let body = sys.body(b).unwrap();
    assert!((body.linear_velocity().z + G * 0.1).abs() < 1e-9);
    assert!((body.angular_velocity().y - 2.0).abs() < 1e-9);
}

#[test]
fn braked_wheel_stands_still_on_a_ten_percent_slope() {
    let p = TMeasyParams::hmmwv();
    let slope = 0.1;
    let terrain: Arc<dyn Terrain> = Arc::new(
        HeightmapTerrain::from_fn(21, 21, [-10.0, -10.0], [1.0, 1.0], 0.9, |x, _| slope * x)
            .unwrap(),
    );
    let mut sys = system();
    let m = p.nominal_load / G;
    let n = terrain.normal(0.0, 0.0);
    let cos = n.z;
    let dz = m * G * cos / p.vertical_stiffness;
    // locked brake: a huge spin inertia
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(m)
                .inertia_diagonal(Vector3::new(p.inertia[0], 1e12, p.inertia[2]))
                .position(n * (p.radius - dz)),
        )
        .unwrap();
    let f = add_tire(&mut sys, b, &p, terrain);
    let tangent = Vector3::new(1.0, 0.0, slope).normalize();
    let (mut mean1, mut mean2) = (0.0, 0.0);
    for k in 1..=4000 {
        sys.step(H).unwrap();
        let s = sys.body(b).unwrap().position().dot(&tangent);
        if k > 2000 && k <= 3000 {
            mean1 += s / 1000.0;
        } else if k > 3000 {
            mean2 += s / 1000.0;
        }
    }
    let o = out(&sys, f);
    // the tread holds the weight's slope component up the slope (+X): F_x = m g sin(theta)
    let sin = slope / (1.0 + slope * slope).sqrt();
    assert!(
        rel(o.fx, m * G * sin) < 1e-3,
        "Fx {} vs {}",
        o.fx,
        m * G * sin
    );
    // no creep: the mean position over the 3rd and the 4th second agree within 1 um
    assert!(
        (mean2 - mean1).abs() < 1e-6,
        "moved {} m in 1 s",
        mean2 - mean1
    );
    assert!(sys.body(b).unwrap().linear_velocity().norm() < 1e-5);
}

#[test]
fn rigid_tire_rolls_on_flat_and_heightmap_terrains_through_contacts() {
    let tire = RigidTire::hmmwv();
    for heightmap in [false, true] {
        let mut sys = system();
        let mat = ContactMaterial::with_friction(0.9);
        if heightmap {
            HeightmapTerrain::from_fn(41, 21, [-10.0, -10.0], [0.5, 1.0], 0.9, |_, _| 0.0)
                .unwrap()
                .add_to_system(&mut sys, mat)
                .unwrap();
        } else {
            FlatTerrain::new(0.0, 0.9)
                .unwrap()
                .add_to_system(&mut sys, mat)
                .unwrap();
        }
        let (shape, pose, material) = tire.collider().unwrap();
        let b = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(tire.mass)
                    .inertia_diagonal(Vector3::from(tire.inertia))
                    .position(Vector3::new(0.0, 0.0, tire.radius))
                    .linear_velocity(Vector3::new(2.0, 0.0, 0.0))
                    .collider(shape, pose, material),
            )
            .unwrap();
        for _ in 0..1000 {
            sys.step(H).unwrap();
        }
        let body = sys.body(b).unwrap();
        // it rests on the ground (no sinking) and ends up rolling: v = R w
        assert!(
            (body.position().z - tire.radius).abs() < 2e-3,
            "z {}",
            body.position().z
        );
        let (v, w) = (body.linear_velocity().x, body.angular_velocity().y);
        assert!(
            v > 0.5 && (v - tire.radius * w).abs() < 1e-2 * v,
            "v {v}, R w {}",
            tire.radius * w
        );
    }
}

/// The rigid tire's SMC tread modulus: carried by its contact material, 2e7 Pa when a
/// description predates the field, and a bad value is named.
#[test]
fn a_rigid_tires_tread_modulus_reaches_its_material() {
    let mut t = RigidTire::hmmwv();
    assert_eq!(t.material().young_modulus, 2e7);
    t.young_modulus = 2e9;
    assert_eq!(t.collider().unwrap().2.young_modulus, 2e9);
    let mut json = serde_json::to_value(Tire::Rigid(RigidTire::hmmwv())).unwrap();
    json.as_object_mut()
        .unwrap()
        .remove("young_modulus")
        .unwrap();
    let old: Tire = serde_json::from_value(json).unwrap();
    assert_eq!(old, Tire::Rigid(RigidTire::hmmwv()));
    t.young_modulus = 0.0;
    let e = t.validate().unwrap_err().to_string();
    assert!(e.contains("rigid_tire.young_modulus"), "{e}");
}

#[test]
fn tire_descriptions_round_trip_and_bad_data_is_named() {
    let t = Tire::TMeasy(TMeasyParams::hmmwv());
    let s = serde_json::to_string(&t).unwrap();
    assert!(s.contains("\"type\":\"TMeasy\""));
    assert_eq!(serde_json::from_str::<Tire>(&s).unwrap(), t);
    let r = Tire::Rigid(RigidTire::hmmwv());
    let s = serde_json::to_string(&r).unwrap();
    assert_eq!(serde_json::from_str::<Tire>(&s).unwrap(), r);
    let mut p = TMeasyParams::hmmwv();
    p.lateral.f_slide[1] = 2.0 * p.lateral.f_max[1];
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("tmeasy.lateral.f_slide[1]"), "{e}");
    let mut p = TMeasyParams::hmmwv();
    p.relaxation_length[0] = -1.0;
    let e = Tire::TMeasy(p).validate().unwrap_err().to_string();
    assert!(
        e.contains("tmeasy.relaxation_length[0]") && e.contains("-1"),
        "{e}"
    );
}

#[test]
fn light_hmmwv_wheel_is_stable_at_two_millisecond_steps_and_loses_its_side_slip() {
    // tire + rim of the HMMWV (56.4 kg), loaded only by its own weight: the stiffest case
    // for the explicit tire forces. Huge roll and yaw inertias stand for the spindle's
    // guidance (a free wheel would precess like a rolling coin).
    let p = TMeasyParams::hmmwv();
    let mut sys = system();
    let m = 37.6 + 18.8;
    let iy = 6.69 + 0.6243;
    let dz = m * G / p.vertical_stiffness;
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass(m)
                .inertia_diagonal(Vector3::new(1e9, iy, 1e9))
                .position(Vector3::new(0.0, 0.0, p.radius - dz))
                .angular_velocity(Vector3::new(0.0, 15.0 / p.radius, 0.0)),
        )
        .unwrap();
    sys.body_mut(b)
        .unwrap()
        .set_linear_velocity(Vector3::new(15.0, 0.5, 0.0))
        .unwrap();
    let f = add_tire(&mut sys, b, &p, flat());
    for _ in 0..1500 {
        sys.step(2e-3).unwrap();
    }
    let body = sys.body(b).unwrap();
    let o = out(&sys, f);
    assert!(
        body.linear_velocity().y.abs() < 1e-3,
        "vy {}",
        body.linear_velocity().y
    );
    assert!(
        body.linear_velocity().z.abs() < 1e-3,
        "vz {}",
        body.linear_velocity().z
    );
    assert!(rel(o.normal_force, m * G) < 1e-2, "Fz {}", o.normal_force);
    let v = body.linear_velocity().x;
    assert!(v > 14.0 && v < 15.0 && (v - o.rolling_radius * o.spin_rate).abs() < 1e-3 * v);
}

#[test]
fn wheel_center_offset_moves_the_contact() {
    let p = TMeasyParams::hmmwv();
    let mut sys = system();
    // body origin 0.1 m above the wheel center, which sits at the static deflection
    let dz = p.nominal_load / p.vertical_stiffness;
    let b = sys
        .add_body(RigidBodyBuilder::kinematic().position(Vector3::new(
            0.0,
            0.0,
            p.radius - dz + 0.1,
        )))
        .unwrap();
    let tire = TMeasyTire::new("tire", b, Vector3::y(), p.clone(), flat())
        .unwrap()
        .with_center(Vector3::new(0.0, 0.0, -0.1))
        .unwrap();
    let f = sys.add_force_element(Box::new(tire)).unwrap();
    sys.step(H).unwrap();
    let o = out(&sys, f);
    assert!(
        rel(o.normal_force, p.nominal_load) < 1e-9,
        "Fz {}",
        o.normal_force
    );
    assert!(o.contact_point.norm() < 1e-12);
    assert!(
        TMeasyTire::new("t", b, Vector3::y(), p, flat())
            .unwrap()
            .with_center(Vector3::new(f64::NAN, 0.0, 0.0))
            .is_err()
    );
}

#[test]
fn combined_slip_is_isotropic_for_equal_curves_and_elliptic_when_sliding() {
    use chrono_vehicle::tire::{CurveAtLoad, characteristic, combined_force};
    let c = CurveAtLoad {
        df0: 1e5,
        s_max: 0.12,
        f_max: 8e3,
        s_slide: 0.6,
        f_slide: 7e3,
    };
    let f = |s: f64| characteristic(s, c.df0, c.s_max, c.f_max, c.s_slide, c.f_slide);
    for &(sx, sy) in &[(0.01, 0.02), (-0.1, 0.05), (0.3, -0.4), (0.0, -0.7)] {
        let (fx, fy) = combined_force(sx, sy, &c, &c);
        let s = f64::hypot(sx, sy);
        // the resultant is the pure-slip curve of |s|, along the slip
        assert!((fx.hypot(fy) - f(s)).abs() < 1e-9 * f(s), "at ({sx}, {sy})");
        assert!((fx * sy - fy * sx).abs() < 1e-9 * f(s) * s);
        assert!(fx * sx + fy * sy > 0.0);
    }
    // different curves: pure slip gives each direction's own curve; in deep sliding the
    // resultant is sqrt((FS_x cos p)^2 + (FS_y sin p)^2), between the two sliding forces
    let p = TMeasyParams::hmmwv();
    let x = p.longitudinal.at_load(p.nominal_load, p.nominal_load, 1.0);
    let y = p.lateral.at_load(p.nominal_load, p.nominal_load, 1.0);
    let (fx, fy) = combined_force(0.05, 0.0, &x, &y);
    let fx_pure = characteristic(0.05, x.df0, x.s_max, x.f_max, x.s_slide, x.f_slide);
    assert!((fx - fx_pure).abs() < 1e-9 * fx_pure && fy == 0.0);
    let (fx, fy) = combined_force(0.0, -0.1, &x, &y);
    let fy_pure = characteristic(0.1, y.df0, y.s_max, y.f_max, y.s_slide, y.f_slide);
    assert!((fy + fy_pure).abs() < 1e-9 * fy_pure && fx == 0.0);
    let (fx, fy) = combined_force(-2.0, 1.5, &x, &y);
    let r = fx.hypot(fy);
    assert!(
        r > y.f_slide.min(x.f_slide) && r < y.f_slide.max(x.f_slide),
        "|F| {r}"
    );
    assert!(fx < 0.0 && fy > 0.0);
}
