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

/// Vertical strain `eps` (compression positive) of the affine uniaxial compression that
/// best explains the overlaps of the last step's grain–grain contacts (bodies outside
/// `structure`): an affine field `u_z = -eps z` closes a contact of unstrained branch
/// length `l` (the touching distance `|x_b - x_a| + delta`) and unit normal `n` by
/// `delta = eps l n_z^2` (to first order in `eps`), so the least-squares fit over the
/// contacts is
///
/// `eps = sum(delta l n_z^2) / sum(l^2 n_z^4)`.
///
/// This is the elastic part of a sample's height under load (penalty contacts: the
/// overlaps; NSC: the solver's residual penetration), so `phi (1 - eps)` is the solid
/// fraction the same packing would have with rigid grains. Laterally confined (a box), the
/// compression is close to uniaxial. 0 without grain–grain contacts.
pub fn uniaxial_overlap_strain(sys: &System, structure: &[u32]) -> anyhow::Result<f64> {
    let (mut num, mut den) = (0.0, 0.0);
    let mut add = |a: u32, b: u32, n: Vector3<f64>, delta: f64| -> anyhow::Result<()> {
        if delta <= 0.0 || structure.contains(&a) || structure.contains(&b) || a == b {
            return Ok(());
        }
        let xa = sys.bodies()[a as usize].position();
        let xb = sys.bodies()[b as usize].position();
        let l = (xb - xa).norm() + delta;
        let nz2 = n.z * n.z;
        num += delta * l * nz2;
        den += l * l * nz2 * nz2;
        Ok(())
    };
    match sys.settings().contact_method {
        ContactMethod::Nsc => {
            for c in sys.contacts() {
                let p = &c.point;
                add(p.owner_a, p.owner_b, c.normal(), -p.distance)?;
            }
        }
        ContactMethod::Smc => {
            for c in sys.smc_contacts() {
                add(c.owner_a, c.owner_b, c.normal, c.overlap)?;
            }
        }
    }
    Ok(if den > 0.0 { num / den } else { 0.0 })
}
