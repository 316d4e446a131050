//! Unit tests of one SMC contact's force ([`super::smc::contact_force`]): the normal law's
//! restitution mapping, the Coulomb cap and history, and the three rolling models.

use nalgebra::Vector3;

use super::smc::*;

fn pair(alpha: f64) -> SmcPair {
    SmcPair {
        radius: 0.01,
        mass: 0.01,
        inertia: 1e-7,
        rolling_inertia: 3.5e-7,
        young: 1e7,
        shear: 4e6,
        alpha,
        friction: 0.5,
        rolling_friction: 0.0,
        spinning_friction: 0.0,
        rolling_model: RollingModel::Relative,
        rolling_damping: 0.0,
    }
}

#[test]
fn undamped_contacts_are_elastic() {
    for m in [SmcModel::Hooke, SmcModel::Hertz] {
        assert!((restitution_of_damping(m, 0.0) - 1.0).abs() < 1e-6, "{m:?}");
    }
}

#[test]
fn linear_model_matches_closed_form_for_light_damping() {
    // Without the clamp, e = exp(-pi zeta / sqrt(1 - zeta^2)), zeta = alpha / 2. The
    // clamp only acts at the end of the contact, where the force is small for light
    // damping, so the two agree to ~1e-3 at zeta = 0.05.
    let alpha = 0.1;
    let zeta: f64 = alpha / 2.0;
    let closed = (-std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt()).exp();
    let e = restitution_of_damping(SmcModel::Hooke, alpha);
    assert!((e - closed).abs() < 5e-3 && e > closed, "{e} {closed}");
}

#[test]
fn damping_mapping_round_trips() {
    for m in [SmcModel::Hooke, SmcModel::Hertz] {
        for e in [0.1, 0.5, 0.9] {
            let a = damping_for_restitution(m, e).unwrap();
            assert!((restitution_of_damping(m, a) - e).abs() < 1e-6, "{m:?} {e}");
        }
    }
    assert!(damping_for_restitution(SmcModel::Hertz, 1.5).is_err());
}

#[test]
fn coulomb_cap_and_history_reset() {
    let p = pair(0.0);
    let kin = SmcKinematics {
        normal: Vector3::z(),
        overlap: 1e-5,
        relative_velocity: Vector3::new(1.0, 0.0, 0.0),
        angular_velocity_a: Vector3::zeros(),
        angular_velocity_b: Vector3::zeros(),
    };
    let f = contact_force(SmcModel::Hertz, &p, 1.0, &kin, &SmcHistory::default(), 1e-3);
    let ft = f.force - Vector3::z() * f.normal;
    assert!((ft.norm() - 0.5 * f.normal).abs() < 1e-12 * f.normal);
    assert!(ft.x < 0.0);
    // The stored displacement carries exactly the capped force.
    let kt = 8.0 * p.shear * (p.radius * kin.overlap).sqrt();
    assert!((f.history.tangential * -kt - ft).norm() < 1e-12 * f.normal);
}

#[test]
fn history_is_rotated_into_the_tangent_plane() {
    let p = pair(0.0);
    let n = Vector3::new(0.0, 0.6, 0.8);
    let kin = SmcKinematics {
        normal: n,
        overlap: 1e-4,
        relative_velocity: Vector3::zeros(),
        angular_velocity_a: Vector3::zeros(),
        angular_velocity_b: Vector3::zeros(),
    };
    let xi0 = Vector3::new(1e-7, 0.0, 0.0) + Vector3::new(0.0, 1e-7, 0.0);
    let hist = SmcHistory {
        tangential: xi0,
        rolling: xi0,
    };
    let f = contact_force(SmcModel::Hertz, &p, 1.0, &kin, &hist, 1e-3);
    assert!(f.history.tangential.dot(&n).abs() < 1e-20);
    assert!((f.history.tangential.norm() - xi0.norm()).abs() < 1e-18);
    // No rolling spring: its angle is not kept.
    assert!(f.history.rolling == Vector3::zeros());
}

#[test]
fn rolling_torque_opposes_rolling_and_is_limited() {
    let mut p = pair(0.0);
    p.rolling_friction = 0.1;
    let kin = SmcKinematics {
        normal: Vector3::z(),
        overlap: 1e-4,
        relative_velocity: Vector3::zeros(),
        angular_velocity_a: Vector3::zeros(),
        angular_velocity_b: Vector3::new(0.0, 2.0, 0.0),
    };
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &SmcHistory::default(), 1e-4);
    assert!(f.torque.y < 0.0 && f.torque.x == 0.0);
    let full = 0.1 * p.radius * f.normal;
    assert!(f.torque.norm() <= full * (1.0 + 1e-12));
    let tiny = SmcKinematics {
        angular_velocity_b: Vector3::new(0.0, 1e-9, 0.0),
        ..kin
    };
    let f = contact_force(
        SmcModel::Hooke,
        &p,
        1.0,
        &tiny,
        &SmcHistory::default(),
        1e-4,
    );
    assert!((f.torque.y + p.inertia * 1e-9 / 1e-4).abs() < 1e-20);
}
#[test]
fn relative_rolling_is_a_couple_and_ignores_a_common_rotation() {
    let mut p = pair(0.0);
    p.rolling_friction = 0.1;
    let mut kin = SmcKinematics {
        normal: Vector3::z(),
        overlap: 1e-4,
        relative_velocity: Vector3::zeros(),
        angular_velocity_a: Vector3::new(0.0, -1.0, 0.0),
        angular_velocity_b: Vector3::new(0.0, 1.0, 0.0),
    };
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &SmcHistory::default(), 1e-6);
    let full = 0.1 * p.radius * f.normal;
    assert!((f.torque.y + full).abs() < 1e-12 * full && f.rolling == [0.0; 2]);
    kin.angular_velocity_a = kin.angular_velocity_b;
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &SmcHistory::default(), 1e-6);
    assert!(f.torque == Vector3::zeros());
}

#[test]
fn per_body_rolling_opposes_each_bodys_own_rotation() {
    let mut p = pair(0.0);
    p.rolling_friction = 0.1;
    p.rolling_model = RollingModel::PerBody;
    // Two grains turning together: each gets the full magnitude, no couple.
    let w = Vector3::new(0.0, 3.0, 4.0);
    let kin = SmcKinematics {
        normal: Vector3::z(),
        overlap: 1e-4,
        relative_velocity: Vector3::zeros(),
        angular_velocity_a: w,
        angular_velocity_b: w,
    };
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &SmcHistory::default(), 1e-6);
    let full = 0.1 * p.radius * f.normal;
    assert!(f.torque == Vector3::zeros());
    assert!(f.rolling.iter().all(|m| (m - full).abs() < 1e-12 * full));
    let t = per_body_rolling_torque(&w, f.rolling[1], 1e-7, 1e-6);
    assert!((t + w.normalize() * full).norm() < 1e-12 * full);
    // A body at rest (a grain on a fixed plane) gets none; the turning one the same
    // torque as from the relative model.
    let on_plane = SmcKinematics {
        angular_velocity_a: Vector3::zeros(),
        angular_velocity_b: Vector3::new(0.0, 2.0, 0.0),
        ..kin
    };
    let none = SmcHistory::default();
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &on_plane, &none, 1e-6);
    p.rolling_model = RollingModel::Relative;
    let g = contact_force(SmcModel::Hooke, &p, 1.0, &on_plane, &none, 1e-6);
    let t = per_body_rolling_torque(&on_plane.angular_velocity_b, f.rolling[1], 1.0, 1e-6);
    assert!(f.rolling[0] == 0.0 && (t - g.torque).norm() < 1e-12 * full);
    // The limit applies to the sum: three contacts cannot reverse the rotation.
    let tiny = Vector3::new(1e-9, 0.0, 0.0);
    let t = per_body_rolling_torque(&tiny, 3.0 * full, 1e-7, 1e-4);
    assert!((t.x + 1e-7 * 1e-9 / 1e-4).abs() < 1e-22 && t.y == 0.0);
}

/// A pair with the rolling spring (`mu_r`, damping ratio `eta`) and a contact along `z` whose
/// body B turns at `w`.
fn spring_contact(mu_r: f64, eta: f64, w: Vector3<f64>) -> (SmcPair, SmcKinematics) {
    let mut p = pair(0.0);
    p.rolling_friction = mu_r;
    p.rolling_model = RollingModel::Spring;
    p.rolling_damping = eta;
    let kin = SmcKinematics {
        normal: Vector3::z(),
        overlap: 1e-5,
        relative_velocity: Vector3::zeros(),
        angular_velocity_a: Vector3::zeros(),
        angular_velocity_b: w,
    };
    (p, kin)
}

/// Ai et al.'s type C: the moment follows the stored angle through `k_r`, the dashpot
/// acts below the cap only, and at the cap the angle is cut back to it.
#[test]
fn rolling_spring_winds_up_then_caps_without_wind_up() {
    let h = 1e-5;
    let w = Vector3::new(0.0, 2.0, 0.0);
    let (p, kin) = spring_contact(0.1, 0.3, w);
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &SmcHistory::default(), h);
    let s_n = hooke_stiffness(&p, 1.0);
    let k_r = 2.25 * s_n * (0.1 * p.radius).powi(2);
    let c_r = 2.0 * 0.3 * (p.rolling_inertia * k_r).sqrt();
    let full = 0.1 * p.radius * f.normal;
    assert!((f.history.rolling - w * h).norm() < 1e-15);
    let expect = -k_r * w * h - c_r * w;
    assert!(expect.norm() < full, "below the cap in this set-up");
    assert!((f.torque - expect).norm() < 1e-12 * expect.norm());
    // Far past the cap: the moment is the cap, against the angle, and the stored
    // angle is the cap's.
    let wound = SmcHistory {
        tangential: Vector3::zeros(),
        rolling: Vector3::new(0.3, 0.4, 0.0),
    };
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &wound, h);
    let dir = (wound.rolling + w * h).normalize();
    assert!((f.torque + dir * full).norm() < 1e-12 * full);
    assert!((f.history.rolling - dir * full / k_r).norm() < 1e-12 * full / k_r);
    // The same angle held by a static contact: the full moment, no creep needed.
    let still = SmcKinematics {
        angular_velocity_b: Vector3::zeros(),
        ..kin
    };
    let held = SmcHistory {
        tangential: Vector3::zeros(),
        rolling: Vector3::new(0.0, 0.5 * full / k_r, 0.0),
    };
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &still, &held, h);
    assert!((f.torque.y + 0.5 * full).abs() < 1e-12 * full);
    // A common rotation winds nothing; a tilted normal takes the angle into its plane.
    let together = SmcKinematics {
        angular_velocity_a: w,
        normal: Vector3::new(0.0, 0.6, 0.8),
        ..kin
    };
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &together, &held, h);
    assert!(f.history.rolling.dot(&together.normal).abs() < 1e-18);
    assert!((f.history.rolling.norm() - held.rolling.norm()).abs() < 1e-15);
    assert!((f.torque.norm() - 0.5 * full).abs() < 1e-12 * full);
}

/// On a flat contact (`R` = 1 m) of a light body the spring would be far stiffer than the
/// step resolves: its stiffness is capped at `I (MAX_ROLLING_OMEGA_H / h)^2`, `I` the
/// centroidal inertia.
#[test]
fn rolling_spring_stiffness_is_capped_by_the_step() {
    let h = 1e-4;
    let w = Vector3::new(1e-3, 0.0, 0.0);
    let (mut p, kin) = spring_contact(0.2, 0.0, w);
    p.radius = 1.0;
    let f = contact_force(SmcModel::Hooke, &p, 1.0, &kin, &SmcHistory::default(), h);
    let uncapped = 2.25 * hooke_stiffness(&p, 1.0) * 0.2f64.powi(2);
    let cap = (MAX_ROLLING_OMEGA_H / h).powi(2) * p.inertia;
    assert!(uncapped > 10.0 * cap, "the set-up must need the cap");
    assert!((f.torque + w * h * cap).norm() < 1e-12 * cap * h * w.norm());
}
