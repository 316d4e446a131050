//! The relaxation of the NSC contact model, pinned: the cone complementarity problem is the
//! convex relaxation of Coulomb friction (M. Anitescu, "Optimization-based simulation of
//! nonsmooth rigid multibody dynamics", Math. Program. 105, 2006), whose solution makes a
//! sliding contact separate with the normal velocity `mu |v_slip|`. A sphere pushed to slide
//! on a plate lifts off by that much in its first step. This is why `granular-shear`'s NSC
//! peak can exceed Taylor's stress–dilatancy balance (docs/validation-granular.md): the
//! sliding contacts do work against the normal load that the sample's volume does not show.
//! If a friction model without this relaxation lands, this test must change with it.

use chrono_core::granular::{Grain, add_grains};
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, SystemSettings};
use xtask::cases::granular::make_system;

#[test]
fn a_sliding_sphere_lifts_by_mu_times_its_slip() {
    let settings = SystemSettings {
        envelope: 1e-4,
        ..SystemSettings::default()
    };
    let mu = 0.5;
    let mut sys = make_system(ContactMethod::Nsc, settings, 1e-10, 2000).unwrap();
    let mat = ContactMaterial::smc(1e7, 0.3, 0.5, mu);
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::Box {
            half_extents: Vector3::new(1.0, 1.0, 0.005),
        },
        Isometry3::identity(),
        mat,
    ))
    .unwrap();
    let r = 0.003;
    let z0 = 0.005 + r;
    let g = [Grain {
        center: Vector3::new(0.0, 0.0, z0),
        radius: r,
    }];
    let b = add_grains(&mut sys, &g, 2500.0, mat).unwrap()[0];
    let m = sys.body(b).unwrap().mass();
    // A push of 5 m g: friction (at most mu m g) cannot hold it, the contact slides.
    sys.body_mut(b)
        .unwrap()
        .set_applied_force(Vector3::new(5.0 * m * 9.81, 0.0, 0.0))
        .unwrap();
    sys.step(1e-3).unwrap();
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
