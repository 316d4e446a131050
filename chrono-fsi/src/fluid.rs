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
//! Fixed and kinematic bodies carry markers too (their loads are computed and reported,
//! [`SphFluid::body_load`], and dropped by the stepper): a body with a prescribed motion is
//! a moving wall.

use chrono_core::bodies::Bodies;
use chrono_core::descriptor::{CcpProblem, Variables};
use chrono_core::force::BodyLoads;
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::math::Vector3;
use chrono_core::{BodyHandle, ChronoError};
use chrono_sph::{RigidMotion, SphSystem};

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
    last_substeps: u64,
    substeps: u64,
}

impl SphFluid {
    pub(crate) fn new(name: String, sph: SphSystem, bodies: Vec<Coupled>) -> Self {
        Self {
            name,
            sph,
            bodies,
            last_substeps: 0,
            substeps: 0,
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

    fn domain_error(&self, e: chrono_sph::SphError) -> ChronoError {
        ChronoError::Domain {
            domain: format!("chrono-sph (item \"{}\")", self.name),
            source: chrono_core::error::DomainError(std::sync::Arc::new(e)),
        }
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
        let t_end = ctx.time + ctx.h;
        let n = self
            .sph
            .advance_exactly(t_end)
            .map_err(|e| self.domain_error(e))?;
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
        Ok(())
    }

    fn add_variables(&mut self, _vars: &mut Variables) {}

    fn load_momentum(&self, _ctx: &StepContext, _vars: &Variables, _k: &mut [f64]) {}

    fn update(
        &mut self,
        _ctx: &StepContext,
        _vars: &Variables,
        _v: &[f64],
        _problem: &CcpProblem,
        _gamma: &[f64],
    ) -> chrono_core::Result<()> {
        Ok(())
    }
}
