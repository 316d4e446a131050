//! The SMC (penalty) time step: contact forces from overlaps ([`crate::contact::smc`]),
//! semi-implicit Euler, joints still by constraint rows.

use nalgebra::Vector3;
use rayon::prelude::*;

use super::{BODY_CHUNK, PARALLEL_MIN_BODIES, StepReport, System};
use crate::body::{BodyHandle, BodyMotion, RigidBody};
use crate::collision::{CollisionWorld, ContactKey, ContactPoint};
use crate::contact::smc::{
    self, RollingModel, SmcContact, SmcHistory, SmcKinematics, SmcModel, SmcPair, SmcSettings,
    damping_for_restitution,
};
use crate::error::{ChronoError, Result};
use crate::material::{effective_shear_modulus, effective_young_modulus};

/// Contacts per rayon task.
const CHUNK: usize = 256;

/// The history (tangential displacement, rolling angle) of one persistent contact.
#[derive(Debug, Clone, Copy)]
struct HistoryEntry {
    key: ContactKey,
    /// Position in its step's contact list (tie-break for duplicate keys: deterministic).
    index: u32,
    history: SmcHistory,
}

/// Per-step buffers and caches of the SMC stepper.
#[derive(Debug, Default)]
pub(crate) struct SmcState {
    pub(crate) contacts: Vec<SmcContact>,
    /// Last step's history, sorted by `(key, index)`.
    history: Vec<HistoryEntry>,
    next_history: Vec<HistoryEntry>,
    /// Per body: contact force (world) and torque (world).
    loads: Vec<[Vector3<f64>; 2]>,
    /// Per body: summed per-body rolling torque magnitudes (N m, `RollingModel::PerBody`).
    rolling: Vec<f64>,
    /// Per collider: curvature radius (infinite for flat shapes).
    radius: Vec<f64>,
    /// `(restitution bits, alpha)` sorted, for `alpha_model`.
    alphas: Vec<(u64, f64)>,
    alpha_model: Option<SmcModel>,
    /// Per body: `1/m` and `1/I` (0 for fixed and kinematic bodies).
    inv_mass: Vec<f64>,
    inv_inertia: Vec<f64>,
    /// Cached step limit: `(bodies, colliders, settings)` it was computed for, and value.
    limit_key: Option<(usize, usize, SmcSettings)>,
    limit: Option<(f64, usize, f64)>,
    /// `loads`/`rolling` may hold non-zero entries beyond the last contacts' owners (an
    /// error mid-step, or the force elements' loads added): zero them all on the next step.
    touched_all: bool,
    pub(crate) timing: SmcTiming,
}

impl SmcState {
    /// Zero the per-body loads this step added: only the contacts' owners hold any,
    /// unless `extra` loads (force elements, joint efforts) were added to every body;
    /// then the next step zeroes them all.
    fn clear_loads(&mut self, extra: bool) {
        if extra || self.loads.len() != self.rolling.len() {
            return;
        }
        for c in &self.contacts {
            for o in [c.owner_a as usize, c.owner_b as usize] {
                self.loads[o] = [Vector3::zeros(); 2];
                self.rolling[o] = 0.0;
            }
        }
        self.touched_all = false;
    }

    /// The contact history: each persistent contact's key, tangential displacement and
    /// rolling angle, in key order (for moving contacts between systems: a distributed run).
    pub(crate) fn history(&self) -> impl Iterator<Item = (ContactKey, SmcHistory)> + '_ {
        self.history.iter().map(|e| (e.key, e.history))
    }

    /// Adds history entries (keys not already present, each once; the caller maps the
    /// colliders) and restores the key order.
    pub(crate) fn import_history(
        &mut self,
        entries: impl IntoIterator<Item = (ContactKey, SmcHistory)>,
    ) {
        self.history
            .extend(entries.into_iter().map(|(key, history)| HistoryEntry {
                key,
                index: 0,
                history,
            }));
        self.history.sort_by_key(|e| (e.key, e.index));
    }

    /// After a body removal: follow the collider renumbering `map` in the tangential
    /// history (entries of removed colliders dropped, see [`ContactKey::remap`]) and forget
    /// the per-body and per-collider caches (rebuilt on the next step).
    pub(crate) fn remap_colliders(&mut self, map: &[Option<u32>]) {
        let mut history: Vec<HistoryEntry> = (self.history.iter())
            .filter_map(|e| {
                Some(HistoryEntry {
                    key: e.key.remap(map)?,
                    ..*e
                })
            })
            .collect();
        history.sort_by_key(|e| (e.key, e.index));
        *self = Self {
            history,
            timing: self.timing,
            ..Self::default()
        };
    }
}

/// Wall time of the parts of the last SMC step (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SmcTiming {
    /// Collision detection, broad phase.
    pub broad_phase: f64,
    /// Collision detection, narrow phase.
    pub narrow_phase: f64,
    /// Contact forces and their accumulation per body (the SMC "assembly").
    pub forces: f64,
    /// Rows solved (joints, items), 0 without rows.
    pub solve: f64,
    /// Velocity and pose update.
    pub integrate: f64,
}

fn harmonic(a: f64, b: f64) -> f64 {
    1.0 / (1.0 / a + 1.0 / b)
}

/// The step limit `t_c / N` over the dynamic bodies: each collider against an equal body
/// (effective mass `m/2`, radius `R/2`) of the stiffest material in the scene, at the
/// characteristic speed. Returns `(h_max, body, t_c)`.
fn step_limit(
    bodies: &[RigidBody],
    world: &CollisionWorld,
    s: &SmcSettings,
) -> Option<(f64, usize, f64)> {
    let stiffest = world
        .colliders()
        .iter()
        .map(|c| c.material())
        .min_by(|a, b| {
            let side =
                |m: &crate::ContactMaterial| (1.0 - m.poisson_ratio.powi(2)) / m.young_modulus;
            side(a).total_cmp(&side(b))
        })?;
    let mut best: Option<(f64, usize, f64)> = None;
    for c in world.colliders() {
        let i = c.owner() as usize;
        let Some(b) = bodies.get(i) else { continue };
        if !b.is_dynamic() {
            continue;
        }
        let r = c.shape().curvature_radius();
        let radius = if r.is_finite() {
            0.5 * r
        } else {
            s.flat_contact_radius
        };
        let pair = SmcPair {
            radius,
            mass: 0.5 * b.mass,
            inertia: 0.0,
            rolling_inertia: 0.0,
            young: effective_young_modulus(&c.material(), &stiffest),
            shear: 0.0,
            alpha: 0.0,
            friction: 0.0,
            rolling_friction: 0.0,
            spinning_friction: 0.0,
            // No rolling friction in the step estimate: the model does not matter.
            rolling_model: RollingModel::default(),
            rolling_damping: 0.0,
        };
        let tc = smc::contact_duration(s.model, &pair, s.characteristic_velocity);
        let h = tc / s.min_steps_per_contact;
        if best.is_none_or(|(bh, _, _)| h < bh) {
            best = Some((h, i, tc));
        }
    }
    best
}

impl System {
    /// The largest SMC step the scene allows, with the body that sets it: `t_c / N` where
    /// `t_c` is the duration of an undamped contact of the body with an equal body of the
    /// stiffest material in the scene at the characteristic speed
    /// ([`contact_duration`](smc::contact_duration)) and `N` is
    /// [`SmcSettings::min_steps_per_contact`]. `None` without dynamic colliders.
    pub fn smc_max_step(&self) -> Option<(f64, BodyHandle)> {
        step_limit(&self.bodies, &self.collision, &self.settings.smc)
            .map(|(h, i, _)| (h, self.bodies.handle(i)))
    }

    /// Wall time of the parts of the last SMC step.
    pub fn smc_timing(&self) -> SmcTiming {
        self.smc.timing
    }

    /// The SMC contacts of the last step (empty in NSC mode).
    pub fn smc_contacts(&self) -> &[SmcContact] {
        &self.smc.contacts
    }

    /// One SMC step of size `h` (s), called by [`step`](Self::step) when the settings say
    /// [`ContactMethod::Smc`](super::ContactMethod::Smc):
    ///
    /// 1. check `h` against [`smc_max_step`](Self::smc_max_step) (an error names the
    ///    body that needs the smaller step);
    /// 2. collide at `q(l)`; each contact's force from its overlap, relative velocity and
    ///    history ([`contact_force`](smc::contact_force)), in parallel;
    /// 3. `v(l+1) = v(l) + h M^-1 (f_applied + f_contact)` (the rotation with the same
    ///    momentum-conserving gyroscopic term as the NSC step); with joints or physics
    ///    items the rows are solved by the CCP solver for `k = M v + h f`, without them
    ///    no problem is assembled;
    /// 4. `q(l+1) = q(l) + h L(q) v(l+1)`.
    ///
    /// Items' collision proxies are not collided in SMC mode: an item that exposes any is
    /// refused with [`ChronoError::ItemNotSupported`] naming it (before anything moves).
    pub(crate) fn step_smc(&mut self, h: f64) -> Result<StepReport> {
        if !(h.is_finite() && h > 0.0) {
            return Err(ChronoError::invalid(
                "h",
                h,
                "the step size must be finite and > 0",
            ));
        }
        self.settings.smc.validate()?;
        // Items' proxies would need item-side contact forces: refuse them rather than let a
        // fluid or a mesh fall through the bodies unnoticed.
        for item in &self.items {
            self.proxies.clear();
            item.collision_proxies(&mut self.proxies);
            if !self.proxies.is_empty() {
                return Err(ChronoError::ItemNotSupported {
                    item: item.name().to_string(),
                    stepper: "the SMC step".into(),
                    reason: format!(
                        "it exposes {} collision proxies, which SMC contact does not collide (use NSC)",
                        self.proxies.len()
                    ),
                });
            }
        }
        self.check_smc_step(h)?;
        self.prepare_smc_caches()?;

        // Collision at q(l).
        self.collision
            .set_sphere_skin(self.settings.smc.grid_skin)?;
        self.collision_state();
        self.collision
            .detect(&self.poses, &self.active, &mut self.points)?;
        self.apply_contact_friction();
        let (broad, narrow) = self.collision.last_timing();
        let t0 = std::time::Instant::now();
        self.smc_forces(h);
        let ctx = self.step_context(h);
        self.gather_loads(&ctx)?;
        let extra = !self.loads_zero;
        if extra {
            for (l, e) in self.smc.loads.iter_mut().zip(self.loads.as_slice()) {
                l[0] += e[0];
                l[1] += e[1];
            }
        }
        let t1 = std::time::Instant::now();
        let (report, bad) = if self.joints.is_empty() && self.items.is_empty() {
            let bad = self.smc_free_update(h);
            let report = StepReport {
                contacts: self.smc.contacts.len(),
                ..StepReport::default()
            };
            (report, bad)
        } else {
            (self.smc_rows_update(h)?, self.first_bad_body())
        };
        self.smc.clear_loads(extra);
        self.smc.timing = SmcTiming {
            broad_phase: broad,
            narrow_phase: narrow,
            forces: (t1 - t0).as_secs_f64(),
            solve: 0.0,
            integrate: t1.elapsed().as_secs_f64(),
        };
        if let Some(i) = bad {
            return Err(self.state_error(i));
        }
        self.time += h;
        self.step_count += 1;
        Ok(report)
    }

    fn check_smc_step(&mut self, h: f64) -> Result<()> {
        let key = (self.bodies.len(), self.collision.len(), self.settings.smc);
        if self.smc.limit_key != Some(key) {
            self.smc.limit = step_limit(&self.bodies, &self.collision, &self.settings.smc);
            self.smc.limit_key = Some(key);
        }
        if let Some((hmax, i, tc)) = self.smc.limit
            && h > hmax
        {
            let s = &self.settings.smc;
            return Err(ChronoError::invalid(
                "h",
                h,
                format!(
                    "too large for SMC contact of body {i} (\"{}\"): contact duration {tc:.3e} s at {} m/s ({:?}), so h must be <= t_c / {} = {hmax:.3e} s",
                    self.bodies[i].name,
                    s.characteristic_velocity,
                    s.model,
                    s.min_steps_per_contact
                ),
            ));
        }
        Ok(())
    }

    /// Per-collider radii, damping per restitution value, per-body inverse masses.
    fn prepare_smc_caches(&mut self) -> Result<()> {
        let st = &mut self.smc;
        let model = self.settings.smc.model;
        let colliders = self.collision.colliders();
        if st.radius.len() != colliders.len() || st.alpha_model != Some(model) {
            st.radius.clear();
            st.radius
                .extend(colliders.iter().map(|c| c.shape().curvature_radius()));
            let mut es: Vec<u64> = colliders
                .iter()
                .map(|c| c.material().restitution.to_bits())
                .collect();
            es.sort_unstable();
            es.dedup();
            st.alphas.clear();
            for e in es {
                st.alphas
                    .push((e, damping_for_restitution(model, f64::from_bits(e))?));
            }
            st.alpha_model = Some(model);
        }
        // Mass and inertia never change after a body is built; a removal resets the
        // caches (`remap_colliders`), an addition changes the count.
        if st.inv_mass.len() != self.bodies.len() {
            st.inv_mass.clear();
            st.inv_inertia.clear();
            for b in &self.bodies {
                if b.is_dynamic() {
                    st.inv_mass.push(1.0 / b.mass);
                    st.inv_inertia.push(3.0 / b.inertia.trace());
                } else {
                    st.inv_mass.push(0.0);
                    st.inv_inertia.push(0.0);
                }
            }
        }
        Ok(())
    }

    /// Contact forces of `self.points` into `self.smc.contacts` and the per-body loads.
    fn smc_forces(&mut self, h: f64) {
        let st = &mut self.smc;
        let n = self.points.len();
        let blank = SmcContact {
            key: ContactKey {
                collider_a: 0,
                collider_b: 0,
                feature_a: 0,
                feature_b: 0,
            },
            owner_a: 0,
            owner_b: 0,
            point: Vector3::zeros(),
            normal: Vector3::zeros(),
            overlap: 0.0,
            normal_force: 0.0,
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            rolling: [0.0; 2],
        };
        st.contacts.clear();
        st.contacts.resize(n, blank);
        st.next_history.clear();
        st.next_history.resize(
            n,
            HistoryEntry {
                key: blank.key,
                index: 0,
                history: SmcHistory::default(),
            },
        );
        let ctx = ForceContext {
            bodies: &self.bodies,
            colliders: self.collision.colliders(),
            radius: &st.radius,
            alphas: &st.alphas,
            inv_mass: &st.inv_mass,
            inv_inertia: &st.inv_inertia,
            history: &st.history,
            settings: &self.settings.smc,
            rolling_model: self.settings.rolling_model,
            h,
        };
        self.points
            .par_iter()
            .zip(st.contacts.par_iter_mut())
            .zip(st.next_history.par_iter_mut())
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(i, ((cp, out), hist))| {
                let (c, history) = ctx.force(cp);
                *out = c;
                *hist = HistoryEntry {
                    key: cp.key,
                    index: i as u32,
                    history,
                };
            });
        st.next_history
            .par_sort_unstable_by(|a, b| a.key.cmp(&b.key).then(a.index.cmp(&b.index)));
        std::mem::swap(&mut st.history, &mut st.next_history);

        // Loads per body, in contact order (deterministic). The buffers are zero between
        // steps except after an error ([`SmcState::clear_loads`]): zeroing 100k bodies'
        // loads every step would cost more than the contacts.
        let nb = self.bodies.len();
        if st.touched_all || st.loads.len() != nb || st.rolling.len() != nb {
            st.loads.clear();
            st.loads.resize(nb, [Vector3::zeros(); 2]);
            st.rolling.clear();
            st.rolling.resize(nb, 0.0);
        }
        // Until `clear_loads` zeroes what this step adds.
        st.touched_all = true;
        for c in &st.contacts {
            if c.normal_force == 0.0 && c.force == Vector3::zeros() {
                continue;
            }
            let (a, b) = (c.owner_a as usize, c.owner_b as usize);
            let (xa, xb) = (self.bodies[a].position, self.bodies[b].position);
            st.loads[b][0] += c.force;
            st.loads[b][1] += (c.point - xb).cross(&c.force) + c.torque;
            st.loads[a][0] -= c.force;
            st.loads[a][1] -= (c.point - xa).cross(&c.force) + c.torque;
            st.rolling[a] += c.rolling[0];
            st.rolling[b] += c.rolling[1];
        }
        // Per-body rolling resistance: summed over the body's contacts, limited once.
        if self.settings.rolling_model == RollingModel::PerBody {
            for (i, b) in self.bodies.iter().enumerate() {
                if st.rolling[i] > 0.0 && st.inv_inertia[i] > 0.0 {
                    let w = b.angular_velocity();
                    st.loads[i][1] +=
                        smc::per_body_rolling_torque(&w, st.rolling[i], 1.0 / st.inv_inertia[i], h);
                }
            }
        }
    }

    /// New velocities and poses without rows, in one pass over the bodies that also
    /// writes the poses and activity the next step's collision detection reads
    /// ([`collision_state`](Self::collision_state)) and checks the new state: the first
    /// (in dense order) non-finite or too fast body, as [`check_state`](Self::check_state)
    /// finds it. Every body is updated even when one is bad (as before the fusion).
    fn smc_free_update(&mut self, h: f64) -> Option<usize> {
        let g = self.settings.gravity;
        let (vmax, wmax) = (self.settings.max_speed, self.settings.max_angular_speed);
        let n = self.bodies.len();
        self.poses.resize(n, nalgebra::Isometry3::identity());
        self.active.resize(n, false);
        let one = |(b, load): (&mut RigidBody, &[Vector3<f64>; 2])| -> bool {
            if b.motion == BodyMotion::Dynamic {
                let mut k = [0.0; 6];
                b.free_momentum(h, &g, load, &mut k);
                b.linear_velocity = Vector3::new(k[0], k[1], k[2]) / b.mass;
                b.angular_velocity = b.inv_inertia() * Vector3::new(k[3], k[4], k[5]);
            }
            if b.motion != BodyMotion::Fixed {
                b.integrate_pose(h);
            }
            is_bad(b, vmax, wmax)
        };
        let loads = &self.smc.loads[..n];
        let bad = if n >= PARALLEL_MIN_BODIES {
            // `min` of the bad indices, not `position_first`: that may stop early and
            // leave later bodies un-updated.
            (self.bodies.par_iter_mut())
                .zip(loads.par_iter())
                .zip(self.poses.par_iter_mut().zip(self.active.par_iter_mut()))
                .enumerate()
                .with_min_len(BODY_CHUNK)
                .filter_map(|(i, ((b, load), (pose, active)))| {
                    let bad = one((&mut *b, load));
                    *pose = b.pose();
                    *active = b.is_dynamic();
                    bad.then_some(i)
                })
                .min()
        } else {
            let mut first = None;
            let it = (self.bodies.iter_mut())
                .zip(loads)
                .zip(self.poses.iter_mut().zip(self.active.iter_mut()));
            for (i, ((b, load), (pose, active))) in it.enumerate() {
                if one((&mut *b, load)) && first.is_none() {
                    first = Some(i);
                }
                *pose = b.pose();
                *active = b.is_dynamic();
            }
            first
        };
        self.poses_fresh = true;
        bad
    }

    /// New velocities and poses with joints' and items' rows solved by the CCP solver.
    fn smc_rows_update(&mut self, h: f64) -> Result<StepReport> {
        let ctx = self.step_context(h);
        self.add_step_variables(&ctx)?;
        let ndof = self.vars.ndof();
        self.k.clear();
        self.k.resize(ndof, 0.0);
        super::step::free_momenta(
            &self.bodies,
            &self.smc.loads,
            &self.settings.gravity,
            h,
            &mut self.momentum,
        );
        for (b, k) in self.bodies.iter().zip(&self.momentum) {
            if let Some(blk) = b.block {
                self.k[self.vars.range(blk)].copy_from_slice(k);
            }
        }
        for item in &self.items {
            item.load_momentum(&ctx, &self.vars, &mut self.k);
        }
        self.rows.clear();
        for j in &mut self.joints {
            j.add_rows(&self.bodies, h, &mut self.rows);
        }
        for item in &mut self.items {
            item.add_constraints(&ctx, &self.vars, &mut self.rows)?;
            item.add_body_constraints(&ctx, &self.bodies, &self.vars, &mut self.rows)?;
        }
        self.problem.assemble(&self.vars, &self.rows, &self.k)?;
        let m = self.problem.n_rows();
        self.gamma.clear();
        self.gamma.resize(m, 0.0);
        let mut solve = Default::default();
        if m > 0 {
            if self.settings.warm_start {
                for j in &self.joints {
                    if j.impulses.len() == j.row_ids.len() {
                        for (id, g) in j.row_ids.iter().zip(&j.impulses) {
                            self.gamma[self.problem.row_index(*id)] = *g;
                        }
                    }
                }
            }
            solve = self.solver.solve(&self.problem, &mut self.gamma);
            if let Some(i) = self.gamma.iter().position(|g| !g.is_finite()) {
                return Err(ChronoError::NonFinite {
                    item: format!("CCP row {i}"),
                    step: self.step_count,
                    time: self.time,
                    what: format!("impulse from solver `{}`", self.solver.name()),
                });
            }
        }
        self.v.clear();
        self.v.resize(ndof, 0.0);
        self.problem.velocities(&self.gamma, &mut self.v);
        self.update_bodies(h);
        for item in &mut self.items {
            item.update(&ctx, &self.vars, &self.v, &self.problem, &self.gamma)?;
        }
        for j in &mut self.joints {
            j.impulses.clear();
            for id in &j.row_ids {
                j.impulses.push(self.gamma[self.problem.row_index(*id)]);
            }
        }
        Ok(StepReport {
            contacts: self.smc.contacts.len(),
            rows: m,
            solve,
            friction_passes: 0,
        })
    }

    /// Non-finite or diverging bodies are errors naming the body and the step.
    pub(crate) fn check_state(&self) -> Result<()> {
        match self.first_bad_body() {
            Some(i) => Err(self.state_error(i)),
            None => Ok(()),
        }
    }

    /// The first non-finite or too fast body in dense order, found in parallel for many
    /// bodies.
    fn first_bad_body(&self) -> Option<usize> {
        let (vmax, wmax) = (self.settings.max_speed, self.settings.max_angular_speed);
        let bad = |b: &RigidBody| is_bad(b, vmax, wmax);
        if self.bodies.len() >= PARALLEL_MIN_BODIES {
            (self.bodies.par_iter())
                .with_min_len(BODY_CHUNK)
                .position_first(bad)
        } else {
            self.bodies.iter().position(bad)
        }
    }

    /// The error for the bad body `i` ([`first_bad_body`](Self::first_bad_body)).
    fn state_error(&self, i: usize) -> ChronoError {
        let (vmax, wmax) = (self.settings.max_speed, self.settings.max_angular_speed);
        let b = &self.bodies[i];
        if !b.state_is_finite() {
            return ChronoError::NonFinite {
                item: format!("body {i} (\"{}\")", b.name),
                step: self.step_count,
                time: self.time,
                what: "position or velocity".into(),
            };
        }
        let (v, w) = (b.linear_velocity.norm(), b.angular_velocity.norm());
        ChronoError::Diverged {
            item: format!("body {i} (\"{}\")", b.name),
            step: self.step_count,
            time: self.time,
            what: format!(
                "speed {v:.3e} m/s (limit {vmax:.1e}), angular speed {w:.3e} rad/s (limit {wmax:.1e})"
            ),
        }
    }
}

/// A body whose state is not finite or faster than the limits (m/s, rad/s).
#[inline]
fn is_bad(b: &RigidBody, vmax: f64, wmax: f64) -> bool {
    !b.state_is_finite() || b.linear_velocity.norm() > vmax || b.angular_velocity.norm() > wmax
}

/// Everything the parallel force loop reads.
struct ForceContext<'a> {
    bodies: &'a [RigidBody],
    colliders: &'a [crate::collision::Collider],
    radius: &'a [f64],
    alphas: &'a [(u64, f64)],
    inv_mass: &'a [f64],
    inv_inertia: &'a [f64],
    history: &'a [HistoryEntry],
    settings: &'a SmcSettings,
    rolling_model: RollingModel,
    h: f64,
}

impl ForceContext<'_> {
    fn force(&self, cp: &ContactPoint) -> (SmcContact, SmcHistory) {
        let (a, b) = (cp.owner_a as usize, cp.owner_b as usize);
        let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
        let (ca, cb) = (cp.collider_a.0 as usize, cp.collider_b.0 as usize);
        let (ma, mb) = (self.colliders[ca].material(), self.colliders[cb].material());
        let r = harmonic(self.radius[ca], self.radius[cb]);
        let radius = if r.is_finite() {
            r
        } else {
            self.settings.flat_contact_radius
        };
        let e_bits = cp.material.restitution.to_bits();
        let alpha = match self.alphas.binary_search_by_key(&e_bits, |x| x.0) {
            Ok(i) => self.alphas[i].1,
            Err(_) => 0.0,
        };
        let point = 0.5 * (cp.point_a + cp.point_b);
        let rolling_inertia = if self.rolling_model == RollingModel::Spring {
            // 1/(I + m d^2) per body, 0 for a fixed or kinematic one.
            let inv = |k: usize, body: &RigidBody| {
                let (im, ii) = (self.inv_mass[k], self.inv_inertia[k]);
                if im > 0.0 {
                    im * ii / (im + (point - body.position).norm_squared() * ii)
                } else {
                    0.0
                }
            };
            1.0 / (inv(a, ba) + inv(b, bb))
        } else {
            0.0
        };
        let pair = SmcPair {
            radius,
            mass: 1.0 / (self.inv_mass[a] + self.inv_mass[b]),
            inertia: 1.0 / (self.inv_inertia[a] + self.inv_inertia[b]),
            rolling_inertia,
            young: effective_young_modulus(&ma, &mb),
            shear: effective_shear_modulus(&ma, &mb),
            alpha,
            friction: cp.material.friction,
            rolling_friction: cp.material.rolling_friction,
            spinning_friction: cp.material.spinning_friction,
            rolling_model: self.rolling_model,
            rolling_damping: self.settings.rolling_damping_ratio,
        };
        let kin = SmcKinematics {
            normal: cp.normal,
            overlap: -cp.distance,
            relative_velocity: bb.point_velocity(&point) - ba.point_velocity(&point),
            angular_velocity_a: ba.angular_velocity(),
            angular_velocity_b: bb.angular_velocity(),
        };
        let at = self.history.partition_point(|e| e.key < cp.key);
        let history = match self.history.get(at) {
            Some(e) if e.key == cp.key => e.history,
            _ => SmcHistory::default(),
        };
        let f = smc::contact_force(
            self.settings.model,
            &pair,
            self.settings.characteristic_velocity,
            &kin,
            &history,
            self.h,
        );
        (
            SmcContact {
                key: cp.key,
                owner_a: cp.owner_a,
                owner_b: cp.owner_b,
                point,
                normal: cp.normal,
                overlap: kin.overlap,
                normal_force: f.normal,
                force: f.force,
                torque: f.torque,
                rolling: f.rolling,
            },
            f.history,
        )
    }
}
