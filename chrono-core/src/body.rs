//! Rigid bodies.
//!
//! State: center-of-mass position `x` (world, m), orientation `q` (unit quaternion, body to
//! world), linear velocity `v` (world, m/s) and angular velocity `w` (**body frame**, rad/s),
//! as in the seed's generalized speeds: `q_dot = L(q) v` with `x_dot = v`, `R_dot = R [w]x`.
//! The inertia tensor `J` is constant in the body frame, about the center of mass.

use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::descriptor::{BlockId, MassOperator};
use crate::error::{ChronoError, Result, check_finite3, check_positive};
use crate::material::ContactMaterial;
use crate::shape::Shape;

/// Handle of a body in a [`System`](crate::system::System): a slot index and the slot's
/// generation. Removing the body bumps the generation, so the handle goes stale (an error on
/// use) instead of naming whatever body later takes the slot. Get handles from
/// [`System::add_body`](crate::System::add_body) or [`System::body_handles`](crate::System::body_handles).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct BodyHandle {
    index: u32,
    generation: u32,
}

crate::slots::generational_handle!(BodyHandle, "body");

/// How a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BodyMotion {
    /// Moved by forces, contacts and joints.
    Dynamic,
    /// Never moves (the ground).
    Fixed,
    /// Moves with the velocity the user prescribes (infinite mass for everything else):
    /// tank walls, drivers, conveyors.
    Kinematic,
}

/// A collision shape attached to a body.
#[derive(Debug, Clone, PartialEq)]
pub struct ColliderDesc {
    /// The shape.
    pub shape: Shape,
    /// Pose of the shape in the body frame.
    pub local_pose: Isometry3<f64>,
    /// Its surface material.
    pub material: ContactMaterial,
}

/// A rigid body. Create it with [`RigidBodyBuilder`].
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    pub(crate) name: String,
    pub(crate) motion: BodyMotion,
    pub(crate) mass: f64,
    pub(crate) inertia: Matrix3<f64>,
    pub(crate) position: Vector3<f64>,
    pub(crate) rotation: UnitQuaternion<f64>,
    pub(crate) linear_velocity: Vector3<f64>,
    pub(crate) angular_velocity: Vector3<f64>,
    pub(crate) force: Vector3<f64>,
    pub(crate) torque: Vector3<f64>,
    pub(crate) colliders: Vec<ColliderDesc>,
    /// The variable block of a dynamic body during a step.
    pub(crate) block: Option<BlockId>,
    /// Constants derived from the mass and inertia (which never change after `build`),
    /// cached so the step does not rebuild them.
    pub(crate) cached: BodyConstants,
}

/// Per-body constants derived once from the mass and the inertia tensor.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BodyConstants {
    /// `J^-1` (zero if `J` is singular, as the step always treated it).
    pub(crate) inv_inertia: Matrix3<f64>,
    /// `J = j I` exactly (a sphere, a cube): the gyroscopic term vanishes.
    pub(crate) isotropic: bool,
}

impl BodyConstants {
    fn new(inertia: &Matrix3<f64>) -> Self {
        let j = inertia[(0, 0)];
        Self {
            // The inverse `MassOperator::rigid_body` takes (same bits).
            inv_inertia: inertia.try_inverse().unwrap_or_else(Matrix3::zeros),
            isotropic: *inertia == Matrix3::from_diagonal_element(j),
        }
    }
}

impl RigidBody {
    /// The body's name (for messages and output).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Dynamic, fixed or kinematic.
    pub fn motion(&self) -> BodyMotion {
        self.motion
    }
    /// True for dynamic bodies.
    pub fn is_dynamic(&self) -> bool {
        self.motion == BodyMotion::Dynamic
    }
    /// Mass, kg.
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// Body-frame inertia tensor about the center of mass, kg m^2.
    pub fn inertia(&self) -> &Matrix3<f64> {
        &self.inertia
    }
    /// Center-of-mass position (world), m.
    pub fn position(&self) -> Vector3<f64> {
        self.position
    }
    /// Orientation (body to world).
    pub fn rotation(&self) -> UnitQuaternion<f64> {
        self.rotation
    }
    /// The pose (body to world).
    pub fn pose(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.position), self.rotation)
    }
    /// Linear velocity of the center of mass (world), m/s.
    pub fn linear_velocity(&self) -> Vector3<f64> {
        self.linear_velocity
    }
    /// Angular velocity in the body frame, rad/s.
    pub fn angular_velocity_body(&self) -> Vector3<f64> {
        self.angular_velocity
    }
    /// Angular velocity in the world frame, rad/s.
    pub fn angular_velocity(&self) -> Vector3<f64> {
        self.rotation * self.angular_velocity
    }
    /// Angular momentum about the center of mass in the world frame, `R J w`, kg m^2/s.
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.rotation * (self.inertia * self.angular_velocity)
    }
    /// Kinetic energy `1/2 m v.v + 1/2 w.J w`, J.
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass * self.linear_velocity.norm_squared()
            + 0.5
                * self
                    .angular_velocity
                    .dot(&(self.inertia * self.angular_velocity))
    }
    /// Velocity of a world point rigidly attached to the body, m/s.
    pub fn point_velocity(&self, world_point: &Vector3<f64>) -> Vector3<f64> {
        self.linear_velocity
            + self
                .angular_velocity()
                .cross(&(world_point - self.position))
    }
    /// The colliders attached to the body.
    pub fn colliders(&self) -> &[ColliderDesc] {
        &self.colliders
    }
    /// The applied force (world, N, through the center of mass) that acts every step until changed.
    pub fn applied_force(&self) -> Vector3<f64> {
        self.force
    }
    /// The applied torque (world, N m) that acts every step until changed.
    pub fn applied_torque(&self) -> Vector3<f64> {
        self.torque
    }

    /// Set the applied force (world, N, at the center of mass).
    pub fn set_applied_force(&mut self, f: Vector3<f64>) -> Result<()> {
        check_finite3("body.force", &f)?;
        self.force = f;
        Ok(())
    }
    /// Set the applied torque (world, N m).
    pub fn set_applied_torque(&mut self, t: Vector3<f64>) -> Result<()> {
        check_finite3("body.torque", &t)?;
        self.torque = t;
        Ok(())
    }
    /// Set the linear velocity (world, m/s); for kinematic bodies this is the prescribed motion.
    pub fn set_linear_velocity(&mut self, v: Vector3<f64>) -> Result<()> {
        check_finite3("body.linear_velocity", &v)?;
        self.linear_velocity = v;
        Ok(())
    }
    /// Set the angular velocity given in the world frame, rad/s.
    pub fn set_angular_velocity(&mut self, w_world: Vector3<f64>) -> Result<()> {
        check_finite3("body.angular_velocity", &w_world)?;
        self.angular_velocity = self.rotation.inverse() * w_world;
        Ok(())
    }
    /// Set the pose (e.g. to reset a scene).
    pub fn set_pose(
        &mut self,
        position: Vector3<f64>,
        rotation: UnitQuaternion<f64>,
    ) -> Result<()> {
        check_finite3("body.position", &position)?;
        if rotation.coords.iter().any(|c| !c.is_finite()) {
            return Err(ChronoError::invalid(
                "body.rotation",
                format!("{:?}", rotation.coords),
                "must be finite",
            ));
        }
        self.position = position;
        self.rotation = rotation;
        Ok(())
    }

    /// The body's 6-dof variable block in the current step (`None` for fixed and kinematic
    /// bodies, which have no variables, and outside a step's assembly). Rows that tie an
    /// item to a body (shafts, attachments) put the body's Jacobian on this block.
    pub fn block(&self) -> Option<BlockId> {
        self.block
    }

    /// The mass operator of this body's 6-dof variable block.
    pub fn mass_operator(&self) -> Result<MassOperator> {
        match self.motion {
            // Checked by `build`; mass and inertia never change after it.
            BodyMotion::Dynamic => Ok(MassOperator::RigidBody {
                mass: self.mass,
                inertia: self.inertia,
                inv_inertia: self.cached.inv_inertia,
            }),
            _ => MassOperator::rigid_body(self.mass, self.inertia),
        }
    }

    /// The 6 Jacobian coefficients of `d . (velocity of the world point p)` with respect to the
    /// body's generalized velocity `[v; w_body]`: `[d; r_b x (R' d)]` with `r_b = R'(p - x)`.
    #[inline]
    pub fn point_jacobian(&self, p: &Vector3<f64>, d: &Vector3<f64>) -> [f64; 6] {
        let rinv = self.rotation.inverse();
        let rb = rinv * (p - self.position);
        let a = rb.cross(&(rinv * d));
        [d.x, d.y, d.z, a.x, a.y, a.z]
    }

    /// [`point_jacobian`](Self::point_jacobian) for several directions at one point: the
    /// rotation's inverse and the body-frame arm computed once (the same operations per
    /// direction, so the same bits as one call per direction).
    #[inline]
    pub fn point_jacobians<const K: usize>(
        &self,
        p: &Vector3<f64>,
        dirs: &[Vector3<f64>; K],
    ) -> [[f64; 6]; K] {
        arm_jacobians(&self.rotation, &(p - self.position), dirs)
    }

    /// The 6 Jacobian coefficients of `a . w_world`: `[0; R' a]`.
    #[inline]
    pub fn angular_jacobian(&self, a: &Vector3<f64>) -> [f64; 6] {
        let b = self.rotation.inverse() * a;
        [0.0, 0.0, 0.0, b.x, b.y, b.z]
    }

    /// `J . [v; w_body]`: the value a Jacobian row takes on this body's current velocity.
    #[inline]
    pub fn jacobian_times_velocity(&self, j: &[f64; 6]) -> f64 {
        let v = &self.linear_velocity;
        let w = &self.angular_velocity;
        j[0] * v.x + j[1] * v.y + j[2] * v.z + j[3] * w.x + j[4] * w.y + j[5] * w.z
    }

    /// The momentum of the free (unconstrained) step, `k = M v + h f`, for the 6 dof.
    ///
    /// Linear: `m v + h (f + m g)`. Angular (body frame): the torque-free part of Euler's
    /// equations `J w_dot = tau - w x J w` is taken so that the world angular momentum is
    /// conserved exactly by the step: with the pose update `R+ = R exp(h [w+])`, the
    /// body-frame momentum must rotate back, `J w+ = exp(-h [w+]) (J w + h tau_b)`. This
    /// implicit equation is solved by fixed-point iteration (a contraction for `h |w|`
    /// well below 1; a few iterations to round-off), started from the explicit value.
    /// `k_ang = J w+`. For an isotropic inertia `J = j I` (spheres) the fixed point is
    /// `w+ = J^-1 l0` exactly (the rotation is about `l0` itself), so `k_ang = l0` without
    /// iterating. Explicit gyroscopic terms gain energy; the one-Newton-step implicit
    /// form loses momentum; this form keeps `R J w` to round-off and the energy bounded.
    ///
    /// `extra` is a load of this step (world force through the center of mass, world torque)
    /// added to the body's applied force and torque: contacts (SMC), force elements, joint
    /// efforts.
    pub(crate) fn free_momentum(
        &self,
        h: f64,
        gravity: &Vector3<f64>,
        extra: &[Vector3<f64>; 2],
        out: &mut [f64],
    ) {
        let f = self.force + extra[0];
        let tau = self.torque + extra[1];
        let lin = self.mass * self.linear_velocity + h * (f + self.mass * gravity);
        let l0 = self.inertia * self.angular_velocity + h * (self.rotation.inverse() * tau);
        // With `J = j I` the fixed point is `w+ = l0 / j` exactly (the rotation
        // `exp(-h [w+])` is about `l0` itself), so `k_ang = J w+ = l0`.
        let ang = if self.cached.isotropic {
            l0
        } else {
            self.gyroscopic_momentum(h, &l0)
        };
        out[..3].copy_from_slice(lin.as_slice());
        out[3..6].copy_from_slice(ang.as_slice());
    }

    /// `J w+` with `J w+ = exp(-h [w+]) l0`, by fixed-point iteration from `J^-1 l0`.
    fn gyroscopic_momentum(&self, h: f64, l0: &Vector3<f64>) -> Vector3<f64> {
        let jinv = &self.cached.inv_inertia;
        let mut w = jinv * l0;
        for _ in 0..50 {
            let next = jinv * (UnitQuaternion::from_scaled_axis(-h * w) * l0);
            let change = (next - w).norm();
            w = next;
            if change <= 1e-15 * (1.0 + w.norm()) {
                break;
            }
        }
        self.inertia * w
    }

    /// `J^-1`, cached (zero for a singular `J`).
    #[inline]
    pub(crate) fn inv_inertia(&self) -> &Matrix3<f64> {
        &self.cached.inv_inertia
    }

    /// Advance the pose with the new velocities: `x += h v`, `q = q exp(h w / 2)`.
    pub(crate) fn integrate_pose(&mut self, h: f64) {
        self.position += h * self.linear_velocity;
        self.rotation = crate::math::integrate_rotation(&self.rotation, &self.angular_velocity, h);
    }

    /// True if every state component is finite.
    pub(crate) fn state_is_finite(&self) -> bool {
        crate::math::is_finite3(&self.position)
            && crate::math::is_finite3(&self.linear_velocity)
            && crate::math::is_finite3(&self.angular_velocity)
            && self.rotation.coords.iter().all(|c| c.is_finite())
    }
}

/// Builder of a [`RigidBody`]; [`build`](Self::build) checks every field.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBodyBuilder {
    name: String,
    motion: BodyMotion,
    mass: f64,
    inertia: Matrix3<f64>,
    position: Vector3<f64>,
    rotation: UnitQuaternion<f64>,
    linear_velocity: Vector3<f64>,
    angular_velocity_world: Vector3<f64>,
    colliders: Vec<ColliderDesc>,
}

impl RigidBodyBuilder {
    fn with_motion(motion: BodyMotion) -> Self {
        Self {
            name: String::new(),
            motion,
            mass: 1.0,
            inertia: Matrix3::identity(),
            position: Vector3::zeros(),
            rotation: UnitQuaternion::identity(),
            linear_velocity: Vector3::zeros(),
            angular_velocity_world: Vector3::zeros(),
            colliders: Vec::new(),
        }
    }
    /// A dynamic body (default mass 1 kg, unit inertia: set them).
    pub fn dynamic() -> Self {
        Self::with_motion(BodyMotion::Dynamic)
    }
    /// A fixed body.
    pub fn fixed() -> Self {
        Self::with_motion(BodyMotion::Fixed)
    }
    /// A kinematic body (moves with its prescribed velocity).
    pub fn kinematic() -> Self {
        Self::with_motion(BodyMotion::Kinematic)
    }
    /// Name for messages and output.
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }
    /// Mass, kg (> 0).
    pub fn mass(mut self, mass: f64) -> Self {
        self.mass = mass;
        self
    }
    /// Principal moments of inertia about the center of mass in the body frame, kg m^2.
    pub fn inertia_diagonal(mut self, i: Vector3<f64>) -> Self {
        self.inertia = Matrix3::from_diagonal(&i);
        self
    }
    /// Full body-frame inertia tensor about the center of mass, kg m^2 (symmetric positive definite).
    pub fn inertia(mut self, j: Matrix3<f64>) -> Self {
        self.inertia = j;
        self
    }
    /// Mass and inertia of a solid `shape` of uniform `density` (kg/m^3), e.g. a box.
    /// An error if the shape has no closed-form inertia (meshes, half-spaces).
    pub fn mass_from_shape(mut self, shape: &Shape, density: f64) -> Result<Self> {
        check_positive("density", density)?;
        shape.validate("shape")?;
        let no_closed_form =
            || ChronoError::invalid("shape", format!("{shape:?}"), "has no closed-form inertia");
        let unit = shape.unit_inertia().ok_or_else(no_closed_form)?;
        let volume = shape.volume().ok_or_else(no_closed_form)?;
        self.mass = density * volume;
        self.inertia = Matrix3::from_diagonal(&(unit * self.mass));
        Ok(self)
    }
    /// Initial center-of-mass position (world), m.
    pub fn position(mut self, p: Vector3<f64>) -> Self {
        self.position = p;
        self
    }
    /// Initial orientation (body to world).
    pub fn rotation(mut self, q: UnitQuaternion<f64>) -> Self {
        self.rotation = q;
        self
    }
    /// Initial linear velocity (world), m/s.
    pub fn linear_velocity(mut self, v: Vector3<f64>) -> Self {
        self.linear_velocity = v;
        self
    }
    /// Initial angular velocity given in the world frame, rad/s.
    pub fn angular_velocity(mut self, w: Vector3<f64>) -> Self {
        self.angular_velocity_world = w;
        self
    }
    /// Attach a collision shape at `local_pose` in the body frame.
    pub fn collider(
        mut self,
        shape: Shape,
        local_pose: Isometry3<f64>,
        material: ContactMaterial,
    ) -> Self {
        self.colliders.push(ColliderDesc {
            shape,
            local_pose,
            material,
        });
        self
    }

    /// Check every field and make the body. Errors name the field (`body.mass`,
    /// `body.inertia`, `body.position`, `body.colliders[2].shape.radius` ...).
    pub fn build(self) -> Result<RigidBody> {
        let field = |f: &str| {
            if self.name.is_empty() {
                format!("body.{f}")
            } else {
                format!("body \"{}\".{f}", self.name)
            }
        };
        if self.motion == BodyMotion::Dynamic {
            check_positive(&field("mass"), self.mass)?;
            crate::descriptor::MassOperator::rigid_body(self.mass, self.inertia).map_err(|e| {
                match e {
                    ChronoError::InvalidParameter {
                        field: f,
                        value,
                        reason,
                    } => ChronoError::InvalidParameter {
                        field: field(&f),
                        value,
                        reason,
                    },
                    other => other,
                }
            })?;
        }
        check_finite3(&field("position"), &self.position)?;
        check_finite3(&field("linear_velocity"), &self.linear_velocity)?;
        check_finite3(&field("angular_velocity"), &self.angular_velocity_world)?;
        if self.rotation.coords.iter().any(|c| !c.is_finite()) {
            return Err(ChronoError::invalid(
                field("rotation"),
                format!("{:?}", self.rotation.coords),
                "must be finite",
            ));
        }
        for (i, c) in self.colliders.iter().enumerate() {
            c.shape.validate(&field(&format!("colliders[{i}].shape")))?;
            c.material.validate().map_err(|e| match e {
                ChronoError::InvalidParameter {
                    field: f,
                    value,
                    reason,
                } => ChronoError::InvalidParameter {
                    field: field(&format!("colliders[{i}].{f}")),
                    value,
                    reason,
                },
                other => other,
            })?;
        }
        let (mass, inertia) = match self.motion {
            BodyMotion::Dynamic => (self.mass, self.inertia),
            // Fixed and kinematic bodies have no variables; keep finite placeholders.
            _ => (self.mass.max(f64::MIN_POSITIVE), self.inertia),
        };
        let angular_velocity = self.rotation.inverse() * self.angular_velocity_world;
        let linear_velocity = if self.motion == BodyMotion::Fixed {
            Vector3::zeros()
        } else {
            self.linear_velocity
        };
        let angular_velocity = if self.motion == BodyMotion::Fixed {
            Vector3::zeros()
        } else {
            angular_velocity
        };
        let cached = BodyConstants::new(&inertia);
        Ok(RigidBody {
            name: self.name,
            motion: self.motion,
            mass,
            inertia,
            position: self.position,
            rotation: self.rotation,
            linear_velocity,
            angular_velocity,
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            colliders: self.colliders,
            block: None,
            cached,
        })
    }
}

/// The rows `[d; (R' r) x (R' d)]` of the directions `dirs` at the world arm `r` (from the
/// centre of mass to the point) of a rigid body with rotation `R`: the Jacobian of
/// `d . (v + w x r)` with respect to `[v; w_body]` ([`RigidBody::point_jacobians`], and the
/// frame-only contact rows built from their geometry: the same operations, so the same bits).
#[inline]
pub(crate) fn arm_jacobians<const K: usize>(
    rotation: &UnitQuaternion<f64>,
    arm: &Vector3<f64>,
    dirs: &[Vector3<f64>; K],
) -> [[f64; 6]; K] {
    let rinv = rotation.inverse();
    let rb = rinv * arm;
    dirs.map(|d| {
        let a = rb.cross(&(rinv * d));
        [d.x, d.y, d.z, a.x, a.y, a.z]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builder_rejects_bad_input_naming_the_field() {
        let e = RigidBodyBuilder::dynamic()
            .name("box")
            .mass(-2.0)
            .build()
            .unwrap_err()
            .to_string();
        assert!(e.contains("body \"box\".mass") && e.contains("-2"), "{e}");
        let e = RigidBodyBuilder::dynamic()
            .inertia_diagonal(Vector3::new(1.0, 0.0, 1.0))
            .build()
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("inertia") && e.contains("positive definite"),
            "{e}"
        );
        let e = RigidBodyBuilder::dynamic()
            .position(Vector3::new(0.0, f64::NAN, 0.0))
            .build()
            .unwrap_err();
        assert!(e.to_string().contains("body.position"), "{e}");
        // fixed bodies need no mass
        assert!(RigidBodyBuilder::fixed().mass(0.0).build().is_ok());
    }

    #[test]
    fn point_jacobian_gives_point_velocity() {
        let b = RigidBodyBuilder::dynamic()
            .position(Vector3::new(1.0, 2.0, 3.0))
            .rotation(UnitQuaternion::from_euler_angles(0.3, -0.2, 0.7))
            .linear_velocity(Vector3::new(0.1, -0.4, 0.2))
            .angular_velocity(Vector3::new(1.0, 0.5, -2.0))
            .build()
            .unwrap();
        let p = Vector3::new(1.5, 1.0, 3.2);
        let d = Vector3::new(0.2, -0.3, 0.9).normalize();
        let j = b.point_jacobian(&p, &d);
        assert!((b.jacobian_times_velocity(&j) - d.dot(&b.point_velocity(&p))).abs() < 1e-12);
        let ja = b.angular_jacobian(&d);
        assert!((b.jacobian_times_velocity(&ja) - d.dot(&b.angular_velocity())).abs() < 1e-12);
    }

    #[test]
    fn free_momentum_of_torque_free_symmetric_spin_is_unchanged() {
        let b = RigidBodyBuilder::dynamic()
            .inertia_diagonal(Vector3::new(1.0, 1.0, 2.0))
            .angular_velocity(Vector3::new(0.0, 0.0, 3.0))
            .build()
            .unwrap();
        let mut k = [0.0; 6];
        b.free_momentum(0.01, &Vector3::zeros(), &[Vector3::zeros(); 2], &mut k);
        assert!((k[5] - 6.0).abs() < 1e-12 && k[3].abs() < 1e-12 && k[4].abs() < 1e-12);
    }

    proptest::proptest! {
        /// The isotropic fast path (`k_ang = l0`) equals the fixed-point iteration it
        /// replaces to round-off (the iteration stops at a relative change of 1e-15).
        #[test]
        fn isotropic_fast_path_matches_the_fixed_point(
            j in 1e-4..10.0f64,
            w in proptest::array::uniform3(-50.0..50.0f64),
            tau in proptest::array::uniform3(-5.0..5.0f64),
            euler in proptest::array::uniform3(-3.0..3.0f64),
            h in 1e-5..2e-3f64,
        ) {
            let mut b = RigidBodyBuilder::dynamic()
                .inertia_diagonal(Vector3::repeat(j))
                .rotation(UnitQuaternion::from_euler_angles(euler[0], euler[1], euler[2]))
                .angular_velocity(Vector3::from(w))
                .build()
                .unwrap();
            proptest::prop_assert!(b.cached.isotropic);
            b.torque = Vector3::from(tau);
            let mut fast = [0.0; 6];
            b.free_momentum(h, &Vector3::zeros(), &[Vector3::zeros(); 2], &mut fast);
            let l0 = b.inertia * b.angular_velocity + h * (b.rotation.inverse() * b.torque);
            let slow = b.gyroscopic_momentum(h, &l0);
            let fast = Vector3::new(fast[3], fast[4], fast[5]);
            proptest::prop_assert!(
                (fast - slow).norm() <= 1e-13 * (1.0 + l0.norm()),
                "{fast} vs {slow}"
            );
        }
    }

    #[test]
    fn constants_are_cached_at_build() {
        let b = RigidBodyBuilder::dynamic()
            .mass(2.0)
            .inertia_diagonal(Vector3::new(1.0, 2.0, 4.0))
            .build()
            .unwrap();
        assert!(!b.cached.isotropic);
        assert_eq!(*b.inv_inertia(), b.inertia.try_inverse().unwrap());
        assert_eq!(
            b.mass_operator().unwrap(),
            MassOperator::rigid_body(2.0, b.inertia).unwrap()
        );
    }
}

/// Push one row coupling two bodies: `ja . u_a + jb . u_b + rhs`, where a non-dynamic body's
/// (known) velocity goes into the right-hand side instead of an entry. Returns `None` if
/// neither body is dynamic (the row would constrain nothing).
pub(crate) fn push_pair_row(
    rows: &mut crate::descriptor::ConstraintRows,
    kind: PairRowKind,
    a: &RigidBody,
    ja: &[f64; 6],
    b: &RigidBody,
    jb: &[f64; 6],
    mut rhs: f64,
    eps: f64,
) -> Option<crate::descriptor::RowId> {
    use crate::descriptor::RowEntry;
    let mut buf = [RowEntry {
        block: BlockId(0),
        coefs: &[],
    }; 2];
    let mut n = 0;
    for (body, j) in [(a, ja), (b, jb)] {
        match body.block {
            Some(block) => {
                buf[n] = RowEntry { block, coefs: j };
                n += 1;
            }
            None => rhs += body.jacobian_times_velocity(j),
        }
    }
    if n == 0 {
        return None;
    }
    let entries = &buf[..n];
    Some(match kind {
        PairRowKind::Bilateral => rows.push_bilateral(entries, rhs, eps),
        PairRowKind::Unilateral => rows.push_unilateral(entries, rhs, eps),
        PairRowKind::Box { lo, hi } => rows.push_box(entries, rhs, eps, lo, hi),
    })
}

/// The kind of a row made by [`push_pair_row`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum PairRowKind {
    Bilateral,
    Unilateral,
    Box { lo: f64, hi: f64 },
}
