//! A tracked vehicle on a moving granular patch ([`GranularPatch`]), and what a test on it
//! reads: the shoes' sinkage and the grains' penetration into the shoes.
//!
//! [`TrackedGranularScene::new`] fills the patch, lets the bed settle (grains only, so the
//! settling steps are cheap), records the settled surface and the relocation template, and
//! sets the vehicle down with its lowest shoe a clearance above the surface, facing +X, the
//! middle of its tracks over the middle of the patch. Each step the owner calls
//! [`TrackedGranularScene::advance`], which moves the patch's rear slab to the front once the
//! tracks' middle is a slab past the patch's middle: the grain count stays fixed however far
//! the vehicle drives.
//!
//! The contact method is the system's (`settings.contact_method`). With SMC every contact,
//! the vehicle's own (shoe on wheel, pin on sprocket) included, is a penalty force from the
//! two colliders' materials (the M113's are in `data/m113.json`), while the joints and
//! the driveline's shafts stay rows of the CCP. With NSC the contacts are CCP rows too; the
//! shoes and wheels on light grains are a heavy-on-light problem for which
//! `chrono_ccp::LocalDirect` is the solver (a projected-gradient solve at a fixed iteration
//! cap leaves the heavy bodies' velocities far from converged).
//!
//! Example (the M113A1 on a small SMC bed; see `m113-granular` for the drive):
//!
//! ```no_run
//! use chrono_core::{ContactMethod, SystemSettings};
//! use chrono_vehicle::m113::m113_data;
//! use chrono_vehicle::terrain::GranularPatchParams;
//! use chrono_vehicle::tracked_granular::TrackedGranularScene;
//!
//! let patch = GranularPatchParams {
//!     length: 6.0, width: 3.0, depth: 0.16, grain_radius: 0.04, density: 2500.0,
//!     friction: 0.8, young_modulus: 2e7, restitution: 0.3, rolling_friction: 0.2, compliance: 0.0,
//!     slab: 0.6, seed: 7, lanes: Vec::new(),
//! };
//! let settings = SystemSettings { contact_method: ContactMethod::Smc, ..Default::default() };
//! let solver = Box::new(chrono_ccp::Schur::new(Default::default()));
//! let scene = TrackedGranularScene::new(m113_data()?, &patch, settings, solver, 2.5e-4, 0.3)?;
//! println!("{} grains, surface at {:.3} m", scene.patch.grains().len(), scene.patch.surface());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use chrono_ccp::CcpSolver;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{BodyHandle, ContactMethod, System, SystemSettings};

use crate::error::{Result, VehicleError, check_non_negative, check_positive};
use crate::hull::lateral_reach;
use crate::obstacle::front_x;
use crate::terrain::{GranularPatch, GranularPatchParams};
use crate::tracked::{TrackedVehicle, TrackedVehicleData, start_height};

/// Gap between the lowest shoe and the settled surface when the vehicle is set down, m.
pub const SET_DOWN_CLEARANCE: f64 = 0.01;

/// The rearmost X of the vehicle in its chassis reference frame at assembly, m: the chain's
/// outer face round the idler at its rearmost travel.
pub fn rear_x(data: &TrackedVehicleData) -> f64 {
    let i = &data.track.idler;
    i.location[0] + i.tensioner.travel[0].min(0.0) - i.radius - data.track.shoe.thickness
}

/// The middle of the tracks' length in the chassis reference frame, m: halfway between
/// [`front_x`] and [`rear_x`].
pub fn footprint_middle_x(data: &TrackedVehicleData) -> f64 {
    0.5 * (front_x(data) + rear_x(data))
}

/// A tracked vehicle on a moving granular patch (see the [module docs](self)).
pub struct TrackedGranularScene {
    /// The system.
    pub sys: System,
    /// The vehicle.
    pub vehicle: TrackedVehicle,
    /// Its description.
    pub data: TrackedVehicleData,
    /// The granular patch.
    pub patch: GranularPatch,
    /// X of the tracks' middle in the chassis reference frame ([`footprint_middle_x`]), m.
    pub middle_x: f64,
    /// Simulated time the bed settled before the vehicle was set down, s.
    pub settle_time: f64,
}

impl TrackedGranularScene {
    /// Build the scene: the patch `patch` (its middle under the tracks' middle), settled for
    /// `settle` s at steps of `h` s with `settings` (the contact method among them) and the
    /// CCP `solver` (`chrono_ccp::Schur` for the pin joints), then the vehicle `data` set down
    /// [`SET_DOWN_CLEARANCE`] above the settled surface. Errors name the field:
    /// `granular_patch.<field>` (also `granular_patch.width` narrower than the vehicle's
    /// running gear and `granular_patch.length` too short for the tracks plus a slab at
    /// either end), `h`, `settle`, or the vehicle data's fields.
    pub fn new(
        data: TrackedVehicleData,
        patch: &GranularPatchParams,
        settings: SystemSettings,
        solver: Box<dyn CcpSolver>,
        h: f64,
        settle: f64,
    ) -> Result<Self> {
        data.validate()?;
        patch.validate()?;
        check_positive("h", h)?;
        check_non_negative("settle", settle)?;
        let span = 2.0 * (data.track_y + lateral_reach(&data.track));
        if patch.width <= span {
            return Err(VehicleError::invalid(
                "granular_patch.width",
                patch.width,
                format!("must exceed the vehicle's width over its running gear, {span:.3} m"),
            ));
        }
        let middle_x = footprint_middle_x(&data);
        // The front of the tracks must stay clear of the front wall until the first
        // relocation (a slab past the middle).
        patch.check_room_for(front_x(&data) - middle_x)?;
        let mut sys = System::new(settings, solver)?;
        let mut gp = GranularPatch::build(&mut sys, patch, middle_x - 0.5 * patch.length)?;
        let n = (settle / h).round() as u64;
        for _ in 0..n {
            sys.step(h)?;
        }
        gp.capture_settled(&sys)?;
        let z0 = start_height(&data, gp.surface(), SET_DOWN_CLEARANCE)?;
        let vehicle =
            TrackedVehicle::build(&mut sys, &data, &Isometry3::translation(0.0, 0.0, z0))?;
        Ok(Self {
            sys,
            vehicle,
            data,
            patch: gp,
            middle_x,
            settle_time: n as f64 * h,
        })
    }

    /// The chassis reference point (world), m.
    pub fn reference(&self) -> Result<Vector3<f64>> {
        let c = self.sys.body(self.vehicle.chassis)?;
        Ok(c.position() - c.rotation() * Vector3::from(self.data.chassis.com))
    }

    /// Move the patch on as the vehicle advances ([`GranularPatch::advance`] with the
    /// tracks' middle); returns the relocations done now.
    pub fn advance(&mut self) -> Result<usize> {
        let c = self.sys.body(self.vehicle.chassis)?;
        let middle = c.position()
            + c.rotation()
                * (Vector3::new(self.middle_x, 0.0, 0.0) - Vector3::from(self.data.chassis.com));
        self.patch.advance(&mut self.sys, middle.x)
    }

    /// The shoes of both sides under the road wheels (centre between the first and the last
    /// road wheel along the chassis X axis and below the wheels' centres): the lower runs.
    pub fn lower_run_shoes(&self) -> Result<Vec<BodyHandle>> {
        let c = self.sys.body(self.vehicle.chassis)?;
        let inv = c.pose().inverse();
        let com = Vector3::from(self.data.chassis.com);
        let rw = &self.data.track.road_wheels;
        let (x_front, x_rear) = (rw.x[0], rw.x[rw.x.len() - 1]);
        let mut out = Vec::new();
        for &s in &self.vehicle.shoes() {
            // The shoe's centre in the chassis reference frame.
            let p = inv
                .transform_point(&self.sys.body(s)?.position().into())
                .coords
                + com;
            if p.x <= x_front && p.x >= x_rear && p.z < rw.z {
                out.push(s);
            }
        }
        Ok(out)
    }

    /// The sinkage of the tracks, m: the settled surface minus the mean height of the lower
    /// runs' ground faces (each shoe's lowest plate corner), over [`lower_run_shoes`](Self::lower_run_shoes).
    /// NaN when no shoe is in a lower run.
    pub fn sinkage(&self) -> Result<f64> {
        let sh = &self.data.track.shoe;
        let half = Vector3::new(0.5 * sh.pitch, 0.5 * sh.width, 0.5 * sh.thickness);
        let shoes = self.lower_run_shoes()?;
        if shoes.is_empty() {
            return Ok(f64::NAN);
        }
        let mut sum = 0.0;
        for &s in &shoes {
            let b = self.sys.body(s)?;
            let mut low = f64::INFINITY;
            for k in 0..8 {
                let corner = Vector3::new(
                    if k & 1 == 0 { -half.x } else { half.x },
                    if k & 2 == 0 { -half.y } else { half.y },
                    if k & 4 == 0 { -half.z } else { half.z },
                );
                low = low.min((b.position() + b.rotation() * corner).z);
            }
            sum += low;
        }
        Ok(self.patch.surface() - sum / shoes.len() as f64)
    }

    /// Grains against shoes in the last step: the largest penetration of a grain into a shoe
    /// (plate or pin end), m, and the number of those contacts. With SMC these are the
    /// penalty contacts' overlaps ([`System::smc_contacts`]); with NSC the contact rows'
    /// penetrations `-distance` ([`System::contacts`], found at the step's start, before the
    /// solve separates them; a contact inside the envelope that does not touch counts with
    /// a penetration <= 0). A grain whose penetration reaches its radius has its centre inside
    /// the shoe: it is passing through. See also
    /// [`grains_inside_shoes`](Self::grains_inside_shoes), which does not depend on the
    /// contact method.
    pub fn grain_shoe_overlap(&self, is_shoe: &[bool], is_grain: &[bool]) -> (f64, usize) {
        let pair = |x: u32, y: u32| {
            is_shoe.get(x as usize).copied().unwrap_or(false)
                && is_grain.get(y as usize).copied().unwrap_or(false)
        };
        let mut max = 0.0_f64;
        let mut n = 0;
        let mut add = |a: u32, b: u32, overlap: f64| {
            if pair(a, b) || pair(b, a) {
                n += 1;
                max = max.max(overlap);
            }
        };
        match self.sys.settings().contact_method {
            ContactMethod::Smc => {
                for c in self.sys.smc_contacts() {
                    add(c.owner_a, c.owner_b, c.overlap);
                }
            }
            ContactMethod::Nsc => {
                for c in self.sys.contacts() {
                    add(c.point.owner_a, c.point.owner_b, -c.point.distance);
                }
            }
        }
        (max, n)
    }

    /// Masks over the system's dense body indices: `(is_shoe, is_grain)`, for
    /// [`grain_shoe_overlap`](Self::grain_shoe_overlap). Valid until bodies are added or
    /// removed.
    pub fn body_masks(&self) -> (Vec<bool>, Vec<bool>) {
        let set = self.sys.body_set();
        let n = self.sys.bodies().len();
        let mut is_shoe = vec![false; n];
        let mut is_grain = vec![false; n];
        for s in self.vehicle.shoes() {
            if let Some(i) = set.dense_index(s) {
                is_shoe[i] = true;
            }
        }
        for &g in self.patch.grains() {
            if let Some(i) = set.dense_index(g) {
                is_grain[i] = true;
            }
        }
        (is_shoe, is_grain)
    }

    /// The number of grains whose centre lies inside a shoe's plate (a box of pitch x width x
    /// thickness in the shoe's frame): grains passing through a shoe. Geometric, so it does
    /// not depend on the contact method; costs grains x shoes distance tests (grains higher
    /// than the chassis reference are skipped).
    pub fn grains_inside_shoes(&self) -> Result<usize> {
        let sh = &self.data.track.shoe;
        let half = Vector3::new(0.5 * sh.pitch, 0.5 * sh.width, 0.5 * sh.thickness);
        let shoes: Vec<Isometry3<f64>> = self
            .vehicle
            .shoes()
            .iter()
            .map(|&s| self.sys.body(s).map(|b| b.pose()))
            .collect::<std::result::Result<_, _>>()?;
        let top = self.reference()?.z;
        let mut n = 0;
        for &g in self.patch.grains() {
            let p = self.sys.body(g)?.position();
            if p.z > top {
                continue;
            }
            for pose in &shoes {
                let l = pose.inverse_transform_point(&p.into());
                if l.x.abs() < half.x && l.y.abs() < half.y && l.z.abs() < half.z {
                    n += 1;
                    break;
                }
            }
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::m113::m113_data;

    fn patch() -> GranularPatchParams {
        GranularPatchParams {
            length: 6.0,
            width: 3.0,
            depth: 0.2,
            grain_radius: 0.05,
            density: 2500.0,
            friction: 0.8,
            young_modulus: 2e7,
            restitution: 0.3,
            rolling_friction: 0.2,
            compliance: 0.0,
            slab: 0.6,
            seed: 7,
            lanes: Vec::new(),
        }
    }

    fn smc() -> SystemSettings {
        SystemSettings {
            contact_method: ContactMethod::Smc,
            ..SystemSettings::default()
        }
    }

    fn solver() -> Box<dyn CcpSolver> {
        Box::new(chrono_ccp::Schur::new(Default::default()).with_max_dense_rows(0))
    }

    /// Set down on the bed, the vehicle's footprint lies over the patch, no grain is inside
    /// a shoe, and the forward-speed start gives the lower runs zero world speed.
    #[test]
    fn the_m113_is_set_down_over_the_patch_with_the_chains_rolling() {
        let d = m113_data().unwrap();
        let mut s =
            TrackedGranularScene::new(d.clone(), &patch(), smc(), solver(), 2.5e-4, 0.05).unwrap();
        let (rear, front) = (s.patch.rear(), s.patch.front());
        assert!(rear < rear_x(&d) && front > front_x(&d), "{rear} {front}");
        assert_eq!(s.grains_inside_shoes().unwrap(), 0);
        let drive = crate::tracked_drive::TrackedDrive::build(&mut s.sys, &s.vehicle, &d).unwrap();
        drive
            .set_forward_speed(&mut s.sys, &s.vehicle, &d, 2.0)
            .unwrap();
        let w = 2.0 / d.track.sprocket.pitch_radius;
        for side in 0..2 {
            assert!((drive.sprocket_speed(&s.sys, side) - w).abs() < 1e-12);
        }
        let ratio = drive.powertrain().transmission().ratio().unwrap();
        let w_in = w / d.driveline.conical_ratio / ratio;
        let crank = drive
            .shafts(&s.sys)
            .unwrap()
            .speed(drive.powertrain().crankshaft());
        assert!((crank - w_in).abs() < 1e-9 * w_in, "{crank} {w_in}");
        let lower = s.lower_run_shoes().unwrap();
        assert!(lower.len() >= 30, "{}", lower.len());
        // Standing on the ground; the shoes next to a bend tilt with it (the pins' central
        // differences there mix the straight run and the arc).
        let mut mean = Vector3::zeros();
        for &b in &lower {
            let v = s.sys.body(b).unwrap().linear_velocity();
            assert!(v.norm() < 0.1, "a lower-run shoe moves at {v}");
            mean += v / lower.len() as f64;
        }
        assert!(mean.norm() < 0.01, "the lower run moves at {mean}");
        let top = s
            .vehicle
            .shoes()
            .into_iter()
            .max_by(|a, b| {
                let z = |h| s.sys.body(h).unwrap().position().z;
                z(*a).total_cmp(&z(*b))
            })
            .unwrap();
        let v = s.sys.body(top).unwrap().linear_velocity();
        assert!((v.x - 4.0).abs() < 0.05, "the upper run moves at {v}");
        // One step later the chains are still closed.
        s.sys.step(2.5e-4).unwrap();
        assert!(s.sys.max_joint_violation() < 1e-3);
    }

    /// NSC grains under the tracks with the heavy-on-light solver (`chrono_ccp::LocalDirect`,
    /// as `m113-granular --set method=nsc`) at a 1 ms step: the vehicle lands on the bed and
    /// rolls on it with no grain passing through a shoe (the contact rows' penetration a
    /// small fraction of a grain radius, no grain centre inside a plate), the chains closed
    /// and the chassis neither thrown up nor sunk. With APGD or Schur at a cap of 60 the
    /// heavy-on-light rows are far from converged (docs/validation-vehicle.md, "Granular
    /// terrain"); the NSC branch of [`TrackedGranularScene::grain_shoe_overlap`] must see the
    /// grain-shoe contacts.
    #[test]
    fn the_m113_lands_and_rolls_on_nsc_grains_with_the_heavy_on_light_solver() {
        let d = m113_data().unwrap();
        let h = 1e-3;
        let solver = Box::new(chrono_ccp::LocalDirect::new(chrono_ccp::SolverSettings {
            tolerance: 1e-3,
            max_iterations: 60,
            record_history: false,
        }));
        let nsc = SystemSettings {
            contact_method: ContactMethod::Nsc,
            ..SystemSettings::default()
        };
        let mut s = TrackedGranularScene::new(d.clone(), &patch(), nsc, solver, h, 0.03).unwrap();
        let drive = crate::tracked_drive::TrackedDrive::build(&mut s.sys, &s.vehicle, &d).unwrap();
        let (is_shoe, is_grain) = s.body_masks();
        let r = patch().grain_radius;
        let (mut worst, mut touching) = (0.0_f64, 0usize);
        let z0 = s.reference().unwrap().z;
        // Land (the lowest shoe starts 1 cm above the bed), then roll at 2 m/s.
        for i in 0..60 {
            if i == 45 {
                drive
                    .set_forward_speed(&mut s.sys, &s.vehicle, &d, 2.0)
                    .unwrap();
            }
            s.advance().unwrap();
            s.sys.step(h).unwrap();
            let (o, n) = s.grain_shoe_overlap(&is_shoe, &is_grain);
            worst = worst.max(o);
            touching = touching.max(n);
            assert_eq!(s.grains_inside_shoes().unwrap(), 0, "step {i}");
        }
        assert!(touching > 20, "grain-shoe contact rows: {touching}");
        assert!(worst < 0.1 * r, "grain penetration into a shoe {worst} m");
        assert!(s.sys.max_joint_violation() < 1e-3);
        let c = s.sys.body(s.vehicle.chassis).unwrap();
        let v = c.linear_velocity();
        assert!(v.iter().all(|x| x.is_finite()), "{v}");
        assert!((v.x - 2.0).abs() < 0.3, "forward speed {}", v.x);
        assert!(v.z.abs() < 0.2, "vertical speed {}", v.z);
        let dz = s.reference().unwrap().z - z0;
        assert!(dz.abs() < 0.05, "the chassis moved {dz} m vertically");
    }

    #[test]
    fn bad_input_is_an_error_naming_the_field() {
        let build = |p: GranularPatchParams, h: f64| {
            TrackedGranularScene::new(m113_data().unwrap(), &p, smc(), solver(), h, 0.0)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        let e = build(
            GranularPatchParams {
                width: 2.0,
                ..patch()
            },
            2.5e-4,
        );
        assert!(e.contains("granular_patch.width"), "{e}");
        let e = build(
            GranularPatchParams {
                length: 4.0,
                slab: 0.5,
                ..patch()
            },
            2.5e-4,
        );
        assert!(e.contains("granular_patch.length"), "{e}");
        let e = build(
            GranularPatchParams {
                depth: f64::NAN,
                ..patch()
            },
            2.5e-4,
        );
        assert!(e.contains("granular_patch.depth"), "{e}");
        assert!(build(patch(), -1.0).contains("`h`"));
    }
}
