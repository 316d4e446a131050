//! Initial particle sets on the cubic lattice of spacing `dp`, and the particle mass that
//! makes a full lattice sum to the rest density.

use chrono_core::error::{ChronoError, Result, check_positive};
use chrono_core::particles::lattice::{Fit, Lattice, Tank};

/// The cell centres `lower + (i + 1/2) dp` of the lattice filling the box
/// `[lower, upper]` (x fastest, then y, then z), m: the nearest whole count of cells along
/// each axis ([`Lattice::fill`] with [`Fit::Nearest`]).
pub fn lattice_box(lower: [f64; 3], upper: [f64; 3], dp: f64) -> Result<Vec<[f64; 3]>> {
    Lattice::new(lower, dp)?.fill(lower, upper, Fit::Nearest)
}

/// Wall markers of a tank whose inner (fluid) box is `[inner_lower, inner_upper]`:
/// `layers` lattice layers beyond each face marked in `sides`
/// (`[x-, x+, y-, y+, z-, z+]`), on the same lattice as [`lattice_box`] of the inner box,
/// so the first marker layer sits `dp` from the last fluid layer. Faces not marked are open
/// (a periodic axis or the free top). The positions of [`Lattice::tank`] anchored at
/// `inner_lower`, counted by [`Fit::Nearest`].
pub fn tank_markers(
    inner_lower: [f64; 3],
    inner_upper: [f64; 3],
    dp: f64,
    layers: usize,
    sides: [bool; 6],
) -> Result<Vec<[f64; 3]>> {
    let tank = Tank::new(inner_lower, inner_upper, layers, sides);
    let walls = Lattice::new(inner_lower, dp)?.tank(&tank, Fit::Nearest)?;
    Ok(walls.into_iter().map(|w| w.position).collect())
}

pub use chrono_core::density_rows::lattice_mass;

/// Markers of a rigid box in its own frame (centred on the body origin, m): the lattice
/// points `-half + (i + 1/2) dp` inside the box `[-half, half]` that lie within `layers`
/// lattice layers of a face, faces normal to an axis of `open` excluded (an axis along
/// which the box spans a periodic slab has no faces). Attach them with
/// [`ConstraintFluid::attach_body`](crate::ConstraintFluid::attach_body): the fluid then
/// sees the box as it sees the marker walls, its first layer `dp / 2` from the face.
/// Each full extent `2 half[a]` must be a whole number of spacings (the markers' lattice
/// must match the fluid's so a marker stands for the same volume `dp^3` as a particle);
/// the error names the axis.
pub fn box_markers(
    half: [f64; 3],
    dp: f64,
    layers: usize,
    open: [bool; 3],
) -> Result<Vec<[f64; 3]>> {
    check_positive("box_markers.spacing", dp)?;
    if layers == 0 {
        return Err(ChronoError::invalid(
            "box_markers.layers",
            layers,
            "must be >= 1",
        ));
    }
    let mut n = [0usize; 3];
    for a in 0..3 {
        check_positive(&format!("box_markers.half[{a}]"), half[a])?;
        let cells = 2.0 * half[a] / dp;
        if (cells - cells.round()).abs() > 1e-6 * cells.max(1.0) || cells.round() < 1.0 {
            return Err(ChronoError::invalid(
                format!("box_markers.half[{a}]"),
                half[a],
                format!("2 half[{a}] must be a whole number of spacings dp = {dp}"),
            ));
        }
        n[a] = cells.round() as usize;
    }
    let mut out = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let idx = [i, j, k];
                let depth = (0..3)
                    .filter(|&a| !open[a])
                    .map(|a| idx[a].min(n[a] - 1 - idx[a]))
                    .min()
                    .unwrap_or(0);
                if depth < layers {
                    out.push(std::array::from_fn(|a| {
                        -half[a] + (idx[a] as f64 + 0.5) * dp
                    }));
                }
            }
        }
    }
    Ok(out)
}
