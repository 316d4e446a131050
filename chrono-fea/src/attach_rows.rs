//! The rows that tie mesh nodes to fixed points or rigid-body points, shared by the
//! implicit mesh items ([`crate::dynamics::CableItem`], [`crate::tet_dynamics::TetItem`]).
//!
//! Per attachment and axis `d`, one bilateral row on the node's position coordinate and, for
//! a body target, the body's point Jacobian: `C_d = x_d - p_d` (node minus target point),
//! `D' v + C_d / h = 0` with the target's known velocity (a kinematic body's) on the right.

use chrono_core::body::RigidBody;
use chrono_core::descriptor::{BlockId, ConstraintRows, RowEntry, RowId};
use chrono_core::item::Contactable;
use chrono_core::{ChronoError, Result as CoreResult};
use nalgebra::{Point3, Vector3};

use crate::dynamics::{AttachTarget, Attachment};

/// Where a mesh item's attachment rows get their data.
pub(crate) struct AttachContext<'a> {
    /// The mesh's variable block.
    pub block: BlockId,
    /// The system's bodies at the start of the step.
    pub bodies: &'a [RigidBody],
    /// Step size, s.
    pub h: f64,
    /// The item's name for messages.
    pub label: &'a str,
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
                let b = ctx
                    .bodies
                    .get(body.0 as usize)
                    .ok_or(ChronoError::UnknownHandle {
                        kind: "body",
                        index: body.0 as usize,
                        field: format!("{}: attachment {ai}", ctx.label),
                    })?;
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
