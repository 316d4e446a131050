//! Slope attachments: a cable node's slope `r_x` kept along a fixed world direction or a
//! direction fixed in a rigid body, as two bilateral rows in the system's CCP.
//!
//! With [`CableItem::attach`](crate::CableItem::attach) of the same node this is a clamp
//! of the cable to the body: position and section rotation follow the body, the body
//! carries the clamp's force and bending moment.
//!
//! # The rows
//!
//! For a unit direction `d` (world, or `R(q) d_B` of a body with rotation `R`), take two
//! unit vectors `e_1`, `e_2` perpendicular to `d` and to each other, fixed with `d` (in
//! the body frame for a body: `e_k = R e_k,B`). The slope `s = r_x` of the node is along
//! `d` when its two components across `d` vanish:
//!
//! ```text
//! C_k = s . e_k = 0,                                   k = 1, 2
//! dC_k/dt = e_k . s_dot + s . (omega x e_k) = e_k . s_dot + (e_k x s) . omega
//! ```
//!
//! (`de_k/dt = omega x e_k`, `omega` the body's world angular velocity). The row is
//! `D' v + b = 0` with `e_k` on the node's free slope coordinates, `(e_k x s)` on the
//! body's angular velocity ([`RigidBody::angular_jacobian`]) and `b = C_k / h`
//! (stabilized as the position rows, [`crate::dynamics`]); a kinematic body has no block
//! and its known `(e_k x s) . omega` goes into `b`. The length of `s` (the axial stretch
//! at the node) stays free, as with [`CableMesh::clamp`](crate::CableMesh::clamp).
//!
//! # Reaction
//!
//! The multipliers `gamma_k` of a step are impulses; the generalized force on the slope
//! is `f = sum_k e_k gamma_k / h` (N m: `s` is dimensionless), which is the couple
//! `M = s x f` on the cable's section (virtual rotation `delta s = delta theta x s`:
//! `f . delta s = (s x f) . delta theta`). The body receives `-M`
//! (`sum_k gamma_k (e_k x s) / h`). The rows exert no force: the clamp force is the
//! position attachment's.

use chrono_core::Result as CoreResult;
use chrono_core::body::{BodyHandle, RigidBody};
use chrono_core::descriptor::{CcpProblem, ConstraintRows, RowEntry, RowId};
use nalgebra::Vector3;

use crate::attach_rows::AttachContext;
use crate::error::{FeaError, Result};
use crate::node::NodeId;

/// The direction a cable node's slope is kept along (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SlopeTarget {
    /// A fixed world direction (any non-zero length; normalized), -.
    Direction(Vector3<f64>),
    /// A direction fixed in a rigid body, in the body frame (non-zero; normalized), -.
    Body {
        /// The body (of the system the item is added to).
        body: BodyHandle,
        /// The direction in the body frame.
        local: Vector3<f64>,
    },
}

/// A node's slope kept along a target direction by two bilateral rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlopeAttachment {
    /// The node.
    pub node: NodeId,
    /// The direction.
    pub target: SlopeTarget,
    /// Unit vectors across the direction (world for a fixed direction, body frame for a
    /// body), `e_1 x e_2 = d`.
    pub across: [Vector3<f64>; 2],
}

impl SlopeAttachment {
    /// The attachment of `node` to `target`, with the two vectors across the direction.
    /// Errors (naming `slope.direction`): a non-finite or zero direction.
    pub fn new(node: NodeId, target: SlopeTarget) -> Result<Self> {
        let d = match target {
            SlopeTarget::Direction(d) | SlopeTarget::Body { local: d, .. } => d,
        };
        let len = d.norm();
        if !(len.is_finite() && len > 0.0) {
            return Err(FeaError::invalid(
                "slope.direction",
                format!("[{}, {}, {}]", d.x, d.y, d.z),
                "must be finite and non-zero",
            ));
        }
        let d = d / len;
        // The world axis least aligned with d gives a well-conditioned e_1.
        let k = (0..3)
            .min_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
            .unwrap_or(0);
        let mut axis = Vector3::zeros();
        axis[k] = 1.0;
        let e1 = (axis - d * d[k]).normalize();
        let e2 = d.cross(&e1);
        Ok(Self {
            node,
            target,
            across: [e1, e2],
        })
    }
}

/// The slope attachments of an item, their rows of the current step and reactions.
#[derive(Debug, Default)]
pub(crate) struct SlopeRows {
    pub attachments: Vec<SlopeAttachment>,
    /// Rows of this step, 2 per attachment (`None`: nothing can move).
    rows: Vec<Option<RowId>>,
    /// The slope `s` and world `e_k` each row was built with.
    frames: Vec<(Vector3<f64>, [Vector3<f64>; 2])>,
    /// Couples on the nodes' sections from the last step, N m.
    couples: Vec<Vector3<f64>>,
    /// One row's coefficients on the block (zeroed between uses).
    coefs: Vec<f64>,
}

impl SlopeRows {
    /// Store an attachment; returns its index.
    pub fn push(&mut self, attachment: SlopeAttachment) -> usize {
        self.attachments.push(attachment);
        self.couples.push(Vector3::zeros());
        self.attachments.len() - 1
    }

    /// The couple of attachment `i` on its node's section during the last step, N m.
    pub fn couple(&self, i: usize) -> Option<Vector3<f64>> {
        self.couples.get(i).copied()
    }

    /// Push the two rows of every attachment (module docs). `slope(n)` is node `n`'s
    /// slope, `free(n, c)` the column of its slope coordinate `c` in the block (`None`
    /// if supported); `nfree` the block's length.
    pub fn push_rows(
        &mut self,
        slope: impl Fn(usize) -> Vector3<f64>,
        free: impl Fn(usize, usize) -> Option<usize>,
        nfree: usize,
        ctx: &AttachContext<'_>,
        rows: &mut ConstraintRows,
    ) -> CoreResult<()> {
        self.rows.clear();
        self.frames.clear();
        self.coefs.resize(nfree, 0.0);
        for (ai, att) in self.attachments.iter().enumerate() {
            let n = att.node.0;
            let s = slope(n);
            let (e, body): ([Vector3<f64>; 2], Option<&RigidBody>) = match att.target {
                SlopeTarget::Direction(_) => (att.across, None),
                SlopeTarget::Body { body, .. } => {
                    let b = ctx.body(body, format_args!("slope attachment {ai}"))?;
                    let r = b.rotation();
                    ([r * att.across[0], r * att.across[1]], Some(b))
                }
            };
            self.frames.push((s, e));
            for ek in &e {
                let (mut known, mut body_entry) = (0.0, None);
                if let Some(b) = body {
                    let j = b.angular_jacobian(&ek.cross(&s));
                    match b.block() {
                        Some(id) => body_entry = Some((id, j)),
                        None => known = b.jacobian_times_velocity(&j),
                    }
                }
                let mut any_free = false;
                for c in 0..3 {
                    if let Some(f) = free(n, c) {
                        self.coefs[f] = ek[c];
                        any_free = true;
                    }
                }
                if !any_free && body_entry.is_none() {
                    self.rows.push(None);
                    continue;
                }
                let mut entries = [RowEntry {
                    block: ctx.block,
                    coefs: &[],
                }; 2];
                let mut n_ent = 0;
                if any_free {
                    entries[0].coefs = &self.coefs;
                    n_ent = 1;
                }
                if let Some((id, j)) = &body_entry {
                    entries[n_ent] = RowEntry {
                        block: *id,
                        coefs: j,
                    };
                    n_ent += 1;
                }
                let b = s.dot(ek) / ctx.h + known;
                self.rows
                    .push(Some(rows.push_bilateral(&entries[..n_ent], b, 0.0)));
                for c in 0..3 {
                    if let Some(f) = free(n, c) {
                        self.coefs[f] = 0.0;
                    }
                }
            }
        }
        Ok(())
    }

    /// The couples `s x sum_k e_k gamma_k / h` from the step's multipliers.
    pub fn record(&mut self, problem: &CcpProblem, gamma: &[f64], h: f64) {
        for (ai, m) in self.couples.iter_mut().enumerate() {
            *m = Vector3::zeros();
            let Some((s, e)) = self.frames.get(ai) else {
                continue;
            };
            let mut f = Vector3::zeros();
            for k in 0..2 {
                if let Some(Some(id)) = self.rows.get(2 * ai + k) {
                    f += e[k] * (gamma[problem.row_index(*id)] / h);
                }
            }
            *m = s.cross(&f);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn across_vectors_are_orthonormal_and_span_the_normal_plane() {
        for d in [
            Vector3::x(),
            Vector3::new(0.0, 0.0, -2.0),
            Vector3::new(1.0, 2.0, -3.0),
            Vector3::new(1e-9, 1.0, 1e-9),
        ] {
            let a = SlopeAttachment::new(NodeId(0), SlopeTarget::Direction(d)).unwrap();
            let [e1, e2] = a.across;
            let u = d.normalize();
            assert!((e1.norm() - 1.0).abs() < 1e-14 && (e2.norm() - 1.0).abs() < 1e-14);
            assert!(e1.dot(&e2).abs() < 1e-14 && e1.dot(&u).abs() < 1e-14);
            assert!((e1.cross(&e2) - u).norm() < 1e-14, "{d:?}");
        }
    }

    #[test]
    fn bad_direction_names_the_field() {
        for d in [Vector3::zeros(), Vector3::new(f64::NAN, 0.0, 1.0)] {
            let e = SlopeAttachment::new(NodeId(0), SlopeTarget::Direction(d))
                .unwrap_err()
                .to_string();
            assert!(e.contains("slope.direction"), "{e}");
        }
    }
}
