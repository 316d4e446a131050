//! A wheeled vehicle assembled from its description: a chassis, axles (each a double
//! wishbone suspension with two wheels and tires), a Pitman-arm steering on the steered
//! axle. The description is serde data ([`VehicleData`], JSON), so another vehicle is
//! another file.

use std::sync::Arc;

use chrono_core::force::ForceHandle;
use chrono_core::math::{Isometry3, Point3, Vector3};
use chrono_core::{BodyHandle, RigidBodyBuilder, System};
use chrono_fea::{NodeId, ShellItem};
use serde::{Deserialize, Serialize};

use crate::aero::{AeroDrag, AeroDragData};
use crate::driveline::{FourWd, FourWdParams, ShaftSystem, Wheel};
use crate::error::{Result, VehicleError};
use crate::powertrain::{Powertrain, PowertrainParams};
use crate::state::{DriverInputs, VehicleState};
use crate::steering::pitman_arm::{PitmanArm, PitmanArmData};
use crate::suspension::double_wishbone::{
    DoubleWishbone, DoubleWishboneData, MassData, WheelMount,
};
use crate::terrain::Terrain;
use crate::tire::{TMeasyTire, Tire};

/// The chassis: mass, inertia and center of mass in the chassis reference frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, from = "ChassisFields")]
pub struct ChassisData {
    /// Mass and principal inertia.
    #[serde(flatten)]
    pub mass: MassData,
    /// Center of mass in the chassis reference frame, m.
    pub com: [f64; 3],
    /// Aerodynamic drag on the chassis ([`AeroDragData`]); none when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aero: Option<AeroDragData>,
}

/// The JSON layout of [`ChassisData`]: mass and inertia beside the center of mass, read as
/// plain fields (serde's `flatten` buffers the content and loses the path of a failing
/// field; this way an error names `chassis.inertia`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ChassisFields {
    mass: f64,
    inertia: [f64; 3],
    com: [f64; 3],
    #[serde(default)]
    aero: Option<AeroDragData>,
}

impl From<ChassisFields> for ChassisData {
    fn from(f: ChassisFields) -> Self {
        Self {
            mass: MassData {
                mass: f.mass,
                inertia: f.inertia,
            },
            com: f.com,
            aero: f.aero,
        }
    }
}

/// A wheel: the rim and its tire (rigid or handling).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelData {
    /// Rim mass and inertia.
    pub rim: MassData,
    /// The tire (its mass and inertia ride on the spindle too).
    pub tire: Tire,
}

impl WheelData {
    /// Check every field (the error names it under `field`).
    pub fn validate(&self, field: &str) -> Result<()> {
        self.rim.validate(&format!("{field}.rim"))?;
        self.tire.validate()?;
        Ok(())
    }

    /// Rim plus tire, as one mass.
    pub fn total_mass(&self) -> MassData {
        let ti = self.tire.inertia();
        MassData {
            mass: self.rim.mass + self.tire.mass(),
            inertia: [0, 1, 2].map(|i| self.rim.inertia[i] + ti[i]),
        }
    }

    /// What the wheel (spindle) body carries: the rim, plus the tire unless the tire is an
    /// ANCF carcass with its own mass.
    pub fn spindle_mass(&self) -> MassData {
        if self.tire.on_spindle() {
            self.total_mass()
        } else {
            self.rim
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
    /// Engine, torque converter and automatic transmission.
    pub powertrain: PowertrainParams,
    /// The 4WD driveline (two axles) and the brakes.
    pub driveline: FourWdParams,
}

impl VehicleData {
    /// Parse a JSON description (the error names the position of a syntax error or the
    /// field that is wrong).
    pub fn from_json(text: &str, path: &str) -> Result<Self> {
        let data: Self = crate::json_path::parse(text, path)?;
        data.validate()?;
        Ok(data)
    }

    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        self.chassis.mass.validate("chassis")?;
        if let Some(a) = &self.chassis.aero {
            a.validate("chassis.aero")?;
        }
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
        if self.axles.len() != 2 {
            return Err(VehicleError::invalid(
                "axles",
                self.axles.len(),
                "the 4WD driveline drives exactly two axles",
            ));
        }
        self.powertrain.validate()?;
        self.driveline.validate()?;
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
    /// The handling tire's force element (`None` for a rigid or ANCF tire).
    pub tire: Option<ForceHandle>,
    /// The ANCF tire's shell item (`None` for a rigid or handling tire).
    pub shell: Option<chrono_core::item::ItemHandle>,
}

/// A wheeled vehicle in a [`System`].
#[derive(Debug, Clone)]
pub struct WheeledVehicle {
    data: VehicleData,
    chassis: BodyHandle,
    /// Chassis reference frame relative to the chassis body frame (the center of mass).
    com_to_ref: Isometry3<f64>,
    suspensions: Vec<DoubleWishbone>,
    steering: PitmanArm,
    wheels: Vec<WheelHandles>,
    powertrain: Powertrain,
    driveline: FourWd,
    /// Index of the [`ShaftSystem`] item in the system.
    shafts: chrono_core::item::ItemHandle,
    /// The bodies `build` added (handles `first_body..end_body`).
    bodies: std::ops::Range<u32>,
    inputs: DriverInputs,
}

impl WheeledVehicle {
    /// Build the vehicle into `sys` with its chassis reference frame at `pose` (world). A
    /// handling tire reads the ground from `terrain`; a rigid tire contacts whatever
    /// colliders the system holds (add the terrain's with
    /// [`Terrain::add_to_system`]).
    pub fn build(
        sys: &mut System,
        data: &VehicleData,
        pose: &Isometry3<f64>,
        terrain: Arc<dyn Terrain>,
    ) -> Result<Self> {
        data.validate()?;
        let first_body = sys.bodies().len() as u32;
        let com = Vector3::from(data.chassis.com);
        let chassis = sys.add_body(
            RigidBodyBuilder::dynamic()
                .name(format!("{}.chassis", data.name))
                .mass(data.chassis.mass.mass)
                .inertia_diagonal(data.chassis.mass.inertia_vector())
                .position(pose.transform_point(&Point3::from(com)).coords)
                .rotation(pose.rotation),
        )?;
        if let Some(aero) = &data.chassis.aero {
            let drag = AeroDrag::new(format!("{}.chassis.aero", data.name), chassis, aero)?;
            sys.add_force_element(Box::new(drag))?;
        }
        let steering = PitmanArm::build(sys, "steering", &data.steering, chassis, pose)?;
        let w = &data.wheel;
        let mount = WheelMount {
            mass: w.spindle_mass(),
            collider: match &w.tire {
                Tire::Rigid(t) => Some(t.collider()?),
                Tire::TMeasy(_) | Tire::Ancf(_) => None,
            },
        };
        // One inflation serves the four wheels.
        let ancf = match &w.tire {
            Tire::Ancf(a) => Some(a.inflate()?),
            _ => None,
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
                let name = format!("{}.{}.{}.tire", data.name, a.name, ["left", "right"][side]);
                let shell = match &ancf {
                    Some(model) => Some(model.mount(sys, &name, ws.spindle)?),
                    None => None,
                };
                let tire = match &w.tire {
                    Tire::Rigid(_) | Tire::Ancf(_) => None,
                    Tire::TMeasy(p) => {
                        let t = TMeasyTire::new(
                            name,
                            ws.spindle,
                            Vector3::y(),
                            p.clone(),
                            terrain.clone(),
                        )?;
                        Some(sys.add_force_element(Box::new(t))?)
                    }
                };
                wheels.push(WheelHandles {
                    spindle: ws.spindle,
                    axle: i,
                    side,
                    tire,
                    shell,
                });
            }
            suspensions.push(s);
        }
        let mut shafts = ShaftSystem::new(format!("{}.driveline", data.name));
        let powertrain = Powertrain::new(&data.powertrain, &mut shafts)?;
        let spindles = [0, 1, 2, 3].map(|i| wheels[i].spindle);
        let driveline = FourWd::new(
            &data.driveline,
            &mut shafts,
            powertrain.output_shaft(),
            spindles,
            chassis,
        )?;
        let shafts = sys.add_item(Box::new(shafts));
        let bodies = first_body..sys.bodies().len() as u32;
        Ok(Self {
            data: data.clone(),
            chassis,
            com_to_ref: Isometry3::translation(-com.x, -com.y, -com.z),
            suspensions,
            steering,
            wheels,
            powertrain,
            driveline,
            shafts,
            bodies,
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

    /// Apply the driver's inputs for the next step (clamped to their ranges): the steering
    /// gear's angle, the engine torque and gear from the throttle, the brake torques.
    pub fn synchronize(&mut self, sys: &mut System, inputs: DriverInputs) -> Result<()> {
        self.inputs = inputs.clamped();
        self.steering.set_input(sys, self.inputs.steering)?;
        let time = sys.time();
        let shafts = sys
            .item_mut::<ShaftSystem>(self.shafts)
            .ok_or_else(|| VehicleError::invalid("vehicle.shafts", self.shafts, "no shaft item"))?;
        self.powertrain
            .synchronize(time, self.inputs.throttle, shafts)?;
        self.driveline.synchronize(self.inputs.brake, shafts)?;
        Ok(())
    }

    /// The powertrain (engine speed and torque, gear, converter state).
    pub fn powertrain(&self) -> &Powertrain {
        &self.powertrain
    }

    /// The driveline.
    pub fn driveline(&self) -> &FourWd {
        &self.driveline
    }

    /// The shaft system (powertrain and driveline shafts) in `sys`.
    pub fn shafts<'a>(&self, sys: &'a System) -> Option<&'a ShaftSystem> {
        sys.item::<ShaftSystem>(self.shafts)
    }

    /// The force (N, world) of the terrain on each tire in the last step of size `h`, ordered
    /// like [`wheels`](Self::wheels). A handling tire reports its own force (normal,
    /// longitudinal and lateral); a rigid tire the contact impulses of the last CCP on its
    /// spindle over `h` (NSC), or the penalty forces (SMC); an ANCF tire the contact
    /// impulses of the last CCP on its node spheres over `h`.
    pub fn tire_forces(&self, sys: &System, h: f64) -> Vec<Vector3<f64>> {
        let mut out = self.rigid_tire_forces(sys, h);
        if self.wheels.iter().any(|w| w.shell.is_some()) {
            let (problem, gamma) = (sys.last_problem(), sys.last_gamma());
            for c in sys.proxy_contacts() {
                let Some(i) = (self.wheels.iter())
                    .position(|w| w.shell.is_some_and(|s| s.index() == c.point.item))
                else {
                    continue;
                };
                let k = problem.row_index(c.row);
                if k + 2 >= gamma.len() {
                    continue;
                }
                // The proxy is side B: the rows' impulse acts on the tire.
                out[i] += (c.normal() * gamma[k] + c.u * gamma[k + 1] + c.w * gamma[k + 2]) / h;
            }
        }
        for (i, w) in self.wheels.iter().enumerate() {
            if let Some(t) = w.tire.and_then(|t| sys.force_element::<TMeasyTire>(t)) {
                let o = t.output();
                out[i] =
                    o.normal * o.normal_force + o.longitudinal_dir * o.fx + o.lateral_dir * o.fy;
            }
        }
        out
    }

    /// The height of the lowest point of wheel `i`'s tire, m: the spindle's height minus
    /// `radius` for a rigid or handling tire, the lowest node of an ANCF carcass minus half
    /// its thickness (the tread's outer face) for an ANCF tire.
    pub fn tire_bottom(&self, sys: &System, i: usize, radius: f64) -> Result<f64> {
        let w = self.wheels.get(i).ok_or_else(|| {
            VehicleError::invalid("wheel", i, format!("{} wheels", self.wheels.len()))
        })?;
        match (w.shell, &self.data.wheel.tire) {
            (Some(shell), Tire::Ancf(a)) => {
                let item = sys.item::<ShellItem>(shell).ok_or_else(|| {
                    VehicleError::invalid("wheels.shell", shell, "not an ANCF tire item")
                })?;
                let low = (item.mesh().nodes().iter())
                    .map(|n| n.position.z)
                    .fold(f64::INFINITY, f64::min);
                Ok(low - 0.5 * a.thickness)
            }
            _ => Ok(sys.body(w.spindle)?.position().z - radius),
        }
    }

    /// True if the point `p` (world, m) lies inside wheel `i`'s ANCF carcass: in the
    /// spindle's frame, inside the section that the carcass' mid surface and the rim line
    /// (bead to bead) enclose at `p`'s angle about the axle, the section interpolated
    /// linearly between the two rings of nodes around `p` (a point-in-polygon test in the
    /// radius–axial plane, so it follows the carcass as it deforms). Always false for a
    /// rigid or handling tire. A grain centre inside a carcass has passed through it.
    pub fn inside_ancf_tire(&self, sys: &System, i: usize, p: &Vector3<f64>) -> Result<bool> {
        let w = self.wheels.get(i).ok_or_else(|| {
            VehicleError::invalid("wheel", i, format!("{} wheels", self.wheels.len()))
        })?;
        let (Some(shell), Tire::Ancf(a)) = (w.shell, &self.data.wheel.tire) else {
            return Ok(false);
        };
        let item = sys
            .item::<ShellItem>(shell)
            .ok_or_else(|| VehicleError::invalid("wheels.shell", shell, "not an ANCF tire item"))?;
        let pose = sys.body(w.spindle)?.pose();
        // (angle about the axle, radius from it, axial position) in the spindle frame.
        let polar = |x: &Vector3<f64>| {
            let l = pose.inverse_transform_vector(&(x - pose.translation.vector));
            (l.z.atan2(l.x), l.x.hypot(l.z), l.y)
        };
        let (theta, rho, y) = polar(p);
        let (n_around, n_across) = (a.n_around, a.n_across);
        let nodes = item.mesh().nodes();
        let step = std::f64::consts::TAU / n_around as f64;
        let u = theta.rem_euclid(std::f64::consts::TAU) / step;
        let i0 = (u.floor() as usize) % n_around;
        let i1 = (i0 + 1) % n_around;
        let t = u - u.floor();
        let section: Vec<(f64, f64)> = (0..=n_across)
            .map(|j| {
                let (_, r0, y0) = polar(&nodes[i0 * (n_across + 1) + j].position);
                let (_, r1, y1) = polar(&nodes[i1 * (n_across + 1) + j].position);
                ((1.0 - t) * r0 + t * r1, (1.0 - t) * y0 + t * y1)
            })
            .collect();
        // Ray casting along +radius over the closed polygon (the last edge: the rim line).
        let mut inside = false;
        for k in 0..section.len() {
            let (ra, ya) = section[k];
            let (rb, yb) = section[(k + 1) % section.len()];
            if (ya > y) != (yb > y) {
                let r_cross = ra + (y - ya) / (yb - ya) * (rb - ra);
                if rho < r_cross {
                    inside = !inside;
                }
            }
        }
        Ok(inside)
    }

    fn rigid_tire_forces(&self, sys: &System, h: f64) -> Vec<Vector3<f64>> {
        let mut out = vec![Vector3::zeros(); self.wheels.len()];
        let index = |owner: u32| {
            let set = sys.body_set();
            (self.wheels.iter()).position(|w| set.dense_index(w.spindle) == Some(owner as usize))
        };
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

    /// Start the vehicle rolling straight ahead at `speed` (m/s along the chassis X axis),
    /// as a vehicle test starts at its target speed: every body of the vehicle translates
    /// at `speed`, the spindles turn at `w = speed / R` (R the tire radius; rolling without
    /// slip: the contact point `v - w R` is at rest) about the spindle axis, and the
    /// driveline and transmission shafts turn at the speeds their gears and differentials
    /// impose on that `w` (axles `w`, differential boxes `w`, driveshafts `w / r_conical`,
    /// gearbox input `w_out / r_gear`), with the engine at the gearbox input speed (the
    /// converter at speed ratio 1). Without the shafts' speeds the first step would spin
    /// them up through the gears, and their inertia reflected through the ratios (about
    /// 1 000 kg equivalent for the HMMWV in first gear) would brake the vehicle. The
    /// transmission stays in its current gear; if the speed is past that gear's upshift
    /// point, the first `synchronize` shifts (and the gearbox row exchanges the shafts'
    /// momentum with the vehicle's).
    pub fn set_forward_speed(&self, sys: &mut System, speed: f64) -> Result<()> {
        if !speed.is_finite() {
            return Err(VehicleError::invalid(
                "speed",
                speed,
                "the initial forward speed must be finite",
            ));
        }
        let rot = sys.body(self.chassis)?.rotation();
        let fwd = rot * Vector3::x();
        let p = self.driveline.params();
        // The axle shafts turn with the spindles about this axis (chassis frame).
        let axle = rot * Vector3::from(p.spindle_axis).normalize();
        let radius = self.data.wheel.tire.radius();
        let w = speed / radius;
        for i in self.bodies.clone() {
            let h = sys.body_set().handle(i as usize);
            let b = sys.body_mut(h)?;
            b.set_linear_velocity(fwd * speed)?;
            b.set_angular_velocity(Vector3::zeros())?;
        }
        for wh in &self.wheels {
            sys.body_mut(wh.spindle)?.set_angular_velocity(axle * w)?;
            if let Some(shell) = wh.shell {
                // The carcass moves rigidly with its spindle: v + w x (r - x), d' = w x d.
                let (x, v) = {
                    let b = sys.body(wh.spindle)?;
                    (b.position(), b.linear_velocity())
                };
                let omega = axle * w;
                let item = sys.item_mut::<ShellItem>(shell).ok_or_else(|| {
                    VehicleError::invalid("wheels.shell", shell, "not an ANCF tire item")
                })?;
                let nodes: Vec<_> = (item.mesh().nodes().iter())
                    .map(|n| (n.position, n.slope))
                    .collect();
                for (k, (r, d)) in nodes.into_iter().enumerate() {
                    item.set_node_velocity(NodeId(k), v + omega.cross(&(r - x)), omega.cross(&d))?;
                }
            }
        }
        let [front_ds, rear_ds] = self.driveline.driveshafts();
        let (w_front, w_rear) = (w / p.front_conical_ratio, w / p.rear_conical_ratio);
        let w_out = 0.5 * (w_front + w_rear);
        let w_in = self
            .powertrain
            .transmission()
            .ratio()
            .map_or(0.0, |r| w_out / r);
        let shafts = sys
            .item_mut::<ShaftSystem>(self.shafts)
            .ok_or_else(|| VehicleError::invalid("shafts", self.shafts, "no shaft system"))?;
        for wheel in Wheel::ALL {
            shafts.set_speed(self.driveline.axle(wheel), w)?;
        }
        let [central, front, rear] = self.driveline.differential_boxes();
        shafts.set_speed(front, w)?;
        shafts.set_speed(rear, w)?;
        shafts.set_speed(front_ds, w_front)?;
        shafts.set_speed(rear_ds, w_rear)?;
        shafts.set_speed(central, w_out)?;
        shafts.set_speed(self.driveline.input_shaft(), w_out)?;
        shafts.set_speed(self.powertrain.input_shaft(), w_in)?;
        shafts.set_speed(self.powertrain.crankshaft(), w_in)?;
        Ok(())
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
