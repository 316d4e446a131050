//! Measurements on a granular bed: surface height and roughness, bulk density in a region,
//! the surface profile of a heap and its flank angles, the forces the grains exert on
//! chosen bodies, the elastic strain of a loaded sample, and the deepest penetration.

use nalgebra::Vector3;

use super::fill::Region;
use crate::body::BodyHandle;
use crate::error::{ChronoError, Result};
use crate::system::{ContactMethod, System, contact_forces};

/// Least-squares line `y = a x + b` through the points `(x, y)`: `(a, b)`; `None` below two
/// points or without spread in `x`.
pub fn line_fit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in pts {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
    }
    (sxx > 0.0).then(|| {
        let a = sxy / sxx;
        (a, my - a * mx)
    })
}

/// The surface of a bed in a square box `|x|, |y| < half_width` (m): the mean and the
/// standard deviation, over square columns of side `cell` (m) at least `margin` (m) from
/// the walls, of the top (`z + r`) of the highest grain in the column. `grains` are
/// `(centre, radius)`; empty columns are left out.
pub fn surface_height(
    grains: &[(Vector3<f64>, f64)],
    half_width: f64,
    cell: f64,
    margin: f64,
) -> (f64, f64) {
    let inner = half_width - margin;
    let n = ((2.0 * inner / cell).floor() as usize).max(1);
    let mut top = vec![f64::NEG_INFINITY; n * n];
    for (x, r) in grains {
        if x.x.abs() >= inner || x.y.abs() >= inner {
            continue;
        }
        let i = (((x.x + inner) / cell) as usize).min(n - 1);
        let j = (((x.y + inner) / cell) as usize).min(n - 1);
        top[i * n + j] = top[i * n + j].max(x.z + r);
    }
    let filled: Vec<f64> = top.into_iter().filter(|t| t.is_finite()).collect();
    let k = filled.len().max(1) as f64;
    let mean = filled.iter().sum::<f64>() / k;
    let var = filled.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / k;
    (mean, var.sqrt())
}

/// Bulk density (kg/m^3): the mass of the grains whose centres lie in `region` over its
/// volume. `grains` are `(centre, mass)`. A centre counts as inside when it is strictly
/// inside horizontally and in `[bottom, top)` vertically. NaN for a region of no volume.
pub fn bulk_density(grains: impl IntoIterator<Item = (Vector3<f64>, f64)>, region: &Region) -> f64 {
    let inside = |x: &Vector3<f64>| match *region {
        Region::Box { lower, upper } => {
            x.x > lower.x
                && x.x < upper.x
                && x.y > lower.y
                && x.y < upper.y
                && x.z >= lower.z
                && x.z < upper.z
        }
        Region::Cylinder {
            base,
            radius,
            height,
        } => x.z >= base.z && x.z < base.z + height && (x.xy() - base.xy()).norm() < radius,
    };
    let volume = match *region {
        Region::Box { lower, upper } => {
            (upper.x - lower.x) * (upper.y - lower.y) * (upper.z - lower.z)
        }
        Region::Cylinder { radius, height, .. } => std::f64::consts::PI * radius * radius * height,
    };
    if !(volume.is_finite() && volume > 0.0) {
        return f64::NAN;
    }
    let mass: f64 = grains
        .into_iter()
        .filter(|(x, _)| inside(x))
        .map(|(_, m)| m)
        .sum();
    mass / volume
}

/// The surface profile of a heap seen from the side: the highest `z` among `points`
/// `(x, z)` in each of `bins` columns of width `width` starting at `x0`, as (column centre,
/// highest z); NaN where a column is empty.
pub fn heap_profile(points: &[(f64, f64)], x0: f64, width: f64, bins: usize) -> Vec<(f64, f64)> {
    let mut top = vec![f64::NAN; bins];
    for &(x, z) in points {
        let b = ((x - x0) / width).floor();
        if b >= 0.0 && (b as usize) < bins {
            let t = &mut top[b as usize];
            if t.is_nan() || z > *t {
                *t = z;
            }
        }
    }
    top.into_iter()
        .enumerate()
        .map(|(i, z)| (x0 + (i as f64 + 0.5) * width, z))
        .collect()
}

/// Angles (degrees) of a symmetric heap's `profile` ([`heap_profile`]) centred on `x = 0`
/// with half-width `half` (m): both flanks together (least-squares slope of `z` against
/// `|x|`, sign flipped, `atan`) and each flank `[left (x < 0), right]`, over `|x|` in
/// `[0.15, 0.85] half` (neither the crest nor the toe). `None` with fewer than 3 columns on
/// a flank.
pub fn flank_angles(profile: &[(f64, f64)], half: f64) -> Option<(f64, [f64; 2])> {
    let band = |x: f64| (0.15 * half..=0.85 * half).contains(&x.abs());
    let pick = |side: f64| -> Vec<(f64, f64)> {
        profile
            .iter()
            .filter(|(x, z)| z.is_finite() && band(*x) && x * side > 0.0)
            .map(|&(x, z)| (x.abs(), z))
            .collect()
    };
    let slope = |pts: &[(f64, f64)]| {
        if pts.len() < 3 {
            None
        } else {
            line_fit(pts).map(|(a, _)| a)
        }
    };
    let (left, right) = (pick(-1.0), pick(1.0));
    let both: Vec<_> = left.iter().chain(&right).copied().collect();
    let deg = |s: f64| (-s).atan().to_degrees();
    Some((
        deg(slope(&both)?),
        [deg(slope(&left)?), deg(slope(&right)?)],
    ))
}

/// Sum of the contact forces (N, world) that bodies outside `structure` (the grains) exert
/// on the bodies in `targets`, in the last step of `sys`. NSC: the contact impulses of the
/// last CCP divided by the step `h` (s); SMC: the penalty forces.
pub fn grain_forces_on(
    sys: &System,
    h: f64,
    targets: &[BodyHandle],
    structure: &[BodyHandle],
) -> Vector3<f64> {
    // Contact owners are dense body indices: translate the handles once.
    let (targets, structure) = (dense_indices(sys, targets), dense_indices(sys, structure));
    let has = |set: &[u32], o: u32| set.contains(&o);
    let is_grain = |o: u32| !has(&structure, o);
    let mut f = Vector3::zeros();
    // Force on B (A gets the opposite): adds the share of `targets` from grains.
    let mut add = |a: u32, b: u32, on_b: Vector3<f64>| {
        if has(&targets, b) && is_grain(a) {
            f += on_b;
        }
        if has(&targets, a) && is_grain(b) {
            f -= on_b;
        }
    };
    for c in contact_forces(sys, h) {
        add(c.owner_a as u32, c.owner_b as u32, c.on_b);
    }
    f
}

/// Vertical strain `eps` (compression positive) of the affine uniaxial compression that
/// best explains the overlaps of the last step's grain–grain contacts (bodies outside
/// `structure`): an affine field `u_z = -eps z` closes a contact of unstrained branch
/// length `l` (the touching distance `|x_b - x_a| + delta`) and unit normal `n` by
/// `delta = eps l n_z^2` (to first order in `eps`), so the least-squares fit over the
/// contacts is
///
/// `eps = sum(delta l n_z^2) / sum(l^2 n_z^4)`.
///
/// This is the elastic part of a sample's height under load (penalty contacts: the
/// overlaps; NSC: the solver's residual penetration), so `phi (1 - eps)` is the solid
/// fraction the same packing would have with rigid grains. Laterally confined (a box), the
/// compression is close to uniaxial. 0 without grain–grain contacts.
pub fn uniaxial_overlap_strain(sys: &System, structure: &[BodyHandle]) -> Result<f64> {
    let (mut num, mut den) = (0.0, 0.0);
    let structure = dense_indices(sys, structure);
    let bodies = sys.bodies();
    let mut add = |a: u32, b: u32, n: Vector3<f64>, delta: f64| -> Result<()> {
        let in_structure = |o: u32| structure.contains(&o);
        if delta <= 0.0 || in_structure(a) || in_structure(b) || a == b {
            return Ok(());
        }
        let position = |o: u32| {
            bodies.get(o as usize).map(|b| b.position()).ok_or_else(|| {
                ChronoError::invalid("contact owner", o, "is not a body of the system")
            })
        };
        let (xa, xb) = (position(a)?, position(b)?);
        let l = (xb - xa).norm() + delta;
        let nz2 = n.z * n.z;
        num += delta * l * nz2;
        den += l * l * nz2 * nz2;
        Ok(())
    };
    match sys.settings().contact_method {
        ContactMethod::Nsc => {
            for c in sys.contacts() {
                let p = &c.point;
                add(p.owner_a, p.owner_b, c.normal(), -p.distance)?;
            }
        }
        ContactMethod::Smc => {
            for c in sys.smc_contacts() {
                add(c.owner_a, c.owner_b, c.normal, c.overlap)?;
            }
        }
    }
    Ok(if den > 0.0 { num / den } else { 0.0 })
}

/// Deepest penetration (m) among the contacts of the last step (NSC) or deepest overlap
/// (SMC); 0 without contacts.
pub fn max_penetration(sys: &System) -> f64 {
    let nsc = sys
        .contacts()
        .iter()
        .map(|c| -c.point.distance)
        .fold(0.0, f64::max);
    let smc = sys
        .smc_contacts()
        .iter()
        .map(|c| c.overlap)
        .fold(0.0, f64::max);
    nsc.max(smc)
}

/// The dense indices (the contact owners' numbering) of the live bodies among `handles`;
/// stale handles are skipped (they own no contact).
fn dense_indices(sys: &System, handles: &[BodyHandle]) -> Vec<u32> {
    handles
        .iter()
        .filter_map(|h| sys.body_set().dense_index(*h).map(|i| i as u32))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn surface_of_a_flat_layer() {
        let d = 0.01;
        let mut grains = Vec::new();
        for i in -5..5 {
            for j in -5..5 {
                let c = Vector3::new((i as f64 + 0.5) * d, (j as f64 + 0.5) * d, 0.03);
                grains.push((c, 0.5 * d));
                grains.push((c - Vector3::new(0.0, 0.0, d), 0.5 * d));
            }
        }
        let (zs, rough) = surface_height(&grains, 0.05, d, 2.0 * d);
        assert!((zs - 0.035).abs() < 1e-12 && rough < 1e-12, "{zs} {rough}");
    }

    #[test]
    fn flank_fit_recovers_the_angle_of_a_cone_profile() {
        let half = 0.1;
        let slope = 30f64.to_radians().tan();
        let pts: Vec<(f64, f64)> = (0..400)
            .map(|i| -half + i as f64 * 0.0005)
            .map(|x| {
                (
                    x,
                    (half - x.abs()) * slope - if x > 0.0 { 0.002 } else { 0.0 },
                )
            })
            .collect();
        let prof = heap_profile(&pts, -half, 0.01, 20);
        let (a, [l, r]) = flank_angles(&prof, half).unwrap();
        assert!((l - 30.0).abs() < 0.5 && (r - 30.0).abs() < 0.5, "{l} {r}");
        assert!((a - 30.0).abs() < 1.0, "{a}");
    }

    #[test]
    fn bulk_density_of_a_box_and_a_cylinder() {
        let grains = [
            (Vector3::new(0.0, 0.0, 0.5), 2.0),
            (Vector3::new(0.0, 0.0, 1.0), 5.0), // on the top: outside
            (Vector3::new(3.0, 0.0, 0.5), 7.0), // beside
        ];
        let b = Region::Box {
            lower: Vector3::new(-1.0, -1.0, 0.0),
            upper: Vector3::new(1.0, 1.0, 1.0),
        };
        assert!((bulk_density(grains, &b) - 0.5).abs() < 1e-15);
        let c = Region::Cylinder {
            base: Vector3::zeros(),
            radius: 1.0,
            height: 1.0,
        };
        assert!((bulk_density(grains, &c) - 2.0 / std::f64::consts::PI).abs() < 1e-15);
        let flat = Region::Box {
            lower: Vector3::zeros(),
            upper: Vector3::new(1.0, 1.0, 0.0),
        };
        assert!(bulk_density(grains, &flat).is_nan());
    }

    #[test]
    fn line_fit_of_a_line() {
        let pts: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, 2.0 * i as f64 + 1.0)).collect();
        let (a, b) = line_fit(&pts).unwrap();
        assert!((a - 2.0).abs() < 1e-12 && (b - 1.0).abs() < 1e-12);
        assert!(line_fit(&pts[..1]).is_none());
    }
}
