//! The forces of the last step's contacts, by either contact method: NSC impulses over the
//! step, SMC penalty forces.

use nalgebra::Vector3;

use super::{ContactMethod, System};

/// One contact's force at the last step: the two bodies (dense indices), the force on the
/// second (N, world; the first gets its opposite) and the contact point (on the second's
/// surface, world).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactForce {
    /// Dense index of body A.
    pub owner_a: usize,
    /// Dense index of body B.
    pub owner_b: usize,
    /// Force on B, N.
    pub on_b: Vector3<f64>,
    /// Contact point, m.
    pub point: Vector3<f64>,
}

/// The forces of the last step's contacts (NSC: impulses over `h` s; SMC: the penalty
/// forces).
pub fn contact_forces(sys: &System, h: f64) -> Vec<ContactForce> {
    let mut out = Vec::new();
    match sys.settings().contact_method {
        ContactMethod::Nsc => {
            let (problem, gamma) = (sys.last_problem(), sys.last_gamma());
            for c in sys.contacts() {
                let k = problem.row_index(c.row);
                if k + 2 >= gamma.len() {
                    continue;
                }
                let on_b = (c.normal() * gamma[k] + c.u * gamma[k + 1] + c.w * gamma[k + 2]) / h;
                out.push(ContactForce {
                    owner_a: c.point.owner_a as usize,
                    owner_b: c.point.owner_b as usize,
                    on_b,
                    point: c.point.point_b,
                });
            }
        }
        ContactMethod::Smc => {
            for c in sys.smc_contacts() {
                out.push(ContactForce {
                    owner_a: c.owner_a as usize,
                    owner_b: c.owner_b as usize,
                    on_b: c.force,
                    point: c.point,
                });
            }
        }
    }
    out
}
