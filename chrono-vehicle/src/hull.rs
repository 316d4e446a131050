//! The collision shape of a tracked vehicle's hull: the lower outline of the hull in the
//! side view (the floor and the lower front plate), each segment a plate of the hull's
//! width and a given thickness lying on the inner side of the outline.
//!
//! A segment from `p` to `q` (chassis frame `[x, z]`, m; the outline runs rear to front
//! along the floor and then up the front plate, so the hull lies above the floor and
//! behind the front plate) becomes a box `|q - p|` long, `width` wide and `thickness`
//! thick whose outer face is the segment: centre `(p + q) / 2 + n t / 2` with the inward
//! normal `n = (-(q_z - p_z), q_x - p_x) / |q - p|`, pitched about Y so that its local X
//! runs along `q - p`. The hull is what touches an obstacle before the running gear can
//! lift it (a step higher than the nose, a ridge under the belly); it must not reach the
//! running gear sideways: its half width stays inside the innermost part of the tracks
//! (sprocket rings and pin ends, wheels, shoe plates), else an error names `hull.width`.

use serde::{Deserialize, Serialize};

use chrono_core::math::{Isometry3, Translation3, UnitQuaternion, Vector3};
use chrono_core::{ContactMaterial, Shape};

use crate::error::{Result, VehicleError, check_finite, check_positive};
use crate::track::TrackData;

/// The hull's collision shape (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HullData {
    /// The hull's lower outline in the side view, `[x, z]` in the chassis reference frame
    /// (m), rear to front: at least two points, consecutive points apart.
    pub profile: Vec<[f64; 2]>,
    /// Width of the hull's plates across the vehicle, m.
    pub width: f64,
    /// Thickness of each plate (inward from the outline), m.
    pub thickness: f64,
    /// Contact material of the hull.
    pub material: ContactMaterial,
}

/// One plate of the hull: its box and its pose in the chassis reference frame.
#[derive(Debug, Clone, PartialEq)]
pub struct HullPlate {
    /// The box.
    pub shape: Shape,
    /// Its pose in the chassis reference frame.
    pub pose: Isometry3<f64>,
}

impl HullData {
    /// Check every field against the running gear `track` whose mid-planes are at
    /// `±track_y` (errors name `{field}.profile[i]`, `{field}.width` ...).
    pub fn validate(&self, field: &str, track: &TrackData, track_y: f64) -> Result<()> {
        let f = |s: &str| format!("{field}.{s}");
        if self.profile.len() < 2 {
            return Err(VehicleError::invalid(
                f("profile"),
                self.profile.len(),
                "at least two points (one plate)",
            ));
        }
        for (i, p) in self.profile.iter().enumerate() {
            check_finite(&format!("{field}.profile[{i}][0]"), p[0])?;
            check_finite(&format!("{field}.profile[{i}][1]"), p[1])?;
            if i > 0 {
                let q = self.profile[i - 1];
                if (p[0] - q[0]).hypot(p[1] - q[1]) < 1e-3 {
                    return Err(VehicleError::invalid(
                        format!("{field}.profile[{i}]"),
                        format!("{p:?}"),
                        "must be at least 1 mm from the previous point",
                    ));
                }
            }
        }
        check_positive(&f("width"), self.width)?;
        check_positive(&f("thickness"), self.thickness)?;
        self.material
            .validate()
            .map_err(|e| VehicleError::invalid(f("material"), "-", e.to_string()))?;
        let inner = track_y - lateral_reach(track);
        if 0.5 * self.width >= inner {
            return Err(VehicleError::invalid(
                f("width"),
                self.width,
                format!(
                    "the hull would reach into the running gear: its half width must stay \
                     below {inner:.4} m (track_y minus the running gear's reach inward from \
                     the track mid-plane)"
                ),
            ));
        }
        Ok(())
    }

    /// The plates in the chassis reference frame (see the [module docs](self)).
    pub fn plates(&self) -> Vec<HullPlate> {
        self.profile
            .windows(2)
            .map(|s| {
                let (p, q) = (s[0], s[1]);
                let (dx, dz) = (q[0] - p[0], q[1] - p[1]);
                let len = dx.hypot(dz);
                let n = [-dz / len, dx / len];
                let t = 0.5 * self.thickness;
                let c = Vector3::new(
                    0.5 * (p[0] + q[0]) + n[0] * t,
                    0.0,
                    0.5 * (p[1] + q[1]) + n[1] * t,
                );
                // A rotation by `a` about +Y takes X to (cos a, 0, -sin a).
                let rot = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -dz.atan2(dx));
                HullPlate {
                    shape: Shape::Box {
                        half_extents: Vector3::new(0.5 * len, 0.5 * self.width, t),
                    },
                    pose: Isometry3::from_parts(Translation3::from(c), rot),
                }
            })
            .collect()
    }

    /// The foremost X of the outline in the chassis reference frame, m.
    pub fn front_x(&self) -> f64 {
        self.profile
            .iter()
            .map(|p| p[0])
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The lowest Z of the outline in the chassis reference frame, m.
    pub fn bottom_z(&self) -> f64 {
        self.profile
            .iter()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min)
    }
}

/// How far the running gear of one side reaches from its track mid-plane, to either side,
/// m: the sprocket rings with the pin ends (which stick out 1 cm past each ring), the
/// road wheels, the idler, the rollers and the shoe plates.
pub fn lateral_reach(track: &TrackData) -> f64 {
    let s = &track.sprocket;
    let mut r = s.gear_offset + 0.5 * (s.gear_width + 0.02);
    r = r.max(0.5 * track.road_wheels.width);
    r = r.max(0.5 * track.idler.width);
    r = r.max(0.5 * track.shoe.width);
    for ro in &track.rollers {
        r = r.max(0.5 * ro.width);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::m113::m113_data;

    /// Each plate's outer face is its outline segment: the segment's ends lie on the box's
    /// outer face (local z = -t/2), at local x = -+len/2.
    #[test]
    fn the_plates_lie_on_the_inner_side_of_the_outline() {
        let hull = m113_data().unwrap().hull.unwrap();
        let plates = hull.plates();
        assert_eq!(plates.len(), hull.profile.len() - 1);
        for (k, pl) in plates.iter().enumerate() {
            let Shape::Box { half_extents: h } = pl.shape else {
                panic!("a box")
            };
            for (j, p) in [hull.profile[k], hull.profile[k + 1]].iter().enumerate() {
                let local = pl
                    .pose
                    .inverse_transform_point(&Vector3::new(p[0], 0.0, p[1]).into());
                let sx = if j == 0 { -1.0 } else { 1.0 };
                assert!((local.x - sx * h.x).abs() < 1e-12, "{k} {j}: {local}");
                assert!((local.z + h.z).abs() < 1e-12, "{k} {j}: {local}");
            }
            // The inside (local +z) is above the floor and behind the front plate.
            let inside = pl.pose.transform_point(&Vector3::new(0.0, 0.0, h.z).into());
            let outside = pl
                .pose
                .transform_point(&Vector3::new(0.0, 0.0, -h.z).into());
            assert!(inside.z > outside.z || inside.x < outside.x, "{k}");
        }
    }

    #[test]
    fn a_hull_reaching_into_the_tracks_is_an_error_naming_the_width() {
        let d = m113_data().unwrap();
        let mut hull = d.hull.clone().unwrap();
        let inner = d.track_y - lateral_reach(&d.track);
        hull.width = 2.0 * inner + 1e-3;
        let e = hull.validate("hull", &d.track, d.track_y).unwrap_err();
        assert!(e.to_string().contains("hull.width"), "{e}");
        hull.width = 2.0 * inner - 1e-3;
        hull.validate("hull", &d.track, d.track_y).unwrap();
        hull.thickness = f64::NAN;
        let e = hull.validate("hull", &d.track, d.track_y).unwrap_err();
        assert!(e.to_string().contains("hull.thickness"), "{e}");
        let mut h2 = d.hull.clone().unwrap();
        h2.profile[1] = [f64::NAN, 0.0];
        let e = h2.validate("hull", &d.track, d.track_y).unwrap_err();
        assert!(e.to_string().contains("hull.profile[1][0]"), "{e}");
    }
}
