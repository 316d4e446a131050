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
//!
//! An axis may be *open* (`open[i]`: the shape spans a periodic direction of the fluid
//! domain, e.g. a horizontal cylinder across a quasi-2-D slab): the faces or caps normal to
//! it carry no markers. Not generated (an error naming the shape): capsules, convex hulls,
//! triangle meshes, half spaces, and the ellipsoid (not yet a chrono-core shape).

use std::f64::consts::PI;

use chrono_core::Shape;

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
        other => {
            return Err(FsiError::UnsupportedShape {
                body: body.to_string(),
                shape: shape_kind(other).to_string(),
            });
        }
    }
    Ok(out)
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
