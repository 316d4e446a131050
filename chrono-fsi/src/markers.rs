//! BCE (boundary condition enforcing) markers of rigid shapes: layers of points inside
//! the surface at the fluid's spacing, in the shape's local frame.
//!
//! A marker stands for the volume `dp^3` of a fluid particle (the wall-marker convention of
//! chrono-sph), so the layers are placed about `dp` apart both along and across the
//! surface, with the outer layer `dp / 2` inside it: the first fluid layer, on average
//! `dp / 2` outside (the fluid lattice points inside the body are removed,
//! [`crate::builder::CARVE_DEPTH`]), is then on average `dp` away, as next to a tank wall. `layers` layers of depth
//! `(k + 1/2) dp`, `k = 0 .. layers`, cover the kernel support when
//! `layers dp >= 2 h` (the caller's choice, see [`crate::FsiBuilder`]).
//!
//! - box (half extents `a`): a lattice of `round(2 a_i / dp)` points per axis whose
//!   cell centres are `(i + 1/2) 2 a_i / n_i` from the face (the spacing adapts so the
//!   faces are exactly `dp_i / 2` outside the outer layer), kept where the depth below
//!   the nearest face is below `layers dp`;
//! - sphere (radius `R`): shells of radius `r_k = R - (k + 1/2) dp` (down to the centre),
//!   each with `round(4 pi r_k^2 / dp^2)` points on a Fibonacci lattice (quasi-uniform,
//!   so the surface is smooth at the particle scale, not a staircase);
//! - cylinder (axis local Y, radius `R`, half length `L`): rings of radius
//!   `r_k = R - (k + 1/2) dp` with `round(2 pi r_k / dp)` points, at axial stations
//!   `(j + 1/2) 2 L / n_y` from the cap, kept where the depth below the mantle or the
//!   nearest cap is below `layers dp`.
//! - ellipsoid (semi-axes `e`): shells that are the ellipsoids of semi-axes
//!   `s_k = e - (k + 1/2) dp` (down to the centre; for `a = b = c` the sphere's shells),
//!   each with `round(4 pi / 3 (s_1 s_2 + s_2 s_3 + s_3 s_1) / dp^2)` points: that is
//!   `dV/ds / dp^2` for the ellipsoid `e - s`, so `N dp^3` is the volume of the slab
//!   between the ellipsoids `e - k dp` and `e - (k+1) dp` to `O(dp^3)` (the slab is `dp`
//!   thick at the axis tips and thinner between them, where the markers spread out to
//!   match). On each shell a Fibonacci lattice whose polar coordinate follows the
//!   cumulative surface area about the *polar* axis (the one whose two partners are
//!   closest in length): uniform in area on a spheroid, on a sphere the sphere's lattice.
//!   A marker's depth is its exact distance to the surface
//!   (`chrono_core::shape::ellipsoid_closest_point`), `(k + 1/2) dp` at the tips and a
//!   little less between.
//!
//! An axis may be *open* (`open[i]`: the shape spans a periodic direction of the fluid
//! domain, e.g. a horizontal cylinder across a quasi-2-D slab): the faces or caps normal to
//! it carry no markers. Not generated (an error naming the shape): capsules, convex hulls,
//! triangle meshes, half spaces. Open axes are ignored for spheres and ellipsoids.

use std::f64::consts::PI;

use chrono_core::Shape;
use chrono_core::math::Vector3;
use chrono_core::shape::ellipsoid_closest_point;

use crate::error::{FsiError, Result};

/// Markers of one shape in its local frame, m, with the depth of each below the surface,
/// m.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShapeMarkers {
    /// Positions (shape-local frame), m.
    pub points: Vec<[f64; 3]>,
    /// Depth of each point below the surface, m (`>= dp / 2` up to round-off).
    pub depth: Vec<f64>,
}

impl ShapeMarkers {
    fn push(&mut self, p: [f64; 3], depth: f64) {
        self.points.push(p);
        self.depth.push(depth);
    }
}

/// The smallest dimension of a shape (m), which must exceed the kernel support, and a
/// name for messages; `None` for shapes without marker generation.
pub fn thickness(shape: &Shape, open: [bool; 3]) -> Option<f64> {
    match shape {
        Shape::Sphere { radius } => Some(2.0 * radius),
        Shape::Ellipsoid { semi_axes } => Some(2.0 * semi_axes.min()),
        Shape::Box { half_extents } => (0..3)
            .filter(|&i| !open[i])
            .map(|i| 2.0 * half_extents[i])
            .reduce(f64::min)
            .or(Some(f64::INFINITY)),
        Shape::Cylinder {
            half_length,
            radius,
        } => Some(if open[1] {
            2.0 * radius
        } else {
            (2.0 * radius).min(2.0 * half_length)
        }),
        _ => None,
    }
}

/// A short name of the shape kind for messages.
pub fn shape_kind(shape: &Shape) -> &'static str {
    match shape {
        Shape::Sphere { .. } => "sphere",
        Shape::Box { .. } => "box",
        Shape::Capsule { .. } => "capsule",
        Shape::Cylinder { .. } => "cylinder",
        Shape::Ellipsoid { .. } => "ellipsoid",
        Shape::ConvexHull { .. } => "convex hull",
        Shape::TriMesh { .. } => "triangle mesh",
        _ => "shape",
    }
}

/// Markers of `shape` (local frame) at spacing `dp` (m), `layers` layers deep, with the
/// faces normal to the `open` local axes left out (see the [module docs](self)). `body`
/// names the body in errors.
pub fn shape_markers(
    body: &str,
    shape: &Shape,
    dp: f64,
    layers: usize,
    open: [bool; 3],
) -> Result<ShapeMarkers> {
    let depth_max = layers as f64 * dp;
    let mut out = ShapeMarkers::default();
    match shape {
        Shape::Box { half_extents } => {
            let a = [half_extents.x, half_extents.y, half_extents.z];
            let n = a.map(|ai| ((2.0 * ai / dp).round() as usize).max(1));
            let step = [0, 1, 2].map(|i| 2.0 * a[i] / n[i] as f64);
            for i in 0..n[0] {
                for j in 0..n[1] {
                    for k in 0..n[2] {
                        let idx = [i, j, k];
                        let p = [0, 1, 2].map(|c| -a[c] + (idx[c] as f64 + 0.5) * step[c]);
                        let depth = (0..3)
                            .filter(|&c| !open[c])
                            .map(|c| a[c] - p[c].abs())
                            .fold(f64::INFINITY, f64::min);
                        if depth < depth_max {
                            out.push(p, depth);
                        }
                    }
                }
            }
        }
        Shape::Sphere { radius } => {
            let r0 = *radius;
            // shells down to the centre (a ball thinner than the layers is filled)
            for k in 0..layers {
                let r = r0 - (k as f64 + 0.5) * dp;
                if r <= 0.0 {
                    break;
                }
                let n = ((4.0 * PI * r * r / (dp * dp)).round() as usize).max(1);
                fibonacci_sphere(n, r, |p| out.push(p, r0 - r));
            }
        }
        Shape::Cylinder {
            half_length,
            radius,
        } => {
            let (l, r0) = (*half_length, *radius);
            let ny = ((2.0 * l / dp).round() as usize).max(1);
            let sy = 2.0 * l / ny as f64;
            // rings from the mantle inwards, down to the axis
            let mut rings: Vec<(f64, usize)> = Vec::new();
            for k in 0.. {
                let r = r0 - (k as f64 + 0.5) * dp;
                if r <= 0.0 {
                    break;
                }
                rings.push((r, ((2.0 * PI * r / dp).round() as usize).max(1)));
            }
            for j in 0..ny {
                let y = -l + (j as f64 + 0.5) * sy;
                let cap = if open[1] { f64::INFINITY } else { l - y.abs() };
                for (k, &(r, n)) in rings.iter().enumerate() {
                    let depth = (r0 - r).min(cap);
                    if depth >= depth_max {
                        continue;
                    }
                    for m in 0..n {
                        // stagger successive rings by half a spacing (no radial lines)
                        let th = 2.0 * PI * (m as f64 + 0.5 * (k % 2) as f64) / n as f64;
                        out.push([r * th.cos(), y, r * th.sin()], depth);
                    }
                }
            }
        }
        Shape::Ellipsoid { semi_axes } => ellipsoid_shells(semi_axes, dp, layers, &mut out),
        other => {
            return Err(FsiError::UnsupportedShape {
                body: body.to_string(),
                shape: shape_kind(other).to_string(),
            });
        }
    }
    Ok(out)
}

/// The ellipsoid's shells (see the [module docs](self)).
fn ellipsoid_shells(e: &Vector3<f64>, dp: f64, layers: usize, out: &mut ShapeMarkers) {
    // Polar axis: the one whose two partners are closest in length (the symmetry axis of
    // a spheroid; Z on a tie, as the sphere); `u, v` the other two.
    let gap = |i: usize| (e[(i + 1) % 3] - e[(i + 2) % 3]).abs();
    let polar = [2, 0, 1]
        .into_iter()
        .min_by(|&i, &j| gap(i).total_cmp(&gap(j)))
        .unwrap_or(2);
    let (iu, iv) = ((polar + 1) % 3, (polar + 2) % 3);
    for k in 0..layers {
        let d = (k as f64 + 0.5) * dp;
        let s = e.map(|x| x - d);
        if s.min() <= 0.0 {
            break;
        }
        let rate = 4.0 * PI / 3.0 * (s.x * s.y + s.y * s.z + s.z * s.x);
        let n = ((rate / (dp * dp)).round() as usize).max(1);
        let z_of = area_quantiles(s[iu], s[iv], s[polar], n);
        let golden = PI * (3.0 - 5f64.sqrt());
        for (i, &z) in z_of.iter().enumerate() {
            let (w, th) = ((1.0 - z * z).max(0.0).sqrt(), golden * i as f64);
            let mut p = Vector3::zeros();
            p[iu] = s[iu] * w * th.cos();
            p[iv] = s[iv] * w * th.sin();
            p[polar] = s[polar] * z;
            if n == 1 {
                p = Vector3::zeros();
            }
            let depth = (p - ellipsoid_closest_point(e, &p)).norm();
            out.push([p.x, p.y, p.z], depth);
        }
    }
}

/// For the ellipsoid with semi-axes `su, sv` (equator) and `sp` (polar), the polar
/// coordinates `z_i` (`x_polar = sp z`) that cut its surface into `n` bands of equal area
/// at the mid-band fractions `(i + 1/2) / n` from the `+z` pole: the cumulative area
/// `A(z)`, from `dA = su sv sp |u / s| dz dphi` on the unit-sphere parametrization, by the
/// midpoint rule (`NZ` bands in `z`, `NPHI` in longitude) and inverted piecewise
/// linearly. On a sphere `A` is linear and `z_i = 1 - (2 i + 1) / n`, the sphere's
/// Fibonacci lattice.
fn area_quantiles(su: f64, sv: f64, sp: f64, n: usize) -> Vec<f64> {
    const NZ: usize = 2000;
    const NPHI: usize = 64;
    let density = |z: f64| {
        let w2 = (1.0 - z * z).max(0.0);
        (0..NPHI)
            .map(|j| {
                let ph = 2.0 * PI * (j as f64 + 0.5) / NPHI as f64;
                let (c, s) = (ph.cos(), ph.sin());
                (w2 * c * c / (su * su) + w2 * s * s / (sv * sv) + z * z / (sp * sp)).sqrt()
            })
            .sum::<f64>()
    };
    // cum[m]: area from z = 1 down to z = 1 - 2 m / NZ (arbitrary units).
    let mut cum = vec![0.0; NZ + 1];
    for m in 0..NZ {
        let z = 1.0 - 2.0 * (m as f64 + 0.5) / NZ as f64;
        cum[m + 1] = cum[m] + density(z);
    }
    let total = cum[NZ];
    let mut out = Vec::with_capacity(n);
    let mut m = 0;
    for i in 0..n {
        let target = total * (i as f64 + 0.5) / n as f64;
        while m + 1 < NZ && cum[m + 1] < target {
            m += 1;
        }
        let f = (target - cum[m]) / (cum[m + 1] - cum[m]);
        out.push(1.0 - 2.0 * (m as f64 + f) / NZ as f64);
    }
    out
}

/// `n` quasi-uniform points on the sphere of radius `r` (the Fibonacci lattice: equal
/// areas in `z`, golden-angle steps in longitude; Gonzalez 2010, Math. Geosci. 42:49).
fn fibonacci_sphere(n: usize, r: f64, mut f: impl FnMut([f64; 3])) {
    if n == 1 {
        f([0.0, 0.0, 0.0]);
        return;
    }
    let golden = PI * (3.0 - 5f64.sqrt());
    for i in 0..n {
        let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
        let s = (1.0 - z * z).max(0.0).sqrt();
        let th = golden * i as f64;
        f([r * s * th.cos(), r * s * th.sin(), r * z]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono_core::math::Vector3;

    /// Every marker lies inside the shape, at least `dp / 2` (less round-off) below the
    /// surface and less than `layers dp` deep; the markers stand for about the shell
    /// volume they replace (`N dp^3` against the exact volume of the layer).
    fn check(shape: &Shape, dp: f64, layers: usize, volume_of_layer: f64, tol: f64) {
        let m = shape_markers("b", shape, dp, layers, [false; 3]).unwrap();
        assert!(!m.points.is_empty());
        for &d in &m.depth {
            assert!(d >= 0.5 * dp - 1e-12, "depth {d}");
            assert!(d < layers as f64 * dp + 1e-12);
        }
        let v = m.points.len() as f64 * dp * dp * dp;
        let rel = (v - volume_of_layer).abs() / volume_of_layer;
        assert!(
            rel < tol,
            "marker volume {v} vs layer {volume_of_layer}: {rel}"
        );
    }

    #[test]
    fn box_layers_fill_the_shell_exactly_on_the_lattice() {
        let dp = 0.01;
        let a = Vector3::new(0.1, 0.05, 0.08);
        let s = Shape::Box { half_extents: a };
        let outer = 8.0 * a.x * a.y * a.z;
        let inner = 8.0 * (a.x - 0.03) * (a.y - 0.03) * (a.z - 0.03);
        check(&s, dp, 3, outer - inner, 1e-9);
    }

    #[test]
    fn sphere_shells_match_the_layer_volume() {
        let dp = 0.01;
        let r = 0.1;
        let s = Shape::Sphere { radius: r };
        let shell = 4.0 / 3.0 * PI * (r.powi(3) - (r - 0.03).powi(3));
        check(&s, dp, 3, shell, 0.01);
        // and the points sit on their shells
        let m = shape_markers("b", &s, dp, 3, [false; 3]).unwrap();
        for (p, d) in m.points.iter().zip(&m.depth) {
            let rr = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((rr + d - r).abs() < 1e-12);
        }
    }

    #[test]
    fn cylinder_rings_match_the_layer_volume() {
        let dp = 0.01;
        let (r, l) = (0.1, 0.15);
        let s = Shape::Cylinder {
            half_length: l,
            radius: r,
        };
        let shell = PI * r * r * 2.0 * l - PI * (r - 0.03).powi(2) * 2.0 * (l - 0.03);
        check(&s, dp, 3, shell, 0.01);
        // open along the axis: only the mantle layers
        let m = shape_markers("b", &s, dp, 3, [false, true, false]).unwrap();
        let mantle = PI * (r * r - (r - 0.03).powi(2)) * 2.0 * l;
        let v = m.points.len() as f64 * dp.powi(3);
        assert!((v - mantle).abs() / mantle < 0.01, "{v} {mantle}");
    }

    fn ellipsoid(a: f64, b: f64, c: f64) -> Shape {
        Shape::Ellipsoid {
            semi_axes: Vector3::new(a, b, c),
        }
    }

    /// Relative difference of the markers' volume `N dp^3` from the volume between the
    /// ellipsoids `e` and `e - layers dp`.
    fn ellipsoid_volume_error(e: Vector3<f64>, dp: f64, layers: usize) -> f64 {
        let m = shape_markers("b", &ellipsoid(e.x, e.y, e.z), dp, layers, [false; 3]).unwrap();
        let vol = |v: Vector3<f64>| 4.0 / 3.0 * PI * v.x * v.y * v.z;
        let shell = vol(e) - vol(e.map(|x| x - layers as f64 * dp));
        (m.points.len() as f64 * dp.powi(3) - shell) / shell
    }

    #[test]
    fn ellipsoid_shells_match_the_layer_volume_and_converge() {
        // The seed's channel ellipsoid (2.25, 2.25, 3) cm, a prolate 3:1 spheroid lying
        // along X and a triaxial one, 3 layers, dp and dp / 2 (fixed physical depth).
        for (e, dp) in [
            (Vector3::new(0.0225, 0.0225, 0.03), 0.004),
            (Vector3::new(0.06, 0.02, 0.02), 0.003),
            (Vector3::new(0.05, 0.035, 0.025), 0.004),
        ] {
            let coarse = ellipsoid_volume_error(e, dp, 3);
            let fine = ellipsoid_volume_error(e, dp / 2.0, 6);
            eprintln!("{e:?} dp {dp}: volume error {coarse:e}, at dp/2 {fine:e}");
            assert!(coarse.abs() < 0.01, "{e:?}: {coarse}");
            assert!(fine.abs() < 0.5 * coarse.abs(), "{e:?}: {coarse} -> {fine}");
        }
    }

    #[test]
    fn ellipsoid_markers_lie_inside_at_their_layer_depth() {
        let e = Vector3::new(0.06, 0.02, 0.025);
        let dp = 0.003;
        let m = shape_markers("b", &ellipsoid(e.x, e.y, e.z), dp, 3, [false; 3]).unwrap();
        let mut shallowest = f64::INFINITY;
        for (p, d) in m.points.iter().zip(&m.depth) {
            let q = Vector3::new(p[0] / e.x, p[1] / e.y, p[2] / e.z).norm();
            assert!(q < 1.0, "{p:?} outside");
            // The depth is the exact distance: its layer's offset at the tips, less
            // between them (the offset ellipsoid is not a parallel surface).
            assert!(*d <= 2.5 * dp + 1e-12 && *d > 0.0, "{p:?}: depth {d}");
            shallowest = shallowest.min(*d / (0.5 * dp));
        }
        // Outer layer: nominal dp / 2; this 3:1 body is at least 0.8 of it everywhere.
        eprintln!("outer layer depth >= {shallowest} dp/2");
        assert!(shallowest > 0.8 && shallowest <= 1.0 + 1e-9, "{shallowest}");
        // Neighbours are about dp apart on each shell: the nearest neighbour of every
        // outer-layer marker within [0.5, 1.5] dp.
        let outer: Vec<_> = m
            .points
            .iter()
            .zip(&m.depth)
            .filter(|(_, d)| **d < dp)
            .map(|(p, _)| Vector3::new(p[0], p[1], p[2]))
            .collect();
        for (i, p) in outer.iter().enumerate() {
            let nn = outer
                .iter()
                .enumerate()
                .filter(|(j, _)| *j != i)
                .map(|(_, q)| (p - q).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nn > 0.5 * dp && nn < 1.5 * dp, "{p:?}: nearest {nn}");
        }
    }

    #[test]
    fn a_round_ellipsoid_has_the_spheres_markers() {
        let (r, dp) = (0.1, 0.01);
        let a = shape_markers("b", &Shape::Sphere { radius: r }, dp, 3, [false; 3]).unwrap();
        let b = shape_markers("b", &ellipsoid(r, r, r), dp, 3, [false; 3]).unwrap();
        assert_eq!(a.points.len(), b.points.len());
        for (p, q) in a.points.iter().zip(&b.points) {
            let d = (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0, f64::max);
            assert!(d < 1e-12, "{p:?} vs {q:?}");
        }
        for (x, y) in a.depth.iter().zip(&b.depth) {
            assert!((x - y).abs() < 1e-12);
        }
        assert_eq!(
            thickness(&ellipsoid(0.1, 0.03, 0.2), [false; 3]),
            Some(0.06)
        );
    }

    #[test]
    fn unsupported_shape_is_an_error_naming_the_body() {
        let s = Shape::Capsule {
            half_length: 0.1,
            radius: 0.05,
        };
        let e = shape_markers("hull", &s, 0.01, 3, [false; 3]).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("hull") && msg.contains("capsule"), "{msg}");
    }
}
