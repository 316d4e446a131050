//! Fickian particle shifting (Lind, Xu, Stansby and Rogers 2012, J. Comput. Phys. 231:
//! 1499-1523; the step-size form of Skillen, Lind, Stansby and Rogers 2013, Comput.
//! Methods Appl. Mech. Engrg. 265: 163-173).
//!
//! Without it, a WCSPH fluid in a long shear flow loses its particle order: in the
//! `fsi-cylinder-array` cell the mean nearest-neighbour distance of the fluid far from
//! the cylinder falls from 0.98 to 0.78 spacings in four seconds, and the array's
//! resistance rises with it (docs/validation-fsi.md). After each step every stepped fluid
//! particle moves down the gradient of the particle concentration `C`:
//!
//! ```text
//! grad C_a = sum_b V_b grad_a W_ab,   V_b = m_b / rho_b   (fluid and wall markers)
//! dr_a     = -A h |v_a| dt grad C_a                       (m)
//! ```
//!
//! `A` dimensionless ([`Shifting::coefficient`](crate::Shifting::coefficient), 2 in
//! Skillen et al.), `h` the smoothing length, `dt` the step. The shift is a diffusion of positions with `D = A h |v| dt`: it
//! acts only where the fluid moves, at a rate independent of the step. Density, velocity
//! and the rest of the state are not corrected for the displacement (a first-order term
//! `dr . grad`, small at `|dr| << h`). Meant for fluid without a free surface: at a
//! surface the kernel's deficit makes `grad C` point outwards and the particles would be
//! pushed out (Lind et al. treat the surface apart; not done here).
//! Not yet over ranks (a distributed system refuses it).

use rayon::prelude::*;

use crate::data::{FLUID, ParticleData};
use crate::interact::PassCtx;
use crate::system::active::ACT_NOW;

/// The shifts `dr` (m) of one step of length `dt` (s) into `out` (zero for walls and
/// frozen particles), from the current positions and the neighbour list of `c`.
pub(crate) fn shifts(
    d: &ParticleData,
    c: &PassCtx<'_>,
    coefficient: f64,
    dt: f64,
    out: &mut Vec<[f64; 3]>,
) {
    out.resize(d.len(), [0.0; 3]);
    let support2 = c.kernel.support() * c.kernel.support();
    let k = coefficient * c.kernel.h() * dt;
    out.par_iter_mut().enumerate().for_each(|(a, o)| {
        *o = [0.0; 3];
        if d.kind[a] != FLUID || c.eval.is_some_and(|e| e[a] & ACT_NOW == 0) {
            return;
        }
        let pa = [d.x[a], d.y[a], d.z[a]];
        let mut g = [0.0; 3];
        for &b in c.list.neighbors(a) {
            let b = b as usize;
            let x = c.grid.displacement(pa, [d.x[b], d.y[b], d.z[b]]);
            let r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
            if r2 >= support2 {
                continue;
            }
            let f = d.mass[b] / d.rho[b] * c.kernel.grad_factor(r2.sqrt());
            g[0] += f * x[0];
            g[1] += f * x[1];
            g[2] += f * x[2];
        }
        let speed = (d.vx[a] * d.vx[a] + d.vy[a] * d.vy[a] + d.vz[a] * d.vz[a]).sqrt();
        let s = -k * speed;
        *o = [s * g[0], s * g[1], s * g[2]];
    });
}
