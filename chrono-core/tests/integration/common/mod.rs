//! Scaffolding shared by chrono-core's integration tests: a tight solver, gravity on an
//! incline, the half-space ground and a sphere.
#![allow(dead_code)]

use chrono_ccp::{Apgd, CcpSolver, SolverSettings};
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System};

/// Magnitude of [`GRAVITY`], m/s^2.
pub fn g() -> f64 {
    -GRAVITY.z
}

/// Gravity tilted by `angle` (rad) about Y: the ground plane z = 0 becomes an incline of
/// that angle whose slope runs down along +x.
pub fn incline_gravity(angle: f64) -> Vector3<f64> {
    Vector3::new(g() * angle.sin(), 0.0, -g() * angle.cos())
}

/// APGD with a tight tolerance (1e-10 m/s) and `max_iterations`, so that the analytic
/// results are not blurred by the solver.
pub fn tight_apgd(max_iterations: usize) -> Box<dyn CcpSolver> {
    Box::new(Apgd::new(SolverSettings {
        tolerance: 1e-10,
        max_iterations,
        record_history: false,
    }))
}

/// Add the fixed half-space z <= 0 (normal +z) named `name`, material `mat`.
pub fn add_ground(sys: &mut System, name: &str, mat: ContactMaterial) -> BodyHandle {
    sys.add_body(RigidBodyBuilder::fixed().name(name).collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        mat,
    ))
    .unwrap()
}

/// A dynamic solid sphere named `ball` of radius `r` (m) and density `density` (kg/m^3)
/// centred at `position`, material `mat`; chain velocities or a rotation onto it.
pub fn sphere(
    r: f64,
    density: f64,
    position: Vector3<f64>,
    mat: ContactMaterial,
) -> RigidBodyBuilder {
    let s = Shape::Sphere { radius: r };
    RigidBodyBuilder::dynamic()
        .name("ball")
        .mass_from_shape(&s, density)
        .unwrap()
        .position(position)
        .collider(s, Isometry3::identity(), mat)
}
