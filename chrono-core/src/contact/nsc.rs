//! NSC contact rows and their warm-start cache.
//!
//! For a contact between A and B with unit normal `n` (from A to B), gap `Phi` and tangents
//! `u, w` ([`tangent_frame`]), the three rows are the relative
//! velocity of B's contact point with respect to A's along `n, u, w`, so `g_n >= 0` pushes
//! the bodies apart. The normal row's right-hand side is the stabilization term of the
//! seed, `b_n = max(Phi / h, -v_rec)`: a gap inside the collision envelope lets the bodies
//! approach by exactly the gap in one step, and a penetration is pushed out at no more than
//! `v_rec` (m/s). A material compliance `c` (m/N) adds `eps = c / h^2` on the normal row.
//!
//! Rolling and spinning friction (Tasora and Anitescu 2013, "A complementarity-based
//! rolling friction model for rigid contacts", Meccanica 48): when the material of a contact
//! between two rigid bodies has `rolling_friction` or `spinning_friction` > 0 and the
//! contact has a finite effective radius `R` ([`ContactPoint::radius`]), the contact gets
//! six rows `(n, u, w, s, r_u, r_w)` in the [`RowGroup::Rolling`] group: the three above and
//! `R (omega_B - omega_A)` along `n, u, w`, with the impulses bounded by
//! `|g_s| <= mu_s g_n` and `|(g_ru, g_rw)| <= mu_r g_n`; the torque impulses are `R g_s`
//! and `R (g_ru, g_rw)`, at most `mu_s R g_n` and `mu_r R g_n`. The factor `R` makes the
//! torque rows speeds (m/s) and their impulses forces (N s) like the force rows: written
//! with `omega` alone, their entries of `N` (`~ 1 / (m R^2)`) exceed the force rows'
//! (`~ 1 / m`) by `1 / R^2` (1e5 for 5 mm grains), the iterative solvers' step is set by
//! the torque rows and a settling bed of grains gains energy instead of coming to rest.
//! Flat contacts (box on ground, `R` infinite) and proxy contacts keep the plain triplet.
//!
//! With [`RollingModel::PerBody`] (Zhou et al. 1999, Physica A 269; used for the angle of
//! repose by Zhou et al. 2002, Powder Technol. 125) the rolling resistance opposes each
//! body's *own* rotation instead: [`PER_BODY_ROWS`] rows `(n, u, w, s, a_n, a_u, a_w, b_n,
//! b_u, b_w)` in the [`RowGroup::RollingPerBody`] group, `a_*` = `R omega_A` and `b_*` =
//! `R omega_B` along `n, u, w` (all three components: the resistance also acts on a
//! rotation about the normal, as Zhou's torque `-mu_r R F_n omega_i / |omega_i|`), each
//! bounded by `|g_a| <= mu_r g_n`, `|g_b| <= mu_r g_n`; the spinning rows stay relative. A
//! side without variables (fixed or kinematic body) leaves its three rows empty: the
//! resistance acts on the moving body only, and not against a kinematic body's own spin.
//!
//! [`RollingModel::Spring`] (SMC's elastic-plastic rolling spring) gets the relative rows:
//! they already hold a static moment up to `mu_r R g_n`, the spring's rigid limit.

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::body::RigidBody;
use crate::collision::{ContactKey, ContactPoint, ProxyContact, ProxyKey};
use crate::contact::nsc_plain;
use crate::contact::smc::RollingModel;
use crate::contact::sorted_map::SortedMap;
use crate::descriptor::{
    BlockId, CcpProblem, ConstraintRows, PER_BODY_ROWS, RowEntry, RowGroup, RowId,
};
use crate::error::{ChronoError, Result};
use crate::item::{Contactable, JacobianSink, PhysicsItem};
use crate::material::ContactMaterial;
use crate::math::tangent_frame;

/// Most variable blocks one contact row may touch (two bodies, or a body plus e.g. the
/// nodes of an element face).
pub const MAX_CONTACT_BLOCKS: usize = 16;

/// One active NSC contact of the current step: between two body colliders
/// ([`ContactPoint`], the default) or between a body collider and an item's proxy
/// ([`NscProxyContact`]).
#[derive(Debug, Clone, PartialEq)]
pub struct NscContact<P = ContactPoint> {
    /// The collision point.
    pub point: P,
    /// First tangent direction (world).
    pub u: Vector3<f64>,
    /// Second tangent direction (world), `w = n x u`.
    pub w: Vector3<f64>,
    /// The id of its normal row.
    pub row: RowId,
}

impl<P: HasNormal> NscContact<P> {
    /// The contact normal (world, from A to B), `n = u x w`.
    pub fn normal(&self) -> Vector3<f64> {
        self.point.normal()
    }
}

/// Collision points that carry a contact normal.
pub trait HasNormal {
    /// World unit normal from A towards B.
    fn normal(&self) -> Vector3<f64>;
}

impl HasNormal for ContactPoint {
    fn normal(&self) -> Vector3<f64> {
        self.normal
    }
}

impl HasNormal for ProxyContact {
    fn normal(&self) -> Vector3<f64> {
        self.normal
    }
}

/// One active NSC contact between a body collider and an item's proxy.
pub type NscProxyContact = NscContact<ProxyContact>;

/// Cached impulses of one contact, as world vectors so that they survive a change of the
/// tangent frame (zero where the contact has no such rows).
#[derive(Debug, Clone, Copy, Default)]
struct Impulses {
    /// Normal impulse (N s).
    normal: f64,
    /// Tangential impulse (N s).
    tangential: Vector3<f64>,
    /// Relative model: the rolling and spinning torque impulse over `R`; per-body model:
    /// the spinning part along the normal.
    torque: Vector3<f64>,
    /// Per-body model: body A's and body B's own rolling torque impulses over `R`.
    own: [Vector3<f64>; 2],
}

/// Cached impulses of the previous step, by persistence key: the normal impulse and the
/// tangential force and torque impulses as world vectors (so they survive a change of the
/// tangent frame).
#[derive(Debug, Clone, Default)]
pub struct WarmStartCache {
    map: SortedMap<ContactKey, Impulses>,
    proxies: SortedMap<ProxyKey, Impulses>,
    /// Scratch of a parallel warm start: each contact's three friction rows.
    rows: Vec<[f64; 3]>,
}

impl WarmStartCache {
    /// Number of cached contacts (body pairs and proxies).
    pub fn len(&self) -> usize {
        self.map.len() + self.proxies.len()
    }
    /// True if empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Forget everything.
    pub fn clear(&mut self) {
        self.map.clear();
        self.proxies.clear();
    }

    /// Follow a renumbering of the colliders (`map`: old id -> new id, `None` if removed,
    /// see [`ContactKey::remap`]) and of the items (`item`: old index -> new index, `None`
    /// if removed): entries of removed colliders or items are dropped.
    pub(crate) fn remap(&mut self, map: Option<&[Option<u32>]>, item: &dyn Fn(u32) -> Option<u32>) {
        if let Some(map) = map {
            self.map.remap(|k| k.remap(map));
        }
        self.proxies.remap(|k| {
            let collider = match map {
                Some(map) => (*map.get(k.collider as usize)?)?,
                None => k.collider,
            };
            let item = item(k.item)?;
            Some(ProxyKey {
                collider,
                item,
                ..k
            })
        });
    }
}

/// Settings of NSC contact rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NscRowSettings {
    /// Step size, s.
    pub h: f64,
    /// Maximum penetration recovery speed `v_rec`, m/s.
    pub max_recovery_speed: f64,
    /// Which rotation the rolling resistance opposes (see the module docs).
    pub rolling_model: RollingModel,
}

/// Reused storage for the Jacobian blocks of one contact (three force rows, three torque
/// rows for rolling friction, four more for the per-body model).
#[derive(Debug, Clone, Default)]
pub struct TripletScratch {
    blocks: Vec<(BlockId, usize, usize)>,
    coefs: [Vec<f64>; PER_BODY_ROWS],
}

impl TripletScratch {
    fn clear(&mut self) {
        self.blocks.clear();
        self.coefs.iter_mut().for_each(Vec::clear);
    }

    /// Record the blocks a contactable reports.
    fn add(&mut self, c: &dyn Fn(&mut JacobianSink<'_>) -> [f64; 3]) -> [f64; 3] {
        c(&mut |blk, j| {
            let start = self.coefs[0].len();
            for (r, jr) in j.iter().enumerate() {
                self.coefs[r].extend_from_slice(jr);
            }
            self.blocks.push((blk, start, j[0].len()));
        })
    }

    /// Record a rigid body's side of a contact at `p` with directions `sign * (n, u, w)`:
    /// the force rows, and with `rolling` the torque rows `sign * d . omega` (angular
    /// velocity in the body frame: coefficients `R' d` on the angular dof). Returns the
    /// known velocities (kinematic bodies) of the six rows.
    fn add_body(
        &mut self,
        body: &RigidBody,
        p: &Vector3<f64>,
        sign: f64,
        dirs: &[Vector3<f64>; 3],
        rolling: Option<f64>,
    ) -> [f64; 6] {
        let signed = dirs.map(|d| d * sign);
        let k = self.add(&|e| body.contact_jacobian(p, &signed, e));
        let mut known = [k[0], k[1], k[2], 0.0, 0.0, 0.0];
        if let Some(radius) = rolling {
            let rinv = body.rotation.inverse();
            for (r, d) in signed.iter().enumerate() {
                let a = rinv * d * radius;
                if body.block.is_some() {
                    self.coefs[3 + r].extend_from_slice(&[0.0, 0.0, 0.0, a.x, a.y, a.z]);
                } else {
                    known[3 + r] = a.dot(&body.angular_velocity);
                }
            }
        }
        known
    }

    /// Record a rigid body's side of a per-body rolling contact (see the module docs): the
    /// force rows and the relative spin row as [`add_body`](Self::add_body), and the three
    /// rows `R d . omega` (`d` = `n, u, w`) of this body's own rolling resistance in
    /// `side` (0: rows `a_*`, 1: rows `b_*`), with zeros in the other side's rows (they keep
    /// the scratch's column layout; [`push_rolling_per_body`](Self::push_rolling_per_body)
    /// does not reference them). Returns the known velocities of rows `n, u, w, s` (a body
    /// without variables resists nothing of its own).
    fn add_body_per_body(
        &mut self,
        body: &RigidBody,
        p: &Vector3<f64>,
        sign: f64,
        dirs: &[Vector3<f64>; 3],
        radius: f64,
        side: usize,
    ) -> [f64; 4] {
        let signed = dirs.map(|d| d * sign);
        let k = self.add(&|e| body.contact_jacobian(p, &signed, e));
        let rinv = body.rotation.inverse();
        let spin = rinv * signed[0] * radius;
        if body.block.is_none() {
            return [k[0], k[1], k[2], spin.dot(&body.angular_velocity)];
        }
        self.coefs[3].extend_from_slice(&[0.0, 0.0, 0.0, spin.x, spin.y, spin.z]);
        for (r, d) in dirs.iter().enumerate() {
            let a = rinv * d * radius;
            let (own, other) = if side == 0 { (4, 7) } else { (7, 4) };
            self.coefs[own + r].extend_from_slice(&[0.0, 0.0, 0.0, a.x, a.y, a.z]);
            self.coefs[other + r].extend_from_slice(&[0.0; 6]);
        }
        [k[0], k[1], k[2], 0.0]
    }

    /// Push the friction triplet of the recorded blocks: `b_n = max(Phi/h, -v_rec)` plus the
    /// known normal velocity, `eps_n = c/h^2`. Errors if more than [`MAX_CONTACT_BLOCKS`]
    /// blocks were recorded (`what` names the contact). `None` if no block was recorded
    /// (both sides fixed).
    fn push_triplet(
        &self,
        rows: &mut ConstraintRows,
        settings: NscRowSettings,
        distance: f64,
        material: &ContactMaterial,
        known: [f64; 3],
        what: &dyn Fn() -> String,
    ) -> Result<Option<RowId>> {
        let nb = self.blocks.len();
        if nb == 0 {
            return Ok(None);
        }
        if nb > MAX_CONTACT_BLOCKS {
            return Err(ChronoError::invalid(
                what(),
                nb,
                "a contact row touches too many variable blocks (limit MAX_CONTACT_BLOCKS)",
            ));
        }
        let h = settings.h;
        let (en, eu, ew) = (self.entries(0), self.entries(1), self.entries(2));
        let bn = (distance / h).max(-settings.max_recovery_speed) + known[0];
        let eps_n = material.compliance / (h * h);
        Ok(Some(rows.push_friction(
            material.friction,
            [&en[..nb], &eu[..nb], &ew[..nb]],
            [bn, known[1], known[2]],
            [eps_n, 0.0, 0.0],
        )))
    }

    /// Push the six rolling-friction rows of the recorded blocks (force rows as in
    /// [`push_triplet`](Self::push_triplet), torque rows with `b = ` the known angular
    /// velocity, both scaled by `R`), coefficients `[mu, mu_s, mu_r]`.
    fn push_rolling(
        &self,
        rows: &mut ConstraintRows,
        settings: NscRowSettings,
        distance: f64,
        material: &ContactMaterial,
        known: [f64; 6],
    ) -> Option<RowId> {
        let nb = self.blocks.len();
        if nb == 0 {
            return None;
        }
        let h = settings.h;
        let e: [_; 6] = std::array::from_fn(|r| self.entries(r));
        let bn = (distance / h).max(-settings.max_recovery_speed) + known[0];
        let eps_n = material.compliance / (h * h);
        Some(rows.push_rolling_friction(
            [
                material.friction,
                material.spinning_friction,
                material.rolling_friction,
            ],
            std::array::from_fn(|r| &e[r][..nb]),
            [bn, known[1], known[2], known[3], known[4], known[5]],
            [eps_n, 0.0, 0.0, 0.0, 0.0, 0.0],
        ))
    }

    /// Push the [`PER_BODY_ROWS`] rows of a per-body rolling contact whose first `na`
    /// recorded blocks are body A's: rows `n, u, w, s` on all blocks (as in
    /// [`push_rolling`](Self::push_rolling)), `a_*` on A's blocks, `b_*` on B's, with zero
    /// right-hand sides; coefficients `[mu, mu_s, mu_r]`.
    fn push_rolling_per_body(
        &self,
        rows: &mut ConstraintRows,
        settings: NscRowSettings,
        distance: f64,
        material: &ContactMaterial,
        known: [f64; 4],
        na: usize,
    ) -> Option<RowId> {
        let nb = self.blocks.len();
        if nb == 0 {
            return None;
        }
        let h = settings.h;
        let e: [_; PER_BODY_ROWS] = std::array::from_fn(|r| self.entries(r));
        let bn = (distance / h).max(-settings.max_recovery_speed) + known[0];
        let eps_n = material.compliance / (h * h);
        let mut b = [0.0; PER_BODY_ROWS];
        b[..4].copy_from_slice(&[bn, known[1], known[2], known[3]]);
        let mut eps = [0.0; PER_BODY_ROWS];
        eps[0] = eps_n;
        Some(rows.push_rolling_per_body(
            [
                material.friction,
                material.spinning_friction,
                material.rolling_friction,
            ],
            std::array::from_fn(|r| match r {
                0..4 => &e[r][..nb],
                4..7 => &e[r][..na],
                _ => &e[r][na..nb],
            }),
            b,
            eps,
        ))
    }

    /// The row entries of direction `r`, the first `n` of the returned array used.
    fn entries(&self, r: usize) -> [RowEntry<'_>; MAX_CONTACT_BLOCKS] {
        std::array::from_fn(|i| match self.blocks.get(i) {
            Some(&(block, start, len)) => RowEntry {
                block,
                coefs: &self.coefs[r][start..start + len],
            },
            None => RowEntry {
                block: BlockId(0),
                coefs: &[],
            },
        })
    }
}

/// Make the contact rows of `points` between rigid bodies, appending to `out`: a friction
/// triplet, or six rows with rolling and spinning friction (see the module docs).
pub fn add_contact_rows(
    points: &[ContactPoint],
    bodies: &[RigidBody],
    settings: NscRowSettings,
    rows: &mut ConstraintRows,
    scratch: &mut TripletScratch,
    out: &mut Vec<NscContact>,
) -> Result<()> {
    // Many contacts without rolling friction (a granular bed): their rows in parallel.
    if points.len() >= nsc_plain::PAR_MIN_CONTACTS && points.iter().all(nsc_plain::is_plain) {
        nsc_plain::add_plain_rows_par(points, bodies, settings, rows, out);
        return Ok(());
    }
    for cp in points {
        let n = cp.normal;
        let (u, w) = tangent_frame(&n);
        let (a, b) = (&bodies[cp.owner_a as usize], &bodies[cp.owner_b as usize]);
        let m = &cp.material;
        let rolling = !nsc_plain::is_plain(cp);
        scratch.clear();
        let dirs = [n, u, w];
        let too_many = |nb: usize| {
            ChronoError::invalid(
                format!("contact {:?}", cp.key),
                nb,
                "a contact row touches too many variable blocks (limit MAX_CONTACT_BLOCKS)",
            )
        };
        if rolling && settings.rolling_model == RollingModel::PerBody {
            let r = cp.radius;
            let ka = scratch.add_body_per_body(a, &cp.point_a, -1.0, &dirs, r, 0);
            let na = scratch.blocks.len();
            let kb = scratch.add_body_per_body(b, &cp.point_b, 1.0, &dirs, r, 1);
            if scratch.blocks.len() > MAX_CONTACT_BLOCKS {
                return Err(too_many(scratch.blocks.len()));
            }
            let known = std::array::from_fn(|r| ka[r] + kb[r]);
            if let Some(row) =
                scratch.push_rolling_per_body(rows, settings, cp.distance, m, known, na)
            {
                out.push(NscContact {
                    point: *cp,
                    u,
                    w,
                    row,
                });
            }
            continue;
        }
        if !rolling {
            if let Some(t) = nsc_plain::plain_triplet(settings, cp, a, b, &dirs) {
                let row = nsc_plain::push_plain(rows, &t);
                out.push(NscContact {
                    point: *cp,
                    u,
                    w,
                    row,
                });
            }
            continue;
        }
        let rolling = Some(cp.radius);
        let ka = scratch.add_body(a, &cp.point_a, -1.0, &dirs, rolling);
        let kb = scratch.add_body(b, &cp.point_b, 1.0, &dirs, rolling);
        if scratch.blocks.len() > MAX_CONTACT_BLOCKS {
            return Err(too_many(scratch.blocks.len()));
        }
        let known: [f64; 6] = std::array::from_fn(|r| ka[r] + kb[r]);
        if let Some(row) = scratch.push_rolling(rows, settings, cp.distance, m, known) {
            out.push(NscContact {
                point: *cp,
                u,
                w,
                row,
            });
        }
    }
    Ok(())
}

/// Make the friction triplets of contacts between body colliders (side A) and item
/// proxies (side B), appending to `out`. Same rows as [`add_contact_rows`]; the proxy's
/// Jacobian comes from [`PhysicsItem::proxy_jacobian`]. Errors: a contact naming a body or
/// item out of range, or touching more than [`MAX_CONTACT_BLOCKS`] blocks.
pub fn add_proxy_contact_rows(
    points: &[ProxyContact],
    bodies: &[RigidBody],
    items: &[Box<dyn PhysicsItem>],
    settings: NscRowSettings,
    rows: &mut ConstraintRows,
    scratch: &mut TripletScratch,
    out: &mut Vec<NscProxyContact>,
) -> Result<()> {
    for cp in points {
        let n = cp.normal;
        let (u, w) = tangent_frame(&n);
        let unknown = |kind, index: u32, field: &str| ChronoError::UnknownHandle {
            kind,
            index: index as usize,
            field: field.into(),
        };
        let body = (bodies.get(cp.owner as usize))
            .ok_or_else(|| unknown("body", cp.owner, "proxy contact owner"))?;
        let item = (items.get(cp.item as usize))
            .ok_or_else(|| unknown("item", cp.item, "proxy contact item"))?;
        scratch.clear();
        let ka = scratch.add(&|e| body.contact_jacobian(&cp.point_a, &[-n, -u, -w], e));
        let kb = scratch.add(&|e| item.proxy_jacobian(cp.proxy, &cp.point_b, &[n, u, w], e));
        let known = std::array::from_fn(|r| ka[r] + kb[r]);
        let what = || format!("item {} (\"{}\") proxy {}", cp.item, item.name(), cp.proxy);
        if let Some(row) =
            scratch.push_triplet(rows, settings, cp.distance, &cp.material, known, &what)?
        {
            out.push(NscContact {
                point: *cp,
                u,
                w,
                row,
            });
        }
    }
    Ok(())
}

/// Fill the contacts' part of `gamma` from `map` (keys not found start at zero).
fn warm_start_from<P: HasNormal + Sync, K: Ord + Copy + Send + Sync>(
    contacts: &[NscContact<P>],
    key: impl Fn(&P) -> K + Sync,
    map: &SortedMap<K, Impulses>,
    scratch: &mut Vec<[f64; 3]>,
    problem: &CcpProblem,
    gamma: &mut [f64],
) {
    let three = |c: &NscContact<P>, g: &Impulses| {
        [g.normal, g.tangential.dot(&c.u), g.tangential.dot(&c.w)]
    };
    // The rows after the three of a contact with rolling friction.
    let rest = |c: &NscContact<P>, g: &Impulses, i: usize, gamma: &mut [f64]| {
        let dirs = [c.normal(), c.u, c.w];
        match c.row.group {
            RowGroup::Rolling => {
                for (k, d) in dirs.iter().enumerate() {
                    gamma[i + 3 + k] = g.torque.dot(d);
                }
            }
            RowGroup::RollingPerBody => {
                gamma[i + 3] = g.torque.dot(&dirs[0]);
                for (k, d) in dirs.iter().enumerate() {
                    gamma[i + 4 + k] = g.own[0].dot(d);
                    gamma[i + 7 + k] = g.own[1].dot(d);
                }
            }
            _ => {}
        }
    };
    if contacts.len() >= nsc_plain::PAR_MIN_CONTACTS {
        // The three rows of every contact in parallel (each on its own; a chunk's lookups
        // follow the keys from a binary search, as `get`'s hint does), written in order
        // after: the same values.
        const CHUNK: usize = 2048;
        scratch.resize(contacts.len(), [0.0; 3]);
        (scratch.par_chunks_mut(CHUNK))
            .zip(contacts.par_chunks(CHUNK))
            .for_each(|(o, cs)| {
                let mut cursor = 0;
                for (x, c) in o.iter_mut().zip(cs) {
                    let g = map.get(&key(&c.point), &mut cursor).unwrap_or_default();
                    *x = three(c, &g);
                }
            });
        let mut cursor = 0;
        for (c, x) in contacts.iter().zip(scratch.iter()) {
            let i = problem.row_index(c.row);
            gamma[i..i + 3].copy_from_slice(x);
            if c.row.group != RowGroup::Friction {
                let g = map.get(&key(&c.point), &mut cursor).unwrap_or_default();
                rest(c, &g, i, gamma);
            }
        }
        return;
    }
    let mut cursor = 0;
    for c in contacts {
        let i = problem.row_index(c.row);
        let g = map.get(&key(&c.point), &mut cursor).unwrap_or_default();
        gamma[i..i + 3].copy_from_slice(&three(c, &g));
        rest(c, &g, i, gamma);
    }
}

/// Replace `map` by the contacts' impulses.
fn store_into<P: HasNormal + Sync, K: Ord + Copy + Send + Sync>(
    contacts: &[NscContact<P>],
    key: impl Fn(&P) -> K + Sync,
    problem: &CcpProblem,
    gamma: &[f64],
    map: &mut SortedMap<K, Impulses>,
) {
    let one = |c: &NscContact<P>| {
        let i = problem.row_index(c.row);
        let n = c.normal();
        let at = |j: usize| n * gamma[j] + c.u * gamma[j + 1] + c.w * gamma[j + 2];
        let mut g = Impulses {
            normal: gamma[i],
            tangential: c.u * gamma[i + 1] + c.w * gamma[i + 2],
            ..Impulses::default()
        };
        match c.row.group {
            RowGroup::Rolling => g.torque = at(i + 3),
            RowGroup::RollingPerBody => {
                g.torque = n * gamma[i + 3];
                g.own = [at(i + 4), at(i + 7)];
            }
            _ => {}
        }
        (key(&c.point), g)
    };
    // Each entry on its own (in parallel for a bed): the same map.
    if contacts.len() >= nsc_plain::PAR_MIN_CONTACTS {
        map.fill_par(contacts.len(), |k| one(&contacts[k]));
        return;
    }
    map.clear();
    for c in contacts {
        let (k, g) = one(c);
        map.push(k, g);
    }
    map.finish();
}

/// Fill the body contacts' part of `gamma` from the cache (keys not found start at zero).
pub fn warm_start(
    contacts: &[NscContact],
    cache: &mut WarmStartCache,
    problem: &CcpProblem,
    gamma: &mut [f64],
) {
    let c = cache;
    warm_start_from(contacts, |p| p.key, &c.map, &mut c.rows, problem, gamma);
}

/// Store the body contacts' impulses for the next step (replacing that part of the cache).
pub fn store(
    contacts: &[NscContact],
    problem: &CcpProblem,
    gamma: &[f64],
    cache: &mut WarmStartCache,
) {
    store_into(contacts, |p| p.key, problem, gamma, &mut cache.map);
}

/// Fill the proxy contacts' part of `gamma` from the cache (keys not found start at zero).
pub fn warm_start_proxies(
    contacts: &[NscProxyContact],
    cache: &mut WarmStartCache,
    problem: &CcpProblem,
    gamma: &mut [f64],
) {
    let c = cache;
    warm_start_from(contacts, |p| p.key, &c.proxies, &mut c.rows, problem, gamma);
}

/// Store the proxy contacts' impulses for the next step (replacing that part of the cache).
pub fn store_proxies(
    contacts: &[NscProxyContact],
    problem: &CcpProblem,
    gamma: &[f64],
    cache: &mut WarmStartCache,
) {
    store_into(contacts, |p| p.key, problem, gamma, &mut cache.proxies);
}
