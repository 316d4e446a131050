//! How domain crates plug into a [`System`](crate::system::System).
//!
//! A [`PhysicsItem`] (a fluid container, an MPM body, an FEA mesh ...) brings its own
//! variable blocks, forces, constraint rows and state update; the system puts them into
//! the same CCP as the rigid bodies, joints and contacts. A [`Contactable`] is anything a
//! contact point can sit on: it provides the Jacobian of the velocity of a world point.

use nalgebra::Vector3;

use crate::bodies::Bodies;
use crate::collision::CollisionProxy;
use crate::descriptor::{BlockId, CcpProblem, ConstraintRows, Variables};
use crate::error::Result;
use crate::force::BodyLoads;

/// The callback of a contact Jacobian: `entry(block, rows)` with `rows[k]` the
/// coefficients of direction `k` on that block (see [`Contactable::contact_jacobian`]).
pub type JacobianSink<'a> = dyn FnMut(BlockId, [&[f64]; 3]) + 'a;

/// What an item needs to know about the current step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepContext {
    /// Step size, s.
    pub h: f64,
    /// Time at the start of the step, s.
    pub time: f64,
    /// Index of the step (0-based).
    pub step: u64,
    /// Gravity, m/s^2.
    pub gravity: Vector3<f64>,
}

/// Handle of a physics item in a [`System`](crate::system::System) (slot index and
/// generation, like [`BodyHandle`](crate::BodyHandle)): stale once the item is removed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ItemHandle {
    index: u32,
    generation: u32,
}

crate::slots::generational_handle!(ItemHandle, "item");

/// A physics item of a domain crate, stepped inside the system's NSC step.
///
/// Items are `Any`, so the owner of a [`System`](crate::system::System) reads its item
/// back with its type: [`System::item`](crate::system::System::item).
///
/// Call order each step (NSC): [`begin_step`](Self::begin_step),
/// [`add_variables`](Self::add_variables), [`advance_explicit`](Self::advance_explicit)
/// (explicit items only, while the body loads are gathered),
/// [`load_momentum`](Self::load_momentum), [`collision_proxies`](Self::collision_proxies)
/// (the system finds their contacts with the body colliders and builds friction rows whose
/// item side comes from [`proxy_jacobian`](Self::proxy_jacobian)),
/// [`add_constraints`](Self::add_constraints),
/// [`add_body_constraints`](Self::add_body_constraints), [`warm_start`](Self::warm_start)
/// (NSC step, warm start on), (solve), [`update`](Self::update).
pub trait PhysicsItem: std::any::Any + Send + Sync {
    /// A name for messages ("fluid", "tire mesh" ...).
    fn name(&self) -> &str;

    /// Prepare the step before any block is added: e.g. an implicit item assembles and
    /// factorizes its iteration matrix `M + h R + h^2 K` at `q(l)` here, because its
    /// coupled mass operator depends on `h`. An error (a matrix that is not positive
    /// definite) aborts the step. Default: nothing.
    fn begin_step(&mut self, _ctx: &StepContext) -> Result<()> {
        Ok(())
    }

    /// Whether this item is *explicit* and exchanges forces with rigid bodies through
    /// [`advance_explicit`](Self::advance_explicit) (an SPH fluid carrying BCE markers on
    /// bodies). Default: `false`. The system then evaluates the body loads every step
    /// (it would otherwise skip them when no force element or joint exists).
    fn exchanges_body_loads(&self) -> bool {
        false
    }

    /// Advance an explicit item over the whole step `[t, t + h]` with its own sub-steps
    /// (the bodies, read-only, at `q(l)`, `v(l)`: the item predicts their motion over the
    /// step), and add into `loads` the mean force and torque it put on each body,
    /// `F = J / h`, `T = L / h`, where `J` and `L` are the linear and angular (about the
    /// body's center of mass) impulses summed over the sub-steps. The multibody step then
    /// adds `h F = J` to the body's momentum `k = M v + h f` (explicit, staggered
    /// coupling: the body sees the fluid impulse of `[t, t + h]`, the fluid saw the body
    /// move with `v(l)`). Called at the start of the step, once, after the force elements
    /// and joint efforts, by both the NSC and the SMC steppers; only for items whose
    /// [`exchanges_body_loads`](Self::exchanges_body_loads) is `true`. An error (a
    /// diverged sub-step) aborts the step. Default: nothing.
    fn advance_explicit(
        &mut self,
        _ctx: &StepContext,
        _bodies: &Bodies,
        _loads: &mut BodyLoads,
    ) -> Result<()> {
        Ok(())
    }

    /// Append this item's variable blocks (remember their ids for the other calls).
    fn add_variables(&mut self, vars: &mut Variables);

    /// Add `M v + h f` for the item's blocks into `k` (applied and internal forces: gravity,
    /// elasticity, pressure ...).
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]);

    /// Append the spheres and thick triangles this item exposes to the body colliders
    /// (particles, beam nodes, shell or tet faces), at the positions of the start of the
    /// step. Default: none. An item that returns proxies must implement
    /// [`proxy_jacobian`](Self::proxy_jacobian).
    fn collision_proxies(&self, _out: &mut Vec<CollisionProxy>) {}

    /// The [`Contactable`] Jacobian of the proxy with id `proxy` at world point `p` along
    /// `dirs` (see [`Contactable::contact_jacobian`]): a particle gives its block with
    /// `d`, a triangle its three nodes with `N_i(p) d` (barycentric weights). `vars` is the
    /// layout of this step (after [`add_variables`](Self::add_variables)). Returns the
    /// known velocity along each direction (a proxy moving with a prescribed motion).
    /// Default: no variables and no known velocity (a fixed proxy).
    fn proxy_jacobian(
        &self,
        _proxy: u32,
        _p: &Vector3<f64>,
        _dirs: &[Vector3<f64>; 3],
        _entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        [0.0; 3]
    }

    /// Add the item's own rows (density, element, internal links). Default: none.
    fn add_constraints(
        &mut self,
        _ctx: &StepContext,
        _vars: &Variables,
        _rows: &mut ConstraintRows,
    ) -> Result<()> {
        Ok(())
    }

    /// Add rows that tie the item to rigid bodies (a node attached to a body or to a fixed
    /// point): `bodies` are the system's bodies at `q(l)`, with their variable blocks for
    /// this step (use [`Contactable::contact_jacobian`] for a body's side of a row; fixed
    /// and kinematic bodies have no block and report their known velocity). Called after
    /// [`add_constraints`](Self::add_constraints). Default: none.
    fn add_body_constraints(
        &mut self,
        _ctx: &StepContext,
        _bodies: &Bodies,
        _vars: &Variables,
        _rows: &mut ConstraintRows,
    ) -> Result<()> {
        Ok(())
    }

    /// Write the warm start of the rows this item pushed in
    /// [`add_constraints`](Self::add_constraints) this step into `gamma` (map them with
    /// [`CcpProblem::row_index`]), e.g. its impulses of the last step. Called after
    /// assembly and before the solve, only when the system's `warm_start` is on.
    /// Default: nothing (the item's rows start from zero).
    fn warm_start(&self, _problem: &CcpProblem, _gamma: &mut [f64]) {}

    /// Take the new velocities `v` (all dof of the step; the item reads its blocks) and the
    /// solution `gamma` of `problem`, and advance positions and internal state by `h`.
    /// Return [`ChronoError::NonFinite`](crate::ChronoError::NonFinite) naming the item if
    /// its state is no longer finite.
    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
    ) -> Result<()>;
}

/// Anything a contact point can sit on.
pub trait Contactable {
    /// Jacobian of `d . (velocity of the material point at world point p)` for each of the
    /// three directions `dirs` (contact normal and tangents): calls `entry(block, rows)` once
    /// per variable block touched, with `rows[k]` the coefficients for `dirs[k]` (length =
    /// the block's ndof). A rigid body gives one block `[d; r_b x R'd]`, a particle `d`,
    /// an FE triangle its three nodes weighted by the shape functions.
    /// Returns the known part of the velocity (e.g. of a kinematic body) along each direction.
    fn contact_jacobian(
        &self,
        p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3];
}

impl Contactable for crate::body::RigidBody {
    fn contact_jacobian(
        &self,
        p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        let j = self.point_jacobians(p, dirs);
        match self.block {
            Some(block) => {
                entry(block, [&j[0], &j[1], &j[2]]);
                [0.0; 3]
            }
            None => j.map(|jk| self.jacobian_times_velocity(&jk)),
        }
    }
}
