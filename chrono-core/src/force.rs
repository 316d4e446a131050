//! Force elements: springs, dampers, tire forces, aerodynamic drag ... anything that applies
//! a force to bodies as a function of their state, without constraint rows.
//!
//! A [`ForceElement`] is evaluated once per step at the state of the start of the step
//! (`q(l)`, `v(l)`); its loads enter the momentum `k = M v + h f` of both time steppers, so
//! it acts explicitly: a stiff element needs `h sqrt(k / m)` well below 1 (for a vehicle
//! suspension, `k` ~ 1e5 N/m on a 60 kg wheel at `h = 1e-3` s gives 0.04).
//!
//! The built-in [`SpringDamper`] is the translational spring-damper-actuator between two
//! points (Chrono's TSDA), with nonlinear tables for the spring and the damper.

use nalgebra::Vector3;

use crate::bodies::Bodies;
use crate::body::BodyHandle;
use crate::curve::Curve;
use crate::error::{ChronoError, Result, check_finite3, check_non_negative};
use crate::item::StepContext;

/// Handle of a force element in a [`System`](crate::system::System) (slot index and
/// generation, like [`BodyHandle`]): stale once the element is removed
/// ([`System::remove_force_element`](crate::system::System::remove_force_element)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ForceHandle {
    index: u32,
    generation: u32,
}

crate::slots::generational_handle!(ForceHandle, "force element");

/// The loads of one step on every body: a force (world, N) through the center of mass and a
/// torque (world, N m). Force elements add into it; the time stepper puts `h` times it into
/// the momentum of the dynamic bodies (loads on fixed and kinematic bodies are dropped).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BodyLoads {
    /// Dense index of each body handle's slot (see [`Bodies`]).
    dense: Vec<usize>,
    centers: Vec<Vector3<f64>>,
    loads: Vec<[Vector3<f64>; 2]>,
}

impl BodyLoads {
    /// Zero loads for `bodies` (keeps their centers of mass for lever arms).
    pub fn reset(&mut self, bodies: &Bodies) {
        self.dense.clear();
        self.dense.extend(bodies.dense_by_slot());
        self.centers.clear();
        self.centers.extend(bodies.iter().map(|b| b.position()));
        self.loads.clear();
        self.loads.resize(bodies.len(), [Vector3::zeros(); 2]);
    }

    /// Zero loads for `bodies` without their centers of mass: for a step in which nothing
    /// adds loads (no force elements, no joints), so no lever arm is needed
    /// ([`add_force_at`](Self::add_force_at) must not be called until the next
    /// [`reset`](Self::reset)).
    pub(crate) fn reset_zero(&mut self, bodies: &Bodies) {
        self.dense.clear();
        self.dense.extend(bodies.dense_by_slot());
        self.centers.clear();
        self.loads.clear();
        self.loads.resize(bodies.len(), [Vector3::zeros(); 2]);
    }

    /// Add force `f` (world, N) acting at the world point `p` on `body`: the force, and the
    /// torque `(p - x) x f` about its center of mass.
    #[inline]
    pub fn add_force_at(&mut self, body: BodyHandle, f: &Vector3<f64>, p: &Vector3<f64>) {
        let i = self.dense[body.index() as usize];
        let arm = p - self.centers[i];
        self.loads[i][0] += f;
        self.loads[i][1] += arm.cross(f);
    }

    /// Add a pure torque `t` (world, N m) on `body`.
    #[inline]
    pub fn add_torque(&mut self, body: BodyHandle, t: &Vector3<f64>) {
        self.loads[self.dense[body.index() as usize]][1] += t;
    }

    /// The force (world, N) and torque about the center of mass (world, N m) on `body`.
    pub fn get(&self, body: BodyHandle) -> [Vector3<f64>; 2] {
        self.loads[self.dense[body.index() as usize]]
    }

    /// All loads, in the dense order of the system's bodies.
    pub fn as_slice(&self) -> &[[Vector3<f64>; 2]] {
        &self.loads
    }
}

/// A force that depends on the bodies' state (see the [module docs](self)).
pub trait ForceElement: std::any::Any + Send + Sync {
    /// A name for messages.
    fn name(&self) -> &str;

    /// Called once when the element is added to a system: check the body handles (an
    /// [`UnknownHandle`](ChronoError::UnknownHandle) error otherwise) and turn world data
    /// given at creation into body-frame data.
    fn attach(&mut self, bodies: &Bodies) -> Result<()>;

    /// The bodies this element acts on: [`System::remove_body`](crate::System::remove_body)
    /// refuses to remove them while the element is in the system.
    fn body_handles(&self) -> Vec<BodyHandle>;

    /// Add this step's loads from the state at the start of the step. May keep what it
    /// computed for output (a spring's length and force).
    fn evaluate(&mut self, ctx: &StepContext, bodies: &Bodies, loads: &mut BodyLoads)
    -> Result<()>;
}

/// Check a handle against the bodies (the error names `field`).
pub fn check_body(field: &str, h: BodyHandle, bodies: &Bodies) -> Result<()> {
    if bodies.contains(h) {
        Ok(())
    } else {
        Err(ChronoError::UnknownHandle {
            kind: "body",
            index: h.index() as usize,
            field: format!("{field} ({h})"),
        })
    }
}

/// A translational spring-damper-actuator between a point on body A and a point on body B.
///
/// With `l = |p_B - p_A|`, `u = (p_B - p_A)/l` and `l_dot = u . (v_B(p_B) - v_A(p_A))`,
/// the scalar force
///
/// ```text
/// f = f_0 - F_s(l - l_0) - F_d(l_dot)
/// ```
///
/// acts on B as `f u` and on A as `-f u` (positive `f` pushes the points apart). `F_s` is
/// the spring's restoring force against deflection (N vs m; `k x` for a linear spring) and
/// `F_d` the damper's force against the rate of extension (N vs m/s; `c l_dot`), both
/// [`Curve`]s, so nonlinear springs, bump stops (a table that is zero inside the free travel)
/// and piecewise dampers are tables; `f_0` is a preload (N). A shock absorber with
/// hydraulic bump stops uses another damper curve `F_b` while the length is outside
/// `[l_min, l_max]` ([`with_bump_damper`](Self::with_bump_damper)). This is the element of
/// Chrono's `ChLinkTSDA`; the suspension tables of the HMMWV are in this form.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringDamper {
    name: String,
    body_a: BodyHandle,
    body_b: BodyHandle,
    world_a: Vector3<f64>,
    world_b: Vector3<f64>,
    local_a: Vector3<f64>,
    local_b: Vector3<f64>,
    rest_length: f64,
    spring: Curve,
    damper: Curve,
    bump_damper: Option<(f64, f64, Curve)>,
    preload: f64,
    length: f64,
    speed: f64,
    force: f64,
}

impl SpringDamper {
    /// A spring-damper between the world point `pa` on body `a` and `pb` on body `b` (at the
    /// bodies' poses when it is added to the system), with rest length `rest_length` (m),
    /// spring and damper curves and no preload.
    pub fn new(
        name: impl Into<String>,
        a: BodyHandle,
        pa: Vector3<f64>,
        b: BodyHandle,
        pb: Vector3<f64>,
        rest_length: f64,
        spring: Curve,
        damper: Curve,
    ) -> Self {
        Self {
            name: name.into(),
            body_a: a,
            body_b: b,
            world_a: pa,
            world_b: pb,
            local_a: Vector3::zeros(),
            local_b: Vector3::zeros(),
            rest_length,
            spring,
            damper,
            bump_damper: None,
            preload: 0.0,
            length: (pb - pa).norm(),
            speed: 0.0,
            force: 0.0,
        }
    }

    /// A linear spring `k` (N/m) and damper `c` (N s/m).
    pub fn linear(
        name: impl Into<String>,
        a: BodyHandle,
        pa: Vector3<f64>,
        b: BodyHandle,
        pb: Vector3<f64>,
        rest_length: f64,
        k: f64,
        c: f64,
    ) -> Self {
        Self::new(
            name,
            a,
            pa,
            b,
            pb,
            rest_length,
            Curve::linear(k),
            Curve::linear(c),
        )
    }

    /// Set the preload `f_0` (N, positive pushes apart).
    pub fn with_preload(mut self, f0: f64) -> Self {
        self.preload = f0;
        self
    }

    /// Use the damper curve `bump` (N vs m/s) instead of the main one while the length is
    /// below `min_length` or above `max_length` (m): hydraulic bump stops of a shock.
    pub fn with_bump_damper(mut self, min_length: f64, max_length: f64, bump: Curve) -> Self {
        self.bump_damper = Some((min_length, max_length, bump));
        self
    }

    /// The length at the last evaluation (at creation: the distance of the points), m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The rate of extension at the last evaluation, m/s.
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// The force at the last evaluation, N (positive pushes apart).
    pub fn force(&self) -> f64 {
        self.force
    }

    /// The rest length, m.
    pub fn rest_length(&self) -> f64 {
        self.rest_length
    }

    /// The two bodies `(a, b)`.
    pub fn bodies(&self) -> (BodyHandle, BodyHandle) {
        (self.body_a, self.body_b)
    }
}

impl ForceElement for SpringDamper {
    fn name(&self) -> &str {
        &self.name
    }

    fn body_handles(&self) -> Vec<BodyHandle> {
        vec![self.body_a, self.body_b]
    }

    fn attach(&mut self, bodies: &Bodies) -> Result<()> {
        let f = |s: &str| format!("spring-damper \"{}\".{s}", self.name);
        check_body(&f("body_a"), self.body_a, bodies)?;
        check_body(&f("body_b"), self.body_b, bodies)?;
        check_finite3(&f("point_a"), &self.world_a)?;
        check_finite3(&f("point_b"), &self.world_b)?;
        check_non_negative(&f("rest_length"), self.rest_length)?;
        if !self.preload.is_finite() {
            return Err(ChronoError::invalid(
                f("preload"),
                self.preload,
                "must be finite",
            ));
        }
        self.spring.validate(&f("spring"))?;
        self.damper.validate(&f("damper"))?;
        if let Some((lo, hi, bump)) = &self.bump_damper {
            check_non_negative(&f("bump_damper.min_length"), *lo)?;
            if !(hi.is_finite() && hi > lo) {
                return Err(ChronoError::invalid(
                    f("bump_damper.max_length"),
                    hi,
                    format!("must be finite and > min_length = {lo}"),
                ));
            }
            bump.validate(&f("bump_damper.curve"))?;
        }
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        self.local_a = a
            .pose()
            .inverse_transform_point(&self.world_a.into())
            .coords;
        self.local_b = b
            .pose()
            .inverse_transform_point(&self.world_b.into())
            .coords;
        if (self.world_b - self.world_a).norm() == 0.0 {
            return Err(ChronoError::invalid(
                f("point_b"),
                format!("{:?}", self.world_b.as_slice()),
                "the two points coincide, so the spring has no direction",
            ));
        }
        Ok(())
    }

    fn evaluate(
        &mut self,
        ctx: &StepContext,
        bodies: &Bodies,
        loads: &mut BodyLoads,
    ) -> Result<()> {
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let pa = a.pose().transform_point(&self.local_a.into()).coords;
        let pb = b.pose().transform_point(&self.local_b.into()).coords;
        let d = pb - pa;
        let l = d.norm();
        if !(l > 0.0 && l.is_finite()) {
            return Err(ChronoError::NonFinite {
                item: format!("spring-damper \"{}\"", self.name),
                step: ctx.step,
                time: ctx.time,
                what: format!("length {l} m (the attachment points coincide or are not finite)"),
            });
        }
        let u = d / l;
        let l_dot = u.dot(&(b.point_velocity(&pb) - a.point_velocity(&pa)));
        let damper = match &self.bump_damper {
            Some((lo, hi, bump)) if l < *lo || l > *hi => bump,
            _ => &self.damper,
        };
        let f = self.preload - self.spring.eval(l - self.rest_length) - damper.eval(l_dot);
        self.length = l;
        self.speed = l_dot;
        self.force = f;
        loads.add_force_at(self.body_b, &(f * u), &pb);
        loads.add_force_at(self.body_a, &(-f * u), &pa);
        Ok(())
    }
}
