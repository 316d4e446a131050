//! Particle shifting: a Fickian diffusion of the fluid's positions down the gradient of
//! the particle concentration `C` (Lind, Xu, Stansby and Rogers 2012, J. Comput. Phys.
//! 231:1499-1523).
//!
//! Without it, a WCSPH fluid in a long shear flow loses its particle order: in the
//! `fsi-cylinder-array` cell the mean nearest-neighbour distance of the fluid far from
//! the cylinder falls from 0.98 to 0.78 spacings in four seconds, and the array's
//! resistance rises with it (docs/validation-fsi.md). After each step every stepped fluid
//! particle moves by
//!
//! ```text
//! grad C_a = sum_b V_b (1 + f_ab) grad_a W_ab,   V_b = m_b / rho_b   (fluid and wall markers)
//! dr_a     = -D_a grad C_a                                           (m)
//! ```
//!
//! in one of two forms ([`ShiftForm`]), `h` the smoothing length, `dt`
//! the step, `A` the [coefficient](crate::Shifting::coefficient):
//!
//! - `LocalSpeed` (Skillen, Lind, Stansby and Rogers 2013): `D_a = A h |v_a| dt`,
//!   `f_ab = 0`; `A` = 2 there.
//! - `DeltaPlus` (Sun, Colagrossi, Marrone and Zhang 2017): `D_a = A h U_max dt` with
//!   `U_max` the largest speed of the stepped fluid at the step, `f_ab = R (W_ab /
//!   W(dp))^n`, `R = 0.2`, `n = 4` (pairs closer than the spacing repel more: against
//!   clumping); their `CFL Ma (2h)^2` per step is `A = 4` at `dt = CFL h / c_0`.
//!
//! Both are diffusions of positions at a rate independent of the step. Density, velocity
//! and the rest of the state are not corrected for the displacement (a first-order term
//! `dr . grad`, small at `|dr| << h`). Meant for fluid without a free surface: at a
//! surface the kernel's deficit makes `grad C` point outwards and the particles would be
//! pushed out (both papers treat the surface apart; not done here).
//! Not yet over ranks (a distributed system refuses it).

use rayon::prelude::*;

use crate::data::{FLUID, ParticleData};
use crate::system::active::ACT_NOW;
use crate::{ShiftForm, Shifting};

/// Sun et al.'s (2017) anti-clumping weight: `f_ab = R (W_ab / W(dp))^n`, `n = 4`.
pub(crate) const CLUMP_R: f64 = 0.2;

/// The shifts `dr` (m) of one step of length `dt` (s) into `out` (zero for walls and
/// for particles not stepped now: `eval` holds the active domain's flags), from each
/// particle's concentration gradient `grad` (1/m; the force pass sums it over the same
/// pairs, positions and volumes, [`crate::pairs::force_pass`]) and the current velocities.
pub(crate) fn shifts(
    d: &ParticleData,
    eval: Option<&[u8]>,
    shifting: Shifting,
    h: f64,
    dt: f64,
    grad: &[[f64; 3]],
    out: &mut Vec<[f64; 3]>,
) {
    out.resize(d.len(), [0.0; 3]);
    let stepped = |a: usize| d.kind[a] == FLUID && eval.is_none_or(|e| e[a] & ACT_NOW != 0);
    let speed = |a: usize| (d.vx[a] * d.vx[a] + d.vy[a] * d.vy[a] + d.vz[a] * d.vz[a]).sqrt();
    let delta_plus = shifting.form == ShiftForm::DeltaPlus;
    // the largest speed: a max is exact in any order, so the same bits on any thread count
    let u_max = if delta_plus {
        (0..d.len())
            .into_par_iter()
            .filter(|&a| stepped(a))
            .map(speed)
            .reduce(|| 0.0, f64::max)
    } else {
        0.0
    };
    let k = shifting.coefficient * h * dt;
    out.par_iter_mut().enumerate().for_each(|(a, o)| {
        *o = [0.0; 3];
        if !stepped(a) {
            return;
        }
        let g = grad[a];
        let s = -k * if delta_plus { u_max } else { speed(a) };
        *o = [s * g[0], s * g[1], s * g[2]];
    });
}
