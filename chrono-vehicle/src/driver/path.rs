//! Paths on the ground plane: polylines with an arc-length parametrization.

use std::f64::consts::PI;

use chrono_core::math::Vector3;
use nalgebra::Vector2;

use crate::error::{Result, VehicleError, check_positive};

/// The point of a [`Path`] closest to a query point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    /// Arc length of the point from the start, m.
    pub s: f64,
    /// The point `(x, y)`, m.
    pub point: Vector2<f64>,
    /// Unit tangent (direction of travel).
    pub tangent: Vector2<f64>,
    /// Signed distance of the query point from the path, m: positive to the left of the
    /// direction of travel.
    pub offset: f64,
}

/// A path in the horizontal plane: a polyline through `points` (world `(x, y)`, m),
/// parametrized by arc length `s` from the first point, optionally closed (the last point
/// joins the first). Queries allocate nothing; the closest-point query visits every
/// segment (`O(n)`).
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    points: Vec<Vector2<f64>>,
    /// `s[i]` is the arc length at `points[i]`; one more entry for a closed path (the end
    /// of the closing segment).
    arc: Vec<f64>,
    closed: bool,
}

impl Path {
    /// An open polyline through at least 2 finite points, consecutive points distinct.
    /// Errors name the point (`path.points[3]`).
    pub fn new(points: Vec<[f64; 2]>) -> Result<Self> {
        Self::build(points, false)
    }

    /// A closed polyline (the last point joins the first; do not repeat it), at least 3
    /// points.
    pub fn closed(points: Vec<[f64; 2]>) -> Result<Self> {
        Self::build(points, true)
    }

    fn build(points: Vec<[f64; 2]>, closed: bool) -> Result<Self> {
        let min = if closed { 3 } else { 2 };
        if points.len() < min {
            return Err(VehicleError::invalid(
                "path.points.len()",
                points.len(),
                format!("a path needs at least {min} points"),
            ));
        }
        let pts: Vec<Vector2<f64>> = points.iter().map(|p| Vector2::new(p[0], p[1])).collect();
        let mut arc = Vec::with_capacity(pts.len() + 1);
        arc.push(0.0);
        let n = pts.len();
        let segs = if closed { n } else { n - 1 };
        for (i, p) in pts.iter().enumerate() {
            if !(p.x.is_finite() && p.y.is_finite()) {
                return Err(VehicleError::invalid(
                    format!("path.points[{i}]"),
                    format!("[{}, {}]", p.x, p.y),
                    "must be finite",
                ));
            }
        }
        for i in 0..segs {
            let l = (pts[(i + 1) % n] - pts[i]).norm();
            if l <= 0.0 {
                return Err(VehicleError::invalid(
                    format!("path.points[{}]", (i + 1) % n),
                    format!("[{}, {}]", pts[(i + 1) % n].x, pts[(i + 1) % n].y),
                    format!("repeats point {i}: segments must have a length"),
                ));
            }
            arc.push(arc[i] + l);
        }
        Ok(Self {
            points: pts,
            arc,
            closed,
        })
    }

    /// A straight path from `start` along `heading` (rad from X, counter-clockwise) of
    /// `length` m.
    pub fn straight(start: [f64; 2], heading: f64, length: f64) -> Result<Self> {
        check_positive("path.length", length)?;
        let end = [
            start[0] + length * heading.cos(),
            start[1] + length * heading.sin(),
        ];
        Self::new(vec![start, end])
    }

    /// The course of a constant-radius turn test: a left circle of `radius` m (720 points)
    /// through `(start_x, 0)` heading +X, centred at `(start_x, radius)`. With `start_x`
    /// the rear axle's `x` in the vehicle frame, a vehicle starting at the origin heading
    /// +X has its rear axle on the circle, whose kinematic (Ackermann) steer angle is
    /// `atan(L / radius)` for the wheelbase `L`.
    pub fn turn_circle(start_x: f64, radius: f64) -> Result<Self> {
        Self::circle([start_x, radius], radius, 720, true)
    }

    /// A closed circle of `radius` about `center` with `n` points (>= 8), travelled
    /// counter-clockwise (a left turn) if `left`, else clockwise, starting at the point
    /// `center - radius * Y` for a left turn (`+ radius * Y` for a right turn), where the
    /// direction of travel is +X.
    pub fn circle(center: [f64; 2], radius: f64, n: usize, left: bool) -> Result<Self> {
        check_positive("path.radius", radius)?;
        if n < 8 {
            return Err(VehicleError::invalid(
                "path.n",
                n,
                "a circle needs >= 8 points",
            ));
        }
        let sign = if left { 1.0 } else { -1.0 };
        let pts = (0..n)
            .map(|k| {
                let a = -0.5 * PI + 2.0 * PI * k as f64 / n as f64;
                [
                    center[0] + radius * a.cos(),
                    center[1] + sign * radius * a.sin(),
                ]
            })
            .collect();
        Self::closed(pts)
    }

    /// Total length, m (including the closing segment of a closed path).
    pub fn length(&self) -> f64 {
        *self.arc.last().expect("a path has points")
    }

    /// Whether the path is closed.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// The polyline's points.
    pub fn points(&self) -> &[Vector2<f64>] {
        &self.points
    }

    fn segment(&self, i: usize) -> (Vector2<f64>, Vector2<f64>) {
        let n = self.points.len();
        (self.points[i], self.points[(i + 1) % n])
    }

    fn segment_count(&self) -> usize {
        self.arc.len() - 1
    }

    /// The point and unit tangent at arc length `s` (m): wrapped for a closed path; for an
    /// open path, beyond its ends the end segments' lines are continued, so that a
    /// look-ahead past the end keeps the last direction.
    pub fn point_at(&self, s: f64) -> (Vector2<f64>, Vector2<f64>) {
        let len = self.length();
        let s = if self.closed { s.rem_euclid(len) } else { s };
        let nseg = self.segment_count();
        let i = (self.arc.partition_point(|&a| a <= s)).clamp(1, nseg) - 1;
        let (a, b) = self.segment(i);
        let l = self.arc[i + 1] - self.arc[i];
        let t = (b - a) / l;
        (a + t * (s - self.arc[i]), t)
    }

    /// The point of the path closest to `p` (world `(x, y)`).
    pub fn closest(&self, p: Vector2<f64>) -> PathPoint {
        let mut best = (f64::INFINITY, 0usize, 0.0f64);
        for i in 0..self.segment_count() {
            let (a, b) = self.segment(i);
            let d = b - a;
            let u = ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            let dist2 = (a + u * d - p).norm_squared();
            if dist2 < best.0 {
                best = (dist2, i, u);
            }
        }
        let (_, i, u) = best;
        let (a, b) = self.segment(i);
        let l = self.arc[i + 1] - self.arc[i];
        let t = (b - a) / l;
        let point = a + u * (b - a);
        let r = p - point;
        PathPoint {
            s: self.arc[i] + u * l,
            point,
            tangent: t,
            offset: t.x * r.y - t.y * r.x,
        }
    }

    /// The path as 3D points at height `z` (for output).
    pub fn to_points3(&self, z: f64) -> Vec<Vector3<f64>> {
        self.points
            .iter()
            .map(|p| Vector3::new(p.x, p.y, z))
            .collect()
    }
}

/// The ISO 3888-1:1999 double lane change ("Passenger cars -- Test track for a severe
/// lane-change manoeuvre -- Part 1: Double lane-change") for a vehicle of width `b` (m):
///
/// | section | length | lane width      |
/// |---------|--------|-----------------|
/// | 1 (entry lane)      | 15 m | `1.1 b + 0.25` |
/// | 2 (lane change)     | 30 m | -              |
/// | 3 (side lane)       | 25 m | `b + 1`        |
/// | 4 (lane change back)| 25 m | -              |
/// | 5 (exit lane)       | 15 m | `1.3 b + 0.25` |
///
/// The side lane is offset to the left by 3.5 m, measured between the right-hand cone
/// lines of lanes 1 and 3, so its center line is `3.5 + (w3 - w1)/2` m left of lane 1's.
/// Section 1 starts at `x = 0`, lane 1 is centered on `y = 0`, travel is along +X.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IsoDoubleLaneChange {
    /// Vehicle width `b`, m.
    pub vehicle_width: f64,
}

impl IsoDoubleLaneChange {
    /// Lengths of the five sections, m.
    pub const SECTION_LENGTHS: [f64; 5] = [15.0, 30.0, 25.0, 25.0, 15.0];
    /// Lateral offset between the right-hand cone lines of lanes 1 and 3, m.
    pub const OFFSET: f64 = 3.5;

    /// For a vehicle of width `vehicle_width` (m, > 0).
    pub fn new(vehicle_width: f64) -> Result<Self> {
        check_positive("iso_double_lane_change.vehicle_width", vehicle_width)?;
        Ok(Self { vehicle_width })
    }

    /// Lane widths of sections 1, 3 and 5, m.
    pub fn lane_widths(&self) -> [f64; 3] {
        let b = self.vehicle_width;
        [1.1 * b + 0.25, b + 1.0, 1.3 * b + 0.25]
    }

    /// `x` of the section boundaries `[0, 15, 45, 70, 95, 110]`, m.
    pub fn boundaries(&self) -> [f64; 6] {
        let mut x = [0.0; 6];
        for k in 0..5 {
            x[k + 1] = x[k] + Self::SECTION_LENGTHS[k];
        }
        x
    }

    /// `y` of the center line of lane 3 (m, left of lane 1's center line).
    pub fn side_lane_center(&self) -> f64 {
        let [w1, w3, _] = self.lane_widths();
        -0.5 * w1 + Self::OFFSET + 0.5 * w3
    }

    /// The reference line `y(x)`: 0 in sections 1 and 5 (and before/after), the lane-3
    /// center in section 3, and in sections 2 and 4 the transition
    /// `y = Y (q - sin(2 pi q)/(2 pi))` (`q` the fraction of the section), whose slope and
    /// curvature vanish at both ends.
    pub fn center_y(&self, x: f64) -> f64 {
        let xb = self.boundaries();
        let y3 = self.side_lane_center();
        let ramp = |q: f64| q - (2.0 * PI * q).sin() / (2.0 * PI);
        if x <= xb[1] || x >= xb[4] {
            0.0
        } else if x < xb[2] {
            y3 * ramp((x - xb[1]) / (xb[2] - xb[1]))
        } else if x <= xb[3] {
            y3
        } else {
            y3 * (1.0 - ramp((x - xb[3]) / (xb[4] - xb[3])))
        }
    }

    /// The course of a lane-change test for a vehicle starting at `x = 0`: the reference
    /// line sampled every `spacing` m from the start, section 1 beginning `lead_in` m
    /// ahead (a straight run-up to the test speed) and `lead_out` m of straight after
    /// section 5. The course ends at [`course_end`](Self::course_end).
    pub fn course(&self, lead_in: f64, lead_out: f64, spacing: f64) -> Result<Path> {
        if !(lead_in.is_finite() && lead_in >= 0.0) {
            return Err(VehicleError::invalid(
                "iso_double_lane_change.lead_in",
                lead_in,
                "must be finite and >= 0",
            ));
        }
        let path = self.path(0.0, lead_out, spacing)?;
        Path::new(path.points().iter().map(|q| [q.x + lead_in, q.y]).collect())
    }

    /// Where the [`course`](Self::course) with `lead_in` and `lead_out` ends, `x` in m.
    pub fn course_end(&self, lead_in: f64, lead_out: f64) -> f64 {
        lead_in + self.boundaries()[5] + lead_out
    }

    /// The reference line as a [`Path`] from `x = -lead_in` to `110 + lead_out`, sampled
    /// every `spacing` m (and at the section boundaries).
    pub fn path(&self, lead_in: f64, lead_out: f64, spacing: f64) -> Result<Path> {
        check_positive("iso_double_lane_change.spacing", spacing)?;
        if !(lead_in.is_finite() && lead_in >= 0.0) {
            return Err(VehicleError::invalid(
                "iso_double_lane_change.lead_in",
                lead_in,
                "must be finite and >= 0",
            ));
        }
        if !(lead_out.is_finite() && lead_out >= 0.0) {
            return Err(VehicleError::invalid(
                "iso_double_lane_change.lead_out",
                lead_out,
                "must be finite and >= 0",
            ));
        }
        let xb = self.boundaries();
        let mut pts = vec![[-lead_in, 0.0]];
        let mut x = -lead_in;
        let end = xb[5] + lead_out;
        let mut k = 0;
        while x < end {
            let mut next = x + spacing;
            while k < 6 && xb[k] <= x {
                k += 1;
            }
            if k < 6 && xb[k] < next {
                next = xb[k];
            }
            x = next.min(end);
            if x - pts.last().map_or(f64::NEG_INFINITY, |p| p[0]) > 1e-9 {
                pts.push([x, self.center_y(x)]);
            }
        }
        Path::new(pts)
    }
}
