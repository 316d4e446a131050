//! A rotational spring-damper between two bodies about an axis fixed in the first, as an
//! explicit force element. The track assembly no longer uses it for its torsion bars: they
//! are the arm joints' implicit [`chrono_core::AxisSpring`]s, stable at any step (this
//! element's damping diverges on a free arm once `c h / I` passes about 2).
//!
//! With `theta` the rotation of body B relative to body A about the axis since assembly
//! (from the relative rotation's scaled axis, exact for a rotation about that axis, which a
//! revolute joint enforces) and `omega` the relative angular velocity along it, the torque
//!
//! ```text
//! T = T_0 - k theta - c omega
//! ```
//!
//! acts on B about the axis and `-T` on A. It is explicit like every force element
//! ([`chrono_core::force`]): `h sqrt(k / I)` must stay well below 1 (the M113's arms: `k` =
//! 2.5e4 N m/rad on about 10 kg m^2 about the pivot at `h` = 1e-3 s gives 0.05).

use chrono_core::bodies::Bodies;
use chrono_core::force::{BodyLoads, check_body};
use chrono_core::item::StepContext;
use chrono_core::math::{UnitQuaternion, Vector3};
use chrono_core::{BodyHandle, ChronoError, ForceElement};

/// A rotational spring-damper with preload (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct TorsionSpring {
    name: String,
    body_a: BodyHandle,
    body_b: BodyHandle,
    axis_world: Vector3<f64>,
    axis_a: Vector3<f64>,
    rel0: UnitQuaternion<f64>,
    stiffness: f64,
    damping: f64,
    preload: f64,
    angle: f64,
    torque: f64,
}

impl TorsionSpring {
    /// A spring between `a` and `b` about the world axis `axis` (at the bodies' poses when it
    /// is added; the rest angle is that pose), rate `k` (N m/rad), damping `c` (N m s/rad),
    /// preload `t0` (N m).
    pub fn new(
        name: impl Into<String>,
        a: BodyHandle,
        b: BodyHandle,
        axis: Vector3<f64>,
        k: f64,
        c: f64,
        t0: f64,
    ) -> Self {
        Self {
            name: name.into(),
            body_a: a,
            body_b: b,
            axis_world: axis.normalize(),
            axis_a: Vector3::zeros(),
            rel0: UnitQuaternion::identity(),
            stiffness: k,
            damping: c,
            preload: t0,
            angle: 0.0,
            torque: t0,
        }
    }

    /// The rotation from the assembled position at the last evaluation, rad.
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// The torque on B at the last evaluation, N m (about the axis).
    pub fn torque(&self) -> f64 {
        self.torque
    }
}

impl ForceElement for TorsionSpring {
    fn name(&self) -> &str {
        &self.name
    }

    fn body_handles(&self) -> Vec<BodyHandle> {
        vec![self.body_a, self.body_b]
    }

    fn attach(&mut self, bodies: &Bodies) -> chrono_core::Result<()> {
        let f = |s: &str| format!("torsion spring \"{}\".{s}", self.name);
        check_body(&f("body_a"), self.body_a, bodies)?;
        check_body(&f("body_b"), self.body_b, bodies)?;
        for (v, s) in [
            (self.stiffness, "stiffness"),
            (self.damping, "damping"),
            (self.preload, "preload"),
        ] {
            if !v.is_finite() {
                return Err(ChronoError::invalid(f(s), v, "must be finite"));
            }
        }
        if !self.axis_world.iter().all(|c| c.is_finite()) {
            return Err(ChronoError::invalid(
                f("axis"),
                "non-finite",
                "must be non-zero",
            ));
        }
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        self.axis_a = a.rotation().inverse() * self.axis_world;
        self.rel0 = a.rotation().inverse() * b.rotation();
        Ok(())
    }

    fn evaluate(
        &mut self,
        _ctx: &StepContext,
        bodies: &Bodies,
        loads: &mut BodyLoads,
    ) -> chrono_core::Result<()> {
        let (a, b) = (&bodies[self.body_a], &bodies[self.body_b]);
        let qa = a.rotation();
        // B's rotation since assembly, in A's frame.
        let d = (qa.inverse() * b.rotation()) * self.rel0.inverse();
        self.angle = d.scaled_axis().dot(&self.axis_a);
        let axis = qa * self.axis_a;
        let omega = (b.angular_velocity() - a.angular_velocity()).dot(&axis);
        self.torque = self.preload - self.stiffness * self.angle - self.damping * omega;
        loads.add_torque(self.body_b, &(axis * self.torque));
        loads.add_torque(self.body_a, &(-axis * self.torque));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono_core::{JointBuilder, JointKind, RigidBodyBuilder, System, SystemSettings};

    /// A pendulum arm on a revolute joint held by the spring: at rest the spring torque
    /// balances gravity, `k theta = T0 + m g L cos(theta)` ~ `T0 + m g L`.
    #[test]
    fn arm_settles_where_the_spring_balances_gravity() {
        let mut sys = System::new(
            SystemSettings::default(),
            Box::new(chrono_ccp::Schur::new(Default::default())),
        )
        .unwrap();
        let ground = sys.add_body(RigidBodyBuilder::fixed()).unwrap();
        let (m, l) = (10.0, 0.5);
        let arm = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass(m)
                    .inertia_diagonal(Vector3::new(0.1, 0.1, 0.1))
                    .position(Vector3::new(-l, 0.0, 0.0)),
            )
            .unwrap();
        sys.add_joint(JointBuilder::at_axis(
            JointKind::Revolute,
            ground,
            arm,
            Vector3::zeros(),
            Vector3::y(),
        ))
        .unwrap();
        let (k, t0) = (2000.0, -10.0);
        let h = sys
            .add_force_element(Box::new(TorsionSpring::new(
                "bar",
                ground,
                arm,
                Vector3::y(),
                k,
                40.0,
                t0,
            )))
            .unwrap();
        for _ in 0..3000 {
            sys.step(1e-3).unwrap();
        }
        let s = sys.force_element::<TorsionSpring>(h).unwrap();
        // Gravity on the arm at x = -L about +Y: r x F = (-L,0,0) x (0,0,-mg) = (0,-mgL,0).
        let g = sys.settings().gravity.norm();
        let theta = s.angle();
        let want = (t0 - m * g * l * theta.cos()) / k;
        assert!((theta - want).abs() < 1e-4, "{theta} vs {want}");
        assert!((s.torque() - m * g * l * theta.cos()).abs() < 0.05 * m * g * l);
    }
}
