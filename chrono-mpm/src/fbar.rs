//! F-bar: each marker's volume change averaged over its grid stencil, against volumetric
//! locking and a checkerboard of the markers' volume changes.
//!
//! With isochoric plastic flow (von Mises, Tresca) or a nearly incompressible elasticity,
//! every marker's `J` is a constraint on the grid's velocity field; with several markers
//! per cell the quadratic-spline field has too few degrees of freedom for them and locks
//! (the footing's limit load at `poisson` 0.49 is 12.5 % high at 4 cells, `docs/mpm.md`).
//! The F-bar method (de Souza Neto, Perić, Dutko & Owen, "Design of simple low order finite
//! elements for large strain analysis of nearly incompressible solids", Int. J. Solids
//! Struct. 33(20-22), 1996) keeps the isochoric part of the deformation gradient and takes
//! its volume change from an average over a patch, `F_bar = (J_avg / J)^(1/3) F`. In MPM
//! the patch can be the background cell (Coombs, Charlton, Cortis & Augarde, "Overcoming
//! volumetric locking in material point methods", CMAME 333, 2018) or the grid stencil
//! through the transfers (Zhao, Jiang & Choo, "Circumventing volumetric locking in
//! explicit material point methods: a simple, efficient, and general approach", IJNME
//! 124(23), 2023). Here the stencil, in the incremental (updated-Lagrangian) form: with the
//! step's increment `dF_p = I + dt grad v_p`, `dJ_p = det dF_p` and the marker's current
//! volume `V_p = V0_p det F_E det F_P`,
//!
//! ```text
//! dJ_i    = sum_p w_ip V_p dJ_p / sum_p w_ip V_p     the volume-weighted average at node i
//! dJbar_p = sum_i w_ip dJ_i                          back at the marker
//! dFbar_p = (dJbar_p / dJ_p)^(1/3) dF_p,   F_E trial = dFbar_p F_E,  then the return mapping
//! ```
//!
//! `F_E` is the marker's state, so the return mapping and the stress both see the averaged
//! volume (the rotation and the isochoric stretch of the increment are the marker's own).
//! Properties (tested in `crate::tests`): a uniform `dJ` is unchanged (the weights are a
//! partition of unity); the total volume change is kept, `sum_p V_p dJbar_p = sum_p V_p dJ_p`
//! (exchange the sums); a checkerboard of `dJ` (alternating from one marker layer to the
//! next, one or two markers per cell) has zero weighted sum at every node of the quadratic
//! spline (the 1-D weights of the two sides balance) and is averaged out.
//!
//! Why the stencil and not the cell: the snow column runs one marker per cell, where a cell
//! average is the marker itself. Why the increments and not the total `J`: smoothing the
//! total `J` every step would diffuse the strain itself (an elastic wave's energy) by an
//! `O(dx^2)` amount per step; smoothing the increments changes a step by `O(dt dx^2)`.

use rayon::prelude::*;

/// Which volume change the F-bar averages ([`crate::MpmSettings::f_bar`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FBar {
    /// No averaging: each marker's own `F`.
    #[default]
    Off,
    /// The step's increment `dJ` averaged with the current volumes `V_p` as weights (the
    /// method of this module).
    Increment,
    /// The total `J` after the step averaged with the reference volumes `V0_p` as weights
    /// (`Jbar = sum V / sum V0` over the stencil), `F_E` trial scaled by
    /// `(Jbar / J)^(1/3)`: restores a checkerboard already present, but smooths the strain
    /// itself every step (an experiment; see the module documentation).
    Total,
    /// The plastic part only: the step's plastic volume change `det F_P' / det F_P` (from
    /// the return mapping) averaged over the stencil like the increments, `F_E` kept (an
    /// experiment against the snow column's checkerboard of `J_P`, `docs/mpm.md`).
    PlasticIncrement,
}

impl std::str::FromStr for FBar {
    type Err = MpmError;

    /// `off`, `increment`, `total` or `plastic`; anything else is an error naming the field `f_bar`.
    fn from_str(s: &str) -> Result<Self, MpmError> {
        match s {
            "off" => Ok(FBar::Off),
            "increment" => Ok(FBar::Increment),
            "total" => Ok(FBar::Total),
            "plastic" => Ok(FBar::PlasticIncrement),
            _ => Err(invalid(
                "f_bar",
                s,
                "must be off, increment, total or plastic",
            )),
        }
    }
}

use crate::body::{P2gMarker, stencil_in_block};
use crate::bspline::Stencil;
use crate::error::{MpmError, invalid};
use crate::grid::{BLOCK, BLOCK3, GHOST, SparseGrid, key, unkey};

/// The least grid blocks of one parallel task (the results do not depend on it).
const BLOCKS_PER_TASK: usize = 8;

/// Calls `f(o, node)` for the 27 nodes `base + o` of the stencil `st`, in the fixed order
/// of `o`, with `node` the index of the node in the grid's node arrays. Every block a
/// stencil reaches is active after P2G.
#[inline]
pub(crate) fn for_stencil_nodes(
    grid: &SparseGrid,
    nb: [usize; 3],
    st: &Stencil,
    mut f: impl FnMut([usize; 3], usize),
) {
    let g0 = [
        (st.base[0] + GHOST) as usize,
        (st.base[1] + GHOST) as usize,
        (st.base[2] + GHOST) as usize,
    ];
    // The (up to 8) blocks of the stencil, looked up once each.
    let b0 = [g0[0] / BLOCK, g0[1] / BLOCK, g0[2] / BLOCK];
    let mut bidx = [[[usize::MAX; 2]; 2]; 2];
    for o0 in 0..3 {
        let g_0 = g0[0] + o0;
        for o1 in 0..3 {
            let g_1 = g0[1] + o1;
            for o2 in 0..3 {
                let g_2 = g0[2] + o2;
                let d = [
                    g_0 / BLOCK - b0[0],
                    g_1 / BLOCK - b0[1],
                    g_2 / BLOCK - b0[2],
                ];
                let slot = &mut bidx[d[0]][d[1]][d[2]];
                if *slot == usize::MAX {
                    *slot = grid
                        .block_index(key([g_0 / BLOCK, g_1 / BLOCK, g_2 / BLOCK], nb))
                        .expect("P2G activated every block of every stencil");
                }
                let l = ((g_0 % BLOCK) * BLOCK + g_1 % BLOCK) * BLOCK + g_2 % BLOCK;
                f([o0, o1, o2], *slot * BLOCK3 + l);
            }
        }
    }
}

/// The nodal averages `dJ_i` (in `nodal[i][0]`, with the weight `sum_p w_ip V_p` in
/// `nodal[i][1]`; 0 where no marker weighs) of the markers' `vol_dj[p] = (V_p, V_p dJ_p)`
/// (indexed by marker). A gather like P2G's: each active block sums the markers of its 8
/// neighbouring marker blocks in the sorted order (`scratch`: P2G's per-marker stencils in
/// that order), so the result is the same bits for any thread count.
pub(crate) fn nodal_average(
    grid: &SparseGrid,
    scratch: &[P2gMarker],
    vol_dj: &[[f64; 2]],
    nb: [usize; 3],
    nodal: &mut Vec<[f64; 2]>,
) {
    nodal.clear();
    nodal.resize(grid.active.len() * BLOCK3, [0.0; 2]);
    nodal
        .par_chunks_mut(BLOCK3)
        .with_min_len(BLOCKS_PER_TASK)
        .enumerate()
        .for_each(|(k, out)| {
            let b = unkey(grid.active[k], nb);
            let lo = [b[0] * BLOCK, b[1] * BLOCK, b[2] * BLOCK];
            for run in grid.runs_reaching(b, nb) {
                for s in run {
                    let p = grid.sorted[s].1 as usize;
                    scatter(&scratch[s], vol_dj[p], lo, out);
                }
            }
            for n in out.iter_mut() {
                *n = if n[0] > 0.0 {
                    [n[1] / n[0], n[0]]
                } else {
                    [0.0, 0.0]
                };
            }
        });
}

/// Adds `w_ip (V_p, V_p dJ_p)` of one marker to the nodes of one block (those of its
/// stencil in the block), as `[sum w V, sum w V dJ]`.
#[inline]
fn scatter(s: &P2gMarker, vd: [f64; 2], lo: [usize; 3], out: &mut [[f64; 2]]) {
    let Some(r) = stencil_in_block(s.g0, lo) else {
        return;
    };
    for o0 in r[0].0..r[0].1 {
        for o1 in r[1].0..r[1].1 {
            for o2 in r[2].0..r[2].1 {
                let w = s.st.weight([o0, o1, o2]);
                let l = ((s.g0[0] + o0 - lo[0]) * BLOCK + (s.g0[1] + o1 - lo[1])) * BLOCK
                    + (s.g0[2] + o2 - lo[2]);
                out[l][0] += w * vd[0];
                out[l][1] += w * vd[1];
            }
        }
    }
}

/// `dJbar_p = sum_i w_ip dJ_i` at the marker of stencil `st`.
#[inline]
pub(crate) fn interpolate(
    grid: &SparseGrid,
    nodal: &[[f64; 2]],
    nb: [usize; 3],
    st: &Stencil,
) -> f64 {
    let mut j = 0.0;
    for_stencil_nodes(grid, nb, st, |o, node| j += st.weight(o) * nodal[node][0]);
    j
}

/// The F-bar factor `(dJbar / dJ)^(1/3)`; `None` unless both are positive and finite.
#[inline]
pub fn factor(dj: f64, dj_bar: f64) -> Option<f64> {
    (dj > 0.0 && dj_bar > 0.0 && dj.is_finite() && dj_bar.is_finite()).then(|| (dj_bar / dj).cbrt())
}
