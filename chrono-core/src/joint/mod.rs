//! Joints as bilateral constraint rows.
//!
//! A joint connects body A and body B through a joint frame fixed on each (`frame_a` in A's
//! body frame, `frame_b` in B's), both equal to the world frame given at creation. Its rows
//! are the velocity-level form of holonomic constraints `C(q) = 0`:
//! `D' v + C/h = 0` (the stabilization term of the seed, so drift is corrected in one step).
//! Rows are built from three primitives on the frames' world points `p` and axes:
//!
//! - point coincidence along a world direction `d`: `C = d.(p_B - p_A)`;
//! - perpendicular axes: `C = a.b` (`a` on A, `b` on B), `C_dot = (w_A - w_B).(a x b)`;
//! - distance: `C = |p_B - p_A| - L`.
//!
//! | joint | rows |
//! |---|---|
//! | spherical | 3 point |
//! | revolute (axis z) | 3 point + 2 perpendicular (`z_A.x_B`, `z_A.y_B`) |
//! | prismatic (axis z) | 2 point (along `x_A`, `y_A`) + 3 perpendicular (lock rotation) |
//! | universal (crossed `x_A`, `y_B`) | 3 point + 1 perpendicular (`x_A.y_B`) |
//! | distance | 1 |
//! | lock | 3 point + 3 perpendicular |
//! | rotational motor | revolute + 1 drive row on the relative spin about z (box-bounded by the torque limit), angle limits as unilateral rows |
//! | linear actuator | prismatic + 1 drive row on the slide (box-bounded by the force limit) |

use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::bodies::Bodies;
use crate::body::{BodyHandle, PairRowKind, RigidBody, push_pair_row};
use crate::descriptor::{ConstraintRows, RowId};
use crate::error::{ChronoError, Result, check_finite, check_finite3};

/// Handle of a joint in a [`System`](crate::system::System) (slot index and generation,
/// like [`BodyHandle`]): stale once the joint is removed
/// ([`System::remove_joint`](crate::system::System::remove_joint)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct JointHandle {
    index: u32,
    generation: u32,
}

crate::slots::generational_handle!(JointHandle, "joint");

/// What a rotational motor or linear actuator drives.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Drive {
    /// Relative speed about/along the joint axis (rad/s or m/s), reached within the effort limit.
    Speed(f64),
    /// Relative angle/position (rad or m), reached within the effort limit (the row drives the
    /// error to zero in one step, like any constraint).
    Position(f64),
    /// A given torque/force (N m or N) applied equal and opposite; no row.
    Effort(f64),
}

/// The type of a joint and its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum JointKind {
    /// Ball joint: the frame origins coincide.
    Spherical,
    /// Hinge about the frame z axis.
    Revolute,
    /// Slider along the frame z axis, no relative rotation.
    Prismatic,
    /// Cardan joint: A's x axis stays perpendicular to B's y axis.
    Universal,
    /// The frame origins stay `distance` apart (m).
    Distance {
        /// The distance, m (> 0).
        distance: f64,
    },
    /// Rigid weld.
    Lock,
    /// A revolute joint with a drive about z and optional angle limits.
    RotationalMotor {
        /// The drive.
        drive: Drive,
        /// Torque limit of a speed/position drive, N m (infinite = ideal).
        max_torque: f64,
        /// Optional relative angle limits `(min, max)`, rad.
        limits: Option<(f64, f64)>,
    },
    /// A prismatic joint with a drive along z.
    LinearActuator {
        /// The drive.
        drive: Drive,
        /// Force limit of a speed/position drive, N (infinite = ideal).
        max_force: f64,
    },
}

/// A linear spring-damper acting along the axis of a [`JointKind::LinearActuator`] or
/// about the axis of a [`JointKind::RotationalMotor`] (in parallel with its drive), with
/// the effort on B (A gets the opposite)
///
/// ```text
/// F = f_0 - k x - c x_dot
/// ```
///
/// where `x` is the joint coordinate from the assembled pose (m or rad: the one
/// [`Drive::Position`] reads), `k` the stiffness (N/m or N m/rad), `c` the damping (N s/m or
/// N m s/rad) and `f_0` the preload (N or N m).
///
/// It is integrated implicitly, as a compliant row of the step's problem: with
/// `x_{n+1} = x_n + h x_dot_{n+1}` and the row's impulse `g = h F_{n+1}`,
///
/// ```text
/// x_dot_{n+1} + g / (h (k h + c)) + (k x_n - f_0) / (k h + c) = 0,
/// ```
///
/// a bilateral row with compliance `eps = 1 / (h (k h + c))` and right-hand side
/// `b = (k x_n - f_0) / (k h + c)`: the linearly implicit (backward) Euler step of the
/// spring-damper, stable for any `h` however stiff the spring or light the bodies, where
/// a force element (explicit) needs `c h / m_eff + k h^2 / (2 m_eff) < 2` (semi-implicit Euler
/// on `m x'' = -k x - c x'`). This is the "soft constraint" form of a spring (C. Lacoursière,
/// "Ghosts and machines: regularized variational methods for interactive simulations of
/// multibodies with dry frictional contacts", PhD thesis, Umeå University, 2007; E. Catto,
/// "Soft constraints", GDC 2011); Project Chrono applies the same backward-Euler
/// linearization to its spring-dampers through their stiffness and damping matrices.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AxisSpring {
    /// Stiffness `k`, N/m (actuator) or N m/rad (motor), >= 0.
    pub stiffness: f64,
    /// Damping `c`, N s/m or N m s/rad, >= 0; `k h + c` must be > 0 at every step.
    pub damping: f64,
    /// Preload `f_0`, N or N m (on B along/about the joint axis at `x = 0`).
    pub preload: f64,
}

impl AxisSpring {
    /// Check the values; `field` names the spring in the message.
    fn validate(&self, field: &str) -> Result<()> {
        for (v, name) in [(self.stiffness, "stiffness"), (self.damping, "damping")] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(ChronoError::invalid(
                    format!("{field}.{name}"),
                    v,
                    "must be finite and >= 0",
                ));
            }
        }
        if self.stiffness == 0.0 && self.damping == 0.0 {
            return Err(ChronoError::invalid(
                format!("{field}.stiffness"),
                self.stiffness,
                "stiffness and damping are both zero (no spring: leave it out)",
            ));
        }
        check_finite(&format!("{field}.preload"), self.preload)?;
        Ok(())
    }
}

/// A joint between two bodies.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub(crate) name: String,
    pub(crate) body_a: BodyHandle,
    pub(crate) body_b: BodyHandle,
    pub(crate) frame_a: Isometry3<f64>,
    pub(crate) frame_b: Isometry3<f64>,
    pub(crate) kind: JointKind,
    /// Relative angle about z, unwrapped across steps (motors).
    pub(crate) angle: f64,
    /// The rows of the current step and their multipliers (impulses, N s or N m s).
    pub(crate) row_ids: Vec<RowId>,
    pub(crate) row_kinds: Vec<RowMeaning>,
    pub(crate) impulses: Vec<f64>,
    pub(crate) h: f64,
    /// The spring-damper along/about the axis (motors and actuators), if any.
    pub(crate) axis_spring: Option<AxisSpring>,
    /// The index of the spring's row in `row_kinds`/`impulses` this step.
    pub(crate) spring_row: Option<usize>,
}

/// What a joint row constrains (for reactions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RowMeaning {
    /// Force along this world direction, applied on B at its frame origin.
    Force(Vector3<f64>),
    /// Torque about this world axis on B.
    Torque(Vector3<f64>),
}

/// Builder of a [`Joint`], given the joint frame in world coordinates at creation.
#[derive(Debug, Clone, PartialEq)]
pub struct JointBuilder {
    name: String,
    body_a: BodyHandle,
    body_b: BodyHandle,
    frame_world: Isometry3<f64>,
    /// B's frame when it differs from A's (distance joints between two anchors).
    frame_b_world: Option<Isometry3<f64>>,
    kind: JointKind,
    axis_spring: Option<AxisSpring>,
}

impl JointBuilder {
    /// A joint of `kind` between bodies `a` and `b` whose frame is `frame_world` (origin and
    /// axes in world coordinates at the bodies' current poses).
    pub fn new(kind: JointKind, a: BodyHandle, b: BodyHandle, frame_world: Isometry3<f64>) -> Self {
        Self {
            name: String::new(),
            body_a: a,
            body_b: b,
            frame_world,
            frame_b_world: None,
            kind,
            axis_spring: None,
        }
    }
    /// A joint whose frame is at world point `origin` with its z axis along `axis` (world).
    pub fn at_axis(
        kind: JointKind,
        a: BodyHandle,
        b: BodyHandle,
        origin: Vector3<f64>,
        axis: Vector3<f64>,
    ) -> Self {
        let rot = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        });
        Self::new(kind, a, b, Isometry3::from_parts(origin.into(), rot))
    }
    /// A distance joint between world point `anchor_a` on body `a` and world point
    /// `anchor_b` on body `b`, keeping them at their current distance `|anchor_b - anchor_a|`.
    pub fn distance_between(
        a: BodyHandle,
        b: BodyHandle,
        anchor_a: Vector3<f64>,
        anchor_b: Vector3<f64>,
    ) -> Self {
        let distance = (anchor_b - anchor_a).norm();
        let mut s = Self::new(
            JointKind::Distance { distance },
            a,
            b,
            Isometry3::translation(anchor_a.x, anchor_a.y, anchor_a.z),
        );
        s.frame_b_world = Some(Isometry3::translation(anchor_b.x, anchor_b.y, anchor_b.z));
        s
    }

    /// Name for messages.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// A spring-damper along/about the axis of a linear actuator or rotational motor,
    /// integrated implicitly (see [`AxisSpring`]); other kinds are refused when the joint is
    /// built.
    pub fn axis_spring(mut self, spring: AxisSpring) -> Self {
        self.axis_spring = Some(spring);
        self
    }

    /// Check the parameters against the bodies and make the joint (the System calls this).
    pub(crate) fn build(self, bodies: &Bodies) -> Result<Joint> {
        let field = |f: &str| {
            if self.name.is_empty() {
                format!("joint.{f}")
            } else {
                format!("joint \"{}\".{f}", self.name)
            }
        };
        for (h, f) in [(self.body_a, "body_a"), (self.body_b, "body_b")] {
            if !bodies.contains(h) {
                return Err(ChronoError::UnknownHandle {
                    kind: "body",
                    index: h.index() as usize,
                    field: format!("{} ({h})", field(f)),
                });
            }
        }
        if self.body_a == self.body_b {
            return Err(ChronoError::invalid(
                field("body_b"),
                self.body_b,
                "must differ from body_a",
            ));
        }
        check_finite3(&field("frame.origin"), &self.frame_world.translation.vector)?;
        if self
            .frame_world
            .rotation
            .coords
            .iter()
            .any(|c| !c.is_finite())
        {
            return Err(ChronoError::invalid(
                field("frame.rotation"),
                format!("{:?}", self.frame_world.rotation.coords),
                "must be finite",
            ));
        }
        let check_drive = |d: &Drive, name: &str| -> Result<()> {
            match d {
                Drive::Speed(x) | Drive::Position(x) | Drive::Effort(x) => {
                    check_finite(&field(name), *x).map(|_| ())
                }
            }
        };
        match &self.kind {
            JointKind::Distance { distance } => {
                crate::error::check_positive(&field("distance"), *distance)?;
            }
            JointKind::RotationalMotor {
                drive,
                max_torque,
                limits,
            } => {
                check_drive(drive, "drive")?;
                if max_torque.is_nan() || *max_torque < 0.0 {
                    return Err(ChronoError::invalid(
                        field("max_torque"),
                        max_torque,
                        "must be >= 0",
                    ));
                }
                if let Some((lo, hi)) = limits
                    && !(lo.is_finite() && hi.is_finite() && lo < hi)
                {
                    return Err(ChronoError::invalid(
                        field("limits"),
                        format!("({lo}, {hi})"),
                        "need finite min < max",
                    ));
                }
            }
            JointKind::LinearActuator { drive, max_force } => {
                check_drive(drive, "drive")?;
                if max_force.is_nan() || *max_force < 0.0 {
                    return Err(ChronoError::invalid(
                        field("max_force"),
                        max_force,
                        "must be >= 0",
                    ));
                }
            }
            _ => {}
        }
        if let Some(sp) = &self.axis_spring {
            check_axis_spring_kind(&self.kind, &field("axis_spring"))?;
            sp.validate(&field("axis_spring"))?;
        }
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let frame_a = a.pose().inverse() * self.frame_world;
        if let Some(fb) = &self.frame_b_world {
            check_finite3(&field("frame_b.origin"), &fb.translation.vector)?;
        }
        let frame_b = b.pose().inverse() * self.frame_b_world.unwrap_or(self.frame_world);
        Ok(Joint {
            name: self.name,
            body_a: self.body_a,
            body_b: self.body_b,
            frame_a,
            frame_b,
            kind: self.kind,
            angle: 0.0,
            row_ids: Vec::new(),
            row_kinds: Vec::new(),
            impulses: Vec::new(),
            h: 0.0,
            axis_spring: self.axis_spring,
            spring_row: None,
        })
    }
}

/// An axis spring needs an axis coordinate: a rotational motor or a linear actuator.
fn check_axis_spring_kind(kind: &JointKind, field: &str) -> Result<()> {
    match kind {
        JointKind::RotationalMotor { .. } | JointKind::LinearActuator { .. } => Ok(()),
        other => Err(ChronoError::invalid(
            field,
            format!("{other:?}"),
            "an axis spring needs a rotational motor or a linear actuator",
        )),
    }
}

/// The row sink used while building a joint's rows: (joint, kind, J_a, J_b, C/h, meaning).
type PushRow<'a> = dyn FnMut(&mut Joint, PairRowKind, [f64; 6], [f64; 6], f64, RowMeaning) + 'a;

/// An effort drive's load for one step: world force and torque on B (A gets the opposite),
/// and the two frame origins where they act.
pub(crate) struct EffortLoad {
    pub force: Vector3<f64>,
    pub torque: Vector3<f64>,
    pub point_a: Vector3<f64>,
    pub point_b: Vector3<f64>,
}

/// World frames of the two sides of a joint.
struct Frames {
    pa: Vector3<f64>,
    pb: Vector3<f64>,
    xa: Vector3<f64>,
    ya: Vector3<f64>,
    za: Vector3<f64>,
    xb: Vector3<f64>,
    yb: Vector3<f64>,
}

impl Joint {
    /// The joint's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The spring-damper along/about the axis, if any ([`AxisSpring`]).
    pub fn axis_spring(&self) -> Option<&AxisSpring> {
        self.axis_spring.as_ref()
    }

    /// Set or remove the axis spring (between steps); only motors and actuators have one.
    pub fn set_axis_spring(&mut self, spring: Option<AxisSpring>) -> Result<()> {
        if let Some(sp) = &spring {
            let field = format!("joint \"{}\".axis_spring", self.name);
            check_axis_spring_kind(&self.kind, &field)?;
            sp.validate(&field)?;
        }
        self.axis_spring = spring;
        Ok(())
    }

    /// The axis spring's effort on B at the last step (N along the axis or N m about it;
    /// A gets the opposite): `F = f_0 - k x_{n+1} - c x_dot_{n+1}`, its row's impulse over
    /// the step. Zero without a spring or before the first step.
    pub fn axis_spring_effort(&self) -> f64 {
        match self.spring_row {
            Some(k) if self.h > 0.0 => self.impulses.get(k).map_or(0.0, |g| g / self.h),
            _ => 0.0,
        }
    }
    /// The two bodies.
    pub fn bodies(&self) -> (BodyHandle, BodyHandle) {
        (self.body_a, self.body_b)
    }
    /// The type and parameters.
    pub fn kind(&self) -> &JointKind {
        &self.kind
    }
    /// Change the drive of a motor or actuator (e.g. from a controller between steps).
    pub fn set_drive(&mut self, new: Drive) -> Result<()> {
        check_finite(
            "joint.drive",
            match new {
                Drive::Speed(x) | Drive::Position(x) | Drive::Effort(x) => x,
            },
        )?;
        match &mut self.kind {
            JointKind::RotationalMotor { drive, .. } | JointKind::LinearActuator { drive, .. } => {
                *drive = new;
                Ok(())
            }
            _ => Err(ChronoError::invalid(
                "joint.drive",
                format!("{new:?}"),
                "this joint has no drive",
            )),
        }
    }

    /// The relative rotation angle of B about the joint z axis (rad, unwrapped), for motors.
    pub fn angle(&self) -> f64 {
        self.angle
    }

    fn frames(&self, a: &RigidBody, b: &RigidBody) -> Frames {
        let fa = a.pose() * self.frame_a;
        let fb = b.pose() * self.frame_b;
        let ra = fa.rotation;
        let rb = fb.rotation;
        Frames {
            pa: fa.transform_point(&Point3::origin()).coords,
            pb: fb.transform_point(&Point3::origin()).coords,
            xa: ra * Vector3::x(),
            ya: ra * Vector3::y(),
            za: ra * Vector3::z(),
            xb: rb * Vector3::x(),
            yb: rb * Vector3::y(),
        }
    }

    /// The largest violation of the position-level constraints (m for points, rad-ish for
    /// axes), at the bodies' current poses.
    pub fn violation(&self, bodies: &Bodies) -> f64 {
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let f = self.frames(a, b);
        let dp = f.pb - f.pa;
        let rb_z = (b.pose() * self.frame_b).rotation * Vector3::z();
        match &self.kind {
            JointKind::Spherical => dp.norm(),
            JointKind::Revolute | JointKind::RotationalMotor { .. } => dp
                .norm()
                .max(f.za.dot(&f.xb).abs())
                .max(f.za.dot(&f.yb).abs()),
            JointKind::Universal => dp.norm().max(f.xa.dot(&f.yb).abs()),
            JointKind::Distance { distance } => (dp.norm() - distance).abs(),
            JointKind::Lock => dp
                .norm()
                .max(f.za.dot(&f.xb).abs())
                .max(f.za.dot(&f.yb).abs())
                .max(f.xa.dot(&f.yb).abs()),
            JointKind::Prismatic | JointKind::LinearActuator { .. } => dp
                .dot(&f.xa)
                .abs()
                .max(dp.dot(&f.ya).abs())
                .max(f.za.dot(&f.xb).abs())
                .max(f.za.dot(&f.yb).abs())
                .max(f.xa.dot(&f.yb).abs())
                .max((1.0 - f.za.dot(&rb_z)).abs()),
        }
    }

    /// Reaction force on body B at its joint frame origin (world, N), from the last step.
    pub fn reaction_force(&self) -> Vector3<f64> {
        if self.h <= 0.0 {
            return Vector3::zeros();
        }
        let mut f = Vector3::zeros();
        for (m, g) in self.row_kinds.iter().zip(&self.impulses) {
            if let RowMeaning::Force(d) = m {
                f += d * (*g / self.h);
            }
        }
        f
    }

    /// Add this joint's rows for a step of size `h`; applies effort drives as forces.
    pub(crate) fn add_rows(&mut self, bodies: &Bodies, h: f64, rows: &mut ConstraintRows) {
        self.row_ids.clear();
        self.row_kinds.clear();
        self.spring_row = None;
        self.h = h;
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let f = self.frames(a, b);
        let dp = f.pb - f.pa;
        let inv_h = 1.0 / h;

        // relative angle about za, unwrapped
        let raw = f.xa.cross(&f.xb).dot(&f.za).atan2(f.xa.dot(&f.xb));
        let two_pi = std::f64::consts::TAU;
        let wraps = ((self.angle - raw) / two_pi).round();
        self.angle = raw + wraps * two_pi;

        let mut push = |joint: &mut Joint,
                        kind: PairRowKind,
                        ja: [f64; 6],
                        jb: [f64; 6],
                        c: f64,
                        meaning: RowMeaning| {
            if let Some(id) = push_pair_row(rows, kind, a, &ja, b, &jb, c, 0.0) {
                joint.row_ids.push(id);
                joint.row_kinds.push(meaning);
            }
        };
        let neg = |j: [f64; 6]| j.map(|x| -x);
        let point_row =
            |joint: &mut Joint, push: &mut PushRow, d: Vector3<f64>, rotating_a: bool| {
                let mut ja = neg(a.point_jacobian(&f.pa, &d));
                if rotating_a {
                    // d rotates with A: d_dot.(p_B - p_A) = w_A.(d x dp)
                    let extra = a.angular_jacobian(&d.cross(&dp));
                    for k in 3..6 {
                        ja[k] += extra[k];
                    }
                }
                let jb = b.point_jacobian(&f.pb, &d);
                push(
                    joint,
                    PairRowKind::Bilateral,
                    ja,
                    jb,
                    d.dot(&dp) * inv_h,
                    RowMeaning::Force(d),
                );
            };
        let perp_row = |joint: &mut Joint, push: &mut PushRow, u: Vector3<f64>, v: Vector3<f64>| {
            let axis = u.cross(&v);
            let ja = a.angular_jacobian(&axis);
            let jb = neg(b.angular_jacobian(&axis));
            push(
                joint,
                PairRowKind::Bilateral,
                ja,
                jb,
                u.dot(&v) * inv_h,
                RowMeaning::Torque(-axis),
            );
        };
        let world = [Vector3::x(), Vector3::y(), Vector3::z()];
        let kind = self.kind.clone();
        match &kind {
            JointKind::Spherical => {
                for d in world {
                    point_row(self, &mut push, d, false);
                }
            }
            JointKind::Revolute | JointKind::RotationalMotor { .. } => {
                for d in world {
                    point_row(self, &mut push, d, false);
                }
                perp_row(self, &mut push, f.za, f.xb);
                perp_row(self, &mut push, f.za, f.yb);
            }
            JointKind::Universal => {
                for d in world {
                    point_row(self, &mut push, d, false);
                }
                perp_row(self, &mut push, f.xa, f.yb);
            }
            JointKind::Lock => {
                for d in world {
                    point_row(self, &mut push, d, false);
                }
                perp_row(self, &mut push, f.za, f.xb);
                perp_row(self, &mut push, f.za, f.yb);
                perp_row(self, &mut push, f.xa, f.yb);
            }
            JointKind::Prismatic | JointKind::LinearActuator { .. } => {
                point_row(self, &mut push, f.xa, true);
                point_row(self, &mut push, f.ya, true);
                perp_row(self, &mut push, f.za, f.xb);
                perp_row(self, &mut push, f.za, f.yb);
                perp_row(self, &mut push, f.xa, f.yb);
            }
            JointKind::Distance { distance } => {
                let len = dp.norm();
                let d = if len > 1e-12 { dp / len } else { Vector3::z() };
                let ja = neg(a.point_jacobian(&f.pa, &d));
                let jb = b.point_jacobian(&f.pb, &d);
                push(
                    self,
                    PairRowKind::Bilateral,
                    ja,
                    jb,
                    (len - distance) * inv_h,
                    RowMeaning::Force(d),
                );
            }
        }
        // The axis spring's row (pushed after the drives and limits): entries, the joint
        // coordinate and the effort's direction.
        let mut spring: Option<([f64; 6], [f64; 6], f64, RowMeaning)> = None;
        // drives and limits
        match &kind {
            JointKind::RotationalMotor {
                drive,
                max_torque,
                limits,
            } => {
                // relative spin rate s = (w_B - w_A).z_A (z_A's own rotation is orthogonal to the
                // perpendicular rows, which keep z_A = z_B)
                let ja = neg(a.angular_jacobian(&f.za));
                let jb = b.angular_jacobian(&f.za);
                spring = Some((ja, jb, self.angle, RowMeaning::Torque(f.za)));
                let lim = max_torque * h;
                match *drive {
                    Drive::Speed(w) => push(
                        self,
                        PairRowKind::Box { lo: -lim, hi: lim },
                        ja,
                        jb,
                        -w,
                        RowMeaning::Torque(f.za),
                    ),
                    Drive::Position(th) => push(
                        self,
                        PairRowKind::Box { lo: -lim, hi: lim },
                        ja,
                        jb,
                        (self.angle - th) * inv_h,
                        RowMeaning::Torque(f.za),
                    ),
                    Drive::Effort(_) => {}
                }
                if let Some((lo, hi)) = *limits {
                    // theta + h s >= lo  and  theta + h s <= hi
                    push(
                        self,
                        PairRowKind::Unilateral,
                        ja,
                        jb,
                        (self.angle - lo) * inv_h,
                        RowMeaning::Torque(f.za),
                    );
                    push(
                        self,
                        PairRowKind::Unilateral,
                        ja.map(|x| -x),
                        jb.map(|x| -x),
                        (hi - self.angle) * inv_h,
                        RowMeaning::Torque(-f.za),
                    );
                }
            }
            JointKind::LinearActuator { drive, max_force } => {
                let mut ja = neg(a.point_jacobian(&f.pa, &f.za));
                let extra = a.angular_jacobian(&f.za.cross(&dp));
                for k in 3..6 {
                    ja[k] += extra[k];
                }
                let jb = b.point_jacobian(&f.pb, &f.za);
                let lim = max_force * h;
                let s = dp.dot(&f.za);
                spring = Some((ja, jb, s, RowMeaning::Force(f.za)));
                match *drive {
                    Drive::Speed(v) => push(
                        self,
                        PairRowKind::Box { lo: -lim, hi: lim },
                        ja,
                        jb,
                        -v,
                        RowMeaning::Force(f.za),
                    ),
                    Drive::Position(x) => push(
                        self,
                        PairRowKind::Box { lo: -lim, hi: lim },
                        ja,
                        jb,
                        (s - x) * inv_h,
                        RowMeaning::Force(f.za),
                    ),
                    Drive::Effort(_) => {}
                }
            }
            _ => {}
        }
        if let (Some(sp), Some((ja, jb, x, meaning))) = (self.axis_spring, spring) {
            // Backward Euler of F = f_0 - k x - c x_dot as a compliant row (see `AxisSpring`).
            let kc = sp.stiffness * h + sp.damping;
            if kc > 0.0 {
                let rhs = (sp.stiffness * x - sp.preload) / kc;
                let eps = 1.0 / (h * kc);
                if let Some(id) =
                    push_pair_row(rows, PairRowKind::Bilateral, a, &ja, b, &jb, rhs, eps)
                {
                    self.spring_row = Some(self.row_kinds.len());
                    self.row_ids.push(id);
                    self.row_kinds.push(meaning);
                }
            }
        }
    }

    /// Effort drives: the torque/force pair to apply this step, as (world force on B at its
    /// frame origin, world torque on B); A gets the opposite.
    pub(crate) fn effort(&self, bodies: &Bodies) -> Option<EffortLoad> {
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let f = self.frames(a, b);
        match self.kind {
            JointKind::RotationalMotor {
                drive: Drive::Effort(t),
                ..
            } => Some(EffortLoad {
                force: Vector3::zeros(),
                torque: f.za * t,
                point_a: f.pa,
                point_b: f.pb,
            }),
            JointKind::LinearActuator {
                drive: Drive::Effort(force),
                ..
            } => Some(EffortLoad {
                force: f.za * force,
                torque: Vector3::zeros(),
                point_a: f.pa,
                point_b: f.pb,
            }),
            _ => None,
        }
    }
}
