//! SMC granular material over ranks: slabs of grains, ghost grains, migration with
//! the tangential contact history.
//!
//! **What is distributed.** A [`System`] in SMC mode whose dynamic bodies are *grains*:
//! bodies with exactly one sphere collider, added after every other body (walls, floors,
//! kinematic drivers). The other bodies are replicated on every rank (each moves the same
//! way everywhere: fixed or kinematic); every grain is whole on one rank, its owner,
//! which steps it. A dynamic body that is not a single sphere would be cut by the slabs
//! (its contacts could straddle two ranks): it is an error naming the body, as are
//! joints, force elements and physics items (not distributed).
//!
//! **Slabs and ghosts.** The grains' coordinates along `axis` are cut into one slab per
//! rank ([`Slabs`], equal grain counts, rebalanced every
//! [`GrainRankSettings::rebalance_every`] rebuilds from a histogram summed over the
//! ranks). A rank also holds *ghosts*: copies of the grains within the halo width
//! `w = 2 r_max + envelope + skin` of its slab, refreshed from their owners after every
//! step. A ghost is an ordinary dynamic body in the rank's system, so its contacts with
//! the owned grains use its true mass and inertia (the damping's effective mass); the
//! rank's own integration of a ghost is overwritten by the refresh.
//!
//! **Rebuilds.** Between rebuilds every grain moved less than `skin / 2` along the axis,
//! so a pair within contact range of an owned grain was within `w` of the slab at the
//! rebuild: every contact of an owned grain is in the rank's system. When a grain of any
//! rank moved farther (a global maximum), every rank rebuilds: each owner sends its grains
//! to their new owners and as ghosts to the ranks whose halo holds them, with the
//! tangential displacement of each contact it is responsible for (at least one grain
//! owned), addressed by *global collider ids* (the other bodies' colliders, then one per
//! grain in grain order); the receiver drops its grains and adds the new set in grain
//! order. So the colliders of every rank keep the order of a single process, each pair
//! has the same orientation (which grain is "a"), and the contact forces on a grain are
//! summed in the same order.
//!
//! **What equals a single process.** The same contacts with the same states and the same
//! history give each owned grain the forces of a single process, added in the same
//! order; results agree to round-off (the tests ask 1e-9 relative over 200 steps and
//! report the difference), and are bit-reproducible for a given rank and thread count.
//!
//! **Failures.** A rank whose step fails returns its error; the others stop at the same
//! step with [`ChronoError::Rank`] naming it (every rank takes part in the step's
//! reduction before returning, so none waits for one that left).

use nalgebra::{Isometry3, Matrix3, Quaternion, Translation3, UnitQuaternion, Vector3};

use super::{Slabs, Transport};
use crate::body::{BodyHandle, BodyMotion, RigidBody, RigidBodyBuilder};
use crate::collision::ContactKey;
use crate::contact::smc::SmcHistory;
use crate::error::{ChronoError, Result};
use crate::material::ContactMaterial;
use crate::shape::Shape;
use crate::system::{ContactMethod, StepReport, System};

/// Values per grain record (migration and ghost creation).
const RECORD: usize = 46;
/// Values per ghost refresh: position, rotation, velocity, angular velocity.
const STATE: usize = 13;
/// Values per history entry: two global collider ids, two features, `xi`, the rolling
/// angle.
const HISTORY: usize = 10;

/// Settings of a granular decomposition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrainRankSettings {
    /// The axis cut into slabs (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// The Verlet skin as a fraction of the largest grain radius: the halo is `skin`
    /// wider than the contact range, and the ranks rebuild when a grain moved `skin / 2`
    /// along the axis.
    pub skin_radii: f64,
    /// Move the cuts to the grains' current quantiles every this many rebuilds (0 =
    /// never).
    pub rebalance_every: u32,
    /// Bins of the histogram the rebalancing reads.
    pub histogram_bins: usize,
}

impl Default for GrainRankSettings {
    fn default() -> Self {
        Self {
            axis: 0,
            skin_radii: 0.5,
            rebalance_every: 4,
            histogram_bins: 4096,
        }
    }
}

impl GrainRankSettings {
    fn validate(&self) -> Result<()> {
        if self.axis > 2 {
            return Err(ChronoError::invalid("axis", self.axis, "must be 0, 1 or 2"));
        }
        if !(self.skin_radii.is_finite() && self.skin_radii > 0.0) {
            return Err(ChronoError::invalid(
                "skin_radii",
                self.skin_radii,
                "must be finite and > 0",
            ));
        }
        if self.histogram_bins == 0 {
            return Err(ChronoError::invalid("histogram_bins", 0, "must be >= 1"));
        }
        Ok(())
    }
}

/// Sums over the ranks (the same on every rank).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrainSummary {
    /// Grains owned over all ranks (the scene's count while nothing is lost).
    pub grains: usize,
    /// Kinetic energy of the grains, J (summed per rank in grain order, then over the
    /// ranks in rank order).
    pub kinetic_energy: f64,
    /// The highest point of any grain, `max (z + r)`, m.
    pub top: f64,
}

/// Counters of this rank.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GrainRankStats {
    /// Grains this rank owns.
    pub owned: usize,
    /// Ghost grains it holds.
    pub ghosts: usize,
    /// Rebuilds so far.
    pub rebuilds: u64,
    /// Of those, rebalances.
    pub rebalances: u64,
    /// Grains that arrived from another owner, summed over the rebuilds.
    pub migrated_in: u64,
    /// `f64` values this rank sent to the others, summed over the run.
    pub values_sent: u64,
    /// Wall time in rebuilds (migration, ghosts, the system's new grain set), s.
    pub rebuild_seconds: f64,
    /// Wall time in the ghosts' refreshes, s.
    pub refresh_seconds: f64,
}

/// One rank of a distributed SMC granular system (see the module docs).
pub struct GrainRanks {
    /// This rank.
    me: usize,
    settings: GrainRankSettings,
    slabs: Slabs,
    system: System,
    /// Bodies and colliders before the grains (replicated on every rank).
    base_bodies: usize,
    base_colliders: usize,
    /// Grains in the scene.
    total: usize,
    halo: f64,
    skin: f64,
    /// Per local grain, in grain order: global id, handle, owner rank, axis coordinate at
    /// the last rebuild.
    ids: Vec<u64>,
    handles: Vec<BodyHandle>,
    owner: Vec<usize>,
    anchor: Vec<f64>,
    /// Per rank: local grains whose state goes there after each step (owned, a ghost
    /// there), and local ghosts refreshed from there; both in grain order.
    send: Vec<Vec<usize>>,
    recv: Vec<Vec<usize>>,
    sbuf: Vec<Vec<f64>>,
    rbuf: Vec<Vec<f64>>,
    stats: GrainRankStats,
}

impl std::fmt::Debug for GrainRanks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GrainRanks")
            .field("slabs", &self.slabs)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

/// A grain's sphere: radius, local pose, material; `None` if `b` is not a grain.
fn grain_sphere(b: &RigidBody) -> Option<(f64, Isometry3<f64>, ContactMaterial)> {
    match (b.motion, b.colliders.as_slice()) {
        (BodyMotion::Dynamic, [c]) => match &c.shape {
            Shape::Sphere { radius } => Some((*radius, c.local_pose, c.material)),
            _ => None,
        },
        _ => None,
    }
}

fn push_record(out: &mut Vec<f64>, id: u64, owner: usize, b: &RigidBody) {
    let (radius, pose, m) = grain_sphere(b).expect("a grain");
    out.push(id as f64);
    out.push(owner as f64);
    out.push(b.mass);
    out.extend_from_slice(b.inertia.as_slice());
    out.extend_from_slice(b.position.as_slice());
    out.extend_from_slice(b.rotation.coords.as_slice());
    out.extend_from_slice(b.linear_velocity.as_slice());
    out.extend_from_slice(b.angular_velocity.as_slice());
    out.extend_from_slice(b.force.as_slice());
    out.extend_from_slice(b.torque.as_slice());
    out.push(radius);
    out.extend_from_slice(pose.translation.vector.as_slice());
    out.extend_from_slice(pose.rotation.coords.as_slice());
    out.extend_from_slice(&[
        m.friction,
        m.restitution,
        m.compliance,
        m.young_modulus,
        m.poisson_ratio,
        m.rolling_friction,
        m.spinning_friction,
    ]);
}

fn v3(s: &[f64]) -> Vector3<f64> {
    Vector3::new(s[0], s[1], s[2])
}

fn quat(s: &[f64]) -> UnitQuaternion<f64> {
    // the stored unit quaternion's own coordinates (i, j, k, w): no renormalization
    UnitQuaternion::new_unchecked(Quaternion::new(s[3], s[0], s[1], s[2]))
}

/// Adds the grain of record `r` to `sys` with exactly the recorded state.
fn add_grain(sys: &mut System, r: &[f64]) -> Result<BodyHandle> {
    let id = r[0] as u64;
    let pose = Isometry3::from_parts(Translation3::from(v3(&r[32..35])), quat(&r[35..39]));
    let m = &r[39..46];
    let material = ContactMaterial {
        friction: m[0],
        restitution: m[1],
        compliance: m[2],
        young_modulus: m[3],
        poisson_ratio: m[4],
        rolling_friction: m[5],
        spinning_friction: m[6],
    };
    let inertia = Matrix3::from_column_slice(&r[3..12]);
    let h = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name(format!("grain {id}"))
            .mass(r[2])
            .inertia(inertia)
            .position(v3(&r[12..15]))
            .collider(Shape::Sphere { radius: r[31] }, pose, material),
    )?;
    let b = sys.body_mut(h)?;
    b.rotation = quat(&r[15..19]);
    b.linear_velocity = v3(&r[19..22]);
    b.angular_velocity = v3(&r[22..25]);
    b.force = v3(&r[25..28]);
    b.torque = v3(&r[28..31]);
    Ok(h)
}

impl GrainRanks {
    /// This rank's part of `whole`, a system every rank built the same way (the whole
    /// scene: the other bodies first, then the grains). The slabs are the grains' count
    /// quantiles along `settings.axis`. Errors: not SMC (`contact_method`), a dynamic
    /// body that is not a single sphere or a body after the grains (naming it), joints,
    /// force elements or items, more ranks than slabs of the halo width (`ranks`), ranks
    /// that built different scenes.
    pub fn new(
        mut whole: System,
        settings: GrainRankSettings,
        t: &mut dyn Transport,
    ) -> Result<Self> {
        settings.validate()?;
        if whole.settings.contact_method != ContactMethod::Smc {
            return Err(ChronoError::invalid(
                "contact_method",
                format!("{:?}", whole.settings.contact_method),
                "a granular decomposition steps SMC contact (the NSC step solves one problem over every body)",
            ));
        }
        if !whole.joints.is_empty() || !whole.force_elements.is_empty() || !whole.items.is_empty() {
            return Err(ChronoError::invalid(
                "system",
                format!(
                    "{} joints, {} force elements, {} items",
                    whole.joints.len(),
                    whole.force_elements.len(),
                    whole.items.len()
                ),
                "joints, force elements and physics items are not distributed over ranks",
            ));
        }
        let bodies = whole.bodies.as_slice();
        let base_bodies = bodies
            .iter()
            .position(|b| b.motion == BodyMotion::Dynamic)
            .unwrap_or(bodies.len());
        for (k, b) in bodies.iter().enumerate().skip(base_bodies) {
            if b.motion != BodyMotion::Dynamic {
                return Err(ChronoError::invalid(
                    format!("bodies[{k}]"),
                    format!("\"{}\"", b.name),
                    "a fixed or kinematic body after the first grain: add the grains last",
                ));
            }
            if grain_sphere(b).is_none() {
                return Err(ChronoError::invalid(
                    format!("bodies[{k}]"),
                    format!("\"{}\"", b.name),
                    "a decomposition would cut this rigid body: only grains (dynamic bodies with one sphere collider) are distributed, each whole on one rank",
                ));
            }
        }
        let total = bodies.len() - base_bodies;
        let base_colliders: usize = bodies[..base_bodies]
            .iter()
            .map(|b| b.colliders.len())
            .sum();
        // every rank must hold the same scene
        let mut check = [total as f64, -(total as f64)];
        t.all_max(&mut check)?;
        if check[0] != total as f64 || -check[1] != total as f64 {
            return Err(ChronoError::invalid(
                "system",
                total,
                format!(
                    "the ranks built scenes of {} to {} grains: every rank must build the same scene",
                    -check[1], check[0]
                ),
            ));
        }
        let mut r_max = 0.0f64;
        for b in &bodies[base_bodies..] {
            let (r, pose, _) = grain_sphere(b).expect("checked");
            r_max = r_max.max(r + pose.translation.vector.norm());
        }
        let skin = settings.skin_radii * r_max;
        let halo = 2.0 * r_max + whole.settings.envelope + skin;
        let coords: Vec<f64> = bodies[base_bodies..]
            .iter()
            .map(|b| b.position[settings.axis])
            .collect();
        let slabs = Slabs::balanced(&coords, &vec![1.0; total], t.size(), halo)?;
        let me = t.rank();
        // this rank's grains (owned and ghosts): records straight from the whole scene
        let keep: Vec<bool> = coords.iter().map(|&c| slabs.near(me, c, halo)).collect();
        let mut records = Vec::new();
        for (g, b) in bodies[base_bodies..].iter().enumerate() {
            if keep[g] {
                push_record(&mut records, g as u64, slabs.owner(coords[g]), b);
            }
        }
        // the whole scene's history among the grains this rank keeps
        let history: Vec<f64> = whole
            .smc
            .history()
            .filter(|(k, _)| {
                [k.collider_a, k.collider_b].iter().all(|&c| {
                    let c = c as usize;
                    c < base_colliders || keep[c - base_colliders]
                })
            })
            .flat_map(|(k, h)| {
                let (xi, th) = (h.tangential, h.rolling);
                [
                    k.collider_a as f64,
                    k.collider_b as f64,
                    k.feature_a as f64,
                    k.feature_b as f64,
                    xi.x,
                    xi.y,
                    xi.z,
                    th.x,
                    th.y,
                    th.z,
                ]
            })
            .collect();
        let handles: Vec<BodyHandle> = whole.bodies.handles().skip(base_bodies).collect();
        let n = t.size();
        let mut ranks = Self {
            me,
            settings,
            slabs,
            system: {
                let tail: Vec<BodyHandle> = handles.into_iter().rev().collect();
                whole.remove_bodies(&tail)?;
                whole
            },
            base_bodies,
            base_colliders,
            total,
            halo,
            skin,
            ids: Vec::new(),
            handles: Vec::new(),
            owner: Vec::new(),
            anchor: Vec::new(),
            send: vec![Vec::new(); n],
            recv: vec![Vec::new(); n],
            sbuf: vec![Vec::new(); n],
            rbuf: vec![Vec::new(); n],
            stats: GrainRankStats::default(),
        };
        ranks.install(me, &[records], &[history])?;
        ranks.check_count(t)?;
        Ok(ranks)
    }

    /// This rank's system (its grains and ghosts after the other bodies).
    pub fn system(&self) -> &System {
        &self.system
    }

    /// The slabs in use.
    pub fn slabs(&self) -> &Slabs {
        &self.slabs
    }

    /// The halo width `w`, m.
    pub fn halo(&self) -> f64 {
        self.halo
    }

    /// This rank's counters.
    pub fn stats(&self) -> GrainRankStats {
        self.stats
    }

    /// This rank, `0..size`.
    pub fn rank(&self) -> usize {
        self.me
    }

    /// Whether local grain `k` (grain order) is owned here.
    fn owns(&self, k: usize) -> bool {
        self.owner[k] == self.me
    }

    /// The grains this rank owns: `(global id, body)`, in grain order.
    pub fn owned(&self) -> impl Iterator<Item = (u64, &RigidBody)> + '_ {
        (0..self.ids.len())
            .filter(move |&k| self.owns(k))
            .map(move |k| {
                let b = &self.system.bodies.as_slice()[self.base_bodies + k];
                (self.ids[k], b)
            })
    }

    /// Grain `id` if this rank owns it (to set a velocity or a force between steps). The
    /// other ranks' ghost copies see the change after the next step's refresh, so their
    /// contacts with it use the old state for that step: change grains before the first
    /// step (or accept one step's lag).
    pub fn grain_mut(&mut self, id: u64) -> Option<&mut RigidBody> {
        let k = self.ids.binary_search(&id).ok()?;
        if !self.owns(k) {
            return None;
        }
        self.system.body_mut(self.handles[k]).ok()
    }

    /// Sums over every rank's owned grains (a collective).
    pub fn summary(&self, t: &mut dyn Transport) -> Result<GrainSummary> {
        let mut ke = 0.0;
        let mut count = 0usize;
        let mut top = f64::NEG_INFINITY;
        for (_, b) in self.owned() {
            ke += b.kinetic_energy();
            count += 1;
            let (r, pose, _) = grain_sphere(b).expect("a grain");
            let centre = b.position + b.rotation * pose.translation.vector;
            top = top.max(centre.z + r);
        }
        let mut sums = [count as f64, ke];
        t.all_sum(&mut sums)?;
        let mut max = [top];
        t.all_max(&mut max)?;
        Ok(GrainSummary {
            grains: sums[0] as usize,
            kinetic_energy: sums[1],
            top: max[0],
        })
    }

    /// One step of size `h` (s) on every rank (a collective): the rank's SMC step, the
    /// failure and displacement reduction, the ghosts' refresh, and a rebuild when a
    /// grain moved half the skin.
    pub fn step(&mut self, h: f64, t: &mut dyn Transport) -> Result<StepReport> {
        let me = t.rank();
        if me != self.me || t.size() != self.send.len() {
            return Err(ChronoError::invalid(
                "transport",
                format!("rank {me} of {}", t.size()),
                format!(
                    "not the transport this rank was built with (rank {} of {})",
                    self.me,
                    self.send.len()
                ),
            ));
        }
        let step = self.system.step_count;
        let result = self.system.step(h);
        let axis = self.settings.axis;
        let bodies = self.system.bodies.as_slice();
        let mut moved = 0.0f64;
        for k in 0..self.ids.len() {
            if self.owner[k] == me {
                let c = bodies[self.base_bodies + k].position[axis];
                moved = moved.max((c - self.anchor[k]).abs());
            }
        }
        let failed = if result.is_err() {
            me as f64 + 1.0
        } else {
            0.0
        };
        // a non-finite displacement is a failure the step did not see
        let moved = if moved.is_finite() {
            moved
        } else {
            f64::INFINITY
        };
        let mut flags = [failed, moved];
        t.all_max(&mut flags)?;
        let report = result?;
        if flags[0] > 0.0 {
            return Err(ChronoError::Rank {
                rank: flags[0] as usize - 1,
                reason: format!("its step {step} failed; this rank stops with it"),
            });
        }
        self.refresh(t)?;
        if flags[1] > 0.5 * self.skin {
            self.rebuild(t)?;
        }
        Ok(report)
    }

    /// Owners send the stepped state of their grains that are ghosts elsewhere.
    fn refresh(&mut self, t: &mut dyn Transport) -> Result<()> {
        let t0 = std::time::Instant::now();
        let bodies = self.system.bodies.as_slice();
        for (q, list) in self.send.iter().enumerate() {
            let buf = &mut self.sbuf[q];
            buf.clear();
            for &k in list {
                let b = &bodies[self.base_bodies + k];
                buf.extend_from_slice(b.position.as_slice());
                buf.extend_from_slice(b.rotation.coords.as_slice());
                buf.extend_from_slice(b.linear_velocity.as_slice());
                buf.extend_from_slice(b.angular_velocity.as_slice());
            }
            self.stats.values_sent += buf.len() as u64;
        }
        let counts: Vec<usize> = self.recv.iter().map(|l| l.len() * STATE).collect();
        t.all_to_all_sized(&self.sbuf, &mut self.rbuf, &counts)?;
        for (q, list) in self.recv.iter().enumerate() {
            for (&k, s) in list.iter().zip(self.rbuf[q].chunks_exact(STATE)) {
                let b = self.system.body_mut(self.handles[k])?;
                b.position = v3(&s[0..3]);
                b.rotation = quat(&s[3..7]);
                b.linear_velocity = v3(&s[7..10]);
                b.angular_velocity = v3(&s[10..13]);
            }
        }
        self.stats.refresh_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// The ranks where a grain at axis coordinate `c` lives after a rebuild (owner and
    /// halos).
    fn presence(&self, c: f64, q: usize) -> bool {
        self.slabs.near(q, c, self.halo)
    }

    /// Migration, new ghosts and the history they need (a collective).
    fn rebuild(&mut self, t: &mut dyn Transport) -> Result<()> {
        let t0 = std::time::Instant::now();
        let me = t.rank();
        let n = t.size();
        let axis = self.settings.axis;
        self.stats.rebuilds += 1;
        let coords: Vec<f64> = (0..self.ids.len())
            .map(|k| self.system.bodies.as_slice()[self.base_bodies + k].position[axis])
            .collect();
        let every = self.settings.rebalance_every as u64;
        if every > 0 && self.stats.rebuilds.is_multiple_of(every) {
            self.rebalance(&coords, t)?;
        }
        let mut out: Vec<Vec<f64>> = vec![Vec::new(); n];
        let mut hist: Vec<Vec<f64>> = vec![Vec::new(); n];
        let bodies = self.system.bodies.as_slice();
        for (k, &c) in coords.iter().enumerate() {
            if !self.owns(k) {
                continue;
            }
            let owner = self.slabs.owner(c);
            for (q, o) in out.iter_mut().enumerate() {
                if self.presence(c, q) {
                    push_record(o, self.ids[k], owner, &bodies[self.base_bodies + k]);
                }
            }
        }
        // the contacts this rank answers for (an owned grain in them), to every rank
        // that will hold both sides
        let base = self.base_colliders;
        let local = |c: u32| -> Option<usize> { (c as usize).checked_sub(base) };
        for (key, h) in self.system.smc.history() {
            let (xi, th) = (h.tangential, h.rolling);
            let (a, b) = (local(key.collider_a), local(key.collider_b));
            let mine = [a, b].iter().flatten().any(|&k| self.owns(k));
            if !mine {
                continue;
            }
            let global = |c: u32| match local(c) {
                Some(k) => (base as u64 + self.ids[k]) as f64,
                None => c as f64,
            };
            let entry = [
                global(key.collider_a),
                global(key.collider_b),
                key.feature_a as f64,
                key.feature_b as f64,
                xi.x,
                xi.y,
                xi.z,
                th.x,
                th.y,
                th.z,
            ];
            for (q, hq) in hist.iter_mut().enumerate() {
                let there = |s: Option<usize>| s.is_none_or(|k| self.presence(coords[k], q));
                if there(a) && there(b) {
                    hq.extend_from_slice(&entry);
                }
            }
        }
        for q in (0..n).filter(|&q| q != me) {
            self.stats.values_sent += (out[q].len() + hist[q].len()) as u64;
        }
        let mut recs = vec![Vec::new(); n];
        let mut hrecv = vec![Vec::new(); n];
        t.all_to_all(&out, &mut recs)?;
        t.all_to_all(&hist, &mut hrecv)?;
        let before: Vec<u64> = (0..self.ids.len())
            .filter(|&k| self.owns(k))
            .map(|k| self.ids[k])
            .collect();
        // drop the grains (the last first: no body moves), then add the new set
        let tail: Vec<BodyHandle> = self.handles.iter().rev().copied().collect();
        self.system.remove_bodies(&tail)?;
        self.install(me, &recs, &hrecv)?;
        self.stats.migrated_in += (0..self.ids.len())
            .filter(|&k| self.owns(k) && before.binary_search(&self.ids[k]).is_err())
            .count() as u64;
        self.check_count(t)?;
        self.stats.rebuild_seconds += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// Cuts at the quantiles of the owned grains' coordinates (a collective).
    fn rebalance(&mut self, coords: &[f64], t: &mut dyn Transport) -> Result<()> {
        let owned: Vec<f64> = (0..coords.len())
            .filter(|&k| self.owns(k))
            .map(|k| coords[k])
            .collect();
        let mut ext = [f64::NEG_INFINITY, f64::NEG_INFINITY];
        for &c in &owned {
            ext = [ext[0].max(c), ext[1].max(-c)];
        }
        t.all_max(&mut ext)?;
        let (lo, hi) = (-ext[1], ext[0]);
        let bins = self.settings.histogram_bins;
        let mut counts = vec![0.0; bins];
        let db = (hi - lo) / bins as f64;
        for &c in &owned {
            let b = if db > 0.0 {
                (((c - lo) / db) as usize).min(bins - 1)
            } else {
                0
            };
            counts[b] += 1.0;
        }
        t.all_sum(&mut counts)?;
        self.slabs = Slabs::from_histogram(&counts, lo, hi, t.size(), self.halo)?;
        self.stats.rebalances += 1;
        Ok(())
    }

    /// Adds the grains of `records` (from every rank) in grain order with the history of
    /// `history`, and rebuilds the refresh lists.
    fn install(&mut self, me: usize, records: &[Vec<f64>], history: &[Vec<f64>]) -> Result<()> {
        let mut recs: Vec<&[f64]> = records
            .iter()
            .flat_map(|r| r.chunks_exact(RECORD))
            .collect();
        recs.sort_by(|a, b| a[0].total_cmp(&b[0]));
        if let Some(w) = recs.windows(2).find(|w| w[0][0] == w[1][0]) {
            return Err(ChronoError::Rank {
                rank: me,
                reason: format!("grain {} arrived twice at a rebuild", w[0][0]),
            });
        }
        self.ids.clear();
        self.handles.clear();
        self.owner.clear();
        self.anchor.clear();
        for r in &recs {
            self.handles.push(add_grain(&mut self.system, r)?);
            self.ids.push(r[0] as u64);
            self.owner.push(r[1] as usize);
            self.anchor.push(r[12 + self.settings.axis]);
        }
        // history: global collider ids -> this rank's (monotone: the order is kept)
        let base = self.base_colliders as u64;
        let mut entries: Vec<(ContactKey, SmcHistory)> = Vec::new();
        for h in history.iter().flat_map(|h| h.chunks_exact(HISTORY)) {
            let map = |g: f64| -> Result<u32> {
                let g = g as u64;
                if g < base {
                    return Ok(g as u32);
                }
                match self.ids.binary_search(&(g - base)) {
                    Ok(k) => Ok((base as usize + k) as u32),
                    Err(_) => Err(ChronoError::Rank {
                        rank: me,
                        reason: format!("a contact of grain {} arrived without it", g - base),
                    }),
                }
            };
            let key = ContactKey {
                collider_a: map(h[0])?,
                collider_b: map(h[1])?,
                feature_a: h[2] as u32,
                feature_b: h[3] as u32,
            };
            entries.push((
                key,
                SmcHistory {
                    tangential: v3(&h[4..7]),
                    rolling: v3(&h[7..10]),
                },
            ));
        }
        // a contact between grains of two owners came from both, with the same values
        entries.sort_by_key(|e| e.0);
        entries.dedup_by_key(|e| e.0);
        self.system.smc.import_history(entries);
        let n = self.send.len();
        for q in 0..n {
            self.send[q].clear();
            self.recv[q].clear();
        }
        for k in 0..self.ids.len() {
            if self.owner[k] == me {
                let c = self.anchor[k];
                for q in 0..n {
                    if q != me && self.slabs.near(q, c, self.halo) {
                        self.send[q].push(k);
                    }
                }
            } else {
                self.recv[self.owner[k]].push(k);
            }
        }
        self.stats.owned = self.owner.iter().filter(|&&o| o == me).count();
        self.stats.ghosts = self.ids.len() - self.stats.owned;
        Ok(())
    }

    /// Every grain owned once over the ranks (a collective).
    fn check_count(&self, t: &mut dyn Transport) -> Result<()> {
        let mut c = [self.stats.owned as f64];
        t.all_sum(&mut c)?;
        if c[0] as usize != self.total {
            return Err(ChronoError::Rank {
                rank: t.rank(),
                reason: format!(
                    "the ranks own {} grains after a rebuild, the scene has {}",
                    c[0], self.total
                ),
            });
        }
        Ok(())
    }
}
