//! A wheeled vehicle assembled from its description: a chassis, axles (each a double
//! wishbone suspension with two wheels and tires), a Pitman-arm steering on the steered
//! axle. The description is serde data ([`VehicleData`], JSON), so another vehicle is
//! another file.

use chrono_core::math::{Isometry3, Point3, Vector3};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System};
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError, check_positive};
use crate::state::{DriverInputs, VehicleState};
use crate::steering::pitman_arm::{PitmanArm, PitmanArmData};
use crate::suspension::double_wishbone::{
    DoubleWishbone, DoubleWishboneData, MassData, WheelMount,
};

/// The chassis: mass, inertia and center of mass in the chassis reference frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChassisData {
    /// Mass and principal inertia.
    #[serde(flatten)]
    pub mass: MassData,
    /// Center of mass in the chassis reference frame, m.
    pub com: [f64; 3],
}

/// A wheel (rim) and a rigid tire: the tire is a cylinder about the spin axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelData {
    /// Rim mass and inertia.
    pub rim: MassData,
    /// Tire mass and inertia.
    pub tire: MassData,
    /// Tire (unloaded) radius, m.
    pub radius: f64,
    /// Tire width, m.
    pub width: f64,
    /// Friction coefficient of the tire on the terrain.
    pub friction: f64,
}

impl WheelData {
    /// Check every field (the error names it under `field`).
    pub fn validate(&self, field: &str) -> Result<()> {
        self.rim.validate(&format!("{field}.rim"))?;
        self.tire.validate(&format!("{field}.tire"))?;
        check_positive(&format!("{field}.radius"), self.radius)?;
        check_positive(&format!("{field}.width"), self.width)?;
        crate::error::check_non_negative(&format!("{field}.friction"), self.friction)?;
        Ok(())
    }

    /// Rim plus tire, as one mass.
    pub fn total_mass(&self) -> MassData {
        MassData {
            mass: self.rim.mass + self.tire.mass,
            inertia: [0, 1, 2].map(|i| self.rim.inertia[i] + self.tire.inertia[i]),
        }
    }
}

/// An axle: its suspension, where it sits, whether it steers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxleData {
    /// Name ("front", "rear").
    pub name: String,
    /// Origin of the suspension frame in the chassis reference frame, m.
    pub location: [f64; 3],
    /// The suspension.
    pub suspension: DoubleWishboneData,
    /// True if its tie rods attach to the steering link (else to the chassis).
    pub steered: bool,
}

/// A wheeled vehicle's description.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleData {
    /// Name.
    pub name: String,
    /// Where the parameters come from.
    #[serde(default)]
    pub source: Vec<String>,
    /// Chassis.
    pub chassis: ChassisData,
    /// Axles, front to rear.
    pub axles: Vec<AxleData>,
    /// Steering (on the axle marked `steered`).
    pub steering: PitmanArmData,
    /// Wheels and tires (all alike).
    pub wheel: WheelData,
}

impl VehicleData {
    /// Parse a JSON description (the error names the position of a syntax error or the
    /// field that is wrong).
    pub fn from_json(text: &str, path: &str) -> Result<Self> {
        let data: Self = serde_json::from_str(text).map_err(|e| VehicleError::Data {
            path: path.to_string(),
            message: e.to_string(),
        })?;
        data.validate()?;
        Ok(data)
    }

    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        self.chassis.mass.validate("chassis")?;
        if self.axles.is_empty() {
            return Err(VehicleError::invalid(
                "axles",
                "[]",
                "a vehicle needs an axle",
            ));
        }
        for (i, a) in self.axles.iter().enumerate() {
            a.suspension.validate(&format!("axles[{i}].suspension"))?;
        }
        if self.axles.iter().filter(|a| a.steered).count() > 1 {
            return Err(VehicleError::invalid(
                "axles.steered",
                "several",
                "one Pitman-arm steering drives one axle",
            ));
        }
        self.steering.validate("steering")?;
        self.wheel.validate("wheel")?;
        Ok(())
    }

    /// The total mass of the vehicle's bodies, kg (chassis, suspensions, steering, wheels).
    pub fn total_mass(&self) -> f64 {
        let s = &self.steering;
        let axles: f64 = self
            .axles
            .iter()
            .map(|a| {
                let d = &a.suspension;
                2.0 * (d.spindle.mass
                    + d.upright.mass
                    + d.upper_arm.mass
                    + d.lower_arm.mass
                    + self.wheel.total_mass().mass)
            })
            .sum();
        self.chassis.mass.mass + axles + s.link.mass + s.arm.mass + s.idler.mass
    }
}

/// The handles of one wheel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelHandles {
    /// The spindle body (wheel and tire ride on it).
    pub spindle: BodyHandle,
    /// Axle index.
    pub axle: usize,
    /// 0 left, 1 right.
    pub side: usize,
}

/// A wheeled vehicle in a [`System`].
#[derive(Debug, Clone, PartialEq)]
pub struct WheeledVehicle {
    data: VehicleData,
    chassis: BodyHandle,
    /// Chassis reference frame relative to the chassis body frame (the center of mass).
    com_to_ref: Isometry3<f64>,
    suspensions: Vec<DoubleWishbone>,
    steering: PitmanArm,
    wheels: Vec<WheelHandles>,
    inputs: DriverInputs,
}

impl WheeledVehicle {
    /// Build the vehicle into `sys` with its chassis reference frame at `pose` (world).
    pub fn build(sys: &mut System, data: &VehicleData, pose: &Isometry3<f64>) -> Result<Self> {
        data.validate()?;
        let com = Vector3::from(data.chassis.com);
        let chassis = sys.add_body(
            RigidBodyBuilder::dynamic()
                .name(format!("{}.chassis", data.name))
                .mass(data.chassis.mass.mass)
                .inertia_diagonal(data.chassis.mass.inertia_vector())
                .position(pose.transform_point(&Point3::from(com)).coords)
                .rotation(pose.rotation),
        )?;
        let steering = PitmanArm::build(sys, "steering", &data.steering, chassis, pose)?;
        let w = &data.wheel;
        let cylinder = Shape::Cylinder {
            half_length: 0.5 * w.width,
            radius: w.radius,
        };
        let material = ContactMaterial::with_friction(w.friction);
        let mount = WheelMount {
            mass: w.total_mass(),
            collider: Some((cylinder, Isometry3::identity(), material)),
        };
        let mut suspensions = Vec::new();
        let mut wheels = Vec::new();
        for (i, a) in data.axles.iter().enumerate() {
            let frame = pose * Isometry3::translation(a.location[0], a.location[1], a.location[2]);
            let tierod_body = if a.steered { steering.link } else { chassis };
            let s = DoubleWishbone::build(
                sys,
                &format!("{}.{}", data.name, a.name),
                &a.suspension,
                chassis,
                &frame,
                tierod_body,
                &mount,
            )?;
            for (side, ws) in s.sides.iter().enumerate() {
                wheels.push(WheelHandles {
                    spindle: ws.spindle,
                    axle: i,
                    side,
                });
            }
            suspensions.push(s);
        }
        Ok(Self {
            data: data.clone(),
            chassis,
            com_to_ref: Isometry3::translation(-com.x, -com.y, -com.z),
            suspensions,
            steering,
            wheels,
            inputs: DriverInputs::default(),
        })
    }

    /// The description it was built from.
    pub fn data(&self) -> &VehicleData {
        &self.data
    }

    /// The chassis body.
    pub fn chassis(&self) -> BodyHandle {
        self.chassis
    }

    /// The suspensions, front to rear.
    pub fn suspensions(&self) -> &[DoubleWishbone] {
        &self.suspensions
    }

    /// The steering.
    pub fn steering(&self) -> &PitmanArm {
        &self.steering
    }

    /// The wheels: axle by axle, left then right.
    pub fn wheels(&self) -> &[WheelHandles] {
        &self.wheels
    }

    /// The last driver inputs.
    pub fn inputs(&self) -> DriverInputs {
        self.inputs
    }

    /// Apply the driver's inputs for the next step (clamped to their ranges): steering.
    pub fn synchronize(&mut self, sys: &mut System, inputs: DriverInputs) -> Result<()> {
        self.inputs = inputs.clamped();
        self.steering.set_input(sys, self.inputs.steering)?;
        Ok(())
    }

    /// The contact force (N, world) of the terrain on each wheel's rigid tire in the last
    /// step of size `h`: the contact impulses of the last CCP on the spindle bodies over `h`
    /// (NSC), or the penalty forces (SMC). Ordered like [`wheels`](Self::wheels).
    pub fn rigid_tire_forces(&self, sys: &System, h: f64) -> Vec<Vector3<f64>> {
        let mut out = vec![Vector3::zeros(); self.wheels.len()];
        let index = |owner: u32| self.wheels.iter().position(|w| w.spindle.0 == owner);
        match sys.settings().contact_method {
            chrono_core::ContactMethod::Nsc => {
                let (problem, gamma) = (sys.last_problem(), sys.last_gamma());
                for c in sys.contacts() {
                    let k = problem.row_index(c.row);
                    if k + 2 >= gamma.len() {
                        continue;
                    }
                    // The rows are B's velocity relative to A's: the impulse acts on B.
                    let on_b =
                        (c.normal() * gamma[k] + c.u * gamma[k + 1] + c.w * gamma[k + 2]) / h;
                    if let Some(i) = index(c.point.owner_b) {
                        out[i] += on_b;
                    }
                    if let Some(i) = index(c.point.owner_a) {
                        out[i] -= on_b;
                    }
                }
            }
            chrono_core::ContactMethod::Smc => {
                for c in sys.smc_contacts() {
                    if let Some(i) = index(c.owner_b) {
                        out[i] += c.force;
                    }
                    if let Some(i) = index(c.owner_a) {
                        out[i] -= c.force;
                    }
                }
            }
        }
        out
    }

    /// The chassis reference frame's pose in the world.
    pub fn reference_pose(&self, sys: &System) -> Result<Isometry3<f64>> {
        Ok(sys.body(self.chassis)?.pose() * self.com_to_ref)
    }

    /// The chassis state at its reference point.
    pub fn state(&self, sys: &System) -> Result<VehicleState> {
        let b = sys.body(self.chassis)?;
        let pose = b.pose() * self.com_to_ref;
        let p = pose.translation.vector;
        Ok(VehicleState {
            time: sys.time(),
            position: p,
            rotation: pose.rotation,
            velocity: b.point_velocity(&p),
            angular_velocity: b.angular_velocity(),
        })
    }
}
