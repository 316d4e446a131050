//! The double wishbone (double A-arm) suspension: per side an upper and a lower control arm
//! hinged to the chassis, an upright on ball joints at the arms' outer ends, a spindle (the
//! wheel carrier) on a revolute joint in the upright, a tie rod that fixes the upright's
//! steer angle, and a spring and a shock between the lower arm and the chassis.
//!
//! | connection | joint |
//! |---|---|
//! | upper/lower arm – chassis | revolute about the line through the arm's front and back pivots |
//! | upper/lower arm – upright | spherical at the arm's outer point |
//! | spindle – upright | revolute about the vehicle's Y axis (the wheel's spin axis) |
//! | tie rod | distance between the inner point (on the chassis or the steering link) and the upright |
//! | spring, shock | [`SpringDamper`] between the chassis and the lower arm |
//!
//! Hardpoints are given for the left side in the suspension frame (X forward, Y left, Z up,
//! origin where the vehicle puts the suspension, typically midway between the lower arms'
//! chassis pivots); the right side mirrors them (`y -> -y`). This is the layout of Chrono's
//! `ChDoubleWishbone` template with its massless tie rod (a distance constraint).

use chrono_core::force::ForceHandle;
use chrono_core::math::{Isometry3, Point3, Vector3};
use chrono_core::{
    BodyHandle, ContactMaterial, Curve, JointBuilder, JointHandle, JointKind, RigidBodyBuilder,
    Shape, SpringDamper, System,
};
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError, check_non_negative, check_positive};

/// Mass (kg) and principal moments of inertia about the center of mass (kg m^2, along the
/// vehicle axes at assembly) of a body of a template.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MassData {
    /// Mass, kg.
    pub mass: f64,
    /// Principal moments of inertia `(Ixx, Iyy, Izz)`, kg m^2.
    pub inertia: [f64; 3],
}

impl MassData {
    /// Check the fields (the error names `field`).
    pub fn validate(&self, field: &str) -> Result<()> {
        check_positive(&format!("{field}.mass"), self.mass)?;
        for (i, c) in ["ixx", "iyy", "izz"].iter().enumerate() {
            check_positive(&format!("{field}.inertia.{c}"), self.inertia[i])?;
        }
        Ok(())
    }

    /// The inertia as a vector.
    pub fn inertia_vector(&self) -> Vector3<f64> {
        Vector3::from(self.inertia)
    }
}

/// The hardpoints of the left side, in the suspension frame, m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WishbonePoints {
    /// Spindle (wheel center) and the spindle's center of mass.
    pub spindle: [f64; 3],
    /// Upright center of mass.
    pub upright: [f64; 3],
    /// Upper arm: front chassis pivot.
    pub uca_front: [f64; 3],
    /// Upper arm: back chassis pivot.
    pub uca_back: [f64; 3],
    /// Upper arm: ball joint on the upright.
    pub uca_upright: [f64; 3],
    /// Upper arm center of mass.
    pub uca_cm: [f64; 3],
    /// Lower arm: front chassis pivot.
    pub lca_front: [f64; 3],
    /// Lower arm: back chassis pivot.
    pub lca_back: [f64; 3],
    /// Lower arm: ball joint on the upright.
    pub lca_upright: [f64; 3],
    /// Lower arm center of mass.
    pub lca_cm: [f64; 3],
    /// Spring: chassis end.
    pub spring_chassis: [f64; 3],
    /// Spring: lower-arm end.
    pub spring_arm: [f64; 3],
    /// Shock: chassis end.
    pub shock_chassis: [f64; 3],
    /// Shock: lower-arm end.
    pub shock_arm: [f64; 3],
    /// Tie rod: inner end (on the steering link, or on the chassis for an unsteered axle).
    pub tierod_inner: [f64; 3],
    /// Tie rod: outer end on the upright.
    pub tierod_upright: [f64; 3],
}

/// The spring: restoring force (N) against deflection `l - l0` (m, positive = extension).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringData {
    /// Free length `l0`, m.
    pub rest_length: f64,
    /// Restoring force against deflection (a table; extrapolated as the table says).
    pub force: Curve,
    /// Bump and rebound stops on the spring's length.
    #[serde(default)]
    pub stops: Option<StopsData>,
}

/// Bump and rebound stops: below `min_length` (bump) and above `max_length` (rebound) an
/// elastomer pushes back with `force(penetration)` (N against m, penetration >= 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopsData {
    /// Spring length at which the bump stop engages, m.
    pub min_length: f64,
    /// Spring length at which the rebound stop engages, m.
    pub max_length: f64,
    /// Stop force against penetration (table from 0).
    pub force: Curve,
}

impl StopsData {
    /// The stops as one spring curve over the deflection `x = l - max_length` of a spring
    /// whose rest length is `max_length`: zero on `[min_length - max_length, 0]`, the stop
    /// table outside (restoring: negative in bump, positive in rebound).
    pub fn spring_curve(&self, field: &str) -> Result<Curve> {
        let free = self.min_length - self.max_length;
        let pts = self.force.points();
        let mut out: Vec<[f64; 2]> = pts
            .iter()
            .rev()
            .filter(|p| p[0] > 0.0)
            .map(|p| [free - p[0], -p[1]])
            .collect();
        out.push([free, 0.0]);
        out.push([0.0, 0.0]);
        out.extend(pts.iter().filter(|p| p[0] > 0.0).map(|p| [p[0], p[1]]));
        Ok(Curve::new(field, out, chrono_core::Extrapolation::Linear)?)
    }
}

/// The shock: damping force (N) against the rate of extension (m/s, positive = rebound),
/// with optional hydraulic bump stops outside a length range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShockData {
    /// Damping force against extension rate in mid-stroke.
    pub force: Curve,
    /// Hydraulic bump stops: `[min_length, max_length]` (m) and the damping curve outside.
    #[serde(default)]
    pub bump: Option<BumpData>,
}

/// The damping curve of a shock outside its mid-stroke length range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BumpData {
    /// Shorter than this (m), the bump curve acts.
    pub min_length: f64,
    /// Longer than this (m), the bump curve acts.
    pub max_length: f64,
    /// Damping force against extension rate outside the range.
    pub force: Curve,
}

/// A double wishbone suspension's description (both sides, mirrored).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DoubleWishboneData {
    /// Left-side hardpoints in the suspension frame.
    pub points: WishbonePoints,
    /// Spindle (without the wheel and tire, which the vehicle adds).
    pub spindle: MassData,
    /// Upright.
    pub upright: MassData,
    /// Upper control arm.
    pub upper_arm: MassData,
    /// Lower control arm.
    pub lower_arm: MassData,
    /// Spring.
    pub spring: SpringData,
    /// Shock absorber.
    pub shock: ShockData,
}

impl DoubleWishboneData {
    /// Check every field (the error names it under `field`).
    pub fn validate(&self, field: &str) -> Result<()> {
        self.spindle.validate(&format!("{field}.spindle"))?;
        self.upright.validate(&format!("{field}.upright"))?;
        self.upper_arm.validate(&format!("{field}.upper_arm"))?;
        self.lower_arm.validate(&format!("{field}.lower_arm"))?;
        check_positive(
            &format!("{field}.spring.rest_length"),
            self.spring.rest_length,
        )?;
        self.spring
            .force
            .validate(&format!("{field}.spring.force"))?;
        if let Some(st) = &self.spring.stops {
            check_positive(&format!("{field}.spring.stops.min_length"), st.min_length)?;
            if !(st.max_length.is_finite() && st.max_length > st.min_length) {
                return Err(VehicleError::invalid(
                    format!("{field}.spring.stops.max_length"),
                    st.max_length,
                    format!("must be finite and > min_length = {}", st.min_length),
                ));
            }
            st.force.validate(&format!("{field}.spring.stops.force"))?;
            if st.force.points()[0] != [0.0, 0.0] {
                return Err(VehicleError::invalid(
                    format!("{field}.spring.stops.force.points[0]"),
                    format!("{:?}", st.force.points()[0]),
                    "a stop table starts at [0, 0] (no force at contact)",
                ));
            }
        }
        self.shock.force.validate(&format!("{field}.shock.force"))?;
        if let Some(b) = &self.shock.bump {
            check_non_negative(&format!("{field}.shock.bump.min_length"), b.min_length)?;
            if !(b.max_length.is_finite() && b.max_length > b.min_length) {
                return Err(VehicleError::invalid(
                    format!("{field}.shock.bump.max_length"),
                    b.max_length,
                    format!("must be finite and > min_length = {}", b.min_length),
                ));
            }
            b.force.validate(&format!("{field}.shock.bump.force"))?;
        }
        let p = &self.points;
        for (name, a, b) in [
            ("uca_back", p.uca_front, p.uca_back),
            ("lca_back", p.lca_front, p.lca_back),
            ("spring_arm", p.spring_chassis, p.spring_arm),
            ("shock_arm", p.shock_chassis, p.shock_arm),
            ("tierod_upright", p.tierod_inner, p.tierod_upright),
        ] {
            if (Vector3::from(a) - Vector3::from(b)).norm() < 1e-6 {
                return Err(VehicleError::invalid(
                    format!("{field}.points.{name}"),
                    format!("{b:?}"),
                    "coincides with the other end of its axis or link",
                ));
            }
        }
        let all = [
            p.spindle,
            p.upright,
            p.uca_front,
            p.uca_back,
            p.uca_upright,
            p.uca_cm,
            p.lca_front,
            p.lca_back,
            p.lca_upright,
            p.lca_cm,
            p.spring_chassis,
            p.spring_arm,
            p.shock_chassis,
            p.shock_arm,
            p.tierod_inner,
            p.tierod_upright,
        ];
        if all.iter().flatten().any(|c| !c.is_finite()) {
            return Err(VehicleError::invalid(
                format!("{field}.points"),
                "non-finite",
                "every hardpoint must be finite",
            ));
        }
        Ok(())
    }
}

/// What the vehicle mounts on a spindle: the wheel's and tire's mass (added to the spindle
/// body) and, for a rigid tire, its collision shape.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelMount {
    /// Wheel plus tire mass and inertia (added to the spindle's).
    pub mass: MassData,
    /// A collider on the spindle body (shape, pose in the spindle frame, material): the
    /// rigid tire's cylinder. `None` for a handling tire (a force element).
    pub collider: Option<(Shape, Isometry3<f64>, ContactMaterial)>,
}

/// The bodies, joints and force elements of one side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WishboneSide {
    /// The spindle (carries the wheel and tire).
    pub spindle: BodyHandle,
    /// The upright.
    pub upright: BodyHandle,
    /// The upper control arm.
    pub upper_arm: BodyHandle,
    /// The lower control arm.
    pub lower_arm: BodyHandle,
    /// The spindle's revolute joint in the upright.
    pub spindle_joint: JointHandle,
    /// The tie rod (distance constraint).
    pub tierod: JointHandle,
    /// The spring.
    pub spring: ForceHandle,
    /// The shock.
    pub shock: ForceHandle,
    /// The bump and rebound stops (if any).
    pub stops: Option<ForceHandle>,
}

/// A double wishbone suspension in a system: `sides[0]` left, `sides[1]` right.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoubleWishbone {
    /// Left and right.
    pub sides: [WishboneSide; 2],
}

/// A frame with its z axis along `axis` at `origin` (world).
pub(crate) fn frame_along(origin: Vector3<f64>, axis: Vector3<f64>) -> Isometry3<f64> {
    let rot = chrono_core::math::UnitQuaternion::rotation_between(&Vector3::z(), &axis)
        .unwrap_or_else(|| {
            chrono_core::math::UnitQuaternion::from_axis_angle(
                &Vector3::x_axis(),
                std::f64::consts::PI,
            )
        });
    Isometry3::from_parts(origin.into(), rot)
}

impl DoubleWishbone {
    /// Build both sides into `sys`. `frame` is the suspension frame in the world (the
    /// chassis pose times the suspension's location); `tierod_body` is the body the tie rods'
    /// inner ends sit on (the steering link, or the chassis); `wheel` is mounted on each
    /// spindle. Bodies start with the suspension frame's orientation.
    pub fn build(
        sys: &mut System,
        name: &str,
        data: &DoubleWishboneData,
        chassis: BodyHandle,
        frame: &Isometry3<f64>,
        tierod_body: BodyHandle,
        wheel: &WheelMount,
    ) -> Result<Self> {
        data.validate(name)?;
        wheel.mass.validate(&format!("{name}.wheel"))?;
        let left = Self::build_side(
            sys,
            name,
            "left",
            1.0,
            data,
            chassis,
            frame,
            tierod_body,
            wheel,
        )?;
        let right = Self::build_side(
            sys,
            name,
            "right",
            -1.0,
            data,
            chassis,
            frame,
            tierod_body,
            wheel,
        )?;
        Ok(Self {
            sides: [left, right],
        })
    }

    fn build_side(
        sys: &mut System,
        name: &str,
        side: &str,
        mirror: f64,
        data: &DoubleWishboneData,
        chassis: BodyHandle,
        frame: &Isometry3<f64>,
        tierod_body: BodyHandle,
        wheel: &WheelMount,
    ) -> Result<WishboneSide> {
        let p = &data.points;
        let w = |a: [f64; 3]| -> Vector3<f64> {
            frame
                .transform_point(&Point3::new(a[0], mirror * a[1], a[2]))
                .coords
        };
        let dir = |a: [f64; 3], b: [f64; 3]| (w(b) - w(a)).normalize();
        let rot = frame.rotation;
        let label = |part: &str| format!("{name}.{side}.{part}");
        let body = |sys: &mut System, part: &str, m: &MassData, at: [f64; 3]| {
            sys.add_body(
                RigidBodyBuilder::dynamic()
                    .name(label(part))
                    .mass(m.mass)
                    .inertia_diagonal(m.inertia_vector())
                    .position(w(at))
                    .rotation(rot),
            )
        };
        let upright = body(sys, "upright", &data.upright, p.upright)?;
        let uca = body(sys, "upper_arm", &data.upper_arm, p.uca_cm)?;
        let lca = body(sys, "lower_arm", &data.lower_arm, p.lca_cm)?;
        let spindle_mass = MassData {
            mass: data.spindle.mass + wheel.mass.mass,
            inertia: [0, 1, 2].map(|i| data.spindle.inertia[i] + wheel.mass.inertia[i]),
        };
        let mut sb = RigidBodyBuilder::dynamic()
            .name(label("spindle"))
            .mass(spindle_mass.mass)
            .inertia_diagonal(spindle_mass.inertia_vector())
            .position(w(p.spindle))
            .rotation(rot);
        if let Some((shape, pose, mat)) = &wheel.collider {
            sb = sb.collider(shape.clone(), *pose, *mat);
        }
        let spindle = sys.add_body(sb)?;

        let joint = |sys: &mut System, part: &str, b: JointBuilder| -> Result<JointHandle> {
            Ok(sys.add_joint(b.name(label(part)))?)
        };
        let spin_axis = rot * Vector3::y();
        let spindle_joint = joint(
            sys,
            "spindle_revolute",
            JointBuilder::new(
                JointKind::Revolute,
                upright,
                spindle,
                frame_along(w(p.spindle), spin_axis),
            ),
        )?;
        joint(
            sys,
            "uca_revolute",
            JointBuilder::new(
                JointKind::Revolute,
                chassis,
                uca,
                frame_along(
                    (w(p.uca_front) + w(p.uca_back)) * 0.5,
                    dir(p.uca_front, p.uca_back),
                ),
            ),
        )?;
        joint(
            sys,
            "lca_revolute",
            JointBuilder::new(
                JointKind::Revolute,
                chassis,
                lca,
                frame_along(
                    (w(p.lca_front) + w(p.lca_back)) * 0.5,
                    dir(p.lca_front, p.lca_back),
                ),
            ),
        )?;
        let at = |q: [f64; 3]| Isometry3::translation(w(q).x, w(q).y, w(q).z);
        joint(
            sys,
            "uca_spherical",
            JointBuilder::new(JointKind::Spherical, uca, upright, at(p.uca_upright)),
        )?;
        joint(
            sys,
            "lca_spherical",
            JointBuilder::new(JointKind::Spherical, lca, upright, at(p.lca_upright)),
        )?;
        let tierod = joint(
            sys,
            "tierod",
            JointBuilder::distance_between(
                tierod_body,
                upright,
                w(p.tierod_inner),
                w(p.tierod_upright),
            ),
        )?;
        let spring = SpringDamper::new(
            label("spring"),
            chassis,
            w(p.spring_chassis),
            lca,
            w(p.spring_arm),
            data.spring.rest_length,
            data.spring.force.clone(),
            Curve::constant(0.0),
        );
        let spring = sys.add_force_element(Box::new(spring))?;
        let stops = match &data.spring.stops {
            Some(st) => Some(sys.add_force_element(Box::new(SpringDamper::new(
                label("stops"),
                chassis,
                w(p.spring_chassis),
                lca,
                w(p.spring_arm),
                st.max_length,
                st.spring_curve(&format!("{name}.spring.stops"))?,
                Curve::constant(0.0),
            )))?),
            None => None,
        };
        let mut shock = SpringDamper::new(
            label("shock"),
            chassis,
            w(p.shock_chassis),
            lca,
            w(p.shock_arm),
            0.0,
            Curve::constant(0.0),
            data.shock.force.clone(),
        );
        if let Some(b) = &data.shock.bump {
            shock = shock.with_bump_damper(b.min_length, b.max_length, b.force.clone());
        }
        let shock = sys.add_force_element(Box::new(shock))?;
        Ok(WishboneSide {
            spindle,
            upright,
            upper_arm: uca,
            lower_arm: lca,
            spindle_joint,
            tierod,
            spring,
            shock,
            stops,
        })
    }
}
