//! Coupled tests: momentum conservation in a triply periodic box, equal and opposite pair
//! forces, exact end times, bad input.

use chrono_ccp::Psor;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_sph::SphSettings;

use crate::{FsiBuilder, FsiError, SphFluid};

fn periodic_settings(dp: f64, l: f64) -> SphSettings {
    SphSettings {
        spacing: dp,
        sound_speed: 10.0,
        viscosity: 1e-2,
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        gravity: [0.0; 3],
        ..SphSettings::default()
    }
}

fn zero_g_system() -> System {
    let s = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    System::new(s, Box::new(Psor::new(Default::default()))).unwrap()
}

/// A triply periodic box of fluid at rest around a free body of `shape` moving at `v0`.
fn periodic_scene(
    shape: Shape,
    density: f64,
    v0: Vector3<f64>,
) -> (System, BodyHandle, ItemHandle) {
    let (dp, l) = (0.02, 0.36);
    let mut sys = zero_g_system();
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .name("float")
                .mass_from_shape(&shape, density)
                .unwrap()
                .position(Vector3::repeat(0.5 * l))
                .linear_velocity(v0)
                .angular_velocity(Vector3::new(0.0, 2.0, 1.0))
                .collider(shape, Isometry3::identity(), Default::default()),
        )
        .unwrap();
    let mut fsi = FsiBuilder::new(periodic_settings(dp, l)).unwrap();
    fsi.add_fluid_box([0.0; 3], [l; 3], None).unwrap();
    fsi.add_body(&sys, b).unwrap();
    let item = sys.add_item(Box::new(fsi.build("water", 1).unwrap()));
    (sys, b, item)
}

fn total_momentum(sys: &System, b: BodyHandle, item: ItemHandle) -> Vector3<f64> {
    let f = sys.item::<SphFluid>(item).unwrap();
    let body = sys.body(b).unwrap();
    f.sph().fluid_momentum() + body.mass() * body.linear_velocity()
}

/// Fluid plus body momentum is conserved to round-off over more than 1000 fluid
/// sub-steps (no walls, no gravity: only the pair forces act, and the body gets exactly
/// the reactions of the kicks the fluid gets).
#[test]
fn momentum_of_fluid_and_body_is_conserved_in_a_periodic_box() {
    // the sphere over 1000 sub-steps, the box (corners, rotation) and the ellipsoid
    // (rotation) over 300
    for (shape, substeps) in [
        (Shape::Sphere { radius: 0.07 }, 1000),
        (
            Shape::Box {
                half_extents: Vector3::new(0.08, 0.05, 0.06),
            },
            300,
        ),
        (
            Shape::Ellipsoid {
                semi_axes: Vector3::new(0.09, 0.06, 0.05),
            },
            300,
        ),
    ] {
        let v0 = Vector3::new(0.3, -0.1, 0.2);
        let (mut sys, b, item) = periodic_scene(shape, 700.0, v0);
        let p0 = total_momentum(&sys, b, item);
        let scale = sys.body(b).unwrap().mass() * v0.norm();
        let mut max_err: f64 = 0.0;
        let mut moved = 0.0;
        while sys.item::<SphFluid>(item).unwrap().substeps() < substeps {
            sys.step(2e-3).unwrap();
            let p = total_momentum(&sys, b, item);
            max_err = max_err.max((p - p0).norm() / scale);
            moved = (sys.body(b).unwrap().linear_velocity() - v0).norm() / v0.norm();
        }
        // the fluid really exchanged momentum with the body
        eprintln!("{substeps} sub-steps: momentum drift {max_err:e}, body velocity change {moved}");
        assert!(moved > 0.05, "body velocity changed by only {moved}");
        assert!(max_err < 1e-12, "momentum drift {max_err:e} (relative)");
    }
}

/// The fluid's force on the markers is exactly the reaction of the markers' force on the
/// fluid (pressure and viscous pair terms), to round-off.
#[test]
fn marker_forces_are_equal_and_opposite() {
    let (mut sys, _b, item) = periodic_scene(
        Shape::Sphere { radius: 0.07 },
        500.0,
        Vector3::new(0.5, 0.0, 0.0),
    );
    for _ in 0..20 {
        sys.step(2e-3).unwrap();
    }
    let f = sys.item::<SphFluid>(item).unwrap();
    let on_fluid = f.sph().fluid_force();
    let on_body = f.sph().carrier_load(0)[0];
    assert!(on_body.norm() > 1e-3, "no force: {on_body}");
    let err = (on_fluid + on_body).norm() / on_body.norm();
    assert!(err < 1e-12, "action {on_fluid} reaction {on_body}: {err:e}");
}

/// The fluid ends each system step exactly at the system's time, with at least as many
/// sub-steps as its stability limit asks.
#[test]
fn the_fluid_ends_each_step_at_the_system_time() {
    let (mut sys, _b, item) = periodic_scene(
        Shape::Sphere { radius: 0.07 },
        500.0,
        Vector3::new(0.5, 0.0, 0.0),
    );
    for h in [1e-3, 3.7e-3, 2e-4] {
        sys.step(h).unwrap();
        let f = sys.item::<SphFluid>(item).unwrap();
        assert_eq!(f.sph().time(), sys.time());
        let dt = f.sph().dt();
        assert!(
            f.last_substeps() as f64 >= (h / dt).floor(),
            "{} sub-steps for h/dt = {}",
            f.last_substeps(),
            h / dt
        );
    }
}

fn tank_builder(dp: f64) -> FsiBuilder {
    let s = SphSettings {
        spacing: dp,
        sound_speed: 10.0,
        domain_lower: [0.0; 3],
        domain_upper: [1.0; 3],
        ..SphSettings::default()
    };
    FsiBuilder::new(s).unwrap()
}

fn one_body(shape: Shape) -> (System, BodyHandle) {
    let mut sys = zero_g_system();
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .name("hull")
                .mass(1.0)
                .inertia_diagonal(Vector3::repeat(0.1))
                .position(Vector3::repeat(0.5))
                .collider(shape, Isometry3::identity(), Default::default()),
        )
        .unwrap();
    (sys, b)
}

#[test]
fn bad_bodies_are_errors_naming_the_body_and_value() {
    let dp = 0.02;
    // thinner than the support 2 h = 2.6 dp
    let (sys, b) = one_body(Shape::Box {
        half_extents: Vector3::new(0.2, 0.2, 0.02),
    });
    let e = tank_builder(dp).add_body(&sys, b).unwrap_err();
    assert!(
        matches!(e, FsiError::BodyThinnerThanSupport { ref body, thickness, .. } if body == "hull" && (thickness - 0.04).abs() < 1e-12),
        "{e}"
    );
    // thick enough for the support, but 3 spacings across a sphere do not resolve it
    let (sys, b) = one_body(Shape::Sphere { radius: 0.03 });
    let e = tank_builder(dp).add_body(&sys, b).unwrap_err();
    assert!(
        matches!(e, FsiError::Unresolved { ref body, .. } if body == "hull"),
        "{e}"
    );
    assert!(e.to_string().contains("0.06"), "{e}");
    // an ellipsoid: its smallest semi-axis decides (2 x 0.025 m < 2 h), then resolution
    let (sys, b) = one_body(Shape::Ellipsoid {
        semi_axes: Vector3::new(0.2, 0.025, 0.1),
    });
    let e = tank_builder(dp).add_body(&sys, b).unwrap_err();
    assert!(
        matches!(e, FsiError::BodyThinnerThanSupport { ref body, ref shape, thickness, .. } if body == "hull" && shape == "ellipsoid" && (thickness - 0.05).abs() < 1e-12),
        "{e}"
    );
    let (sys, b) = one_body(Shape::Ellipsoid {
        semi_axes: Vector3::new(0.2, 0.035, 0.1),
    });
    let e = tank_builder(dp).add_body(&sys, b).unwrap_err();
    assert!(
        matches!(e, FsiError::Unresolved { ref body, ref shape, .. } if body == "hull" && shape == "ellipsoid"),
        "{e}"
    );
    assert!(e.to_string().contains("0.07"), "{e}");
    // a shape without marker generation
    let (sys, b) = one_body(Shape::Capsule {
        half_length: 0.1,
        radius: 0.1,
    });
    let e = tank_builder(dp).add_body(&sys, b).unwrap_err();
    assert!(
        matches!(e, FsiError::UnsupportedShape { ref body, ref shape } if body == "hull" && shape == "capsule"),
        "{e}"
    );
}

/// A fluid stepped outside the system, or with another gravity, is refused with an error
/// naming the field.
#[test]
fn mismatched_gravity_is_an_error() {
    let (mut sys, b) = one_body(Shape::Sphere { radius: 0.1 });
    let mut fsi = FsiBuilder::new(SphSettings {
        spacing: 0.02,
        sound_speed: 10.0,
        domain_lower: [0.0; 3],
        domain_upper: [1.0; 3],
        periodic: [true; 3],
        gravity: [0.0, 0.0, -9.81],
        ..SphSettings::default()
    })
    .unwrap();
    fsi.add_fluid_box([0.0; 3], [1.0, 1.0, 0.2], None).unwrap();
    fsi.add_body(&sys, b).unwrap();
    sys.add_item(Box::new(fsi.build("water", 1).unwrap()));
    let e = sys.step(1e-3).unwrap_err();
    assert!(e.to_string().contains("gravity"), "{e}");
}

/// A box at rest at its Archimedes draft in still water (slab tank, gravity) does not
/// drift: no horizontal motion (the scene is symmetric), no tilt, and it stays within a
/// quarter spacing of where it started (the draft acceptance of issue 24).
#[test]
fn floating_box_at_rest_does_not_drift() {
    use crate::scene::{FloatShape, FloatingParams, floating};
    let p = FloatingParams {
        shape: FloatShape::Box,
        body_size: 0.08,
        depth: 0.12,
        length: 8.0,
        spacing: 0.02,
        offset: 0.0,
        ..FloatingParams::default()
    };
    let mut scene = floating(&p, Box::new(Psor::new(Default::default()))).unwrap();
    let x0 = scene.system.body(scene.body).unwrap().position();
    let mut max_dz: f64 = 0.0;
    while scene.system.time() < 0.3 {
        scene.system.step(1e-3).unwrap();
        let x = scene.system.body(scene.body).unwrap().position();
        max_dz = max_dz.max((x.z - x0.z).abs());
    }
    let body = scene.system.body(scene.body).unwrap();
    let x = body.position();
    let dx = ((x.x - x0.x).powi(2) + (x.y - x0.y).powi(2)).sqrt();
    let tilt = body.rotation().angle();
    eprintln!("rest: horizontal drift {dx:e} m, tilt {tilt:e} rad, largest heave {max_dz:e} m");
    // round-off only: the scene and its carving are mirror-symmetric
    assert!(dx < 1e-8 * p.spacing, "horizontal drift {dx:e} m");
    assert!(tilt < 1e-8, "tilt {tilt:e} rad");
    assert!(max_dz < 0.25 * p.spacing, "heave {max_dz:e} m");
}
