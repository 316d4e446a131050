//! A tracked vehicle from a description: a chassis (rigid body) and two
//! [`TrackAssembly`]s, left at `+track_y` and right at `-track_y`; and the flat-ground
//! scene and contact-force sums the validation cases read.
//!
//! The chassis collides through its hull's plates ([`crate::hull`]) when the data has a
//! `hull`; without one it has no collision shape. The sprockets turn freely, are held, or are driven through
//! [`TrackAssembly::set_sprocket_drive`]; the powertrain and the steering driveline are
//! [`crate::tracked_drive::TrackedDrive`].

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use chrono_ccp::CcpSolver;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{BodyHandle, ContactMaterial, Drive, RigidBodyBuilder, System, SystemSettings};

use crate::driveline::TrackDrivelineParams;
use crate::error::{Result, VehicleError, check_positive};
use crate::hull::HullData;
use crate::powertrain::PowertrainParams;
use crate::suspension::MassData;
use crate::terrain::{FlatTerrain, Terrain};
use crate::track::{TrackAssembly, TrackData};

/// Published figures of the real vehicle, kept with the model for the validation cases (SI).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PublishedData {
    /// Combat mass, kg.
    pub combat_mass: f64,
    /// Nominal (zero-penetration) ground pressure, Pa: weight over `2 track_width
    /// ground_contact_length`.
    pub ground_pressure: f64,
    /// Ground contact length of a track, m.
    pub ground_contact_length: f64,
    /// Track (shoe) width, m.
    pub track_width: f64,
    /// Tread (track centre to centre), m.
    pub tread: f64,
    /// Highest vertical obstacle, m.
    pub vertical_obstacle: f64,
    /// Ground clearance (flat ground to the hull's floor), m.
    pub ground_clearance: f64,
    /// Steepest grade climbed (rise over run, e.g. 0.6 for 60 %).
    pub max_grade: f64,
    /// Top road speed, m/s.
    pub road_speed: f64,
    /// Engine rated power, W.
    pub engine_power: f64,
    /// Engine speed at the rated power, rpm.
    pub engine_speed: f64,
}

/// The chassis (hull) of a tracked vehicle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackedChassisData {
    /// Mass and inertia (about the centre of mass).
    pub mass: MassData,
    /// Centre of mass in the chassis reference frame, m.
    pub com: [f64; 3],
}

/// A tracked vehicle's description (the M113's is `data/m113.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackedVehicleData {
    /// Name.
    pub name: String,
    /// The references the values come from.
    pub sources: Vec<String>,
    /// Where each value comes from, by field path.
    pub provenance: BTreeMap<String, String>,
    /// Published figures of the real vehicle.
    pub published: PublishedData,
    /// The chassis.
    pub chassis: TrackedChassisData,
    /// Lateral distance of each track's mid-plane from the chassis reference, m.
    pub track_y: f64,
    /// The running gear of one side (both sides share it).
    pub track: TrackData,
    /// Engine, torque converter and transmission.
    pub powertrain: PowertrainParams,
    /// The driveline to the sprockets: the braked differential, or the differential
    /// steering unit with `driveline.steering` = `dsu` (`driveline.dsu`).
    pub driveline: TrackDrivelineParams,
    /// The hull's collision shape (none: the chassis does not collide).
    #[serde(default)]
    pub hull: Option<HullData>,
    /// The material of the test course's rigid obstacles (the vertical step of
    /// [`crate::obstacle`]), fixed with the vehicle's data so that an obstacle case does
    /// not choose it. A contact pair takes the lower friction of its two materials.
    #[serde(default)]
    pub obstacle: Option<ContactMaterial>,
}

impl TrackedVehicleData {
    /// Read a description from JSON `text` (read from `path`, named in errors) and validate
    /// it: a value of the wrong type names its field path, a value out of range (a track
    /// with fewer shoes than its loop needs, a tooth count that does not match the pitch, a
    /// negative tensioner preload, ...) names its field and value.
    pub fn from_json(text: &str, path: &str) -> Result<Self> {
        let d: Self = crate::json_path::parse(text, path)?;
        d.validate()?;
        Ok(d)
    }

    /// Check every field (errors name it), including that each side's chain closes round
    /// its wheels within the tensioner's travel.
    pub fn validate(&self) -> Result<()> {
        self.chassis.mass.validate("chassis.mass")?;
        if self.chassis.com.iter().any(|c| !c.is_finite()) {
            return Err(VehicleError::invalid(
                "chassis.com",
                format!("{:?}", self.chassis.com),
                "must be finite",
            ));
        }
        check_positive("track_y", self.track_y)?;
        self.track.validate("track")?;
        // Too few or too many shoes for the loop is a data error (it names
        // `track.shoe.count[side]`), found on reading, not first when the vehicle is built.
        for (side, &n) in self.track.shoe.count.iter().enumerate() {
            crate::track::geometry::check_shoe_count(&self.track, n, side)?;
        }
        self.powertrain.validate()?;
        self.driveline.validate("driveline")?;
        if let Some(h) = &self.hull {
            h.validate("hull", &self.track, self.track_y)?;
        }
        if let Some(m) = &self.obstacle {
            m.validate()
                .map_err(|e| VehicleError::invalid("obstacle", "-", e.to_string()))?;
        }
        Ok(())
    }

    /// The mass of the whole vehicle (chassis and both sides' running gear), kg.
    pub fn total_mass(&self) -> f64 {
        self.chassis.mass.mass
            + self.track.side_mass(self.track.shoe.count[0])
            + self.track.side_mass(self.track.shoe.count[1])
    }

    /// The mass of both tracks' shoes, kg.
    pub fn chain_mass(&self) -> f64 {
        self.track.chain_mass(self.track.shoe.count[0])
            + self.track.chain_mass(self.track.shoe.count[1])
    }

    /// Nominal ground pressure of the model, Pa: `m g / (2 b L)` with the model's mass, the
    /// shoe width `b` and the ground contact length `L` from the first to the last road
    /// wheel centre, gravity `g` (m/s^2).
    pub fn nominal_ground_pressure(&self, g: f64) -> f64 {
        self.total_mass() * g / (2.0 * self.track.shoe.width * self.contact_length())
    }

    /// The torque on each sprocket that holds the model on a slope of `grade` (rise over
    /// run, e.g. 0.6 for 60 %) at gravity `g` (m/s^2), N m: the weight's component down the
    /// slope, `m g sin(atan grade)`, shared by the two sprockets at their pitch radius,
    /// `m g sin(atan grade) r_p / 2`. It is the least a drive that climbs that grade must
    /// give at the sprockets (rolling resistance and the track's internal losses only add
    /// to it). Errors name the field: `grade` negative or not finite, `g` not positive.
    pub fn grade_sprocket_torque(&self, grade: f64, g: f64) -> Result<f64> {
        if !(grade >= 0.0 && grade.is_finite()) {
            return Err(VehicleError::invalid(
                "grade",
                grade,
                "must be >= 0 and finite",
            ));
        }
        check_positive("g", g)?;
        let angle = grade.atan();
        Ok(self.total_mass() * g * angle.sin() * self.track.sprocket.pitch_radius / 2.0)
    }

    /// [`Self::grade_sprocket_torque`] at the published steepest grade
    /// (`published.max_grade`, named in the error if it is negative or not finite), N m.
    pub fn published_grade_sprocket_torque(&self, g: f64) -> Result<f64> {
        let grade = self.published.max_grade;
        if !(grade >= 0.0 && grade.is_finite()) {
            return Err(VehicleError::invalid(
                "published.max_grade",
                grade,
                "must be >= 0 and finite",
            ));
        }
        self.grade_sprocket_torque(grade, g)
    }

    /// The model's ground contact length: first to last road wheel centre, m.
    pub fn contact_length(&self) -> f64 {
        let x = &self.track.road_wheels.x;
        x[0] - x[x.len() - 1]
    }
}

/// A tracked vehicle in a system.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedVehicle {
    /// The chassis body.
    pub chassis: BodyHandle,
    /// Left (0) and right (1) running gear.
    pub sides: [TrackAssembly; 2],
}

impl TrackedVehicle {
    /// Build `data` into `sys` with the chassis reference frame at `pose` (world).
    pub fn build(
        sys: &mut System,
        data: &TrackedVehicleData,
        pose: &Isometry3<f64>,
    ) -> Result<Self> {
        data.validate()?;
        let com = pose.transform_point(&data.chassis.com.into()).coords;
        let mut cb = RigidBodyBuilder::dynamic()
            .name("chassis")
            .mass(data.chassis.mass.mass)
            .inertia_diagonal(data.chassis.mass.inertia_vector())
            .position(com)
            .rotation(pose.rotation);
        if let Some(h) = &data.hull {
            // The body frame is the chassis frame moved to the centre of mass.
            let to_body = Isometry3::translation(
                -data.chassis.com[0],
                -data.chassis.com[1],
                -data.chassis.com[2],
            );
            for p in h.plates() {
                cb = cb.collider(p.shape, to_body * p.pose, h.material);
            }
        }
        let chassis = sys.add_body(cb)?;
        let side = |sys: &mut System, k: usize| {
            let y = if k == 0 { data.track_y } else { -data.track_y };
            let frame = pose * Isometry3::translation(0.0, y, 0.0);
            TrackAssembly::build(sys, &data.track, k, chassis, &frame)
        };
        let left = side(sys, 0)?;
        let right = side(sys, 1)?;
        Ok(Self {
            chassis,
            sides: [left, right],
        })
    }

    /// Set both sprockets' drives (see [`TrackAssembly::set_sprocket_drive`]).
    pub fn set_sprocket_drives(&self, sys: &mut System, drive: Drive) -> Result<()> {
        for s in &self.sides {
            s.set_sprocket_drive(sys, drive)?;
        }
        Ok(())
    }

    /// Lock both tracks' adjusters where they stand if the data's are grease cylinders
    /// ([`crate::track::AdjusterKind::Grease`]; call it once the vehicle has settled: the
    /// adjustment); returns whether it locked them. A spring adjuster is left as it is.
    pub fn lock_adjusters(&self, sys: &mut System, data: &TrackedVehicleData) -> Result<bool> {
        if data.track.idler.tensioner.adjuster != crate::track::AdjusterKind::Grease {
            return Ok(false);
        }
        for s in &self.sides {
            s.lock_adjuster(sys)?;
        }
        Ok(true)
    }

    /// All shoes of both sides.
    pub fn shoes(&self) -> Vec<BodyHandle> {
        self.sides.iter().flat_map(|s| s.shoes.clone()).collect()
    }

    /// Set the vehicle rolling straight ahead at `speed` (m/s along the chassis X axis),
    /// the tracks without slip: every body moves with the chassis; the sprockets, road
    /// wheels and idlers spin about the chassis Y axis at `speed / r` (pitch radius, wheel
    /// radius, idler radius); each chain moves round its loop at `speed` relative to the
    /// chassis, backwards along the lower run, so the shoes on the ground stand still.
    ///
    /// The chain's velocity is read from the pins' current positions: pin `k` moves along
    /// `t_k = (p_{k+1} - p_{k-1}) / |...|` (the loop's direction there, sign such that the
    /// lowest pin moves rearward), and shoe `k` between pins `k` and `k+1` gets the
    /// rigid-body velocity of that pair, `v = (u_k + u_{k+1}) / 2` and the spin `omega_y =
    /// (u_{k+1} - u_k) . (y x d) / |d|^2` about Y (`d` the shoe's pin-to-pin vector). On
    /// the straight runs this is exact; round the wheels the pins' chords leave a residual
    /// of order `(pitch / r)^2` that the first step's joint rows take up. The powertrain's
    /// shafts are set by [`crate::tracked_drive::TrackedDrive::set_forward_speed`].
    /// Errors: `speed` not finite (named `speed`).
    pub fn set_forward_speed(
        &self,
        sys: &mut System,
        data: &TrackedVehicleData,
        speed: f64,
    ) -> Result<()> {
        crate::error::check_finite("speed", speed)?;
        let rot = sys.body(self.chassis)?.rotation();
        let (fwd, y) = (rot * Vector3::x(), rot * Vector3::y());
        let base = fwd * speed;
        let set = |sys: &mut System, b: BodyHandle, v: Vector3<f64>, w: Vector3<f64>| {
            let body = sys.body_mut(b)?;
            body.set_linear_velocity(v)?;
            body.set_angular_velocity(w)?;
            Ok::<(), VehicleError>(())
        };
        set(sys, self.chassis, base, Vector3::zeros())?;
        let t = &data.track;
        for s in &self.sides {
            set(sys, s.sprocket, base, y * (speed / t.sprocket.pitch_radius))?;
            set(sys, s.carrier, base, Vector3::zeros())?;
            set(sys, s.idler, base, y * (speed / t.idler.radius))?;
            for r in &s.road_wheels {
                set(sys, r.arm, base, Vector3::zeros())?;
                set(sys, r.wheel, base, y * (speed / t.road_wheels.radius))?;
            }
            for (k, &ro) in s.rollers.iter().enumerate() {
                set(sys, ro, base, y * (speed / t.rollers[k].radius))?;
            }
            // The pins: at each shoe's rear end (shoe k runs from pin k to pin k+1).
            let n = s.shoes.len();
            let mut pins = Vec::with_capacity(n);
            for &b in &s.shoes {
                let body = sys.body(b)?;
                pins.push(body.position() - body.rotation() * Vector3::x() * (0.5 * t.shoe.pitch));
            }
            let lowest = (0..n)
                .min_by(|&a, &b| pins[a].z.total_cmp(&pins[b].z))
                .unwrap_or(0);
            let tangent = |k: usize| (pins[(k + 1) % n] - pins[(k + n - 1) % n]).normalize();
            let sign = if tangent(lowest).dot(&fwd) > 0.0 {
                -1.0
            } else {
                1.0
            };
            let u: Vec<Vector3<f64>> = (0..n).map(|k| tangent(k) * (sign * speed)).collect();
            for k in 0..n {
                let (ua, ub) = (u[k], u[(k + 1) % n]);
                let d = pins[(k + 1) % n] - pins[k];
                let wy = (ub - ua).dot(&y.cross(&d)) / d.norm_squared();
                set(sys, s.shoes[k], base + 0.5 * (ua + ub), y * wy)?;
            }
        }
        Ok(())
    }
}

/// The height of the chassis reference above a ground at `ground` (m) that puts the lowest
/// shoe plate `clearance` m above it (the assembled chains' lowest pin minus half a shoe
/// thickness), m.
pub fn start_height(data: &TrackedVehicleData, ground: f64, clearance: f64) -> Result<f64> {
    data.validate()?;
    let t = &data.track;
    let mut lowest = f64::INFINITY;
    for side in 0..2 {
        let l = crate::track::geometry::layout(t, t.shoe.count[side], side)?;
        lowest = l.pins.iter().map(|p| p[1]).fold(lowest, f64::min);
    }
    Ok(ground + clearance - (lowest - 0.5 * t.shoe.thickness))
}

pub use chrono_core::system::{ContactForce, contact_forces};

/// Sum of the contact forces on the bodies of `group` from bodies outside it, N.
pub fn group_contact_force(
    sys: &System,
    forces: &[ContactForce],
    group: &[BodyHandle],
) -> Vector3<f64> {
    let set = sys.body_set();
    let idx: Vec<usize> = group.iter().filter_map(|&b| set.dense_index(b)).collect();
    let mut f = Vector3::zeros();
    for c in forces {
        let (a, b) = (idx.contains(&c.owner_a), idx.contains(&c.owner_b));
        if b && !a {
            f += c.on_b;
        } else if a && !b {
            f -= c.on_b;
        }
    }
    f
}

/// A system with flat rigid ground at `z = 0` (its material: friction `mu`) and a tracked
/// vehicle whose lowest shoe is 5 mm above it.
pub struct TrackedFlatScene {
    /// The system (default settings).
    pub sys: System,
    /// The vehicle.
    pub vehicle: TrackedVehicle,
    /// Its description.
    pub data: TrackedVehicleData,
    /// The ground body.
    pub ground: BodyHandle,
}

impl TrackedFlatScene {
    /// Build the scene with the CCP `solver` (`chrono_ccp::Schur` solves the pin joints
    /// directly).
    pub fn new(data: TrackedVehicleData, mu: f64, solver: Box<dyn CcpSolver>) -> Result<Self> {
        let mut sys = System::new(SystemSettings::default(), solver)?;
        let terrain = Arc::new(FlatTerrain::new(0.0, mu)?);
        let ground = terrain.add_to_system(&mut sys, ContactMaterial::with_friction(mu))?;
        let z0 = start_height(&data, 0.0, crate::scene::START_CLEARANCE)?;
        let vehicle =
            TrackedVehicle::build(&mut sys, &data, &Isometry3::translation(0.0, 0.0, z0))?;
        Ok(Self {
            sys,
            vehicle,
            data,
            ground,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::m113::m113_data;

    fn solver() -> Box<dyn CcpSolver> {
        Box::new(chrono_ccp::Schur::new(Default::default()))
    }

    #[test]
    fn m113_model_mass_and_pressure_match_the_published_figures() {
        let d = m113_data().unwrap();
        let m = d.total_mass();
        assert!((m - d.published.combat_mass).abs() < 1e-3 * m, "{m}");
        assert!((d.contact_length() - d.published.ground_contact_length).abs() < 1e-3);
        let p = d.nominal_ground_pressure(chrono_core::math::GRAVITY_MAGNITUDE);
        assert!((p / d.published.ground_pressure - 1.0).abs() < 0.03, "{p}");
    }

    #[test]
    fn the_grade_torque_balances_the_weight_down_the_slope() {
        let d = m113_data().unwrap();
        let g = chrono_core::math::GRAVITY_MAGNITUDE;
        let r_p = d.track.sprocket.pitch_radius;
        // Both sprockets' thrust equals the weight's component down the slope.
        for grade in [0.0, 0.3, 0.6, 1.0, 2.5] {
            let t = d.grade_sprocket_torque(grade, g).unwrap();
            let down_slope = d.total_mass() * g * grade / (1.0 + grade * grade).sqrt();
            assert!((2.0 * t / r_p - down_slope).abs() < 1e-9 * down_slope.max(1.0));
        }
        // A 45 deg slope: sin 45 deg of the weight.
        let t = d.grade_sprocket_torque(1.0, g).unwrap();
        let w = d.total_mass() * g;
        assert!((2.0 * t / r_p / w - 0.5_f64.sqrt()).abs() < 1e-12);
        // The M113A1's published 60 %: 0.514 of the weight, about 6.94 kN m a side.
        let t = d.published_grade_sprocket_torque(g).unwrap();
        assert!((2.0 * t / r_p / w - 0.6 / 1.36_f64.sqrt()).abs() < 1e-12);
        assert!((t - 6.94e3).abs() < 10.0, "{t}");
        // Bad input names the field.
        for (grade, gg, field) in [
            (-0.1, g, "`grade`"),
            (f64::NAN, g, "`grade`"),
            (0.6, 0.0, "`g`"),
        ] {
            let e = d.grade_sprocket_torque(grade, gg).unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
        let mut bad = d.clone();
        bad.published.max_grade = -0.6;
        let e = bad
            .published_grade_sprocket_torque(g)
            .unwrap_err()
            .to_string();
        assert!(e.contains("published.max_grade"), "{e}");
    }

    #[test]
    fn the_assembled_m113_starts_with_closed_chains() {
        let s = TrackedFlatScene::new(m113_data().unwrap(), 0.8, solver()).unwrap();
        assert!(
            s.sys.max_joint_violation() < 1e-9,
            "{}",
            s.sys.max_joint_violation()
        );
        for side in &s.vehicle.sides {
            assert_eq!(side.shoes.len(), side.pins.len());
            assert!(side.layout.closure_error < 1e-9);
        }
        assert_eq!(s.vehicle.sides[0].shoes.len(), 63);
        assert_eq!(s.vehicle.sides[1].shoes.len(), 64);
        let m: f64 = s
            .sys
            .bodies()
            .iter()
            .filter(|b| b.is_dynamic())
            .map(|b| b.mass())
            .sum();
        assert!((m - s.data.total_mass()).abs() < 1e-6 * m);
    }

    #[test]
    fn bad_inputs_are_errors_naming_the_field() {
        let build = |d: TrackedVehicleData| {
            TrackedFlatScene::new(d, 0.8, solver())
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        let mut d = m113_data().unwrap();
        d.track.shoe.count[0] = 55;
        let e = build(d);
        assert!(
            e.contains("track.shoe.count[0]") && e.contains("too few"),
            "{e}"
        );

        let mut d = m113_data().unwrap();
        d.track.sprocket.num_teeth = 11;
        let e = build(d);
        assert!(
            e.contains("track.sprocket.num_teeth") && e.contains("pitch"),
            "{e}"
        );

        let mut d = m113_data().unwrap();
        d.track.idler.tensioner.preload = -1.0;
        let e = build(d);
        assert!(e.contains("track.idler.tensioner.preload"), "{e}");

        let mut d = m113_data().unwrap();
        d.track.shoe.pin_radius = 0.05;
        let e = build(d);
        assert!(e.contains("track.shoe.pin_radius"), "{e}");

        // A trough narrower than the pin, and troughs so wide they leave no tooth.
        for g in [0.015, 0.3] {
            let mut d = m113_data().unwrap();
            d.track.sprocket.gap_radius = g;
            let e = build(d);
            assert!(e.contains("track.sprocket.gap_radius"), "{g}: {e}");
        }

        let mut d = m113_data().unwrap();
        d.track.materials.sprocket.friction = -0.1;
        let e = build(d);
        assert!(e.contains("track.materials.sprocket"), "{e}");

        let mut d = m113_data().unwrap();
        d.track.rollers.push(crate::track::RollerData {
            location: [-2.0, 0.3],
            radius: 0.12,
            width: 0.2,
            mass: MassData {
                mass: 10.0,
                inertia: [0.1, 0.1, 0.1],
            },
        });
        let e = build(d);
        assert!(e.contains("track.rollers[0].location"), "{e}");

        // Arm stops on the wrong side of the assembled arm.
        for (travel, field) in [
            ([0.1, 0.2], "track.road_wheels.arm_travel[0]"),
            ([-0.1, -0.05], "track.road_wheels.arm_travel[1]"),
            ([f64::NAN, 0.2], "track.road_wheels.arm_travel[0]"),
        ] {
            let mut d = m113_data().unwrap();
            d.track.road_wheels.arm_travel = Some(travel);
            let e = build(d);
            assert!(e.contains(field), "{travel:?}: {e}");
        }
    }

    /// A grease adjuster, locked after the vehicle has settled, holds the idler where it
    /// stood while the chain's pull on it grows (the sprockets driven: the drive pulls the
    /// upper run, which pulls the idler forward); a spring adjuster yields by `dF / k`.
    /// The arm stops hold the arms within their travel.
    #[test]
    fn a_locked_grease_adjuster_holds_the_idler_and_the_stops_hold_the_arms() {
        let run = |adjuster: crate::track::AdjusterKind| {
            let mut d = m113_data().unwrap();
            d.track.idler.tensioner.adjuster = adjuster;
            d.track.road_wheels.arm_travel = Some([-0.02, 0.02]);
            let mut s = TrackedFlatScene::new(d, 0.8, solver()).unwrap();
            let h = 3e-3;
            s.vehicle
                .set_sprocket_drives(&mut s.sys, Drive::Speed(0.0))
                .unwrap();
            for _ in 0..60 {
                s.sys.step(h).unwrap();
            }
            let locked = s.vehicle.lock_adjusters(&mut s.sys, &s.data).unwrap();
            let x0 = s.vehicle.sides[0].adjuster_travel(&s.sys).unwrap();
            // A large drive torque pulls the upper run.
            s.vehicle
                .set_sprocket_drives(&mut s.sys, Drive::Effort(8.0e3))
                .unwrap();
            let mut arm: f64 = 0.0;
            for _ in 0..40 {
                s.sys.step(h).unwrap();
                for side in &s.vehicle.sides {
                    for k in 0..side.road_wheels.len() {
                        arm = arm.max(side.arm_angle(&s.sys, k).unwrap().abs());
                    }
                }
            }
            let x1 = s.vehicle.sides[0].adjuster_travel(&s.sys).unwrap();
            let f = s.vehicle.sides[0].adjuster_force(&s.sys).unwrap();
            (locked, x1 - x0, f, arm)
        };
        let (locked, dx, f, arm) = run(crate::track::AdjusterKind::Grease);
        assert!(locked);
        assert!(dx.abs() < 1e-4, "locked adjuster moved {dx} m");
        assert!(f > 0.0 && f.is_finite(), "{f}");
        assert!(arm < 0.02 + 2e-3, "{arm}");
        let (locked, dx, _, _) = run(crate::track::AdjusterKind::Spring);
        assert!(!locked);
        assert!(dx.abs() > 1e-3, "the spring adjuster stayed within {dx} m");
    }

    /// Every contact of the running gear enters the problem once: the pins in the sprocket's
    /// tooth gaps (cylinders on the teeth's hull slices) used to put each end of their line
    /// contacts in two or three times, a quarter of the M113's contact rows.
    #[test]
    fn the_pins_on_the_sprocket_teeth_are_each_one_contact() {
        // The vehicle cases' solver (the complement matrix-free, 60 iterations).
        let settings = chrono_core::descriptor::SolverSettings {
            tolerance: 1e-8,
            max_iterations: 60,
            record_history: false,
        };
        let solver = Box::new(chrono_ccp::Schur::new(settings).with_max_dense_rows(0));
        let mut s = TrackedFlatScene::new(m113_data().unwrap(), 0.8, solver).unwrap();
        s.vehicle
            .set_sprocket_drives(&mut s.sys, Drive::Speed(2.0))
            .unwrap();
        let mut sprocket_contacts = 0;
        for _ in 0..40 {
            s.sys.step(4e-3).unwrap();
            let cs = s.sys.contacts();
            for (i, a) in cs.iter().enumerate() {
                let a = &a.point;
                let name = |o: u32| s.sys.bodies()[o as usize].name().to_string();
                if name(a.owner_a).contains("sprocket") || name(a.owner_b).contains("sprocket") {
                    sprocket_contacts += 1;
                }
                for b in &cs[i + 1..] {
                    assert!(
                        !a.coincides(&b.point, 1e-6),
                        "the same contact twice: {a:?}"
                    );
                }
            }
        }
        assert!(sprocket_contacts > 0, "no pin on a sprocket tooth");
    }
}
