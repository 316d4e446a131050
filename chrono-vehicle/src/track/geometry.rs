//! The chain's loop in the track's side plane `(x, z)` and the pins placed on it.
//!
//! The chain wraps a sequence of circles clockwise seen from the left (+Y): the sprocket
//! (its pitch circle: the pin centres), the road wheels front to rear and the idler (their
//! radius plus half the shoe thickness, the pins being at mid-thickness). Between two
//! circles it runs along their outer common tangent, so the loop is straight segments and
//! arcs and its length is exact. The pins go one pitch apart in chord length (the shoes are
//! rigid), starting where the chain arrives on the sprocket: on the sprocket's pitch circle
//! consecutive pins are then exactly one tooth apart when the sprocket's pitch radius matches
//! the pitch ([`super::TrackData::validate`]). The idler slides along its tensioner's X
//! travel until the last chord ends on the first pin ([`layout`]): the loop closes to the
//! bisection's precision (reported as [`ChainLayout::closure_error`]).

use std::f64::consts::TAU;

use crate::error::{Result, VehicleError};

use super::TrackData;

/// A circle of the loop: centre `[x, z]` (m) and radius (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    /// Centre `[x, z]`, m.
    pub center: [f64; 2],
    /// Radius, m.
    pub radius: f64,
}

#[derive(Debug, Clone, Copy)]
enum Segment {
    /// Clockwise arc from angle `a0` through `sweep` (rad, >= 0).
    Arc {
        c: [f64; 2],
        r: f64,
        a0: f64,
        sweep: f64,
    },
    Line {
        p0: [f64; 2],
        p1: [f64; 2],
    },
}

impl Segment {
    fn length(&self) -> f64 {
        match *self {
            Segment::Arc { r, sweep, .. } => r * sweep,
            Segment::Line { p0, p1 } => (p1[0] - p0[0]).hypot(p1[1] - p0[1]),
        }
    }
    fn at(&self, s: f64) -> [f64; 2] {
        match *self {
            Segment::Arc { c, r, a0, .. } => {
                let a = a0 - s / r;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            }
            Segment::Line { p0, p1 } => {
                let l = self.length();
                let t = if l > 0.0 { s / l } else { 0.0 };
                [p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1])]
            }
        }
    }
}

/// The closed loop around the circles: arcs and tangent segments, parametrized by arc
/// length from the arrival point on the first circle.
#[derive(Debug, Clone)]
pub struct LoopPath {
    segments: Vec<(f64, Segment)>,
    length: f64,
}

impl LoopPath {
    /// The loop around `circles` (at least 2), wrapped clockwise in the `(x, z)` plane in the
    /// given order. `names[i]` is the field of circle `i` for errors: a circle that lies
    /// inside the loop of the others (the chain cannot wrap it convexly) is an error naming it.
    pub fn new(circles: &[Circle], names: &[String]) -> Result<Self> {
        let n = circles.len();
        assert!(n >= 2 && names.len() == n);
        // Outward unit normal of the tangent from circle i to circle i+1.
        let normal = |i: usize| -> Result<[f64; 2]> {
            let (a, b) = (circles[i], circles[(i + 1) % n]);
            let d = [b.center[0] - a.center[0], b.center[1] - a.center[1]];
            let l = d[0].hypot(d[1]);
            let s = (a.radius - b.radius) / l;
            if !(l > 0.0 && s.abs() < 1.0) {
                return Err(VehicleError::invalid(
                    names[(i + 1) % n].clone(),
                    format!("{:?}", b.center),
                    format!(
                        "overlaps {} so the chain has no tangent between them",
                        names[i]
                    ),
                ));
            }
            let e = [d[0] / l, d[1] / l];
            let left = [-e[1], e[0]];
            let c = (1.0 - s * s).sqrt();
            Ok([s * e[0] + c * left[0], s * e[1] + c * left[1]])
        };
        let normals = (0..n).map(normal).collect::<Result<Vec<_>>>()?;
        let mut segments = Vec::with_capacity(2 * n);
        let mut s = 0.0;
        let mut total_sweep = 0.0;
        let mut largest = (0usize, 0.0f64);
        for i in 0..n {
            let c = circles[i];
            let n_in = normals[(i + n - 1) % n];
            let n_out = normals[i];
            let a_in = n_in[1].atan2(n_in[0]);
            let a_out = n_out[1].atan2(n_out[0]);
            let mut sweep = (a_in - a_out).rem_euclid(TAU);
            if sweep > TAU - 1e-9 {
                sweep = 0.0;
            }
            total_sweep += sweep;
            if sweep > largest.1 {
                largest = (i, sweep);
            }
            let arc = Segment::Arc {
                c: c.center,
                r: c.radius,
                a0: a_in,
                sweep,
            };
            segments.push((s, arc));
            s += arc.length();
            let p0 = [
                c.center[0] + c.radius * n_out[0],
                c.center[1] + c.radius * n_out[1],
            ];
            let b = circles[(i + 1) % n];
            let p1 = [
                b.center[0] + b.radius * n_out[0],
                b.center[1] + b.radius * n_out[1],
            ];
            let line = Segment::Line { p0, p1 };
            segments.push((s, line));
            s += line.length();
        }
        if (total_sweep - TAU).abs() > 1e-6 {
            return Err(VehicleError::invalid(
                names[largest.0].clone(),
                format!("{:?}", circles[largest.0].center),
                "the chain cannot wrap the wheels in this order as one convex loop",
            ));
        }
        Ok(Self {
            segments,
            length: s,
        })
    }

    /// The loop's length, m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The point at arc length `s` (m; taken modulo the length), `[x, z]`.
    pub fn point(&self, s: f64) -> [f64; 2] {
        let s = s.rem_euclid(self.length);
        let k = self.segments.partition_point(|(s0, _)| *s0 <= s).max(1) - 1;
        let (s0, seg) = self.segments[k];
        seg.at((s - s0).min(seg.length()))
    }

    /// The arc length `s' > s` at which the chord from `point(s)` is `chord` long (m), found
    /// by bisection (the loop is convex, so the chord grows with `s'` over a pitch).
    pub fn chord_step(&self, s: f64, chord: f64) -> f64 {
        let p = self.point(s);
        let dist = |t: f64| {
            let q = self.point(t);
            (q[0] - p[0]).hypot(q[1] - p[1])
        };
        let mut hi = s + 2.0 * chord;
        while dist(hi) < chord && hi < s + 0.5 * self.length {
            hi += chord;
        }
        let mut lo = s;
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if dist(mid) < chord {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo < 1e-14 {
                break;
            }
        }
        0.5 * (lo + hi)
    }
}

/// The assembled chain of one side.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainLayout {
    /// Pin centres `[x, z]` in the track frame, m, in chain order (pin `k` joins shoe
    /// `k - 1` and shoe `k`; shoe `k` runs from pin `k` to pin `k + 1`).
    pub pins: Vec<[f64; 2]>,
    /// Idler offset along X from its nominal location that closes the loop, m.
    pub idler_offset: f64,
    /// Distance between the end of the last chord and the first pin, m.
    pub closure_error: f64,
    /// Length of the loop the pins lie on, m.
    pub loop_length: f64,
    /// Angle (rad, from +X towards +Z) of the first pin about the sprocket centre.
    pub sprocket_start_angle: f64,
}

/// The circles of the loop with the idler moved by `offset` along X: the sprocket's pitch
/// circle (the pins seat in its gaps) and, for the road wheels and the idler, the circle of
/// radius `sqrt((r + t/2)^2 + (p/2)^2)` (wheel radius `r`, shoe thickness `t`, pitch `p`).
/// Where the chain bends round a wheel a plate is a chord between two pins: on that circle
/// its inner face is tangent to the wheel at its middle. With the pins on `r + t/2` (pins at
/// mid-thickness; so until 2026-12-05) the plates cut up to
/// `(r + t/2)(1 - cos(asin(p / (2 (r + t/2)))))` into the wheel, 1.0 cm round the M113's
/// idler and 0.9 cm at its first road wheel: a rigid (NSC) contact pushed that out in the
/// first steps; a penalty (SMC) contact would start with it loaded. The straight runs now
/// start that much (0.9 cm for the M113) off the road wheels, which settle onto them.
pub fn loop_circles(track: &TrackData, offset: f64) -> (Vec<Circle>, Vec<String>) {
    let half_t = 0.5 * track.shoe.thickness;
    let mut c = vec![Circle {
        center: track.sprocket.location,
        radius: track.sprocket.pitch_radius,
    }];
    let mut names = vec!["track.sprocket.location".to_string()];
    let r = &track.road_wheels;
    for (k, &x) in r.x.iter().enumerate() {
        c.push(Circle {
            center: [x, r.z],
            radius: (r.radius + half_t).hypot(0.5 * track.shoe.pitch),
        });
        names.push(format!("track.road_wheels.x[{k}]"));
    }
    let i = &track.idler;
    c.push(Circle {
        center: [i.location[0] + offset, i.location[1]],
        radius: (i.radius + half_t).hypot(0.5 * track.shoe.pitch),
    });
    names.push("track.idler.location".to_string());
    (c, names)
}

/// The loop round the wheels of `track` with the idler moved `offset` m along X.
fn path_at(track: &TrackData, offset: f64) -> Result<LoopPath> {
    let (c, names) = loop_circles(track, offset);
    LoopPath::new(&c, &names)
}

/// Arc length reached by `shoes` chords of `pitch` from s = 0 on `path`, minus its length:
/// negative when the chain is too short for the loop, positive when too long.
fn chain_excess(path: &LoopPath, shoes: usize, pitch: f64) -> f64 {
    let mut s = 0.0;
    for _ in 0..shoes {
        s = path.chord_step(s, pitch);
    }
    s - path.length()
}

/// Check that `shoes` shoes can close round the wheels of `track` (validated) somewhere in
/// the tensioner's travel, without placing them: the check [`layout`] starts with, cheap
/// enough for reading data. Errors name `track.shoe.count[side]` with the loop length and
/// the shortfall or surplus.
pub fn check_shoe_count(track: &TrackData, shoes: usize, side: usize) -> Result<()> {
    let pitch = track.shoe.pitch;
    // The loop shortens as the idler moves forward (+X): `rear` is the longest loop,
    // `fwd` the shortest.
    let [rear, fwd] = track.idler.tensioner.travel;
    let (p_rear, p_fwd) = (path_at(track, rear)?, path_at(track, fwd)?);
    let (g_rear, g_fwd) = (
        chain_excess(&p_rear, shoes, pitch),
        chain_excess(&p_fwd, shoes, pitch),
    );
    let field = format!("track.shoe.count[{side}]");
    if g_fwd < 0.0 {
        return Err(VehicleError::invalid(
            field,
            shoes,
            format!(
                "{shoes} shoes of pitch {pitch} m are too few: the shortest loop around the \
                 wheels (idler at its forward travel limit) is {:.4} m, {:.4} m more than the \
                 chain reaches",
                p_fwd.length(),
                -g_fwd
            ),
        ));
    }
    if g_rear > 0.0 {
        return Err(VehicleError::invalid(
            field,
            shoes,
            format!(
                "{shoes} shoes of pitch {pitch} m are too many: the longest loop (idler at its \
                 rearward travel limit) is {:.4} m, {:.4} m less than the chain",
                p_rear.length(),
                g_rear
            ),
        ));
    }
    Ok(())
}

/// Place `shoes` shoes around the wheels of `track` (validated), moving the idler within its
/// tensioner travel until the chain closes. Errors name `track.shoe.count[side]` when the
/// chain is too short or too long for the travel ([`check_shoe_count`]).
pub fn layout(track: &TrackData, shoes: usize, side: usize) -> Result<ChainLayout> {
    check_shoe_count(track, shoes, side)?;
    let pitch = track.shoe.pitch;
    let [rear, fwd] = track.idler.tensioner.travel;
    // The excess rises with the offset: bisect for its root.
    let (mut a, mut b) = (rear, fwd);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if chain_excess(&path_at(track, m)?, shoes, pitch) > 0.0 {
            b = m;
        } else {
            a = m;
        }
        if b - a < 1e-15 {
            break;
        }
    }
    let offset = 0.5 * (a + b);
    // The idler must clear the last road wheel where the chain puts it.
    let i = &track.idler;
    let r = &track.road_wheels;
    let last = [r.x[r.x.len() - 1], r.z];
    let gap =
        (i.location[0] + offset - last[0]).hypot(i.location[1] - last[1]) - i.radius - r.radius;
    if gap < 0.0 {
        return Err(VehicleError::invalid(
            "track.idler.location",
            format!("{:?}", i.location),
            format!(
                "with {shoes} shoes the idler sits {offset:.4} m along X from here and overlaps \
                 the last road wheel by {:.4} m",
                -gap
            ),
        ));
    }
    let path = path_at(track, offset)?;
    let mut pins = Vec::with_capacity(shoes);
    let mut s = 0.0;
    for _ in 0..shoes {
        pins.push(path.point(s));
        s = path.chord_step(s, pitch);
    }
    let end = path.point(s);
    let closure_error = (end[0] - pins[0][0]).hypot(end[1] - pins[0][1]);
    let c = track.sprocket.location;
    let sprocket_start_angle = (pins[0][1] - c[1]).atan2(pins[0][0] - c[0]);
    Ok(ChainLayout {
        pins,
        idler_offset: offset,
        closure_error,
        loop_length: path.length(),
        sprocket_start_angle,
    })
}

/// The angle (rad) a pitch chord subtends on a circle of radius `r`: `2 asin(p / 2r)`.
pub fn chord_angle(pitch: f64, r: f64) -> f64 {
    2.0 * (0.5 * pitch / r).clamp(-1.0, 1.0).asin()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::m113::m113_data;
    use std::f64::consts::PI;

    #[test]
    fn two_circle_loop_has_the_belt_length() {
        let c = [
            Circle {
                center: [0.0, 0.0],
                radius: 0.3,
            },
            Circle {
                center: [-2.0, 0.0],
                radius: 0.3,
            },
        ];
        let names = vec!["a".to_string(), "b".to_string()];
        let p = LoopPath::new(&c, &names).unwrap();
        assert!((p.length() - (4.0 + TAU * 0.3)).abs() < 1e-12);
        // Start on top of the first circle's arrival point, going clockwise (down the front).
        let q = p.point(0.0);
        assert!(
            (q[0] - 0.0).abs() < 1e-12 && (q[1] - 0.3).abs() < 1e-12,
            "{q:?}"
        );
        let q = p.point(0.3 * PI);
        assert!((q[1] + 0.3).abs() < 1e-12, "{q:?}");
        // Unequal radii: length = 2 sqrt(d^2 - (r1 - r2)^2) + r1 (pi + 2 b) + r2 (pi - 2 b).
        let c2 = [
            c[0],
            Circle {
                center: [-2.0, 0.0],
                radius: 0.2,
            },
        ];
        let p = LoopPath::new(&c2, &names).unwrap();
        let b = (0.1f64 / 2.0).asin();
        let want = 2.0 * (4.0f64 - 0.01).sqrt() + 0.3 * (PI + 2.0 * b) + 0.2 * (PI - 2.0 * b);
        assert!((p.length() - want).abs() < 1e-12, "{} {want}", p.length());
    }

    #[test]
    fn a_wheel_inside_the_loop_is_an_error_naming_it() {
        let mk = |x: f64, z: f64| Circle {
            center: [x, z],
            radius: 0.3,
        };
        let names: Vec<String> = ["s", "w0", "w1", "i"]
            .iter()
            .map(|x| x.to_string())
            .collect();
        // w1 lifted far above the line of the others: the chain would have to wrap it
        // concavely.
        let c = [mk(0.0, 0.0), mk(-1.0, -1.0), mk(-2.0, 0.5), mk(-3.0, -1.0)];
        let e = LoopPath::new(&c, &names).unwrap_err().to_string();
        assert!(
            e.contains("w1") || e.contains("`i`") || e.contains("w0"),
            "{e}"
        );
    }

    #[test]
    fn m113_chain_closes_and_seats_on_the_sprocket() {
        let d = m113_data().unwrap();
        let t = &d.track;
        for side in 0..2 {
            let n = t.shoe.count[side];
            let l = layout(t, n, side).unwrap();
            assert_eq!(l.pins.len(), n);
            assert!(l.closure_error < 1e-9, "closure {}", l.closure_error);
            let [rear, fwd] = t.idler.tensioner.travel;
            assert!(l.idler_offset > rear && l.idler_offset < fwd);
            // Every chord is one pitch, including the closing one.
            for k in 0..n {
                let (a, b) = (l.pins[k], l.pins[(k + 1) % n]);
                let d = (b[0] - a[0]).hypot(b[1] - a[1]);
                assert!((d - t.shoe.pitch).abs() < 1e-9, "chord {k}: {d}");
            }
            // Pins on the sprocket's pitch circle are one tooth apart.
            let c = t.sprocket.location;
            let tooth = TAU / t.sprocket.num_teeth as f64;
            let r = |p: [f64; 2]| (p[0] - c[0]).hypot(p[1] - c[1]);
            let mut seated = 0;
            for k in 0..n - 1 {
                let (a, b) = (l.pins[k], l.pins[k + 1]);
                if (r(a) - t.sprocket.pitch_radius).abs() < 1e-9
                    && (r(b) - t.sprocket.pitch_radius).abs() < 1e-9
                {
                    let da = (a[1] - c[1]).atan2(a[0] - c[0]) - (b[1] - c[1]).atan2(b[0] - c[0]);
                    assert!((da.rem_euclid(TAU) - tooth).abs() < 1e-3, "{da}");
                    seated += 1;
                }
            }
            assert!(seated >= 3, "{seated} pin pairs on the sprocket");
        }
        // The right track has one shoe more: its idler sits further back (lower X).
        let l0 = layout(t, t.shoe.count[0], 0).unwrap();
        let l1 = layout(t, t.shoe.count[1], 1).unwrap();
        assert!(l1.idler_offset < l0.idler_offset);
    }

    /// No plate cuts into a road wheel or the idler: the distance from each wheel's centre
    /// to each plate's chord, less half a plate thickness (the inner face), is at least the
    /// wheel's radius; round the idler some plates touch it (tangent at their middle). With
    /// the pins on `r + t/2` (before 2026-12-05) the plates cut 1.0 cm into the idler.
    #[test]
    fn m113_plates_touch_but_do_not_cut_into_the_wheels() {
        let d = m113_data().unwrap();
        let t = &d.track;
        let half_t = 0.5 * t.shoe.thickness;
        for side in 0..2 {
            let l = layout(t, t.shoe.count[side], side).unwrap();
            let i = &t.idler;
            let mut wheels: Vec<([f64; 2], f64)> = t
                .road_wheels
                .x
                .iter()
                .map(|&x| ([x, t.road_wheels.z], t.road_wheels.radius))
                .collect();
            wheels.push(([i.location[0] + l.idler_offset, i.location[1]], i.radius));
            let n = l.pins.len();
            for (k, &(c, r)) in wheels.iter().enumerate() {
                let mut closest = f64::INFINITY;
                for j in 0..n {
                    let (a, b) = (l.pins[j], l.pins[(j + 1) % n]);
                    let gap = crate::track::assembly::segment_distance(c, a, b) - half_t - r;
                    assert!(
                        gap > -1e-9,
                        "side {side}, wheel {k}, plate {j}: cuts {gap:.2e} m in"
                    );
                    closest = closest.min(gap);
                }
                // Every wheel is near the chain (the road wheels within the 0.9 cm the
                // straight runs start off them).
                assert!(closest < 0.01, "side {side}, wheel {k}: {closest}");
            }
        }
    }

    #[test]
    fn too_few_or_too_many_shoes_are_errors_naming_the_count() {
        let d = m113_data().unwrap();
        let t = &d.track;
        let e = layout(t, 50, 0).unwrap_err().to_string();
        assert!(
            e.contains("track.shoe.count[0]") && e.contains("too few"),
            "{e}"
        );
        let e = layout(t, 80, 1).unwrap_err().to_string();
        assert!(
            e.contains("track.shoe.count[1]") && e.contains("too many"),
            "{e}"
        );
    }
}
