//! The relaxation of the NSC contact model, pinned: the cone complementarity problem is the
//! convex relaxation of Coulomb friction (M. Anitescu, "Optimization-based simulation of
//! nonsmooth rigid multibody dynamics", Math. Program. 105, 2006), whose solution makes a
//! sliding contact separate with the normal velocity `mu |v_slip|`. A sphere pushed to slide
//! on a plate lifts off by that much in its first step. This is why `granular-shear`'s NSC
//! peak can exceed Taylor's stress–dilatancy balance (docs/validation-granular.md): the
//! sliding contacts do work against the normal load that the sample's volume does not show.
//! The Coulomb law of [`FrictionLaw::Coulomb`] (de Saxcé passes) removes the lift: the same
//! push leaves the sphere on the plate with the analytic velocities of Coulomb sliding.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::{Grain, add_grains};
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::system::ContactMethod;
use chrono_core::{
    BodyHandle, ContactMaterial, FrictionLaw, RigidBodyBuilder, Shape, System, SystemSettings,
};

const MU: f64 = 0.5;
const R: f64 = 0.003;
const Z0: f64 = 0.005 + R;

/// A sphere of radius `R` resting on a plate, pushed along x by 5 m g (friction, at most
/// `MU m g`, cannot hold it: the contact slides).
fn pushed_sphere(friction_law: FrictionLaw) -> (System, BodyHandle) {
    let settings = SystemSettings {
        envelope: 1e-4,
        friction_law,
        ..SystemSettings::default()
    };
    let mu = MU;
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-10,
        max_iterations: 2000,
        record_history: false,
    });
    let settings = SystemSettings {
        contact_method: ContactMethod::Nsc,
        ..settings
    };
    let mut sys = System::new(settings, Box::new(solver)).unwrap();
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, mu);
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::Box {
            half_extents: Vector3::new(1.0, 1.0, 0.005),
        },
        Isometry3::identity(),
        mat,
    ))
    .unwrap();
    let g = [Grain {
        center: Vector3::new(0.0, 0.0, Z0),
        radius: R,
    }];
    let b = add_grains(&mut sys, &g, 2500.0, mat).unwrap()[0];
    let m = sys.body(b).unwrap().mass();
    sys.body_mut(b)
        .unwrap()
        .set_applied_force(Vector3::new(5.0 * m * GRAVITY.norm(), 0.0, 0.0))
        .unwrap();
    (sys, b)
}

#[test]
fn a_sliding_sphere_lifts_by_mu_times_its_slip() {
    let (mu, r, z0) = (MU, R, Z0);
    let (mut sys, b) = pushed_sphere(FrictionLaw::Relaxed);
    let report = sys.step(1e-3).unwrap();
    assert_eq!(report.friction_passes, 0);
    let body = sys.body(b).unwrap();
    let (v, w) = (body.linear_velocity(), body.angular_velocity());
    // Slip of the contact point (below the centre): v + w x (-r e_z), x component.
    let slip = v.x - w.y * r;
    assert!(slip > 1e-3, "the contact must slide: slip {slip}");
    assert!(
        (v.z - mu * slip).abs() < 1e-6 * slip,
        "normal velocity {} against mu * slip {}",
        v.z,
        mu * slip
    );
    assert!(body.position().z > z0, "the sphere lifts off");
}

#[test]
fn coulomb_passes_slide_the_sphere_without_lift() {
    let h = 1e-3;
    let g = GRAVITY.norm();
    let (mut sys, b) = pushed_sphere(FrictionLaw::Coulomb { passes: 50 });
    let report = sys.step(h).unwrap();
    assert!(
        report.friction_passes >= 1 && report.friction_passes < 50,
        "passes {}",
        report.friction_passes
    );
    let body = sys.body(b).unwrap();
    let (v, w) = (body.linear_velocity(), body.angular_velocity());
    // Coulomb sliding: normal impulse m g h, friction impulse MU m g h against the slip.
    // v_x = (5 - MU) g h; the friction torque R MU m g h about +y on I = 2/5 m R^2 gives
    // w_y = MU g h / (0.4 R); the slip v_x - w_y R = (5 - 3.5 MU) g h stays positive.
    let vx = (5.0 - MU) * g * h;
    let wy = MU * g * h / (0.4 * R);
    assert!((v.x - vx).abs() < 1e-6 * vx, "v_x {} against {vx}", v.x);
    assert!((w.y - wy).abs() < 1e-6 * wy, "w_y {} against {wy}", w.y);
    assert!(v.z.abs() < 1e-6 * vx, "no lift: v_z {}", v.z);
    assert!(
        (body.position().z - Z0).abs() < 1e-9,
        "z {}",
        body.position().z
    );
}

#[test]
fn coulomb_passes_are_rejected_when_zero() {
    let settings = SystemSettings {
        friction_law: FrictionLaw::Coulomb { passes: 0 },
        ..SystemSettings::default()
    };
    let e = settings.validate().unwrap_err().to_string();
    assert!(e.contains("friction_law.passes") && e.contains('0'), "{e}");
}

/// A sphere launched sliding at `v0` on the plate: friction `MU m g` slows the centre and
/// spins the sphere up until it rolls, after `t* = 2 v0 / (7 MU g)` at `5/7 v0` (e.g.
/// Goldstein's billiard ball). With Coulomb's law it never leaves the plate, and the
/// implicit velocity update reaches rolling in the step that contains `t*`.
#[test]
fn coulomb_passes_roll_up_a_launched_sphere_on_the_plate() {
    let (h, g, v0) = (1e-3, GRAVITY.norm(), 0.5);
    let (mut sys, b) = pushed_sphere(FrictionLaw::Coulomb { passes: 50 });
    {
        let body = sys.body_mut(b).unwrap();
        body.set_applied_force(Vector3::zeros()).unwrap();
        body.set_linear_velocity(Vector3::new(v0, 0.0, 0.0))
            .unwrap();
    }
    let t_roll = 2.0 * v0 / (7.0 * MU * g);
    let mut rolled_at = None;
    for k in 1..=60 {
        sys.step(h).unwrap();
        let body = sys.body(b).unwrap();
        let (v, w) = (body.linear_velocity(), body.angular_velocity());
        assert!(
            (body.position().z - Z0).abs() < 1e-9,
            "step {k}: z {} left the plate",
            body.position().z
        );
        let slip = v.x - w.y * R;
        if rolled_at.is_none() && slip.abs() < 1e-6 * v0 {
            rolled_at = Some(k as f64 * h);
        }
    }
    let t = rolled_at.expect("the sphere must roll");
    assert!(
        t >= t_roll - 1e-12 && t < t_roll + h,
        "rolling from {t} s, expected the step containing {t_roll} s"
    );
    let vx = sys.body(b).unwrap().linear_velocity().x;
    assert!(
        (vx - 5.0 / 7.0 * v0).abs() < 1e-6 * v0,
        "rolling speed {vx}"
    );
}
