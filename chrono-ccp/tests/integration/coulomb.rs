//! Coulomb's law by de Saxcé passes (`FrictionLaw::Coulomb`) on random single contacts: a
//! sphere at rest on a plate, pushed by a random horizontal force, with a random friction
//! coefficient. One step must satisfy Coulomb's law exactly as the analytic single-contact
//! problem does: no normal velocity (the relaxed cone would lift a sliding sphere at
//! `mu |slip|`), the normal impulse carries the weight, and the friction impulse is inside the
//! disc of radius `mu N` — on its rim and against the slip when the contact slides, with no
//! slip when it is inside.

use chrono_ccp::{Apgd, Psor, SolverSettings};
use chrono_core::descriptor::CcpSolver;
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::{ContactMaterial, FrictionLaw, RigidBodyBuilder, Shape, System, SystemSettings};
use proptest::prelude::*;

const H: f64 = 1e-3;
const R: f64 = 0.01;
const DENSITY: f64 = 2500.0;
/// The passes converge linearly at `3.5 mu^2 / (1 + 3.5 mu^2)` for a sphere on a plate
/// (0.83 at mu = 1.2): ~110 passes from a shift of ~0.07 m/s to the tolerance 1e-9 m/s.
const PASSES: usize = 400;

/// One step of the pushed sphere; returns (velocity, angular velocity, mass, passes).
fn step(
    solver: Box<dyn CcpSolver>,
    mu: f64,
    push: Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>, f64, usize) {
    let settings = SystemSettings {
        envelope: 1e-4,
        friction_law: FrictionLaw::Coulomb { passes: PASSES },
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, solver).unwrap();
    let mat = ContactMaterial::with_friction(mu);
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        mat,
    ))
    .unwrap();
    let ball = Shape::Sphere { radius: R };
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass_from_shape(&ball, DENSITY)
                .unwrap()
                .position(Vector3::new(0.0, 0.0, R))
                .collider(ball, Isometry3::identity(), mat),
        )
        .unwrap();
    let m = sys.body(b).unwrap().mass();
    sys.body_mut(b)
        .unwrap()
        .set_applied_force(push * m * -GRAVITY.z)
        .unwrap();
    let report = sys.step(H).unwrap();
    let body = sys.body(b).unwrap();
    (
        body.linear_velocity(),
        body.angular_velocity(),
        m,
        report.friction_passes,
    )
}

fn solvers() -> Vec<(&'static str, Box<dyn CcpSolver>)> {
    let s = SolverSettings {
        tolerance: 1e-9,
        max_iterations: 5000,
        record_history: false,
    };
    vec![
        ("apgd", Box::new(Apgd::new(s.clone()))),
        ("psor", Box::new(Psor::new(s))),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn one_step_obeys_coulomb(
        mu in 0.0f64..1.2,
        px in -6.0f64..6.0,
        py in -6.0f64..6.0,
    ) {
        let g = -GRAVITY.z;
        let push = Vector3::new(px, py, 0.0);
        for (name, solver) in solvers() {
            let (v, w, m, passes) = step(solver, mu, push);
            let scale = g * H;
            prop_assert!(passes < PASSES, "{}: passes {}", name, passes);
            // No lift.
            prop_assert!(v.z.abs() < 1e-6 * scale, "{}: v_z {:e}", name, v.z);
            // Impulses from the momentum change (the sphere started at rest): normal m g h,
            // tangential m v_t - F_t h.
            let n = m * (v.z + g * H);
            prop_assert!((n - m * g * H).abs() < 1e-6 * m * g * H, "{}: N {}", name, n);
            let ft = m * Vector3::new(v.x, v.y, 0.0) - push * m * g * H;
            // Slip of the contact point at -R e_z.
            let slip = v + w.cross(&Vector3::new(0.0, 0.0, -R));
            let slip_t = Vector3::new(slip.x, slip.y, 0.0);
            prop_assert!(ft.norm() <= mu * n * (1.0 + 1e-6) + 1e-12, "{}: |F_t| {} > mu N {}", name, ft.norm(), mu * n);
            if slip_t.norm() > 1e-6 * scale {
                // Sliding: on the rim, against the slip.
                prop_assert!((ft.norm() - mu * n).abs() < 1e-6 * m * g * H, "{}: |F_t| {} vs mu N {}", name, ft.norm(), mu * n);
                if mu > 0.0 {
                    let cos = -ft.dot(&slip_t) / (ft.norm() * slip_t.norm());
                    prop_assert!(cos > 1.0 - 1e-6, "{}: friction not against the slip (cos {})", name, cos);
                }
            }
        }
    }
}
