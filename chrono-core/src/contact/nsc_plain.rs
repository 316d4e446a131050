//! The friction triplet of a contact between two rigid bodies without rolling friction
//! (the granular case), computed in fixed arrays, and the rows of many such contacts
//! written in parallel straight into the friction group.
//!
//! The parallel writer gives every contact its slots from a prefix sum of its entry count
//! (one entry per side with variables), then fills chunks of contacts on their own: each
//! value is computed by the same operations as when the rows are pushed one contact at a
//! time ([`push_plain`]), so the rows are the same bits for any thread count.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::nsc::{NscContact, NscRowSettings};
use crate::body::RigidBody;
use crate::collision::ContactPoint;
use crate::descriptor::{BlockId, ConstraintRows, ContactFrame, RowEntry, RowGroup, RowId};
use crate::parallel::{grow, split_parts};

/// Below this many contacts the rows are written on the calling thread.
pub(super) const PAR_MIN_CONTACTS: usize = 2048;

/// Contacts per task of the parallel writer.
const CHUNK: usize = 512;

/// The values of one contact's friction triplet (rows `n, u, w`).
#[derive(Debug, Clone, Copy)]
pub(super) struct PlainTriplet {
    /// The variable blocks of the sides that have one (side A first); `nb` of them.
    blocks: [BlockId; 2],
    nb: usize,
    /// Per block in `blocks`: its coefficients in the three rows.
    coefs: [[[f64; 6]; 3]; 2],
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

/// The number of sides of `cp` with variables (its entries per row).
#[inline]
fn sides_with_variables(cp: &ContactPoint, bodies: &[RigidBody]) -> usize {
    usize::from(bodies[cp.owner_a as usize].block.is_some())
        + usize::from(bodies[cp.owner_b as usize].block.is_some())
}

/// The friction triplet of `cp` between `a` and `b` (`dirs` = `n, u, w`): each side's rows
/// `-d` (A) or `d` (B) by one [`RigidBody::point_jacobians`], the known velocities of a
/// side without variables moved into `b`, `b_n = max(Phi / h, -v_rec)` plus the known
/// normal velocity, the compliance `c / h^2` on the normal row, and the frame (normal and
/// arms) the rows were built from. `None` if neither body has variables.
pub(super) fn plain_triplet(
    settings: NscRowSettings,
    cp: &ContactPoint,
    a: &RigidBody,
    b: &RigidBody,
    dirs: &[Vector3<f64>; 3],
) -> Option<PlainTriplet> {
    // One side: its rows `sign * d` and the known velocities (a body without variables).
    let side = |body: &RigidBody, p: &Vector3<f64>, sign: f64| {
        let signed = dirs.map(|d| d * sign);
        let j = body.point_jacobians(p, &signed);
        let known = match body.block {
            Some(_) => [0.0; 3],
            None => j.map(|jk| body.jacobian_times_velocity(&jk)),
        };
        (j, known)
    };
    let (ja, ka) = side(a, &cp.point_a, -1.0);
    let (jb, kb) = side(b, &cp.point_b, 1.0);
    let known: [f64; 3] = std::array::from_fn(|r| ka[r] + kb[r]);
    let mut blocks = [BlockId(0); 2];
    let mut coefs = [[[0.0; 6]; 3]; 2];
    let mut nb = 0;
    for (block, j) in [(a.block, ja), (b.block, jb)] {
        if let Some(block) = block {
            blocks[nb] = block;
            coefs[nb] = j;
            nb += 1;
        }
    }
    if nb == 0 {
        return None;
    }
    let h = settings.h;
    let m = &cp.material;
    let bn = (cp.distance / h).max(-settings.max_recovery_speed) + known[0];
    let arm = |p: &Vector3<f64>, body: &RigidBody| (p - body.position).into();
    Some(PlainTriplet {
        blocks,
        nb,
        coefs,
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

/// Push `t`'s rows and its frame (as built from it: the problem applies sphere pairs
/// matrix-free without re-checking the rows,
/// [`ConstraintRows::set_contact_frame_of_built_rows`]).
pub(super) fn push_plain(rows: &mut ConstraintRows, t: &PlainTriplet) -> RowId {
    let nb = t.nb;
    let entries: [[RowEntry; 2]; 3] = std::array::from_fn(|r| {
        std::array::from_fn(|s| RowEntry {
            block: t.blocks[s],
            coefs: &t.coefs[s][r],
        })
    });
    let row = rows.push_friction(
        t.mu,
        [&entries[0][..nb], &entries[1][..nb], &entries[2][..nb]],
        t.b,
        t.eps,
    );
    rows.set_contact_frame_of_built_rows(row, t.frame);
    row
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
    /// Its first triplet (within the group) and first entry (within the group).
    t0: usize,
    e0: usize,
    row_ptr: &'a mut [u32],
    ent_block: &'a mut [u32],
    ent_coef: &'a mut [u32],
    coefs: &'a mut [f64],
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
    // Triplets and entries per chunk, and the totals.
    let count = |ch: &[ContactPoint]| {
        ch.iter().fold((0, 0), |(t, e), cp| {
            let nb = sides_with_variables(cp, bodies);
            (t + usize::from(nb > 0), e + 3 * nb)
        })
    };
    let counts: Vec<(usize, usize)> = points.par_chunks(CHUNK).map(count).collect();
    let (nt, ne) = counts
        .iter()
        .fold((0, 0), |(t, e), &(ct, ce)| (t + ct, e + ce));
    if nt == 0 {
        return;
    }
    let g = &mut rows.groups[RowGroup::Friction as usize];
    if g.row_ptr.is_empty() {
        g.row_ptr.push(0);
    }
    // The group's sizes before: rows, entries, coefficients, triplets, frames, contacts.
    let (r0, e0, c0) = (g.b.len(), g.ent_block.len(), g.coefs.len());
    let (k0, f0, o0) = (g.mu.len(), g.frames.len(), out.len());
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
    // Every new slot is written below (but `frames_built`: each new frame is built from
    // its rows, so its slot is made `true` here); the slots are made in parallel.
    grow(&mut g.row_ptr, r0 + 1 + 3 * nt, 0);
    grow(&mut g.ent_block, e0 + ne, 0);
    grow(&mut g.ent_coef, e0 + ne, 0);
    grow(&mut g.coefs, c0 + 6 * ne, 0.0);
    grow(&mut g.b, r0 + 3 * nt, 0.0);
    grow(&mut g.eps, r0 + 3 * nt, 0.0);
    grow(&mut g.mu, k0 + nt, 0.0);
    grow(&mut g.frames, f0 + nt, empty_frame);
    grow(&mut g.frames_built, f0 + nt, true);
    // Every contact with a triplet (a bed of spheres): the contacts out in one indexed
    // pass after the rows, without placeholders.
    let every = nt == points.len();
    if !every {
        grow(out, o0 + nt, placeholder);
    }

    let ts = || counts.iter().map(|c| c.0);
    let es = || counts.iter().map(|c| c.1);
    let mut parts: Vec<Part> = Vec::with_capacity(counts.len());
    let mut row_ptr = split_parts(&mut g.row_ptr[r0 + 1..], ts().map(|t| 3 * t)).into_iter();
    let mut ent_block = split_parts(&mut g.ent_block[e0..], es()).into_iter();
    let mut ent_coef = split_parts(&mut g.ent_coef[e0..], es()).into_iter();
    let mut coefs = split_parts(&mut g.coefs[c0..], es().map(|e| 6 * e)).into_iter();
    let mut b = split_parts(&mut g.b[r0..], ts().map(|t| 3 * t)).into_iter();
    let mut eps = split_parts(&mut g.eps[r0..], ts().map(|t| 3 * t)).into_iter();
    let mut mu = split_parts(&mut g.mu[k0..], ts()).into_iter();
    let mut frames = split_parts(&mut g.frames[f0..], ts()).into_iter();
    let mut outs = (!every).then(|| split_parts(&mut out[o0..], ts()).into_iter());
    let (mut t, mut e) = (k0, e0);
    for (i, &(ct, ce)) in counts.iter().enumerate() {
        parts.push(Part {
            c0: i * CHUNK,
            t0: t,
            e0: e,
            row_ptr: next(&mut row_ptr),
            ent_block: next(&mut ent_block),
            ent_coef: next(&mut ent_coef),
            coefs: next(&mut coefs),
            b: next(&mut b),
            eps: next(&mut eps),
            mu: next(&mut mu),
            frames: next(&mut frames),
            out: outs.as_mut().map(next),
        });
        (t, e) = (t + ct, e + ce);
    }
    // Coefficient offsets: the group's coefficients before, then 6 per new entry.
    let coef_at = |entry: usize| (c0 + 6 * (entry - e0)) as u32;
    let fill = |mut p: Part| {
        let chunk = &points[p.c0..(p.c0 + CHUNK).min(points.len())];
        let (mut t, mut e) = (0, 0);
        for cp in chunk {
            let n = cp.normal;
            let (u, w) = crate::math::tangent_frame(&n);
            let (a, bb) = (&bodies[cp.owner_a as usize], &bodies[cp.owner_b as usize]);
            let Some(tr) = plain_triplet(settings, cp, a, bb, &[n, u, w]) else {
                continue;
            };
            for r in 0..3 {
                for s in 0..tr.nb {
                    p.ent_block[e] = tr.blocks[s].0;
                    p.ent_coef[e] = coef_at(p.e0 + e);
                    p.coefs[6 * e..6 * e + 6].copy_from_slice(&tr.coefs[s][r]);
                    e += 1;
                }
                p.row_ptr[3 * t + r] = (p.e0 + e) as u32;
                p.b[3 * t + r] = tr.b[r];
                p.eps[3 * t + r] = tr.eps[r];
            }
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
