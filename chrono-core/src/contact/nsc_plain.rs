//! The friction triplet of a contact between two rigid bodies without rolling friction
//! (the granular case), stored as its geometry alone
//! ([`ConstraintRows::push_friction_frame`]: normal, arms, `b`, `eps`, `mu`; the problem
//! builds the 36 Jacobian coefficients only if a row-level access needs them), and the
//! triplets of many such contacts written in parallel straight into the friction group.
//!
//! The parallel writer fills chunks of contacts on their own, each value computed by the
//! same operations as when the triplets are pushed one contact at a time
//! ([`push_plain`]), so the rows are the same bits for any thread count.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::nsc::{NscContact, NscRowSettings};
use crate::body::RigidBody;
use crate::collision::ContactPoint;
use crate::descriptor::{ConstraintRows, ContactFrame, FrameKind, RowGroup, RowId};
use crate::parallel::{grow, split_parts};

/// Below this many contacts the rows are written on the calling thread.
pub(super) const PAR_MIN_CONTACTS: usize = 2048;

/// Contacts per task of the parallel writer.
const CHUNK: usize = 512;

/// The values of one contact's friction triplet (rows `n, u, w`).
#[derive(Debug, Clone, Copy)]
pub(super) struct PlainTriplet {
    b: [f64; 3],
    eps: [f64; 3],
    mu: f64,
    frame: ContactFrame,
}

/// Whether the contact `cp` gets the plain triplet (no rolling or spinning friction, or
/// no finite effective radius for it).
#[inline]
pub(super) fn is_plain(cp: &ContactPoint) -> bool {
    let m = &cp.material;
    !((m.rolling_friction > 0.0 || m.spinning_friction > 0.0)
        && cp.radius.is_finite()
        && cp.radius > 0.0)
}

/// The friction triplet of `cp` between `a` and `b` (`dirs` = `n, u, w`): the frame
/// (normal, the blocks, the arms `p - x`), the known velocities of a side without
/// variables moved into `b` (its rows `-d` (A) or `d` (B) by one
/// [`RigidBody::point_jacobians`] times its velocity), `b_n = max(Phi / h, -v_rec)` plus
/// the known normal velocity, the compliance `c / h^2` on the normal row. `None` if
/// neither body has variables.
pub(super) fn plain_triplet(
    settings: NscRowSettings,
    cp: &ContactPoint,
    a: &RigidBody,
    b: &RigidBody,
    dirs: &[Vector3<f64>; 3],
) -> Option<PlainTriplet> {
    if a.block.is_none() && b.block.is_none() {
        return None;
    }
    // The known velocities of a side without variables along `sign * d`.
    let known_of = |body: &RigidBody, p: &Vector3<f64>, sign: f64| match body.block {
        Some(_) => [0.0; 3],
        None => {
            let signed = dirs.map(|d| d * sign);
            let j = body.point_jacobians(p, &signed);
            j.map(|jk| body.jacobian_times_velocity(&jk))
        }
    };
    let (ka, kb) = (
        known_of(a, &cp.point_a, -1.0),
        known_of(b, &cp.point_b, 1.0),
    );
    let known: [f64; 3] = std::array::from_fn(|r| ka[r] + kb[r]);
    let h = settings.h;
    let m = &cp.material;
    let bn = (cp.distance / h).max(-settings.max_recovery_speed) + known[0];
    let arm = |p: &Vector3<f64>, body: &RigidBody| (p - body.position).into();
    Some(PlainTriplet {
        b: [bn, known[1], known[2]],
        eps: [m.compliance / (h * h), 0.0, 0.0],
        mu: m.friction,
        frame: ContactFrame {
            normal: dirs[0].into(),
            blocks: [a.block, b.block],
            arms: [arm(&cp.point_a, a), arm(&cp.point_b, b)],
        },
    })
}

#[cfg(test)]
impl PlainTriplet {
    pub(super) fn mu_of(&self) -> f64 {
        self.mu
    }
    pub(super) fn b_of(&self) -> [f64; 3] {
        self.b
    }
    pub(super) fn eps_of(&self) -> [f64; 3] {
        self.eps
    }
    pub(super) fn frame_of(&self) -> ContactFrame {
        self.frame
    }
}

/// Push `t` as its geometry alone ([`ConstraintRows::push_friction_frame`]).
pub(super) fn push_plain(rows: &mut ConstraintRows, t: &PlainTriplet) -> RowId {
    rows.push_friction_frame(t.mu, t.frame, t.b, t.eps)
}

/// The contact out of `cp` (tangents `u`, `w`) whose triplet is the group's `k`-th.
#[inline]
fn contact_out(cp: &ContactPoint, u: Vector3<f64>, w: Vector3<f64>, k: usize) -> NscContact {
    NscContact {
        point: *cp,
        u,
        w,
        row: RowId {
            group: RowGroup::Friction,
            index: (3 * k) as u32,
        },
    }
}

/// One task's share of the friction group's arrays (and of the contacts out).
struct Part<'a> {
    /// The first contact of the task.
    c0: usize,
    /// Its first triplet (within the group).
    t0: usize,
    b: &'a mut [f64],
    eps: &'a mut [f64],
    mu: &'a mut [f64],
    frames: &'a mut [(u32, ContactFrame)],
    /// `None` when every contact gets a triplet (the contacts out are written after).
    out: Option<&'a mut [NscContact]>,
}

/// The next part of a split (there is one per chunk).
fn next<I: Iterator>(it: &mut I) -> I::Item {
    it.next().expect("one part per chunk")
}

/// Append the plain triplets of `points` (every one [`is_plain`]) to the friction group of
/// `rows` and their contacts to `out`, in parallel over chunks of contacts: the same rows,
/// frames and contacts, bit for bit, as pushing them one by one with [`push_plain`].
pub(super) fn add_plain_rows_par(
    points: &[ContactPoint],
    bodies: &[RigidBody],
    settings: NscRowSettings,
    rows: &mut ConstraintRows,
    out: &mut Vec<NscContact>,
) {
    // Triplets per chunk (a contact between two bodies without variables has none), and
    // the total.
    let has_vars = |cp: &ContactPoint| {
        bodies[cp.owner_a as usize].block.is_some() || bodies[cp.owner_b as usize].block.is_some()
    };
    let counts: Vec<usize> = (points.par_chunks(CHUNK))
        .map(|ch| ch.iter().filter(|cp| has_vars(cp)).count())
        .collect();
    let nt: usize = counts.iter().sum();
    if nt == 0 {
        return;
    }
    let g = &mut rows.groups[RowGroup::Friction as usize];
    if g.row_ptr.is_empty() {
        g.row_ptr.push(0);
    }
    // The group's sizes before: rows, entries, triplets, frames, contacts.
    let (r0, k0, f0, o0) = (g.b.len(), g.mu.len(), g.frames.len(), out.len());
    let e0 = g.ent_block.len() as u32;
    debug_assert_eq!(r0, 3 * k0, "the friction group holds triplets");
    let placeholder = NscContact {
        point: points[0],
        u: Vector3::zeros(),
        w: Vector3::zeros(),
        row: RowId {
            group: RowGroup::Friction,
            index: 0,
        },
    };
    let empty_frame = (
        0,
        ContactFrame {
            normal: [0.0; 3],
            blocks: [None; 2],
            arms: [[0.0; 3]; 2],
        },
    );
    // The new rows have no entries: their ends are the group's entry count. Every other
    // new slot is written below (but `frame_kind`: every new frame is the triplet itself);
    // the slots are made in parallel.
    grow(&mut g.row_ptr, r0 + 1 + 3 * nt, e0);
    grow(&mut g.b, r0 + 3 * nt, 0.0);
    grow(&mut g.eps, r0 + 3 * nt, 0.0);
    grow(&mut g.mu, k0 + nt, 0.0);
    grow(&mut g.frames, f0 + nt, empty_frame);
    grow(&mut g.frame_kind, f0 + nt, FrameKind::Only);
    // Every contact with a triplet (a bed of spheres): the contacts out in one indexed
    // pass after the rows, without placeholders.
    let every = nt == points.len();
    if !every {
        grow(out, o0 + nt, placeholder);
    }

    let ts = || counts.iter().copied();
    let mut parts: Vec<Part> = Vec::with_capacity(counts.len());
    let mut b = split_parts(&mut g.b[r0..], ts().map(|t| 3 * t)).into_iter();
    let mut eps = split_parts(&mut g.eps[r0..], ts().map(|t| 3 * t)).into_iter();
    let mut mu = split_parts(&mut g.mu[k0..], ts()).into_iter();
    let mut frames = split_parts(&mut g.frames[f0..], ts()).into_iter();
    let mut outs = (!every).then(|| split_parts(&mut out[o0..], ts()).into_iter());
    let mut t = k0;
    for (i, &ct) in counts.iter().enumerate() {
        parts.push(Part {
            c0: i * CHUNK,
            t0: t,
            b: next(&mut b),
            eps: next(&mut eps),
            mu: next(&mut mu),
            frames: next(&mut frames),
            out: outs.as_mut().map(next),
        });
        t += ct;
    }
    let fill = |mut p: Part| {
        let chunk = &points[p.c0..(p.c0 + CHUNK).min(points.len())];
        let mut t = 0;
        for cp in chunk {
            let n = cp.normal;
            let (u, w) = crate::math::tangent_frame(&n);
            let (a, bb) = (&bodies[cp.owner_a as usize], &bodies[cp.owner_b as usize]);
            let Some(tr) = plain_triplet(settings, cp, a, bb, &[n, u, w]) else {
                continue;
            };
            p.b[3 * t..3 * t + 3].copy_from_slice(&tr.b);
            p.eps[3 * t..3 * t + 3].copy_from_slice(&tr.eps);
            let k = p.t0 + t;
            p.mu[t] = tr.mu;
            p.frames[t] = (k as u32, tr.frame);
            if let Some(out) = p.out.as_deref_mut() {
                out[t] = contact_out(cp, u, w, k);
            }
            t += 1;
        }
    };
    parts.into_par_iter().for_each(fill);
    drop(outs);
    if every {
        (out).par_extend(points.par_iter().enumerate().map(|(i, cp)| {
            let (u, w) = crate::math::tangent_frame(&cp.normal);
            contact_out(cp, u, w, k0 + i)
        }));
    }
}
