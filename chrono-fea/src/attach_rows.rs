//! The rows that tie mesh nodes to fixed points or rigid-body points, shared by the
//! implicit mesh items ([`crate::dynamics::CableItem`], [`crate::tet_dynamics::TetItem`],
//! [`crate::shell_dynamics::ShellItem`]), and the rows that tie a shell node's director to
//! a fixed direction or a direction of a rigid body.
//!
//! Per attachment and axis `d`, one bilateral row on the node's position coordinate and, for
//! a body target, the body's point Jacobian: `C_d = x_d - p_d` (node minus target point),
//! `D' v + C_d / h = 0` with the target's known velocity (a kinematic body's) on the right.

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
                let known = b.contact_jacobian(&p, &dirs, &mut |id, r| {
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
                let j = b.angular_jacobian(&a.cross(&e_c));
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
