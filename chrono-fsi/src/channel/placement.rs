//! Where the channel's solids go ([`super`]): the beams on a grid over the floor, the
//! ellipsoids at seeded random centres and orientations without overlap.

use std::f64::consts::PI;

use chrono_core::math::{UnitQuaternion, Vector3};

use super::ChannelParams;
use crate::error::{FsiError, Result};

/// A small deterministic generator (SplitMix64, Steele, Lea & Flood 2014) for the
/// placement: no dependency, the same bodies on every machine.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniformly random rotation: the body's z axis uniform on the sphere
    /// (`cos theta` uniform in `[-1, 1]`), then a uniform spin about it (together the
    /// uniform (Haar) measure on rotations).
    fn rotation(&mut self) -> UnitQuaternion<f64> {
        let (cz, phi, spin) = (
            2.0 * self.next() - 1.0,
            2.0 * PI * self.next(),
            2.0 * PI * self.next(),
        );
        let s = (1.0 - cz * cz).max(0.0).sqrt();
        let axis = Vector3::new(s * phi.cos(), s * phi.sin(), cz);
        let tilt = UnitQuaternion::rotation_between(&Vector3::z(), &axis)
            .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI));
        tilt * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), spin)
    }
}

/// The beams' roots: a grid of `nx x ny` cells over the floor (as square as the floor
/// allows), one root at each of the first `n` cell centres, row by row.
pub fn beam_roots(p: &ChannelParams) -> Vec<Vector3<f64>> {
    let n = p.beams;
    if n == 0 {
        return Vec::new();
    }
    let nx = ((n as f64 * p.length / p.width).sqrt().round() as usize).clamp(1, n);
    let ny = n.div_ceil(nx);
    (0..n)
        .map(|k| {
            let (i, j) = (k % nx, k / nx);
            Vector3::new(
                (i as f64 + 0.5) * p.length / nx as f64,
                (j as f64 + 0.5) * p.width / ny as f64,
                0.0,
            )
        })
        .collect()
}

/// The clearance (m) the placement keeps between the ellipsoids' bounding spheres, and
/// from the walls and the beams: half the smallest semi-axis, which is at least one
/// spacing whenever the ellipsoid is resolved (4 spacings across), and does not depend
/// on the spacing, so a resolution sweep keeps the same bodies.
pub fn placement_gap(p: &ChannelParams) -> f64 {
    0.5 * p.semi_axes.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The ellipsoids' centres and orientations (see the [channel module docs](crate::channel)); an error
/// naming `ellipsoids` when they do not fit.
pub fn place_ellipsoids(
    p: &ChannelParams,
    roots: &[Vector3<f64>],
) -> Result<Vec<(Vector3<f64>, UnitQuaternion<f64>)>> {
    let r = p.semi_axes.iter().copied().fold(0.0, f64::max);
    let gap = placement_gap(p);
    let (lo, hi) = (
        Vector3::new(r, r + gap, r + gap),
        Vector3::new(p.length - r, p.width - r - gap, p.height - r - gap),
    );
    if p.ellipsoids > 0 && (0..3).any(|a| hi[a] < lo[a]) {
        return Err(FsiError::invalid(
            "semi_axes",
            format!("{:?}", p.semi_axes),
            "the ellipsoids do not fit in the channel with a spacing of fluid around them",
        ));
    }
    let rb = 0.5 * p.beam_diameter;
    let mut rng = SplitMix(p.seed);
    let mut out: Vec<(Vector3<f64>, UnitQuaternion<f64>)> = Vec::new();
    let attempts = 2000 * p.ellipsoids.max(1);
    for _ in 0..attempts {
        if out.len() == p.ellipsoids {
            break;
        }
        let c = Vector3::new(
            lo.x + rng.next() * (hi.x - lo.x),
            lo.y + rng.next() * (hi.y - lo.y),
            lo.z + rng.next() * (hi.z - lo.z),
        );
        let q = rng.rotation();
        let clear_bodies = out.iter().all(|(o, _)| {
            let mut dx = c.x - o.x;
            dx -= p.length * (dx / p.length).round();
            let d2 = dx * dx + (c.y - o.y).powi(2) + (c.z - o.z).powi(2);
            d2 >= (2.0 * r + gap).powi(2)
        });
        let clear_beams = roots.iter().all(|b| {
            let mut dx = c.x - b.x;
            dx -= p.length * (dx / p.length).round();
            c.z - r >= p.beam_length + gap || (dx * dx + (c.y - b.y).powi(2)).sqrt() >= r + rb + gap
        });
        if clear_bodies && clear_beams {
            out.push((c, q));
        }
    }
    if out.len() < p.ellipsoids {
        return Err(FsiError::invalid(
            "ellipsoids",
            p.ellipsoids,
            format!(
                "only {} fit without overlap after {attempts} random tries (bounding spheres {gap} m apart, clear of the beams)",
                out.len()
            ),
        ));
    }
    Ok(out)
}
