//! The [`System`]: bodies, joints, collision, contact, physics items, a CCP solver, and the
//! NSC time stepper ([`System::step`]).
//!
//! ```no_run
//! # fn solver() -> Box<dyn chrono_core::descriptor::CcpSolver> { unimplemented!() }
//! use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
//! use chrono_core::math::{Isometry3, Vector3};
//! let mut sys = System::new(SystemSettings::default(), solver()).unwrap();
//! let mat = ContactMaterial::with_friction(0.5);
//! sys.add_body(RigidBodyBuilder::fixed().collider(Shape::HalfSpace { normal: Vector3::z() }, Isometry3::identity(), mat)).unwrap();
//! let b = Shape::Box { half_extents: Vector3::new(0.5, 0.5, 0.5) };
//! let bx = sys.add_body(RigidBodyBuilder::dynamic().mass_from_shape(&b, 1000.0).unwrap()
//!     .position(Vector3::new(0.0, 0.0, 2.0)).collider(b, Isometry3::identity(), mat)).unwrap();
//! for _ in 0..100 { sys.step(0.01).unwrap(); }
//! println!("{}", sys.body(bx).unwrap().position());
//! ```

mod contact_forces;
mod coulomb;
mod remove;
mod smc_step;
mod step;

pub use contact_forces::{ContactForce, contact_forces};
pub use coulomb::FrictionLaw;

pub use smc_step::SmcTiming;

use nalgebra::Vector3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::bodies::Bodies;
use crate::body::{BodyHandle, RigidBody, RigidBodyBuilder};
use crate::collision::{CollisionProxy, CollisionWorld, ContactPoint, ProxyContact};
use crate::contact::nsc::{NscContact, NscProxyContact, TripletScratch, WarmStartCache};
pub use crate::contact::smc::{RollingModel, SmcModel, SmcSettings};
use crate::descriptor::{CcpProblem, CcpSolver, ConstraintRows, SolveStats, Variables};
use crate::error::{ChronoError, Result, check_finite3, check_non_negative, check_positive};
use crate::force::{BodyLoads, ForceElement, ForceHandle};
use crate::item::{ItemHandle, PhysicsItem, StepContext};
use crate::joint::{Joint, JointBuilder, JointHandle};
use crate::material::ContactFriction;
use crate::slots::SlotTable;

/// Below this many bodies the per-body loops of a step run serially (a vehicle's dozen
/// bodies would pay more for the rayon dispatch than for the work).
pub(crate) const PARALLEL_MIN_BODIES: usize = 1024;
/// Bodies per rayon task in the per-body loops.
pub(crate) const BODY_CHUNK: usize = 256;

/// How contacts act: by complementarity (impulses from the CCP) or by penalty forces.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactMethod {
    /// Non-smooth contact: friction cones in the CCP (Anitescu–Tasora).
    #[default]
    Nsc,
    /// Smooth contact: Hooke or Hertz–Mindlin penalty forces ([`crate::contact::smc`]).
    Smc,
}

/// Settings of a [`System`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SystemSettings {
    /// Gravity, m/s^2 (Z up).
    pub gravity: Vector3<f64>,
    /// Collision envelope `delta`, m: contacts enter the problem while the gap is below it.
    pub envelope: f64,
    /// Maximum speed at which penetration is recovered, m/s (Chrono's default 0.6).
    pub max_recovery_speed: f64,
    /// Warm-start the solver with the previous step's impulses (contacts by persistence key,
    /// joints by row).
    pub warm_start: bool,
    /// A body faster than this (m/s) means the simulation diverged: the step returns
    /// [`ChronoError::Diverged`] naming it.
    pub max_speed: f64,
    /// A body spinning faster than this (rad/s) means the simulation diverged.
    pub max_angular_speed: f64,
    /// NSC (default) or SMC contact; [`System::step`] dispatches on it.
    #[serde(default)]
    pub contact_method: ContactMethod,
    /// Settings of SMC contact (used when `contact_method` is `Smc`).
    #[serde(default)]
    pub smc: SmcSettings,
    /// Friction law of NSC contacts: the relaxed cone (default, one solve per step) or
    /// Coulomb's law by de Saxcé passes ([`FrictionLaw`]).
    #[serde(default)]
    pub friction_law: FrictionLaw,
    /// Which rotation rolling resistance opposes, for both methods: the relative rotation
    /// of the two bodies (default) or each body's own (Zhou et al. 1999); or, in SMC, an
    /// elastic-plastic spring on the relative rotation that holds a static moment (Ai et
    /// al. 2011, type C; NSC treats it as relative) ([`RollingModel`]).
    #[serde(default)]
    pub rolling_model: RollingModel,
}

impl Default for SystemSettings {
    fn default() -> Self {
        Self {
            gravity: crate::math::GRAVITY,
            envelope: 0.005,
            max_recovery_speed: 0.6,
            warm_start: true,
            max_speed: 1e4,
            max_angular_speed: 1e5,
            contact_method: ContactMethod::Nsc,
            smc: SmcSettings::default(),
            friction_law: FrictionLaw::Relaxed,
            rolling_model: RollingModel::Relative,
        }
    }
}

impl SystemSettings {
    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        check_finite3("settings.gravity", &self.gravity)?;
        check_non_negative("settings.envelope", self.envelope)?;
        check_positive("settings.max_recovery_speed", self.max_recovery_speed)?;
        check_positive("settings.max_speed", self.max_speed)?;
        check_positive("settings.max_angular_speed", self.max_angular_speed)?;
        self.smc.validate()?;
        self.friction_law.validate()?;
        Ok(())
    }
}

/// What one step did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepReport {
    /// Number of contact points in the problem.
    pub contacts: usize,
    /// Number of rows of the CCP.
    pub rows: usize,
    /// The solver's statistics (summed over the solves of the step).
    pub solve: SolveStats,
    /// Re-solves of [`FrictionLaw::Coulomb`] done in this step (0 for the relaxed law).
    pub friction_passes: usize,
}

/// A multibody system stepped by the NSC (complementarity) method.
///
/// # Handles and removal
///
/// Bodies, joints, force elements and physics items are named by generational handles
/// ([`BodyHandle`], [`JointHandle`], [`ForceHandle`], [`ItemHandle`]): a slot index and the
/// slot's generation. The values stay dense in memory ([`bodies`](Self::bodies) is a slice;
/// the solver and collision loops run over it), a slot table maps a handle to its position.
/// [`remove_body`](Self::remove_body), [`remove_bodies`](Self::remove_bodies),
/// [`remove_joint`](Self::remove_joint), [`remove_force_element`](Self::remove_force_element)
/// and [`remove_item`](Self::remove_item) swap-remove (the last value takes the freed
/// position, its handle stays valid) and bump the slot's generation: the removed handle is
/// stale, and using it is an error naming it ([`ChronoError::StaleBody`],
/// [`ChronoError::StaleJoint`], [`ChronoError::StaleForce`], [`ChronoError::StaleItem`]),
/// never another value, even after a new one reuses the slot.
///
/// Body removal costs O(1) for the bodies plus the caches keyed by body or collider: the
/// collision world is updated in place (the removed body's colliders leave, the last body's
/// take their place; see [`CollisionWorld::remove_owners`]), the warm-start impulses and
/// SMC tangential histories follow the new collider ids and drop the removed body's
/// contacts (so contacts in flight with it simply end; the others keep their warm start).
/// Joints and force elements cannot outlive their bodies: removing a body they refer to is
/// [`ChronoError::BodyInUse`] naming them (remove them first). A system from which bodies
/// were removed before any step steps bit-identically to one built without them in the
/// same order; removing, between steps, a body that touches nothing keeps the others'
/// steps bit-identical too when the dense order of the others does not change (the
/// removed body was the last one, or the last body took its place and was next to it).
pub struct System {
    pub(crate) settings: SystemSettings,
    pub(crate) bodies: Bodies,
    pub(crate) joints: Vec<Joint>,
    /// Joint handle -> index into `joints`.
    pub(crate) joint_slots: SlotTable,
    pub(crate) items: Vec<Box<dyn PhysicsItem>>,
    /// Item handle -> index into `items`.
    pub(crate) item_slots: SlotTable,
    pub(crate) force_elements: Vec<Box<dyn ForceElement>>,
    /// Force element handle -> index into `force_elements`.
    pub(crate) force_slots: SlotTable,
    pub(crate) collision: CollisionWorld,
    pub(crate) solver: Box<dyn CcpSolver>,
    pub(crate) time: f64,
    pub(crate) step_count: u64,
    // per-step buffers, reused
    pub(crate) vars: Variables,
    pub(crate) rows: ConstraintRows,
    pub(crate) problem: CcpProblem,
    pub(crate) k: Vec<f64>,
    pub(crate) v: Vec<f64>,
    pub(crate) gamma: Vec<f64>,
    pub(crate) points: Vec<ContactPoint>,
    pub(crate) contacts: Vec<NscContact>,
    pub(crate) proxies: Vec<CollisionProxy>,
    pub(crate) proxy_points: Vec<ProxyContact>,
    pub(crate) proxy_contacts: Vec<NscProxyContact>,
    pub(crate) triplet: TripletScratch,
    pub(crate) cache: WarmStartCache,
    pub(crate) poses: Vec<nalgebra::Isometry3<f64>>,
    /// Per body: `k = M v + h f` of the step (zeros for bodies without variables).
    pub(crate) momentum: Vec<[f64; 6]>,
    pub(crate) active: Vec<bool>,
    /// `poses` and `active` hold the bodies' current state: written by the fused SMC body
    /// pass, cleared by every path that can change a body (`body_mut`, additions,
    /// removals, the NSC update), so [`collision_state`](Self::collision_state) can skip
    /// its pass over the bodies.
    pub(crate) poses_fresh: bool,
    /// `loads` is the all-zero load of the current body set (no force elements, no
    /// joints): [`gather_loads`](Self::gather_loads) need not rebuild it.
    pub(crate) loads_zero: bool,
    pub(crate) smc: smc_step::SmcState,
    /// Loads of force elements and joint efforts of the current step.
    pub(crate) loads: BodyLoads,
    /// Per-body friction overrides ([`System::set_contact_friction`]), indexed by body.
    pub(crate) contact_friction: Vec<Option<ContactFriction>>,
    /// Normal-bias shifts of the de Saxcé passes, per cone block (friction, then rolling).
    pub(crate) coulomb_shift: Vec<f64>,
    pub(crate) coulomb_next: Vec<f64>,
}

impl System {
    /// A new empty system with the given settings and CCP solver (e.g. from `chrono-ccp`).
    pub fn new(settings: SystemSettings, solver: Box<dyn CcpSolver>) -> Result<Self> {
        settings.validate()?;
        let collision = CollisionWorld::new(settings.envelope)?;
        Ok(Self {
            settings,
            bodies: Bodies::new(),
            joints: Vec::new(),
            joint_slots: SlotTable::default(),
            items: Vec::new(),
            item_slots: SlotTable::default(),
            force_elements: Vec::new(),
            force_slots: SlotTable::default(),
            collision,
            solver,
            time: 0.0,
            step_count: 0,
            vars: Variables::new(),
            rows: ConstraintRows::new(),
            problem: CcpProblem::new(),
            k: Vec::new(),
            v: Vec::new(),
            gamma: Vec::new(),
            points: Vec::new(),
            contacts: Vec::new(),
            proxies: Vec::new(),
            proxy_points: Vec::new(),
            proxy_contacts: Vec::new(),
            triplet: TripletScratch::default(),
            cache: WarmStartCache::default(),
            poses: Vec::new(),
            momentum: Vec::new(),
            active: Vec::new(),
            poses_fresh: false,
            loads_zero: false,
            smc: smc_step::SmcState::default(),
            loads: BodyLoads::default(),
            contact_friction: Vec::new(),
            coulomb_shift: Vec::new(),
            coulomb_next: Vec::new(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &SystemSettings {
        &self.settings
    }

    /// Change the settings (validated).
    pub fn set_settings(&mut self, settings: SystemSettings) -> Result<()> {
        settings.validate()?;
        self.collision.set_envelope(settings.envelope)?;
        self.settings = settings;
        Ok(())
    }

    /// The solver.
    pub fn solver(&self) -> &dyn CcpSolver {
        self.solver.as_ref()
    }

    /// The solver, mutable (to change its settings).
    pub fn solver_mut(&mut self) -> &mut dyn CcpSolver {
        self.solver.as_mut()
    }

    /// Replace the solver.
    pub fn set_solver(&mut self, solver: Box<dyn CcpSolver>) {
        self.solver = solver;
    }

    /// Add a body (checked by its builder) and its colliders.
    pub fn add_body(&mut self, builder: RigidBodyBuilder) -> Result<BodyHandle> {
        let body = builder.build()?;
        // Colliders are owned by the body's dense index (its position in `bodies()`).
        let owner = self.bodies.len() as u32;
        for c in body.colliders() {
            self.collision
                .add_collider(owner, &c.shape, c.local_pose, c.material)?;
        }
        self.poses_fresh = false;
        self.loads_zero = false;
        Ok(self.bodies.insert(body))
    }

    /// Make every contact of `body` with another body use the friction coefficients
    /// `friction` instead of the minimum of the two colliders' ([`ContactMaterial::combine`](crate::ContactMaterial::combine);
    /// `None` restores it). Where both bodies of a contact carry one, their minimum applies.
    /// Applies to body–body contacts by both methods (NSC cones and SMC forces), not to the
    /// contacts of physics items' proxies. For walls rougher than the grains they hold
    /// (grain–wall friction above grain–grain friction, Zhou et al., Powder Technol. 125,
    /// 2002); see [`ContactFriction`].
    pub fn set_contact_friction(
        &mut self,
        body: BodyHandle,
        friction: Option<ContactFriction>,
    ) -> Result<()> {
        let i = self.bodies.try_index(body)?;
        if let Some(f) = &friction {
            f.validate()?;
        }
        if self.contact_friction.len() <= i {
            self.contact_friction.resize(i + 1, None);
        }
        self.contact_friction[i] = friction;
        Ok(())
    }

    /// The friction override of `body`, if any ([`System::set_contact_friction`]).
    pub fn contact_friction(&self, body: BodyHandle) -> Option<ContactFriction> {
        let i = self.bodies.dense_index(body)?;
        self.contact_friction.get(i).copied().flatten()
    }

    /// Write the per-body friction overrides into this step's contact points.
    pub(crate) fn apply_contact_friction(&mut self) {
        if self.contact_friction.iter().all(Option::is_none) {
            return;
        }
        let get = |i: u32| self.contact_friction.get(i as usize).copied().flatten();
        for cp in &mut self.points {
            let f = match (get(cp.owner_a), get(cp.owner_b)) {
                (None, None) => continue,
                (Some(f), None) | (None, Some(f)) => f,
                (Some(a), Some(b)) => a.min(&b),
            };
            f.apply(&mut cp.material);
        }
    }

    /// Add a joint; an error if it names a body that is not in the system or has bad
    /// parameters. Contacts between the two bodies are disabled (they are joined).
    pub fn add_joint(&mut self, builder: JointBuilder) -> Result<JointHandle> {
        let joint = builder.build(&self.bodies)?;
        let (a, b) = joint.bodies();
        let (a, b) = (self.bodies.try_index(a)?, self.bodies.try_index(b)?);
        self.collision.exclude_pair(a as u32, b as u32);
        let (index, generation) = self.joint_slots.insert();
        self.joints.push(joint);
        Ok(JointHandle::new(index, generation))
    }

    /// Add a physics item of a domain crate; its handle.
    pub fn add_item(&mut self, item: Box<dyn PhysicsItem>) -> ItemHandle {
        let (index, generation) = self.item_slots.insert();
        self.items.push(item);
        ItemHandle::new(index, generation)
    }

    /// Add a force element (spring-damper, tire, drag ...): it is checked against the bodies
    /// ([`ForceElement::attach`]) and evaluated at the start of every step.
    pub fn add_force_element(&mut self, mut element: Box<dyn ForceElement>) -> Result<ForceHandle> {
        element.attach(&self.bodies)?;
        let (index, generation) = self.force_slots.insert();
        self.force_elements.push(element);
        Ok(ForceHandle::new(index, generation))
    }

    /// The force element `h` with its type, or `None` if the handle is stale or the type
    /// is wrong.
    pub fn force_element<T: ForceElement>(&self, h: ForceHandle) -> Option<&T> {
        let i = self.force_slots.resolve(h.index(), h.generation())?;
        let e: &dyn std::any::Any = self.force_elements[i].as_ref();
        e.downcast_ref::<T>()
    }

    /// The force element `h` with its type, mutably (to change a setting between steps).
    pub fn force_element_mut<T: ForceElement>(&mut self, h: ForceHandle) -> Option<&mut T> {
        let i = self.force_slots.resolve(h.index(), h.generation())?;
        let e: &mut dyn std::any::Any = self.force_elements[i].as_mut();
        e.downcast_mut::<T>()
    }

    /// The handles of all force elements, in the order they are evaluated in.
    pub fn force_handles(&self) -> impl ExactSizeIterator<Item = ForceHandle> + '_ {
        (0..self.force_elements.len()).map(|i| {
            let (index, generation) = self.force_slots.handle_at(i);
            ForceHandle::new(index, generation)
        })
    }

    /// The loads of the force elements and joint efforts of the last step, per body.
    pub fn element_loads(&self) -> &BodyLoads {
        &self.loads
    }

    /// Evaluate the force elements and the joint efforts at the current state into
    /// `self.loads`, then advance the explicit items over the step
    /// ([`PhysicsItem::advance_explicit`]), which add their mean loads. A non-finite load is an error naming the element and the step.
    pub(crate) fn gather_loads(&mut self, ctx: &StepContext) -> Result<()> {
        let explicit = self.items.iter().any(|i| i.exchanges_body_loads());
        if self.force_elements.is_empty() && self.joints.is_empty() && !explicit {
            // Nothing adds loads: zero, kept from the last step while the bodies stay.
            if !self.loads_zero {
                self.loads.reset_zero(&self.bodies);
                self.loads_zero = true;
            }
            return Ok(());
        }
        self.loads_zero = false;
        self.loads.reset(&self.bodies);
        for e in &mut self.force_elements {
            e.evaluate(ctx, &self.bodies, &mut self.loads)?;
            if let Some(i) =
                self.loads.as_slice().iter().position(|l| {
                    !(crate::math::is_finite3(&l[0]) && crate::math::is_finite3(&l[1]))
                })
            {
                return Err(ChronoError::NonFinite {
                    item: format!("force element \"{}\"", e.name()),
                    step: self.step_count,
                    time: self.time,
                    what: format!("load on body {i}"),
                });
            }
        }
        for j in &self.joints {
            if let Some(load) = j.effort(&self.bodies) {
                let (ha, hb) = j.bodies();
                self.loads.add_force_at(hb, &load.force, &load.point_b);
                self.loads.add_torque(hb, &load.torque);
                self.loads.add_force_at(ha, &(-load.force), &load.point_a);
                self.loads.add_torque(ha, &(-load.torque));
            }
        }
        if explicit {
            for item in &mut self.items {
                if !item.exchanges_body_loads() {
                    continue;
                }
                item.advance_explicit(ctx, &self.bodies, &mut self.loads)?;
                if let Some(i) = self.loads.as_slice().iter().position(|l| {
                    !(crate::math::is_finite3(&l[0]) && crate::math::is_finite3(&l[1]))
                }) {
                    return Err(ChronoError::NonFinite {
                        item: format!("item \"{}\"", item.name()),
                        step: self.step_count,
                        time: self.time,
                        what: format!("load on body {i}"),
                    });
                }
            }
        }
        Ok(())
    }

    /// A body; [`ChronoError::StaleBody`] if `h` was removed or is not from this system.
    pub fn body(&self, h: BodyHandle) -> Result<&RigidBody> {
        self.bodies
            .get(h)
            .ok_or(ChronoError::StaleBody { handle: h })
    }

    /// A body, mutable (to set forces or prescribed velocities between steps).
    pub fn body_mut(&mut self, h: BodyHandle) -> Result<&mut RigidBody> {
        // The caller may move the body: the cached poses are stale.
        self.poses_fresh = false;
        self.bodies
            .get_mut(h)
            .ok_or(ChronoError::StaleBody { handle: h })
    }

    /// All bodies, in dense order: the order they were added in, except that removing a
    /// body moves the last one into its place ([`remove_body`](Self::remove_body)).
    pub fn bodies(&self) -> &[RigidBody] {
        &self.bodies
    }

    /// The bodies with their handles ([`Bodies`]: `handles()`, `iter_with_handles()`,
    /// `dense_index(h)`).
    pub fn body_set(&self) -> &Bodies {
        &self.bodies
    }

    /// The handles of all bodies, in the order of [`bodies`](Self::bodies).
    pub fn body_handles(&self) -> impl ExactSizeIterator<Item = BodyHandle> + '_ {
        self.bodies.handles()
    }

    /// A joint; [`ChronoError::StaleJoint`] if `h` was removed or is not from this system.
    pub fn joint(&self, h: JointHandle) -> Result<&Joint> {
        let i = (self.joint_slots)
            .resolve(h.index(), h.generation())
            .ok_or(ChronoError::StaleJoint { handle: h })?;
        Ok(&self.joints[i])
    }

    /// A joint, mutable (to change a drive).
    pub fn joint_mut(&mut self, h: JointHandle) -> Result<&mut Joint> {
        let i = (self.joint_slots)
            .resolve(h.index(), h.generation())
            .ok_or(ChronoError::StaleJoint { handle: h })?;
        Ok(&mut self.joints[i])
    }

    /// The handles of all joints, in the order of [`joints`](Self::joints).
    pub fn joint_handles(&self) -> impl ExactSizeIterator<Item = JointHandle> + '_ {
        (0..self.joints.len()).map(|i| {
            let (index, generation) = self.joint_slots.handle_at(i);
            JointHandle::new(index, generation)
        })
    }

    /// All joints, in dense order (removing one moves the last into its place).
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The physics items.
    pub fn items(&self) -> &[Box<dyn PhysicsItem>] {
        &self.items
    }

    /// The item `h` (as returned by [`add_item`](Self::add_item)) as its concrete type `T`;
    /// `None` if the handle is stale or the item is not a `T`.
    pub fn item<T: PhysicsItem>(&self, h: ItemHandle) -> Option<&T> {
        let i = self.item_slots.resolve(h.index(), h.generation())?;
        let item: &dyn std::any::Any = self.items[i].as_ref();
        item.downcast_ref::<T>()
    }

    /// The item `h` as its concrete type `T`, mutable (to change its state between steps).
    pub fn item_mut<T: PhysicsItem>(&mut self, h: ItemHandle) -> Option<&mut T> {
        let i = self.item_slots.resolve(h.index(), h.generation())?;
        let item: &mut dyn std::any::Any = self.items[i].as_mut();
        item.downcast_mut::<T>()
    }

    /// The handles of all items, in the order of [`items`](Self::items).
    pub fn item_handles(&self) -> impl ExactSizeIterator<Item = ItemHandle> + '_ {
        (0..self.items.len()).map(|i| {
            let (index, generation) = self.item_slots.handle_at(i);
            ItemHandle::new(index, generation)
        })
    }

    /// The collision world.
    pub fn collision(&self) -> &CollisionWorld {
        &self.collision
    }

    /// The contacts of the last step.
    pub fn contacts(&self) -> &[NscContact] {
        &self.contacts
    }

    /// The contacts of the last step between body colliders and items' collision proxies.
    pub fn proxy_contacts(&self) -> &[NscProxyContact] {
        &self.proxy_contacts
    }

    /// The CCP of the last step (for inspection, capture, or solver experiments).
    pub fn last_problem(&self) -> &CcpProblem {
        &self.problem
    }

    /// The solution of the last step's CCP.
    pub fn last_gamma(&self) -> &[f64] {
        &self.gamma
    }

    /// Simulation time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Number of steps taken.
    pub fn step_count(&self) -> u64 {
        self.step_count
    }

    /// Largest position-level violation over all joints.
    pub fn max_joint_violation(&self) -> f64 {
        self.joints
            .iter()
            .map(|j| j.violation(&self.bodies))
            .fold(0.0, f64::max)
    }

    /// The bodies' poses and activity (dynamic or not) for this step's collision
    /// detection, into `self.poses` and `self.active` (in parallel for many bodies).
    pub(crate) fn collision_state(&mut self) {
        if self.poses_fresh && self.poses.len() == self.bodies.len() {
            return;
        }
        self.poses.clear();
        self.active.clear();
        if self.bodies.len() >= PARALLEL_MIN_BODIES {
            self.poses
                .par_extend(self.bodies.par_iter().map(RigidBody::pose));
            (self.active).par_extend(self.bodies.par_iter().map(RigidBody::is_dynamic));
        } else {
            self.poses.extend(self.bodies.iter().map(RigidBody::pose));
            self.active
                .extend(self.bodies.iter().map(RigidBody::is_dynamic));
        }
    }

    /// Total kinetic energy of the dynamic bodies, J.
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|b| b.is_dynamic())
            .map(|b| b.kinetic_energy())
            .sum()
    }
}
