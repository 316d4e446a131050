//! Forces that the grains of a granular scene exert on chosen bodies (walls, a shear box's
//! frame, an intruder), from the last step's contacts of either method.

use chrono_core::System;
use chrono_core::system::ContactMethod;
use nalgebra::Vector3;

/// Sum of the contact forces (N, world) that bodies outside `structure` (the grains) exert
/// on the bodies in `targets`, in the last step. NSC: the contact impulses of the last
/// CCP divided by `h`; SMC: the penalty forces.
pub fn grain_forces_on(sys: &System, h: f64, targets: &[u32], structure: &[u32]) -> Vector3<f64> {
    let is_grain = |o: u32| !structure.contains(&o);
    let mut f = Vector3::zeros();
    // Force on B (A gets the opposite): returns the share of `targets` from grains.
    let mut add = |a: u32, b: u32, on_b: Vector3<f64>| {
        if targets.contains(&b) && is_grain(a) {
            f += on_b;
        }
        if targets.contains(&a) && is_grain(b) {
            f -= on_b;
        }
    };
    match sys.settings().contact_method {
        ContactMethod::Nsc => {
            let (problem, gamma) = (sys.last_problem(), sys.last_gamma());
            for c in sys.contacts() {
                let k = problem.row_index(c.row);
                if k + 2 >= gamma.len() {
                    continue;
                }
                // Rows n, u, w are B's velocity relative to A's: the impulse acts on B.
                let imp = c.normal() * gamma[k] + c.u * gamma[k + 1] + c.w * gamma[k + 2];
                add(c.point.owner_a, c.point.owner_b, imp / h);
            }
        }
        ContactMethod::Smc => {
            for c in sys.smc_contacts() {
                add(c.owner_a, c.owner_b, c.force);
            }
        }
    }
    f
}
