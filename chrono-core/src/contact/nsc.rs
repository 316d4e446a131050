//! NSC contact rows and their warm-start cache.
//!
//! For a contact between A and B with unit normal `n` (from A to B), gap `Phi` and tangents
//! `u, w` ([`tangent_frame`](crate::math::tangent_frame)), the three rows are the relative
//! velocity of B's contact point with respect to A's along `n, u, w`, so `g_n >= 0` pushes
//! the bodies apart. The normal row's right-hand side is the stabilization term of the
//! seed, `b_n = max(Phi / h, -v_rec)`: a gap inside the collision envelope lets the bodies
//! approach by exactly the gap in one step, and a penetration is pushed out at no more than
//! `v_rec` (m/s). A material compliance `c` (m/N) adds `eps = c / h^2` on the normal row.

use std::collections::HashMap;

use nalgebra::Vector3;

use crate::body::RigidBody;
use crate::collision::{ContactKey, ContactPoint, ProxyContact, ProxyKey};
use crate::descriptor::{BlockId, CcpProblem, ConstraintRows, RowEntry, RowId};
use crate::error::{ChronoError, Result};
use crate::item::{Contactable, JacobianSink, PhysicsItem};
use crate::math::tangent_frame;

/// Most variable blocks one proxy contact row may touch (a body plus, e.g., the nodes of
/// an element face).
pub const MAX_CONTACT_BLOCKS: usize = 16;

/// One active NSC contact of the current step.
#[derive(Debug, Clone, PartialEq)]
pub struct NscContact {
    /// The collision point.
    pub point: ContactPoint,
    /// First tangent direction (world).
    pub u: Vector3<f64>,
    /// Second tangent direction (world), `w = n x u`.
    pub w: Vector3<f64>,
    /// The id of its normal row.
    pub row: RowId,
}

/// One active NSC contact between a body collider and an item's proxy.
#[derive(Debug, Clone, PartialEq)]
pub struct NscProxyContact {
    /// The collision point.
    pub point: ProxyContact,
    /// First tangent direction (world).
    pub u: Vector3<f64>,
    /// Second tangent direction (world), `w = n x u`.
    pub w: Vector3<f64>,
    /// The id of its normal row.
    pub row: RowId,
}

/// Cached impulses of the previous step, by persistence key: the normal impulse and the
/// tangential impulse as a world vector (so it survives a change of the tangent frame).
#[derive(Debug, Clone, Default)]
pub struct WarmStartCache {
    map: HashMap<ContactKey, (f64, Vector3<f64>)>,
    proxies: HashMap<ProxyKey, (f64, Vector3<f64>)>,
}

impl WarmStartCache {
    /// Number of cached contacts (body pairs and proxies).
    pub fn len(&self) -> usize {
        self.map.len() + self.proxies.len()
    }
    /// True if empty.
    pub fn is_empty(&self) -> bool {
        self.map.is_empty() && self.proxies.is_empty()
    }
    /// Forget everything.
    pub fn clear(&mut self) {
        self.map.clear();
        self.proxies.clear();
    }
}

/// Reused storage for the Jacobian blocks of one contact triplet.
#[derive(Debug, Clone, Default)]
pub struct TripletScratch {
    blocks: Vec<(BlockId, usize, usize)>,
    coefs: [Vec<f64>; 3],
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

/// Make the friction triplets of contacts between body colliders (side A) and item
/// proxies (side B), appending to `out`. Same rows as [`add_contact_rows`]; the proxy's
/// Jacobian comes from [`PhysicsItem::proxy_jacobian`]. Errors: a contact naming an item
/// out of range, or touching more than [`MAX_CONTACT_BLOCKS`] blocks.
#[allow(clippy::too_many_arguments)]
pub fn add_proxy_contact_rows(
    points: &[ProxyContact],
    bodies: &[RigidBody],
    items: &[Box<dyn PhysicsItem>],
    settings: NscRowSettings,
    rows: &mut ConstraintRows,
    scratch: &mut TripletScratch,
    out: &mut Vec<NscProxyContact>,
) -> Result<()> {
    let h = settings.h;
    for cp in points {
        let n = cp.normal;
        let (u, w) = tangent_frame(&n);
        let (dirs_a, dirs_b) = ([-n, -u, -w], [n, u, w]);
        let body = bodies
            .get(cp.owner as usize)
            .ok_or(ChronoError::UnknownHandle {
                kind: "body",
                index: cp.owner as usize,
                field: "proxy contact owner".into(),
            })?;
        let item = items
            .get(cp.item as usize)
            .ok_or(ChronoError::UnknownHandle {
                kind: "item",
                index: cp.item as usize,
                field: "proxy contact item".into(),
            })?;
        scratch.clear();
        let ka = scratch.add(&|e| body.contact_jacobian(&cp.point_a, &dirs_a, e));
        let kb = scratch.add(&|e| item.proxy_jacobian(cp.proxy, &cp.point_b, &dirs_b, e));
        let nb = scratch.blocks.len();
        if nb == 0 {
            continue;
        }
        if nb > MAX_CONTACT_BLOCKS {
            return Err(ChronoError::invalid(
                format!("item {} (\"{}\") proxy {}", cp.item, item.name(), cp.proxy),
                nb,
                "a contact row touches too many variable blocks (limit MAX_CONTACT_BLOCKS)",
            ));
        }
        let known: [f64; 3] = std::array::from_fn(|r| ka[r] + kb[r]);
        let (en, eu, ew) = (scratch.entries(0), scratch.entries(1), scratch.entries(2));
        let bn = (cp.distance / h).max(-settings.max_recovery_speed) + known[0];
        let eps_n = cp.material.compliance / (h * h);
        let row = rows.push_friction(
            cp.material.friction,
            [&en[..nb], &eu[..nb], &ew[..nb]],
            [bn, known[1], known[2]],
            [eps_n, 0.0, 0.0],
        );
        out.push(NscProxyContact {
            point: *cp,
            u,
            w,
            row,
        });
    }
    Ok(())
}

/// Fill the proxy contacts' part of `gamma` from the cache (keys not found start at zero).
pub fn warm_start_proxies(
    contacts: &[NscProxyContact],
    cache: &WarmStartCache,
    problem: &CcpProblem,
    gamma: &mut [f64],
) {
    for c in contacts {
        let i = problem.row_index(c.row);
        let (gn, gt) = cache
            .proxies
            .get(&c.point.key)
            .copied()
            .unwrap_or((0.0, Vector3::zeros()));
        gamma[i] = gn;
        gamma[i + 1] = gt.dot(&c.u);
        gamma[i + 2] = gt.dot(&c.w);
    }
}

/// Store the proxy contacts' impulses for the next step (replacing that part of the cache).
pub fn store_proxies(
    contacts: &[NscProxyContact],
    problem: &CcpProblem,
    gamma: &[f64],
    cache: &mut WarmStartCache,
) {
    cache.proxies.clear();
    for c in contacts {
        let i = problem.row_index(c.row);
        cache.proxies.insert(
            c.point.key,
            (gamma[i], c.u * gamma[i + 1] + c.w * gamma[i + 2]),
        );
    }
}

/// Settings of NSC contact rows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NscRowSettings {
    /// Step size, s.
    pub h: f64,
    /// Maximum penetration recovery speed `v_rec`, m/s.
    pub max_recovery_speed: f64,
}

/// Make the friction triplets of `points` between rigid bodies, appending to `out`.
pub fn add_contact_rows(
    points: &[ContactPoint],
    bodies: &[RigidBody],
    settings: NscRowSettings,
    rows: &mut ConstraintRows,
    out: &mut Vec<NscContact>,
) {
    let h = settings.h;
    for cp in points {
        let n = cp.normal;
        let (u, w) = tangent_frame(&n);
        let dirs_b = [n, u, w];
        let dirs_a = [-n, -u, -w];
        let a = &bodies[cp.owner_a as usize];
        let b = &bodies[cp.owner_b as usize];
        // Up to two blocks per row; coefficient storage for each side.
        let mut blocks: [(BlockId, [[f64; 6]; 3], usize); 2] = [(BlockId(0), [[0.0; 6]; 3], 0); 2];
        let mut nb = 0;
        let mut known = [0.0; 3];
        for (body, p, dirs) in [(a, &cp.point_a, &dirs_a), (b, &cp.point_b, &dirs_b)] {
            let k = body.contact_jacobian(p, dirs, &mut |blk, j| {
                let mut c = [[0.0; 6]; 3];
                for r in 0..3 {
                    c[r][..j[r].len()].copy_from_slice(j[r]);
                }
                blocks[nb] = (blk, c, j[0].len());
                nb += 1;
            });
            for r in 0..3 {
                known[r] += k[r];
            }
        }
        if nb == 0 {
            continue;
        }
        let e = |r: usize, i: usize| RowEntry {
            block: blocks[i].0,
            coefs: &blocks[i].1[r][..blocks[i].2],
        };
        let (rn, ru, rw) = ([e(0, 0), e(0, 1)], [e(1, 0), e(1, 1)], [e(2, 0), e(2, 1)]);
        let (rn, ru, rw) = (&rn[..nb], &ru[..nb], &rw[..nb]);
        let bn = (cp.distance / h).max(-settings.max_recovery_speed) + known[0];
        let eps_n = cp.material.compliance / (h * h);
        let row = rows.push_friction(
            cp.material.friction,
            [rn, ru, rw],
            [bn, known[1], known[2]],
            [eps_n, 0.0, 0.0],
        );
        out.push(NscContact {
            point: *cp,
            u,
            w,
            row,
        });
    }
}

/// Fill the contacts' part of `gamma` from the cache (keys not found start at zero).
pub fn warm_start(
    contacts: &[NscContact],
    cache: &WarmStartCache,
    problem: &CcpProblem,
    gamma: &mut [f64],
) {
    for c in contacts {
        let i = problem.row_index(c.row);
        match cache.map.get(&c.point.key) {
            Some((gn, gt)) => {
                gamma[i] = *gn;
                gamma[i + 1] = gt.dot(&c.u);
                gamma[i + 2] = gt.dot(&c.w);
            }
            None => {
                gamma[i] = 0.0;
                gamma[i + 1] = 0.0;
                gamma[i + 2] = 0.0;
            }
        }
    }
}

/// Store the contacts' impulses for the next step (replacing the cache).
pub fn store(
    contacts: &[NscContact],
    problem: &CcpProblem,
    gamma: &[f64],
    cache: &mut WarmStartCache,
) {
    cache.map.clear();
    for c in contacts {
        let i = problem.row_index(c.row);
        cache.map.insert(
            c.point.key,
            (gamma[i], c.u * gamma[i + 1] + c.w * gamma[i + 2]),
        );
    }
}
