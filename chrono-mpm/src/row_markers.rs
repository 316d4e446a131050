//! The fixed marker lattices of the split's density rows ([`crate::pressure`]): wall layers
//! of a plane-strain slab, the markers of a box-shaped kinematic body, and the lattice's
//! gradient moment that turns row impulses into pressures.

use chrono_core::particles::Kernel;

use crate::error::{Result, invalid, positive};

/// `a = (1/dim) sum_j F(r_j) r_j^2` over the lattice of spacing `dp` without its centre
/// (`F = W'(r)/r`, [`Kernel::grad_factor`]; in the plane of a 2-D kernel), 1/m^dim: the
/// lattice's `sum_j F x_j x_j' = a I`. For the continuous kernel `a dp^dim = -1`.
pub fn lattice_gradient_moment(kernel: &Kernel, dp: f64) -> f64 {
    let reach = (kernel.support() / dp).ceil() as i64;
    let dim = kernel.dim();
    let ks = if dim == 3 { -reach..=reach } else { 0..=0 };
    let js = if dim >= 2 { -reach..=reach } else { 0..=0 };
    let mut sum = 0.0;
    for k in ks {
        for j in js.clone() {
            for i in -reach..=reach {
                if i == 0 && j == 0 && k == 0 {
                    continue;
                }
                let r = dp * ((i * i + j * j + k * k) as f64).sqrt();
                sum += kernel.grad_factor(r) * r * r;
            }
        }
    }
    sum / f64::from(dim)
}

/// Fixed wall markers of a plane-strain slab (the plane `y = y`, the 2-D kernel) on the
/// lattice of spacing `dp`: `layers` layers beyond the walls of the box `[x0, x1] x [z0, z1]`
/// (m): the floor `z < z0` (when `floor`) and the sides `x < x0`, `x > x1` (when `sides`)
/// up to `z1`, the corners filled. The inner layer lies `dp / 2` from the wall, as the
/// material's first layer does. Use at least
/// `chrono_core::particles::lattice::wall_layers(h_over_dp)` layers. Errors name the field.
pub fn slab_wall_markers(
    x: [f64; 2],
    z: [f64; 2],
    y: f64,
    dp: f64,
    layers: usize,
    floor: bool,
    sides: bool,
) -> Result<Vec<[f64; 3]>> {
    positive("walls.dp", dp)?;
    if !(x[1] > x[0] && z[1] > z[0]) {
        return Err(invalid(
            "walls.x / walls.z",
            format!("{x:?}, {z:?}"),
            "each must be an increasing pair",
        ));
    }
    let nx = ((x[1] - x[0]) / dp + 1e-9).floor() as i64;
    let nz = ((z[1] - z[0]) / dp + 1e-9).floor() as i64;
    let l = layers as i64;
    let mut out = Vec::new();
    let x_lo = if sides { -l } else { 0 };
    let x_hi = if sides { nx + l } else { nx };
    for k in -l..nz {
        for i in x_lo..x_hi {
            let in_floor = k < 0;
            let in_side = i < 0 || i >= nx;
            if (in_floor && floor) || (!in_floor && in_side && sides) {
                out.push([
                    x[0] + (i as f64 + 0.5) * dp,
                    y,
                    z[0] + (k as f64 + 0.5) * dp,
                ]);
            }
        }
    }
    Ok(out)
}

/// Markers of a rigid box in a plane-strain slab (offsets from the box's centre, m, in the
/// plane `y = y_offset` relative to the centre): the lattice points `-half + (i + 1/2) dp`
/// of the box's `x`–`z` section within `layers` lattice layers of its faces (with
/// `half[0] = half width`, `half[2] = half height`), for
/// [`PressureRows::attach_rigid`](crate::pressure::PressureRows::attach_rigid). Errors name the field.
pub fn box_slab_markers(
    half: [f64; 3],
    y_offset: f64,
    dp: f64,
    layers: usize,
) -> Result<Vec<[f64; 3]>> {
    positive("rigid_markers.dp", dp)?;
    positive("rigid_markers.half[0]", half[0])?;
    positive("rigid_markers.half[2]", half[2])?;
    let nx = ((2.0 * half[0]) / dp + 1e-9).floor() as usize;
    let nz = ((2.0 * half[2]) / dp + 1e-9).floor() as usize;
    let mut out = Vec::new();
    for i in 0..nx {
        for k in 0..nz {
            let edge = i.min(nx - 1 - i).min(k.min(nz - 1 - k));
            if edge < layers {
                out.push([
                    -half[0] + (i as f64 + 0.5) * dp,
                    y_offset,
                    -half[2] + (k as f64 + 0.5) * dp,
                ]);
            }
        }
    }
    Ok(out)
}
