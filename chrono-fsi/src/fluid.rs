//! [`SphFluid`]: an explicit WCSPH fluid as a [`PhysicsItem`] of a chrono-core
//! [`System`](chrono_core::System), two-way coupled to rigid bodies through BCE markers.
//!
//! # The coupling (explicit, staggered)
//!
//! At the start of each system step `[t, t + h]` (from
//! [`PhysicsItem::advance_explicit`]):
//!
//! 1. each coupled body's markers get the motion the body has at `t`, advanced with its
//!    velocity: `x_c(s) = x(t) + (s - t) v(t)`, `R(s) = exp((s - t) [w(t)]) R(t)`; the
//!    marker velocity is the rigid motion `v + w x r`, its acceleration in the pressure
//!    extrapolation `(g - a_w)` the centripetal `w x (w x r)` only: the body's
//!    acceleration is not known before its step, and a lagged estimate fed back through
//!    the marker pressures acts as an explicit added mass (unstable for light bodies);
//! 2. the fluid advances to `t + h` exactly, by as many sub-steps as its own stability
//!    limits need (CFL, force, viscous; the last sub-step shortened,
//!    [`SphSystem::advance_exactly`]); the markers move at every sub-step;
//! 3. the impulse of the fluid on each body's markers over the sub-steps,
//!    `J = sum_n dt_n (F_n + F_(n+1)) / 2` (the same forces the fluid's kick-drift-kick
//!    kicks use, with opposite sign: fluid plus body momentum is conserved to round-off),
//!    and the angular impulse about the centre of mass, enter the body's momentum as the
//!    mean load `J / h` over the multibody step.
//!
//! The body then moves with its new velocity `v(t + h)`, so the markers of the next step
//! start from the body's actual pose: between steps they jump by `h (v(t+h) - v(t))`.
//!
//! **Stability.** The body's velocity is frozen over a step while the fluid reacts to it,
//! and the fluid's reaction (an added mass `m_a`) reaches the body one step late: the
//! classic added-mass instability of staggered coupling, softened here because the weakly
//! compressible fluid answers a velocity jump over the acoustic time `D / c_s`, not at
//! once. Measured (`examples/coupling_stability.rs`: a sphere of diameter `D = 0.14 m`
//! moving through a periodic box, `c_s = 10 m/s`, `D / c_s = 14 ms`, fluid sub-step
//! `dt = 0.5 ms`; multibody step `h = k dt`):
//!
//! ```text
//! m_a/m (ratio rho_b/rho)   k = 1   4      16       64
//! 0.5   (1)                 ok      ok     ok       ok
//! 1     (0.5)               ok      ok     ok       ok
//! 2.5   (0.2)               ok      ok     ok       diverged
//! 5     (0.1)               ok      ok     ok       diverged
//! 10    (0.05)              ok      ok     diverged diverged
//! ```
//!
//! i.e. stable while about `(m_a / m) h c_s / D < 3`; one or a few fluid sub-steps per
//! multibody step are stable for every density ratio tried.
//!
//! **ANCF cables** ([`crate::cable`]) coupled to the fluid are owned by the fluid item
//! (the system gives an item no access to another): their markers are placed from the
//! nodal coordinates and velocities at `t` and move with constant velocity over the step
//! (a point carrier of chrono-sph), and the markers' impulses over the sub-steps, mapped to
//! the nodal coordinates with the shape-function weights, enter the cable's implicit step
//! as the mean generalized load `Q = J / h` (added to the cable's momentum `h Q` in
//! [`load_momentum`](PhysicsItem::load_momentum)). The item forwards every other call
//! (variables, rows, contact proxies, update) to its cables.
//!
//! Fixed and kinematic bodies carry markers too (their loads are computed and reported,
//! [`SphFluid::body_load`], and dropped by the stepper): a body with a prescribed motion is
//! a moving wall.

use chrono_core::bodies::Bodies;
use chrono_core::collision::CollisionProxy;
use chrono_core::descriptor::{BlockId, CcpProblem, ConstraintRows, Variables};
use chrono_core::force::BodyLoads;
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::math::Vector3;
use chrono_core::{BodyHandle, ChronoError};
use chrono_fea::CableItem;
use chrono_sph::{RigidMotion, SphSystem};

use crate::cable::CableMarkers;

/// Bits of a contact proxy id below the cable index (see
/// [`SphFluid::collision_proxies`](PhysicsItem::collision_proxies)).
const PROXY_BITS: u32 = 24;

/// An ANCF cable coupled to the fluid, owned by the fluid item.
#[derive(Debug)]
pub(crate) struct CoupledCable {
    pub item: CableItem,
    pub markers: CableMarkers,
    /// The point carrier index in the SPH system.
    pub carrier: usize,
    /// Scratch: marker positions, velocities and impulses.
    pub x: Vec<[f64; 3]>,
    pub v: Vec<[f64; 3]>,
    pub impulse: Vec<[f64; 3]>,
    /// The mean generalized load of the last step (6 per node).
    pub load: Vec<f64>,
    /// The mean force of the fluid on the cable over the last step, N.
    pub force: Vector3<f64>,
    /// The mean force on each marker over the last step, N.
    pub marker_force: Vec<[f64; 3]>,
    /// The cable's variable block of this step.
    pub block: Option<BlockId>,
}

impl CoupledCable {
    pub fn new(item: CableItem, markers: CableMarkers, carrier: usize) -> Self {
        let n = markers.len();
        let ndof = item.mesh().ndof();
        Self {
            item,
            markers,
            carrier,
            x: vec![[0.0; 3]; n],
            v: vec![[0.0; 3]; n],
            impulse: vec![[0.0; 3]; n],
            load: vec![0.0; ndof],
            force: Vector3::zeros(),
            marker_force: vec![[0.0; 3]; n],
            block: None,
        }
    }

    /// Places the markers at the cable's state (positions into `x`, velocities into `v`).
    pub fn place(&mut self) -> crate::Result<()> {
        let item = &self.item;
        self.markers.place(
            chrono_core::item::PhysicsItem::name(item),
            item.mesh(),
            |n| {
                item.node_velocity(n)
                    .unwrap_or((Vector3::zeros(), Vector3::zeros()))
            },
            &mut self.x,
            &mut self.v,
        )
    }
}

/// A body coupled to the fluid.
#[derive(Debug, Clone)]
pub(crate) struct Coupled {
    pub handle: BodyHandle,
    pub name: String,
    /// The carrier index in the SPH system.
    pub carrier: usize,
    /// Markers of the body.
    pub markers: usize,
    /// The mean force and torque (world, about the centre of mass) of the last step.
    pub load: [Vector3<f64>; 2],
}

/// An SPH fluid coupled to rigid bodies (see the [module docs](self)); build one with
/// [`FsiBuilder`](crate::FsiBuilder) and add it with
/// [`System::add_item`](chrono_core::System::add_item).
#[derive(Debug)]
pub struct SphFluid {
    pub(crate) name: String,
    pub(crate) sph: SphSystem,
    pub(crate) bodies: Vec<Coupled>,
    pub(crate) cables: Vec<CoupledCable>,
    last_substeps: u64,
    substeps: u64,
    /// Wall time inside [`SphSystem::advance_exactly`] so far, s.
    advance_time: f64,
    /// Wall time of the item's explicit phase so far (marker placement, the fluid's
    /// advance, impulse gathering and the cables' nodal loads), s.
    explicit_time: f64,
}

impl SphFluid {
    pub(crate) fn new(
        name: String,
        sph: SphSystem,
        bodies: Vec<Coupled>,
        cables: Vec<CoupledCable>,
    ) -> Self {
        Self {
            name,
            sph,
            bodies,
            cables,
            last_substeps: 0,
            substeps: 0,
            advance_time: 0.0,
            explicit_time: 0.0,
        }
    }

    /// The SPH system (particles, probes, VTK output).
    pub fn sph(&self) -> &SphSystem {
        &self.sph
    }

    /// The SPH system, mutable (e.g. to damp a start-up: [`SphSystem::set_damping`]).
    pub fn sph_mut(&mut self) -> &mut SphSystem {
        &mut self.sph
    }

    /// Fluid sub-steps of the last system step.
    pub fn last_substeps(&self) -> u64 {
        self.last_substeps
    }

    /// Fluid sub-steps so far.
    pub fn substeps(&self) -> u64 {
        self.substeps
    }

    /// Wall time (s) spent so far in the fluid's own advance
    /// ([`SphSystem::advance_exactly`], the markers' motion and force gathering at each
    /// sub-step included: [`chrono_sph::Timings::markers`]).
    pub fn advance_wall_time(&self) -> f64 {
        self.advance_time
    }

    /// Wall time (s) spent so far in the item's explicit phase: placing the bodies' and
    /// cables' markers for the step, the fluid's advance
    /// ([`advance_wall_time`](Self::advance_wall_time)), and turning the markers'
    /// impulses into body loads and the cables' nodal loads. The difference to the
    /// advance is the coupling's own work at each multibody step.
    pub fn explicit_wall_time(&self) -> f64 {
        self.explicit_time
    }

    /// Number of markers on `body` (0 if the body is not coupled).
    pub fn markers_of(&self, body: BodyHandle) -> usize {
        (self.bodies.iter())
            .find(|c| c.handle == body)
            .map_or(0, |c| c.markers)
    }

    /// The mean fluid force (world, N) and torque about the centre of mass (world, N m) on
    /// `body` over the last system step; `None` if the body is not coupled.
    pub fn body_load(&self, body: BodyHandle) -> Option<[Vector3<f64>; 2]> {
        (self.bodies.iter())
            .find(|c| c.handle == body)
            .map(|c| c.load)
    }

    /// Number of coupled cables.
    pub fn num_cables(&self) -> usize {
        self.cables.len()
    }

    /// Cable `k` (in the order of [`FsiBuilder::add_cable`](crate::FsiBuilder::add_cable)).
    pub fn cable(&self, k: usize) -> Option<&CableItem> {
        self.cables.get(k).map(|c| &c.item)
    }

    /// Cable `k`, mutable (e.g. to set node velocities before the first step).
    pub fn cable_mut(&mut self, k: usize) -> Option<&mut CableItem> {
        self.cables.get_mut(k).map(|c| &mut c.item)
    }

    /// The BCE markers of cable `k`.
    pub fn cable_markers(&self, k: usize) -> Option<&CableMarkers> {
        self.cables.get(k).map(|c| &c.markers)
    }

    /// The mean fluid force on cable `k` over the last system step, N.
    pub fn cable_force(&self, k: usize) -> Option<Vector3<f64>> {
        self.cables.get(k).map(|c| c.force)
    }

    /// The mean fluid force on each marker of cable `k` over the last system step, N.
    pub fn cable_marker_forces(&self, k: usize) -> Option<&[[f64; 3]]> {
        self.cables.get(k).map(|c| c.marker_force.as_slice())
    }

    /// The mean generalized load of the fluid on the nodal coordinates of cable `k` over
    /// the last system step (6 per node: N on positions, N m on slopes).
    pub fn cable_load(&self, k: usize) -> Option<&[f64]> {
        self.cables.get(k).map(|c| c.load.as_slice())
    }

    /// The explicit phase (see the [module docs](self)).
    fn advance_coupled(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        loads: &mut BodyLoads,
    ) -> chrono_core::Result<()> {
        let g = self.sph.settings().gravity;
        if (0..3).any(|i| g[i] != ctx.gravity[i]) {
            return Err(ChronoError::invalid(
                "sph settings.gravity",
                format!("{g:?}"),
                format!("must equal the system's gravity {:?}", ctx.gravity),
            ));
        }
        let t_fluid = self.sph.time();
        if (t_fluid - ctx.time).abs() > 1e-9 * (1.0 + ctx.time.abs()) {
            return Err(ChronoError::invalid(
                "fluid time",
                t_fluid,
                format!(
                    "must equal the system time {} s (step the fluid only through the system)",
                    ctx.time
                ),
            ));
        }
        for c in &mut self.bodies {
            let b = bodies
                .get(c.handle)
                .ok_or(ChronoError::StaleBody { handle: c.handle })?;
            let (v, w) = (b.linear_velocity(), b.angular_velocity());
            let motion = RigidMotion {
                t0: ctx.time,
                position: b.position(),
                rotation: b.rotation(),
                velocity: v,
                angular_velocity: w,
                // no lagged body acceleration in the pressure extrapolation: fed back
                // through the marker pressures it acts as an explicit added mass
                acceleration: Vector3::zeros(),
                angular_acceleration: Vector3::zeros(),
            };
            self.sph
                .set_carrier_motion(c.carrier, motion)
                .map_err(|e| {
                    ChronoError::invalid(format!("body \"{}\" motion", c.name), "", e.to_string())
                })?;
        }
        for c in &mut self.cables {
            c.place().map_err(|e| {
                ChronoError::invalid(
                    format!("cable \"{}\" markers", c.item.name()),
                    "",
                    e.to_string(),
                )
            })?;
            self.sph
                .set_point_motion(c.carrier, ctx.time, &c.x, &c.v)
                .map_err(|e| {
                    ChronoError::invalid(
                        format!("cable \"{}\" markers", c.item.name()),
                        "",
                        e.to_string(),
                    )
                })?;
        }
        let t_end = ctx.time + ctx.h;
        let t_adv = std::time::Instant::now();
        let n = self.sph.advance_exactly(t_end);
        self.advance_time += t_adv.elapsed().as_secs_f64();
        let n = n.map_err(|e| self.domain_error(e))?;
        self.last_substeps = n;
        self.substeps += n;
        let inv_h = 1.0 / ctx.h;
        for c in &mut self.bodies {
            let [j, l] = self.sph.take_carrier_impulse(c.carrier);
            let (f, t) = (j * inv_h, l * inv_h);
            c.load = [f, t];
            let x = bodies[c.handle].position();
            loads.add_force_at(c.handle, &f, &x);
            loads.add_torque(c.handle, &t);
        }
        for c in &mut self.cables {
            self.sph
                .take_point_impulses(c.carrier, &mut c.impulse)
                .map_err(|e| self_domain_error(&self.name, e))?;
            c.force = Vector3::zeros();
            for (j, f) in c.impulse.iter().zip(c.marker_force.iter_mut()) {
                *f = [j[0] * inv_h, j[1] * inv_h, j[2] * inv_h];
                c.force += Vector3::new(f[0], f[1], f[2]);
            }
            c.load.fill(0.0);
            c.markers
                .nodal_loads(c.item.mesh(), &c.marker_force, &mut c.load);
            if let Some(i) = c.load.iter().position(|x| !x.is_finite()) {
                return Err(ChronoError::NonFinite {
                    item: format!("item \"{}\" (cable \"{}\")", self.name, c.item.name()),
                    step: ctx.step,
                    time: ctx.time,
                    what: format!("fluid load on coordinate {i}"),
                });
            }
        }
        Ok(())
    }

    fn domain_error(&self, e: chrono_sph::SphError) -> ChronoError {
        self_domain_error(&self.name, e)
    }
}

fn self_domain_error(name: &str, e: chrono_sph::SphError) -> ChronoError {
    ChronoError::Domain {
        domain: format!("chrono-sph (item \"{name}\")"),
        source: chrono_core::error::DomainError(std::sync::Arc::new(e)),
    }
}

impl PhysicsItem for SphFluid {
    fn name(&self) -> &str {
        &self.name
    }

    fn exchanges_body_loads(&self) -> bool {
        true
    }

    fn advance_explicit(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        loads: &mut BodyLoads,
    ) -> chrono_core::Result<()> {
        let t0 = std::time::Instant::now();
        let r = self.advance_coupled(ctx, bodies, loads);
        self.explicit_time += t0.elapsed().as_secs_f64();
        r
    }

    /// The cables' `M + h R + h^2 K` (see [`CableItem`]).
    fn begin_step(&mut self, ctx: &StepContext) -> chrono_core::Result<()> {
        for c in &mut self.cables {
            c.item.begin_step(ctx)?;
        }
        Ok(())
    }

    /// The cables' blocks (the block of each is remembered for
    /// [`load_momentum`](PhysicsItem::load_momentum)).
    fn add_variables(&mut self, vars: &mut Variables) {
        for c in &mut self.cables {
            let before = vars.len();
            c.item.add_variables(vars);
            c.block = (vars.len() > before).then_some(BlockId(before as u32));
        }
    }

    /// The cables' `M v + h f`, plus the fluid's impulse `h Q = J` on their free
    /// coordinates (the system calls [`advance_explicit`](PhysicsItem::advance_explicit)
    /// after the items' [`begin_step`](PhysicsItem::begin_step), so the load of this step
    /// enters here).
    fn load_momentum(&self, ctx: &StepContext, vars: &Variables, k: &mut [f64]) {
        for c in &self.cables {
            c.item.load_momentum(ctx, vars, k);
            let Some(blk) = c.block else { continue };
            let kb = &mut k[vars.range(blk)];
            let map = c.item.dof_map();
            for (g, q) in c.load.iter().enumerate() {
                if let Some(f) = map.free_index(g) {
                    kb[f] += ctx.h * q;
                }
            }
        }
    }

    /// The cables' proxies, their ids tagged with the cable index above
    /// 24 bits (`PROXY_BITS`).
    fn collision_proxies(&self, out: &mut Vec<CollisionProxy>) {
        for (k, c) in self.cables.iter().enumerate() {
            let start = out.len();
            c.item.collision_proxies(out);
            for p in &mut out[start..] {
                p.id |= (k as u32) << PROXY_BITS;
            }
        }
    }

    fn proxy_jacobian(
        &self,
        proxy: u32,
        p: &Vector3<f64>,
        dirs: &[Vector3<f64>; 3],
        entry: &mut dyn FnMut(BlockId, [&[f64]; 3]),
    ) -> [f64; 3] {
        let k = (proxy >> PROXY_BITS) as usize;
        match self.cables.get(k) {
            Some(c) => c
                .item
                .proxy_jacobian(proxy & ((1 << PROXY_BITS) - 1), p, dirs, entry),
            None => [0.0; 3],
        }
    }

    fn add_constraints(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> chrono_core::Result<()> {
        for c in &mut self.cables {
            c.item.add_constraints(ctx, vars, rows)?;
        }
        Ok(())
    }

    fn add_body_constraints(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        vars: &Variables,
        rows: &mut ConstraintRows,
    ) -> chrono_core::Result<()> {
        for c in &mut self.cables {
            c.item.add_body_constraints(ctx, bodies, vars, rows)?;
        }
        Ok(())
    }

    fn warm_start(&self, problem: &CcpProblem, gamma: &mut [f64]) {
        for c in &self.cables {
            c.item.warm_start(problem, gamma);
        }
    }

    fn update(
        &mut self,
        ctx: &StepContext,
        vars: &Variables,
        v: &[f64],
        problem: &CcpProblem,
        gamma: &[f64],
    ) -> chrono_core::Result<()> {
        for c in &mut self.cables {
            c.item.update(ctx, vars, v, problem, gamma)?;
        }
        Ok(())
    }
}
