//! Track templates: the running gear of a tracked vehicle, one side at a time, built from a
//! serde description like the wheeled templates.
//!
//! - [`geometry`]: the loop the chain wraps (sprocket pitch circle, road wheels, idler), the
//!   pins placed one pitch apart along it and the idler position that closes the loop;
//! - [`torsion`]: the torsion-bar spring (a rotational spring-damper with preload between
//!   the chassis and a road-wheel arm);
//! - [`assembly`]: one side in a system: sprocket (two gear rings whose teeth drive the
//!   shoes' pin ends), idler on a tensioner (a carrier on a prismatic joint pushed rearward
//!   by a preloaded spring-damper), road wheels on trailing arms with torsion bars and rotary
//!   shocks, optional support rollers, and single-pin shoes joined by revolute joints; all
//!   contacts (shoe–wheel, pin–sprocket, shoe–ground) are ordinary CCP contact rows with
//!   the data's materials.
//!
//! Frames: the track frame is the chassis frame shifted to the track's mid-plane
//! (`y = ±track_y`); positions in the data are `[x, z]` in that plane, X forward, Z up, m.
//! Both sides have the same side-view geometry (only `y` differs); the shoe count can
//! differ (the M113 has 63 on the left and 64 on the right).
//!
//! The chain is assembled from the data: the pins go one pitch apart around the wheels,
//! and the idler slides along its tensioner (within its travel) until the last pin meets
//! the first. A chain too short or too long for that travel, a sprocket whose tooth count
//! does not match the pitch at its pitch radius, a negative preload: each is an error
//! naming the field.

pub mod assembly;
pub mod geometry;
pub mod torsion;

use serde::{Deserialize, Serialize};

use chrono_core::ContactMaterial;

use crate::error::{Result, VehicleError, check_finite, check_non_negative, check_positive};
use crate::suspension::MassData;

pub use assembly::{RoadWheel, TrackAssembly};
pub use geometry::{ChainLayout, Circle};
pub use torsion::TorsionSpring;

/// The drive sprocket: two gear rings (one each side of the shoes, at `±gear_offset` from
/// the track mid-plane) of `num_teeth` teeth each; the shoes' pin ends seat in the gaps at
/// the pitch radius and the teeth push on them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SprocketData {
    /// Centre `[x, z]` in the track frame, m.
    pub location: [f64; 2],
    /// Sprocket (both gears and hub) mass and inertia.
    pub mass: MassData,
    /// Number of teeth of each gear ring.
    pub num_teeth: usize,
    /// Pitch radius: where the pin centres sit in the gaps, m. Must equal
    /// `pitch / (2 sin(pi / num_teeth))` within 0.1 %.
    pub pitch_radius: f64,
    /// Tooth tip radius, m (> pitch radius).
    pub tip_radius: f64,
    /// Width of each gear ring, m.
    pub gear_width: f64,
    /// Lateral distance of each gear ring's mid-plane from the track mid-plane, m (the shoe
    /// plate lies between the rings: `> shoe.width / 2 + gear_width / 2`).
    pub gear_offset: f64,
    /// Radius of each tooth gap, m: the gap is a circular trough whose bottom is the pin
    /// seat (radius `pitch_radius - shoe.pin_radius` from the sprocket centre) and whose
    /// centre lies on the gap's mid-line `gap_radius` beyond it. A loaded pin rolls up the
    /// trough's side until the chain's tension balances the drive force, and leaves it at
    /// the exit without bearing on a radial face (the scalloped gear of Project Chrono's
    /// M113 sprocket: troughs of radius 0.089 m). Must exceed `shoe.pin_radius`, and the
    /// teeth between two troughs must keep a width at the tip radius.
    pub gap_radius: f64,
}

impl SprocketData {
    /// Half-angle (rad) that a tooth gap subtends at radius `r` from the sprocket centre:
    /// the trough (centre at `c = seat + gap_radius` on the gap's mid-line, radius
    /// `gap_radius`) meets the circle of radius `r` at `cos b = (c^2 + r^2 - R^2) / (2 c r)`;
    /// 0 at or below the seat radius `seat`.
    pub fn gap_half_angle(&self, seat: f64, r: f64) -> f64 {
        let c = seat + self.gap_radius;
        let rg = self.gap_radius;
        if r <= seat {
            return 0.0;
        }
        ((c * c + r * r - rg * rg) / (2.0 * c * r))
            .clamp(-1.0, 1.0)
            .acos()
    }
}

/// What holds the idler once the track is adjusted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AdjusterKind {
    /// The preloaded spring-damper all the time (Project Chrono's M113 tensioner): the
    /// idler moves forward by `dF / stiffness` when the chain's pull on it grows by `dF`.
    #[default]
    Spring,
    /// A grease cylinder (a track adjusting link): grease pumped in pushes the idler out
    /// until the track's sag is right, then the trapped grease holds the link's length.
    /// In the model the spring-damper sets the idler while the vehicle settles (the
    /// adjustment, at the preload), then [`TrackAssembly::lock_adjuster`] holds the carrier
    /// where it stands (a rigid constraint row on its slide: the grease taken as
    /// incompressible); the chain's pull on the idler is then whatever the loop needs.
    Grease,
}

/// The tensioner: a preloaded spring-damper pushing the idler carrier rearward along the
/// track frame's X axis, optionally locked after the adjustment ([`AdjusterKind`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TensionerData {
    /// Force at the assembled position, N (>= 0, pushes the idler rearward).
    pub preload: f64,
    /// Stiffness, N/m (the force falls by this much per metre of rearward travel).
    pub stiffness: f64,
    /// Damping, N s/m.
    pub damping: f64,
    /// Range of the idler position along X relative to `idler.location`, m: `[rearward
    /// limit (<= 0), forward limit (>= 0)]`, the range the assembly may place it in.
    pub travel: [f64; 2],
    /// What holds the idler after the adjustment (`"spring"`, the default, or `"grease"`).
    #[serde(default)]
    pub adjuster: AdjusterKind,
}

/// The idler: a wheel at the rear on a carrier that slides along the tensioner.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdlerData {
    /// Nominal centre `[x, z]` in the track frame, m.
    pub location: [f64; 2],
    /// Wheel radius, m.
    pub radius: f64,
    /// Wheel width, m.
    pub width: f64,
    /// Wheel mass and inertia.
    pub mass: MassData,
    /// Carrier mass and inertia.
    pub carrier: MassData,
    /// The tensioner.
    pub tensioner: TensionerData,
}

/// The torsion bar of a road-wheel arm: torque `T = preload - k theta - c theta_dot` about
/// the track frame's +Y axis on the arm (reaction on the chassis), `theta` the arm's
/// rotation from its assembled position.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TorsionBarData {
    /// Rate `k`, N m/rad.
    pub stiffness: f64,
    /// Damping `c`, N m s/rad.
    pub damping: f64,
    /// Torque at the assembled position, N m (about +Y; a trailing arm carrying load needs
    /// a negative one).
    pub preload: f64,
}

/// The road wheels: all of one size, on trailing arms with torsion bars.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoadWheelData {
    /// Wheel centres' X in the track frame, m, front to rear.
    pub x: Vec<f64>,
    /// Wheel centres' Z in the track frame (assembled position), m.
    pub z: f64,
    /// Wheel radius, m.
    pub radius: f64,
    /// Wheel width (both discs of a dual wheel as one cylinder), m.
    pub width: f64,
    /// Wheel mass and inertia.
    pub wheel: MassData,
    /// Arm mass and inertia (centre of mass midway between pivot and wheel).
    pub arm: MassData,
    /// Arm pivot relative to the wheel centre `[dx, dz]`, m (a trailing arm: `dx > 0`).
    pub arm_pivot: [f64; 2],
    /// The torsion bar of every arm.
    pub torsion_bar: TorsionBarData,
    /// Rotary shock: extra damping at the pivot, N m s/rad, on the wheels in `shock_wheels`.
    pub shock_damping: f64,
    /// Indices of the wheels with a shock absorber.
    pub shock_wheels: Vec<usize>,
    /// The arms' travel: `[rebound, jounce]`, rad, each arm's rotation about the track
    /// frame's +Y from its assembled position at which a stop holds it (rebound `< 0`: the
    /// wheel down; jounce `> 0`: the wheel up, towards the hull). The stops are rigid
    /// (unilateral constraint rows); absent, the arms swing freely against the torsion
    /// bars. A wheel travel `s` (m, at the wheel centre) on an arm of length `l` is about
    /// `s / l` rad. Rigid stops on the rigid chain with a locked (grease) adjuster
    /// over-constrain the loop when an arm sits on its stop: `m113-step` at +-0.15 rad
    /// drifted 0.24 m (docs/validation-vehicle.md, "`m113-step`: the track adjuster").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm_travel: Option<[f64; 2]>,
}

/// A support (return) roller under the upper run, fixed to the chassis by a revolute joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RollerData {
    /// Centre `[x, z]` in the track frame, m. Its top must not poke through the upper run
    /// of the assembled chain.
    pub location: [f64; 2],
    /// Radius, m.
    pub radius: f64,
    /// Width, m.
    pub width: f64,
    /// Mass and inertia.
    pub mass: MassData,
}

/// A single-pin track shoe: a plate (box) `pitch` long, `width` wide, `thickness` thick,
/// with the pins at its ends at mid-thickness; the pin ends reach out to the sprocket's
/// gear rings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShoeData {
    /// Pin-to-pin distance, m.
    pub pitch: f64,
    /// Plate width, m.
    pub width: f64,
    /// Plate thickness, m.
    pub thickness: f64,
    /// Pin (end connector) radius, m (< thickness / 2, so pins never touch the ground).
    pub pin_radius: f64,
    /// Mass and inertia of one shoe.
    pub mass: MassData,
    /// Number of shoes on the left and the right track.
    pub count: [usize; 2],
}

/// The contact materials of the running gear (NSC friction; SMC constants for later).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackMaterials {
    /// Shoe plate and pins (against wheels, sprocket and ground; the terrain's own
    /// material combines with it by the minimum friction).
    pub shoe: ContactMaterial,
    /// Road wheels, idler and rollers.
    pub wheel: ContactMaterial,
    /// The sprocket's gear rings (steel, against the pin ends).
    pub sprocket: ContactMaterial,
}

/// One track's running gear (both sides share it; see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackData {
    /// The drive sprocket (front).
    pub sprocket: SprocketData,
    /// The idler and its tensioner (rear).
    pub idler: IdlerData,
    /// The road wheels and their suspension.
    pub road_wheels: RoadWheelData,
    /// Support rollers (none on a flat-track suspension).
    #[serde(default)]
    pub rollers: Vec<RollerData>,
    /// The shoes.
    pub shoe: ShoeData,
    /// Contact materials.
    pub materials: TrackMaterials,
}

fn check_point(field: &str, p: [f64; 2]) -> Result<()> {
    check_finite(&format!("{field}[0]"), p[0])?;
    check_finite(&format!("{field}[1]"), p[1])?;
    Ok(())
}

impl TrackData {
    /// Check every field (the error names it under `field`, e.g. `track`).
    pub fn validate(&self, field: &str) -> Result<()> {
        let f = |s: &str| format!("{field}.{s}");
        let sh = &self.shoe;
        check_positive(&f("shoe.pitch"), sh.pitch)?;
        check_positive(&f("shoe.width"), sh.width)?;
        check_positive(&f("shoe.thickness"), sh.thickness)?;
        check_positive(&f("shoe.pin_radius"), sh.pin_radius)?;
        if sh.pin_radius >= 0.5 * sh.thickness {
            return Err(VehicleError::invalid(
                f("shoe.pin_radius"),
                sh.pin_radius,
                format!("must be < thickness / 2 = {}", 0.5 * sh.thickness),
            ));
        }
        sh.mass.validate(&f("shoe.mass"))?;
        for (i, &n) in sh.count.iter().enumerate() {
            if n < 8 {
                return Err(VehicleError::invalid(
                    format!("{field}.shoe.count[{i}]"),
                    n,
                    "a track needs at least 8 shoes",
                ));
            }
        }

        let s = &self.sprocket;
        check_point(&f("sprocket.location"), s.location)?;
        s.mass.validate(&f("sprocket.mass"))?;
        if s.num_teeth < 3 {
            return Err(VehicleError::invalid(
                f("sprocket.num_teeth"),
                s.num_teeth,
                "a sprocket needs at least 3 teeth",
            ));
        }
        check_positive(&f("sprocket.pitch_radius"), s.pitch_radius)?;
        let want = sh.pitch / (2.0 * (std::f64::consts::PI / s.num_teeth as f64).sin());
        if (s.pitch_radius - want).abs() > 1e-3 * want {
            return Err(VehicleError::invalid(
                f("sprocket.num_teeth"),
                s.num_teeth,
                format!(
                    "does not match the shoe pitch {} m at the pitch radius {} m: {} teeth need \
                     a pitch radius of {want:.5} m (pitch / (2 sin(pi / teeth)))",
                    sh.pitch, s.pitch_radius, s.num_teeth
                ),
            ));
        }
        if !(s.tip_radius.is_finite() && s.tip_radius > s.pitch_radius + sh.pin_radius) {
            return Err(VehicleError::invalid(
                f("sprocket.tip_radius"),
                s.tip_radius,
                "must exceed pitch_radius + shoe.pin_radius (the teeth must reach past the pins)",
            ));
        }
        check_positive(&f("sprocket.gear_width"), s.gear_width)?;
        if !(s.gap_radius.is_finite() && s.gap_radius > sh.pin_radius) {
            return Err(VehicleError::invalid(
                f("sprocket.gap_radius"),
                s.gap_radius,
                "must exceed shoe.pin_radius (the pin must fit in the trough)",
            ));
        }
        if !(s.gear_offset.is_finite() && s.gear_offset > 0.5 * (sh.width + s.gear_width)) {
            return Err(VehicleError::invalid(
                f("sprocket.gear_offset"),
                s.gear_offset,
                format!(
                    "must exceed (shoe.width + gear_width) / 2 = {} (the rings sit outside the \
                     shoe plate)",
                    0.5 * (sh.width + s.gear_width)
                ),
            ));
        }
        // Two troughs must leave a tooth at the tip radius.
        let seat = s.pitch_radius - sh.pin_radius;
        let tip_gap = s.gap_half_angle(seat, s.tip_radius);
        if tip_gap >= std::f64::consts::PI / s.num_teeth as f64 {
            return Err(VehicleError::invalid(
                f("sprocket.gap_radius"),
                s.gap_radius,
                format!(
                    "the troughs leave no tooth at the tip radius {} m (each gap spans {:.1}                      deg there, a tooth pitch is {:.1} deg)",
                    s.tip_radius,
                    2.0 * tip_gap.to_degrees(),
                    360.0 / s.num_teeth as f64
                ),
            ));
        }

        let i = &self.idler;
        check_point(&f("idler.location"), i.location)?;
        check_positive(&f("idler.radius"), i.radius)?;
        check_positive(&f("idler.width"), i.width)?;
        i.mass.validate(&f("idler.mass"))?;
        i.carrier.validate(&f("idler.carrier"))?;
        let t = &i.tensioner;
        check_non_negative(&f("idler.tensioner.preload"), t.preload)?;
        check_positive(&f("idler.tensioner.stiffness"), t.stiffness)?;
        check_non_negative(&f("idler.tensioner.damping"), t.damping)?;
        if !(t.travel[0].is_finite() && t.travel[0] <= 0.0) {
            return Err(VehicleError::invalid(
                f("idler.tensioner.travel[0]"),
                t.travel[0],
                "the rearward limit must be finite and <= 0",
            ));
        }
        if !(t.travel[1].is_finite() && t.travel[1] >= 0.0 && t.travel[1] > t.travel[0]) {
            return Err(VehicleError::invalid(
                f("idler.tensioner.travel[1]"),
                t.travel[1],
                "the forward limit must be finite, >= 0 and above the rearward limit",
            ));
        }

        let r = &self.road_wheels;
        if r.x.len() < 2 {
            return Err(VehicleError::invalid(
                f("road_wheels.x"),
                r.x.len(),
                "at least two road wheels",
            ));
        }
        for (k, w) in r.x.windows(2).enumerate() {
            check_finite(&format!("{field}.road_wheels.x[{k}]"), w[0])?;
            if !w[1].is_finite() || w[1] >= w[0] - 2.0 * r.radius {
                return Err(VehicleError::invalid(
                    format!("{field}.road_wheels.x[{}]", k + 1),
                    w[1],
                    "road wheels go front to rear without overlapping",
                ));
            }
        }
        check_finite(&f("road_wheels.z"), r.z)?;
        check_positive(&f("road_wheels.radius"), r.radius)?;
        check_positive(&f("road_wheels.width"), r.width)?;
        r.wheel.validate(&f("road_wheels.wheel"))?;
        r.arm.validate(&f("road_wheels.arm"))?;
        check_point(&f("road_wheels.arm_pivot"), r.arm_pivot)?;
        if r.arm_pivot[0].hypot(r.arm_pivot[1]) < 1e-3 {
            return Err(VehicleError::invalid(
                f("road_wheels.arm_pivot"),
                format!("{:?}", r.arm_pivot),
                "the pivot must be away from the wheel centre",
            ));
        }
        check_non_negative(
            &f("road_wheels.torsion_bar.stiffness"),
            r.torsion_bar.stiffness,
        )?;
        check_non_negative(&f("road_wheels.torsion_bar.damping"), r.torsion_bar.damping)?;
        check_finite(&f("road_wheels.torsion_bar.preload"), r.torsion_bar.preload)?;
        check_non_negative(&f("road_wheels.shock_damping"), r.shock_damping)?;
        if let Some([lo, hi]) = r.arm_travel {
            if !(lo.is_finite() && lo < 0.0) {
                return Err(VehicleError::invalid(
                    f("road_wheels.arm_travel[0]"),
                    lo,
                    "the rebound stop must be finite and < 0 (rad from the assembled arm)",
                ));
            }
            if !(hi.is_finite() && hi > 0.0) {
                return Err(VehicleError::invalid(
                    f("road_wheels.arm_travel[1]"),
                    hi,
                    "the jounce stop must be finite and > 0 (rad from the assembled arm)",
                ));
            }
        }
        for (k, &w) in r.shock_wheels.iter().enumerate() {
            if w >= r.x.len() {
                return Err(VehicleError::invalid(
                    format!("{field}.road_wheels.shock_wheels[{k}]"),
                    w,
                    format!("there are {} road wheels", r.x.len()),
                ));
            }
        }
        for (k, ro) in self.rollers.iter().enumerate() {
            let g = |s: &str| format!("{field}.rollers[{k}].{s}");
            check_point(&g("location"), ro.location)?;
            check_positive(&g("radius"), ro.radius)?;
            check_positive(&g("width"), ro.width)?;
            ro.mass.validate(&g("mass"))?;
        }
        self.materials
            .shoe
            .validate()
            .map_err(|e| VehicleError::invalid(f("materials.shoe"), "-", e.to_string()))?;
        self.materials
            .wheel
            .validate()
            .map_err(|e| VehicleError::invalid(f("materials.wheel"), "-", e.to_string()))?;
        self.materials
            .sprocket
            .validate()
            .map_err(|e| VehicleError::invalid(f("materials.sprocket"), "-", e.to_string()))?;
        Ok(())
    }

    /// The mass of one side's running gear with `shoes` shoes (sprocket, idler and carrier,
    /// road wheels and arms, rollers, shoes), kg.
    pub fn side_mass(&self, shoes: usize) -> f64 {
        let r = &self.road_wheels;
        self.sprocket.mass.mass
            + self.idler.mass.mass
            + self.idler.carrier.mass
            + r.x.len() as f64 * (r.wheel.mass + r.arm.mass)
            + self.rollers.iter().map(|x| x.mass.mass).sum::<f64>()
            + shoes as f64 * self.shoe.mass.mass
    }

    /// The mass of one side's shoes, kg.
    pub fn chain_mass(&self, shoes: usize) -> f64 {
        shoes as f64 * self.shoe.mass.mass
    }
}

#[cfg(test)]
mod gap_tests {
    use crate::m113::m113_data;

    /// The trough meets the circle of radius `r` where `gap_half_angle` says: that point lies
    /// on the trough's circle; at and below the seat the gap closes.
    #[test]
    fn the_gap_half_angle_lies_on_the_trough() {
        let s = m113_data().unwrap().track.sprocket;
        let seat = 0.2266;
        let c = seat + s.gap_radius;
        assert_eq!(s.gap_half_angle(seat, seat), 0.0);
        assert_eq!(s.gap_half_angle(seat, 0.9 * seat), 0.0);
        for r in [0.23, 0.2466, 0.27, 0.29] {
            let b = s.gap_half_angle(seat, r);
            let (x, y) = (r * b.cos(), r * b.sin());
            let d = (x - c).hypot(y);
            assert!((d - s.gap_radius).abs() < 1e-12, "{r}: {d}");
            assert!(b > 0.0 && b < std::f64::consts::PI / s.num_teeth as f64);
        }
    }
}
