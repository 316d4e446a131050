//! The rows that tie mesh nodes to fixed points or rigid-body points, shared by the
//! implicit mesh items ([`crate::dynamics::CableItem`], [`crate::tet_dynamics::TetItem`],
//! [`crate::shell_dynamics::ShellItem`]), and the rows that tie a shell node's director to
//! a fixed direction or a direction of a rigid body.
//!
//! Per attachment and axis `d`, one bilateral row on the node's position coordinate and, for
//! a body target, the body's point Jacobian: `C_d = x_d - p_d` (node minus target point),
//! `D' v + C_d / h = 0` with the target's known velocity (a kinematic body's) on the right.
//!
//! ## The body's lever arm: at the end of the step
//!
//! The mesh's force enters its step linearized to the end of the step,
//! `F(q) - h K_T v+ ~ F(q + h v+)`. For an equivariant internal force (elastic, follower
//! pressure) a rigid turn of the mesh turns that force with it: `K_T (w x q) = w x G`,
//! `G = Q - F_p`, so over a step the reaction the mesh sends through a row turns by
//! `h omega` with the body. Taken on the body with its start-of-step arm `p - x`, that
//! turned force has a lever arm the body does not see, and the pair (node, body) injects
//! the torque `h^2 sum_b (omega x a_b) x G_b` per step: a prestressed mesh on a spinning
//! body (an inflated tire on its rim: bead reactions of some 10 kN) spins itself up
//! exponentially at a rate proportional to `h` (issue 27: rim 10 -> 50 rad/s in 0.3 s at
//! h = 2 ms). The body's side of a row is therefore taken at the end-of-step point
//! `p + h omega x (p - x)` (and a director target at `a + h omega x a`), with the body's
//! known `omega`: the pair's torque then cancels the turn to `O(h^2)` per step, and the
//! constraint value `C` still uses the start point (the drift correction is unchanged).

use chrono_core::Bodies;
use chrono_core::body::{BodyHandle, RigidBody};
use chrono_core::descriptor::{BlockId, ConstraintRows, RowEntry, RowId};
use chrono_core::item::Contactable;
use chrono_core::{ChronoError, Result as CoreResult};
use nalgebra::{Point3, Vector3};

use crate::dynamics::{AttachTarget, Attachment};
use crate::shell_dynamics::DirectorTarget;

/// Where a mesh item's attachment rows get their data.
pub(crate) struct AttachContext<'a> {
    /// The mesh's variable block.
    pub block: BlockId,
    /// The system's bodies at the start of the step.
    pub bodies: &'a Bodies,
    /// Step size, s.
    pub h: f64,
    /// The item's name for messages.
    pub label: &'a str,
}

impl AttachContext<'_> {
    /// The body of `handle` at the start of the step; the error names the item and
    /// `what` (e.g. `"slope attachment 2"`) when the handle is not in the system.
    pub fn body(
        &self,
        handle: BodyHandle,
        what: std::fmt::Arguments<'_>,
    ) -> CoreResult<&RigidBody> {
        self.bodies.get(handle).ok_or(ChronoError::UnknownHandle {
            kind: "body",
            index: handle.index() as usize,
            field: format!("{}: {what} ({handle})", self.label),
        })
    }
}

/// Push the rows of every attachment into `rows` and their ids (or `None` for an axis that
/// nothing can move: a supported coordinate at a fixed target) into `ids`, three per
/// attachment. `position(node)` is the node's position, `free(node, d)` the column of its
/// position coordinate `d` in the mesh block (`None` if supported); `coefs` is a zeroed
/// scratch row of the block's length (left zeroed).
pub(crate) fn push_attachment_rows(
    attachments: &[Attachment],
    position: impl Fn(usize) -> CoreResult<Vector3<f64>>,
    free: impl Fn(usize, usize) -> Option<usize>,
    ctx: &AttachContext<'_>,
    coefs: &mut [f64],
    rows: &mut ConstraintRows,
    ids: &mut Vec<Option<RowId>>,
) -> CoreResult<()> {
    let dirs = [Vector3::x(), Vector3::y(), Vector3::z()];
    for (ai, att) in attachments.iter().enumerate() {
        let node_position = position(att.node.0)?;
        let mut body_rows: Option<(BlockId, [[f64; 6]; 3], usize)> = None;
        let (target, known) = match att.target {
            AttachTarget::Point(p) => (p, [0.0; 3]),
            AttachTarget::Body { body, local } => {
                let b = ctx.body(body, format_args!("attachment {ai}"))?;
                let p = (b.pose() * Point3::from(local)).coords;
                // The body's side at the end of the step (module docs): its arm turned by
                // `h omega`, the turn the mesh's linearized force already carries.
                let p_end = p + ctx.h * b.angular_velocity().cross(&(p - b.position()));
                let known = b.contact_jacobian(&p_end, &dirs, &mut |id, r| {
                    let mut c = [[0.0; 6]; 3];
                    let len = r[0].len().min(6);
                    for k in 0..3 {
                        c[k][..len].copy_from_slice(&r[k][..len]);
                    }
                    body_rows = Some((id, c, len));
                });
                (p, known)
            }
        };
        for d in 0..3 {
            let f = free(att.node.0, d);
            if f.is_none() && body_rows.is_none() {
                ids.push(None);
                continue;
            }
            // At most two entries (the mesh block, the body block): no allocation.
            let mut entries = [RowEntry {
                block: ctx.block,
                coefs: &[],
            }; 2];
            let mut n_ent = 0;
            let neg: [f64; 6];
            if let Some(f) = f {
                coefs[f] = 1.0;
            }
            if f.is_some() {
                entries[0].coefs = coefs;
                n_ent = 1;
            }
            if let Some((id, c, len)) = &body_rows {
                neg = c[d].map(|x| -x);
                entries[n_ent] = RowEntry {
                    block: *id,
                    coefs: &neg[..*len],
                };
                n_ent += 1;
            }
            let b = (node_position[d] - target[d]) / ctx.h - known[d];
            ids.push(Some(rows.push_bilateral(&entries[..n_ent], b, 0.0)));
            if let Some(f) = f {
                coefs[f] = 0.0;
            }
        }
    }
    Ok(())
}

/// Push the three rows of every director attachment `(node, target)`: per axis `c`,
/// `C_c = d_c - a_c` with `d` the node's director and `a` the target direction (a fixed
/// world vector, or `R a_local` for a body), `d_dot_c - (omega x a)_c + C_c / h = 0`;
/// the body's side is `-(a x e_c) . omega` ([`RigidBody::angular_jacobian`]), its known
/// value for a body without a block. `director(n)` is node `n`'s director, `free(n, c)`
/// the column of its director coordinate `c` (`None` if supported); `coefs` a zeroed
/// scratch row of the block's length (left zeroed); ids as in [`push_attachment_rows`].
pub(crate) fn push_director_rows(
    attachments: &[(usize, DirectorTarget)],
    director: impl Fn(usize) -> Vector3<f64>,
    free: impl Fn(usize, usize) -> Option<usize>,
    ctx: &AttachContext<'_>,
    coefs: &mut [f64],
    rows: &mut ConstraintRows,
    ids: &mut Vec<Option<RowId>>,
) -> CoreResult<()> {
    for (ai, &(node, target)) in attachments.iter().enumerate() {
        let d = director(node);
        let (a, body) = match target {
            DirectorTarget::Fixed(a) => (a, None),
            DirectorTarget::Body { body, local } => {
                let b = ctx.body(body, format_args!("director attachment {ai}"))?;
                (b.rotation() * local, Some(b))
            }
        };
        for c in 0..3 {
            let f = free(node, c);
            let mut e_c = Vector3::zeros();
            e_c[c] = 1.0;
            let (mut known, mut body_entry) = (0.0, None);
            if let Some(b) = body {
                // `a` turned by `h omega`: the end of the step, as for the positions.
                let a_end = a + ctx.h * b.angular_velocity().cross(&a);
                let j = b.angular_jacobian(&a_end.cross(&e_c));
                match b.block() {
                    Some(id) => body_entry = Some((id, j.map(|x| -x))),
                    None => known = b.jacobian_times_velocity(&j),
                }
            }
            if f.is_none() && body_entry.is_none() {
                ids.push(None);
                continue;
            }
            let mut entries = [RowEntry {
                block: ctx.block,
                coefs: &[],
            }; 2];
            let mut n_ent = 0;
            if let Some(f) = f {
                coefs[f] = 1.0;
                entries[0].coefs = coefs;
                n_ent = 1;
            }
            if let Some((id, j)) = &body_entry {
                entries[n_ent] = RowEntry {
                    block: *id,
                    coefs: j,
                };
                n_ent += 1;
            }
            let b = (d[c] - a[c]) / ctx.h - known;
            ids.push(Some(rows.push_bilateral(&entries[..n_ent], b, 0.0)));
            if let Some(f) = f {
                coefs[f] = 0.0;
            }
        }
    }
    Ok(())
}
