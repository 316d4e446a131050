//! Tests of the constraint-fluid coupling ([`crate::cfluid`]).

use chrono_ccp::Apgd;
use chrono_cfluid::{CfluidSettings, ConstraintFluid};
use chrono_core::descriptor::SolverSettings;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::{Fit, Lattice};
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};

use crate::builder::signed_distance;
use crate::cfluid::{CfluidFloat, attach_body, floating_cfluid};
use crate::error::FsiError;
use crate::scene::{FloatShape, FloatingParams};

const DP: f64 = 0.02;
const SIDE: f64 = 0.32;

/// The momentum balance holds for any iterate (each row's and contact's impulses sum to
/// zero on their own), so a short solve serves.
fn solver() -> Box<Apgd> {
    Box::new(Apgd::new(SolverSettings {
        tolerance: 1e-6,
        max_iterations: 40,
        record_history: false,
    }))
}

/// A triply periodic box of constraint fluid at rest without gravity, a free body of
/// `shape` in its middle moving at `v0`.
fn periodic_scene(
    shape: Shape,
    density: f64,
    v0: Vector3<f64>,
) -> (System, BodyHandle, ItemHandle) {
    periodic_scene_with(shape, density, v0, 0.0, solver())
}

/// [`periodic_scene`] with the fluid's `surface_deficit` and the system's solver.
fn periodic_scene_with(
    shape: Shape,
    density: f64,
    v0: Vector3<f64>,
    surface_deficit: f64,
    solver: Box<Apgd>,
) -> (System, BodyHandle, ItemHandle) {
    let settings = CfluidSettings {
        surface_deficit,
        spacing: DP,
        domain_lower: [0.0; 3],
        domain_upper: [SIDE; 3],
        periodic: [true; 3],
        ..CfluidSettings::default()
    };
    let mut sys = System::new(
        SystemSettings {
            gravity: Vector3::zeros(),
            envelope: 0.25 * DP,
            ..SystemSettings::default()
        },
        solver,
    )
    .unwrap();
    let c = 0.5 * SIDE;
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .name("float")
                .mass_from_shape(&shape, density)
                .unwrap()
                .position(Vector3::new(c, c, c))
                .linear_velocity(v0)
                .collider(shape.clone(), Isometry3::identity(), Default::default()),
        )
        .unwrap();
    let fluid: Vec<[f64; 3]> = Lattice::new([0.0; 3], DP)
        .unwrap()
        .fill([0.0; 3], [SIDE; 3], Fit::Floor)
        .unwrap()
        .into_iter()
        .filter(|q| {
            // carved as the floating scene: no contact sphere overlaps the body
            signed_distance(&shape, [q[0] - c, q[1] - c, q[2] - c], [false; 3]) > (0.5 - 1e-6) * DP
        })
        .collect();
    let mut item = ConstraintFluid::new("water", settings, &fluid, &[]).unwrap();
    let n = attach_body(&mut item, &sys, b).unwrap();
    assert!(n > 0);
    let id = sys.add_item(Box::new(item));
    (sys, b, id)
}

fn total_momentum(sys: &System, b: BodyHandle, id: ItemHandle) -> Vector3<f64> {
    let f = sys.item::<ConstraintFluid>(id).unwrap();
    let m = f.particle_mass();
    let fluid: Vector3<f64> = f
        .velocities()
        .iter()
        .map(|v| m * Vector3::new(v[0], v[1], v[2]))
        .sum();
    let body = sys.body(b).unwrap();
    fluid + body.mass() * body.linear_velocity()
}

/// One CCP for fluid and body: every density row's impulse on the body's markers is the
/// reaction of its impulse on the particles (the row's gradient sums to zero by
/// translation invariance), and so is every contact's; so the fluid's plus the body's
/// momentum is constant to round-off, whatever the solver's residual, for every shape
/// with markers.
#[test]
fn momentum_of_constraint_fluid_and_body_is_conserved() {
    for shape in [
        Shape::Sphere { radius: 0.07 },
        Shape::Box {
            half_extents: Vector3::new(0.08, 0.05, 0.06),
        },
        Shape::Cylinder {
            half_length: 0.06,
            radius: 0.06,
        },
        Shape::Ellipsoid {
            semi_axes: Vector3::new(0.09, 0.06, 0.05),
        },
    ] {
        let v0 = Vector3::new(0.3, -0.1, 0.2);
        let (mut sys, b, id) = periodic_scene(shape.clone(), 700.0, v0);
        let p0 = total_momentum(&sys, b, id);
        let scale = sys.body(b).unwrap().mass() * v0.norm();
        let mut max_err: f64 = 0.0;
        for _ in 0..15 {
            sys.step(2e-3).unwrap();
            max_err = max_err.max((total_momentum(&sys, b, id) - p0).norm() / scale);
        }
        let moved = (sys.body(b).unwrap().linear_velocity() - v0).norm() / v0.norm();
        eprintln!("{shape:?}: momentum drift {max_err:e}, body velocity change {moved}");
        assert!(
            moved > 0.05,
            "{shape:?}: body velocity changed by only {moved}"
        );
        assert!(
            max_err < 1e-12,
            "{shape:?}: momentum drift {max_err:e} (relative)"
        );
    }
}

/// Shapes without markers and bodies the spacing does not resolve are errors naming the
/// body.
#[test]
fn bad_bodies_are_named() {
    let settings = CfluidSettings {
        spacing: DP,
        domain_lower: [0.0; 3],
        domain_upper: [SIDE; 3],
        periodic: [true; 3],
        ..CfluidSettings::default()
    };
    let fluid = [[0.01, 0.01, 0.01]];
    for (shape, what) in [
        (
            Shape::Capsule {
                half_length: 0.05,
                radius: 0.05,
            },
            "no BCE marker generation",
        ),
        (
            Shape::Sphere { radius: 0.02 },
            "thinner than the kernel support",
        ),
        (
            Shape::Box {
                half_extents: Vector3::new(0.1, 0.1, 0.035),
            },
            "does not resolve",
        ),
    ] {
        let mut sys = System::new(SystemSettings::default(), solver()).unwrap();
        let b = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .name("odd")
                    .mass(1.0)
                    .position(Vector3::new(0.16, 0.16, 0.16))
                    .collider(shape.clone(), Isometry3::identity(), Default::default()),
            )
            .unwrap();
        let mut item = ConstraintFluid::new("water", settings.clone(), &fluid, &[]).unwrap();
        let e = attach_body(&mut item, &sys, b).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("\"odd\"") && msg.contains(what),
            "{shape:?}: {msg}"
        );
    }
    // no collider at all
    let mut sys = System::new(SystemSettings::default(), solver()).unwrap();
    let b = sys
        .add_body(RigidBodyBuilder::dynamic().name("bare").mass(1.0))
        .unwrap();
    let mut item = ConstraintFluid::new("water", settings, &fluid, &[]).unwrap();
    assert!(matches!(
        attach_body(&mut item, &sys, b),
        Err(FsiError::NoShape { body }) if body == "bare"
    ));
}

/// The floating scene's fluid keeps its volume: the lattice carved around the body holds
/// the tank's water less the body's volume below the level, up to the cells the carving
/// takes or leaves along the wetted surface (a point goes when its contact sphere would
/// overlap the body: at most a layer one spacing thick), so the volume reading starts at
/// the Archimedes draft (the body is placed there) within that layer's volume over the
/// tank's plan area, for each shape.
#[test]
fn the_floating_scene_starts_at_its_archimedes_draft() {
    for shape in [FloatShape::Box, FloatShape::Cylinder, FloatShape::Sphere] {
        let p = FloatingParams {
            shape,
            body_size: 0.1,
            depth: 0.15,
            length: if shape == FloatShape::Sphere {
                3.0
            } else {
                20.0
            },
            width: 3.0,
            spacing: DP,
            offset: 0.0,
            ..FloatingParams::default()
        };
        let scene = floating_cfluid(&p, &CfluidFloat::default(), solver()).unwrap();
        let d = scene.draft(&p);
        let (s, da) = (p.body_size, scene.draft_archimedes);
        let [len, width] = scene.tank;
        // wetted area over plan area (the slab shapes per unit width)
        let wet_over_plan = match shape {
            FloatShape::Box => (crate::scene::BOX_ASPECT * s + 2.0 * da) / len,
            FloatShape::Cylinder => 0.5 * std::f64::consts::PI * s / len,
            FloatShape::Sphere => 0.5 * std::f64::consts::PI * s * s / (len * width),
        };
        let bound = wet_over_plan * DP;
        eprintln!(
            "{shape:?}: start draft {d} against {da} ({} particles), bound {bound}",
            scene.fluid().n_fluid()
        );
        assert!((d - da).abs() < bound, "{shape:?}: {d} against {da}");
    }
}

/// The added mass a constraint fluid gives a sphere started impulsively in a periodic
/// box: with one-sided rows the fluid next to the sphere (10-25 % short of `rho_0`: the
/// markers of a convex surface) is a free surface that pushes but never pulls, and the
/// sphere keeps most of its speed; with those deficits on bilateral rows
/// (`surface_deficit` 0.3) the added mass after six steps is the potential flow's
/// `rho V / 2` (a little more in the box: 4.4 % solid fraction). `docs/validation-fsi.md`,
/// "Constraint fluids".
#[test]
fn a_sphere_gets_its_added_mass_only_where_the_near_body_rows_are_bilateral() {
    let ca = |deficit: f64| {
        let tight = Box::new(Apgd::new(SolverSettings {
            tolerance: 1e-7,
            max_iterations: 1000,
            record_history: false,
        }));
        let r = 0.07;
        let (mut sys, b, _) = periodic_scene_with(
            Shape::Sphere { radius: r },
            700.0,
            Vector3::new(0.1, 0.0, 0.0),
            deficit,
            tight,
        );
        let m = sys.body(b).unwrap().mass();
        let displaced = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        for _ in 0..6 {
            sys.step(1e-3).unwrap();
        }
        let v = sys.body(b).unwrap().linear_velocity().x / 0.1;
        (1.0 / v - 1.0) * m / displaced
    };
    let (one_sided, bilateral) = (ca(0.0), ca(0.3));
    eprintln!("effective added-mass coefficient: one-sided {one_sided}, bilateral {bilateral}");
    assert!(one_sided < 0.25, "one-sided rows: C_a {one_sided}");
    assert!(
        (bilateral - 0.55).abs() < 0.08,
        "bilateral near-body rows: C_a {bilateral}"
    );
    let bad = CfluidSettings {
        surface_deficit: -0.1,
        ..CfluidSettings::default()
    };
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("cfluid.surface_deficit"), "{e}");
}
