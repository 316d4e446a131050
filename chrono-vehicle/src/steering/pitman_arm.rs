//! Pitman-arm steering: the steering gear turns the Pitman arm about a chassis-fixed axis;
//! the arm moves the steering link (drag link) through a universal joint; an idler arm on
//! the other side holds the link's far end (revolute to the chassis, ball joint on the link);
//! the suspension's tie rods attach to the link.
//!
//! The steering input `s` in `[-1, 1]` sets the Pitman arm's angle to `s * max_angle` by a
//! position-driven rotational motor (one bilateral row in the CCP, exact in one step), so
//! the wheels' angles follow from the linkage's kinematics, not from a formula.
//!
//! Points and axes are given in the steering frame (X forward, Y left, Z up before the
//! frame's pitch), which the vehicle places on the chassis at `location` rotated by
//! `pitch_deg` about Y (the layout of Chrono's `ChPitmanArm`, with its revolute-spherical
//! idler link modelled as a light idler-arm body).

use chrono_core::math::{Isometry3, Point3, UnitQuaternion, Vector3};
use chrono_core::{
    BodyHandle, Drive, JointBuilder, JointHandle, JointKind, RigidBodyBuilder, System,
};
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError, check_positive};
use crate::suspension::double_wishbone::{MassData, frame_along};

/// A Pitman-arm steering's description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PitmanArmData {
    /// Origin of the steering frame in the chassis reference frame, m.
    pub location: [f64; 3],
    /// Rotation of the steering frame about the chassis Y axis, degrees.
    pub pitch_deg: f64,
    /// Steering link (drag link) mass and its center of mass (steering frame, m).
    pub link: MassData,
    /// Center of mass of the steering link, m.
    pub link_cm: [f64; 3],
    /// Pitman arm mass.
    pub arm: MassData,
    /// Center of mass of the Pitman arm, m.
    pub arm_cm: [f64; 3],
    /// Idler arm mass (a light body standing for a massless revolute-spherical link).
    pub idler: MassData,
    /// Pitman arm's revolute joint to the chassis (the steering gear output), m.
    pub revolute: [f64; 3],
    /// Axis of that revolute joint.
    pub revolute_axis: [f64; 3],
    /// Universal joint between the arm and the link, m.
    pub universal: [f64; 3],
    /// Universal joint's axis on the arm.
    pub universal_axis_arm: [f64; 3],
    /// Universal joint's axis on the link.
    pub universal_axis_link: [f64; 3],
    /// Idler arm's revolute joint to the chassis, m.
    pub idler_revolute: [f64; 3],
    /// Axis of the idler arm's revolute joint.
    pub idler_axis: [f64; 3],
    /// Idler arm's ball joint on the link, m.
    pub idler_spherical: [f64; 3],
    /// Pitman arm angle at full steering input, degrees.
    pub max_angle_deg: f64,
}

impl PitmanArmData {
    /// Check every field (the error names it under `field`).
    pub fn validate(&self, field: &str) -> Result<()> {
        self.link.validate(&format!("{field}.link"))?;
        self.arm.validate(&format!("{field}.arm"))?;
        self.idler.validate(&format!("{field}.idler"))?;
        check_positive(&format!("{field}.max_angle_deg"), self.max_angle_deg)?;
        if self.max_angle_deg >= 90.0 {
            return Err(VehicleError::invalid(
                format!("{field}.max_angle_deg"),
                self.max_angle_deg,
                "must be below 90 degrees",
            ));
        }
        for (name, a) in [
            ("revolute_axis", self.revolute_axis),
            ("universal_axis_arm", self.universal_axis_arm),
            ("universal_axis_link", self.universal_axis_link),
            ("idler_axis", self.idler_axis),
        ] {
            let v = Vector3::from(a);
            if !(v.norm().is_finite() && v.norm() > 1e-9) {
                return Err(VehicleError::invalid(
                    format!("{field}.{name}"),
                    format!("{a:?}"),
                    "an axis must be a finite non-zero vector",
                ));
            }
        }
        let u = Vector3::from(self.universal_axis_arm).normalize();
        let v = Vector3::from(self.universal_axis_link).normalize();
        if u.dot(&v).abs() > 1e-6 {
            return Err(VehicleError::invalid(
                format!("{field}.universal_axis_link"),
                format!("{:?}", self.universal_axis_link),
                "must be perpendicular to universal_axis_arm",
            ));
        }
        if !self.pitch_deg.is_finite() {
            return Err(VehicleError::invalid(
                format!("{field}.pitch_deg"),
                self.pitch_deg,
                "must be finite",
            ));
        }
        Ok(())
    }

    /// The steering frame in the chassis reference frame.
    pub fn frame(&self) -> Isometry3<f64> {
        Isometry3::from_parts(
            Vector3::from(self.location).into(),
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), self.pitch_deg.to_radians()),
        )
    }
}

/// A Pitman-arm steering in a system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PitmanArm {
    /// The steering link (the front tie rods' inner ends sit on it).
    pub link: BodyHandle,
    /// The Pitman arm.
    pub arm: BodyHandle,
    /// The idler arm.
    pub idler: BodyHandle,
    /// The steering gear: a position-driven motor on the arm's revolute joint.
    pub motor: JointHandle,
    /// Arm angle at full input, rad.
    pub max_angle: f64,
}

impl PitmanArm {
    /// Build into `sys` on `chassis`, whose reference frame is `chassis_frame` (world).
    pub fn build(
        sys: &mut System,
        name: &str,
        data: &PitmanArmData,
        chassis: BodyHandle,
        chassis_frame: &Isometry3<f64>,
    ) -> Result<Self> {
        data.validate(name)?;
        let frame = chassis_frame * data.frame();
        let w = |a: [f64; 3]| frame.transform_point(&Point3::from(a)).coords;
        let d = |a: [f64; 3]| frame.rotation * Vector3::from(a).normalize();
        let body = |sys: &mut System, part: &str, m: &MassData, at: Vector3<f64>| {
            sys.add_body(
                RigidBodyBuilder::dynamic()
                    .name(format!("{name}.{part}"))
                    .mass(m.mass)
                    .inertia_diagonal(m.inertia_vector())
                    .position(at)
                    .rotation(frame.rotation),
            )
        };
        let link = body(sys, "link", &data.link, w(data.link_cm))?;
        let arm = body(sys, "arm", &data.arm, w(data.arm_cm))?;
        let idler_cm = (w(data.idler_revolute) + w(data.idler_spherical)) * 0.5;
        let idler = body(sys, "idler", &data.idler, idler_cm)?;
        let motor = sys.add_joint(
            JointBuilder::new(
                JointKind::RotationalMotor {
                    drive: Drive::Position(0.0),
                    max_torque: f64::INFINITY,
                    limits: None,
                },
                chassis,
                arm,
                frame_along(w(data.revolute), d(data.revolute_axis)),
            )
            .name(format!("{name}.gear")),
        )?;
        // Universal: the joint frame's x axis is the arm's axis, its y axis the link's.
        let ua = d(data.universal_axis_arm);
        let ul = d(data.universal_axis_link);
        let rot = UnitQuaternion::from_basis_unchecked(&[ua, ul, ua.cross(&ul)]);
        sys.add_joint(
            JointBuilder::new(
                JointKind::Universal,
                arm,
                link,
                Isometry3::from_parts(w(data.universal).into(), rot),
            )
            .name(format!("{name}.universal")),
        )?;
        sys.add_joint(
            JointBuilder::new(
                JointKind::Revolute,
                chassis,
                idler,
                frame_along(w(data.idler_revolute), d(data.idler_axis)),
            )
            .name(format!("{name}.idler_revolute")),
        )?;
        let s = w(data.idler_spherical);
        sys.add_joint(
            JointBuilder::new(
                JointKind::Spherical,
                idler,
                link,
                Isometry3::translation(s.x, s.y, s.z),
            )
            .name(format!("{name}.idler_spherical")),
        )?;
        Ok(Self {
            link,
            arm,
            idler,
            motor,
            max_angle: data.max_angle_deg.to_radians(),
        })
    }

    /// Set the steering input `s` in `[-1, 1]` (clamped; positive turns left): the arm's
    /// angle becomes `-s * max_angle`.
    pub fn set_input(&self, sys: &mut System, s: f64) -> Result<()> {
        let s = if s.is_nan() { 0.0 } else { s.clamp(-1.0, 1.0) };
        sys.joint_mut(self.motor)?
            .set_drive(Drive::Position(-s * self.max_angle))?;
        Ok(())
    }
}
