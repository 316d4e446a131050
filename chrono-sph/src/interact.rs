//! The particle interaction passes (parallel over particles, reading the CSR neighbour
//! list): wall-marker extrapolation, the fluid derivatives, the Shepard filter.
//!
//! Fluid equations (Monaghan 2005, Rep. Prog. Phys. 68, 1703; Morris, Fox and Zhu 1997,
//! J. Comput. Phys. 136, 214), with `x_ab = x_a - x_b`, `v_ab = v_a - v_b`,
//! `grad_a W_ab = F(r) x_ab` and `rho_ab = (rho_a + rho_b) / 2`:
//!
//! ```text
//! d rho_a / dt = rho_a sum_b (m_b / rho_b) v_ab . grad_a W_ab                    (continuity)
//!                + 2 delta h c_s sum_b (m_b / rho_b) psi_ba (-F_ab)  (fluid b)  (delta-SPH)
//! d v_a / dt   = - sum_b m_b (p_a / rho_a^2 + p_b / rho_b^2) grad_a W_ab        (pressure)
//!                + sum_b m_b (mu_a + mu_b) (x_ab . grad_a W_ab) v_ab / (rho_ab^2 r_ab^2)
//!                  = sum_b m_b 2 mu F_ab v_ab / rho_ab^2                           (Morris viscosity)
//!                - sum_b m_b Pi_ab grad_a W_ab                                  (artificial, optional)
//!                + g + f                                                        (body forces)
//! Delta v_a    = zeta sum_b (m_b / rho_ab) (v_b - v_a) W_ab   (fluid b)         (XSPH)
//! ```
//!
//! with `psi_ba` the density difference of [`DensityDiffusion`] (Molteni and Colagrossi
//! 2009; Fourtakas et al. 2019),
//! `Pi_ab = -alpha c_s h (v_ab . x_ab) / (rho_ab (r^2 + 0.01 h^2))` when
//! `v_ab . x_ab < 0` (Monaghan 1992). The pressure and viscous pair terms are
//! antisymmetric in `(a, b)` once multiplied by `m_a`, so the fluid momentum changes
//! only through walls and body forces. The Morris term is written with
//! `x_ab . grad_a W_ab / r_ab^2 = F_ab` exactly: Morris et al.'s regularization
//! `r^2 + 0.01 h^2` is only needed for kernels whose `F` is singular at `r = 0` (ours are
//! finite), and it weakened the viscous force by 0.9 % on the lattice at `h = 1.5 dp`.
//!
//! Walls (Adami, Hu and Adams, J. Comput. Phys. 231 (2012) 7057-7075), for a wall
//! marker `w` with fluid neighbours `f`:
//!
//! ```text
//! p_w   = (sum_f p_f W_wf + (b - a_w) . sum_f rho_f x_wf W_wf) / sum_f W_wf
//! rho_w = rho(p_w)      (inverse Tait),   m_w = rho_w dp^3 (fixed marker volume)
//! v~_f  = sum_f v_f W_wf / sum_f W_wf,   d~_f = sum_f d_f W_wf / sum_f W_wf
//! v_w   = v_prescribed - (d_w / max(d~_f, 0.2 h)) (v~_f - v_prescribed)   (NoSlip::Linear)
//! v_w   = 2 v_prescribed - v~_f                                          (NoSlip::Adami)
//! ```
//!
//! (`b`: the fluid's body acceleration, gravity plus the settings' body force; `d_w`: the
//! marker's depth behind the wall surface, `d_f = n . (x_f - x_w) - d_w` the
//! fluid neighbour's distance in front of it, `n` the inward wall normal); `v_w` enters the
//! viscous term only.
//!
//! so the wall pushes back exactly as much as the fluid presses (no leak) and, with
//! `p_w` clamped at 0, never pulls (no sticking). The continuity equation uses the
//! prescribed wall velocity.

use chrono_core::particles::{CellGrid, Kernel, NeighborList};
use rayon::prelude::*;

use crate::carrier::{NO_CARRIER, POINT_CARRIER};
use crate::data::{Deriv, FLUID, ParticleData, WALL};
use crate::eos::Tait;
use crate::settings::{DensityDiffusion, NoSlip};
use crate::system::active::{ACT_NEXT, ACT_NOW, LISTED};

/// Everything the passes read besides the particle arrays.
pub(crate) struct PassCtx<'a> {
    pub kernel: &'a Kernel,
    pub eos: &'a Tait,
    pub grid: &'a CellGrid,
    /// Whether some axis of `grid` is periodic (the displacement of a pair may then
    /// wrap; else it is the plain difference).
    pub periodic: bool,
    pub list: &'a NeighborList,
    pub mu: f64,
    pub alpha: f64,
    pub xsph: f64,
    pub accel: [f64; 3],
    pub gravity: [f64; 3],
    pub wall_acc: [f64; 3],
    pub wall_vel: [f64; 3],
    pub clamp_wall_pressure: bool,
    /// Volume of a wall marker, `dp^3`: its mass follows its density, `m_w = rho_w dp^3`.
    pub wall_volume: f64,
    /// The density diffusion form.
    pub diffusion: DensityDiffusion,
    /// `2 delta h c_s` (0 = no diffusion), m^2/s.
    pub diffusion_coef: f64,
    /// `1 / c_s^2`, s^2/m^2.
    pub inv_c2: f64,
    /// The no-slip extrapolation.
    pub no_slip: NoSlip,
    /// The active domain's flags of each particle
    /// ([`crate::system::active`]; `None`: every particle is evaluated): fluid particles
    /// are evaluated when active now or next, wall markers when listed, and the Shepard
    /// filter touches the fluid active now.
    pub eval: Option<&'a [u8]>,
    /// The force pass also sums the particle-concentration gradient of the shifting
    /// ([`crate::shifting`]): 0 no, 1 `sum_b V_b grad W_ab`, 2 with the anti-clumping
    /// weight `1 + R (W_ab / W(dp))^4`.
    pub shift: u8,
    /// `1 / W(dp)`, m^3: the kernel's inverse value at one spacing (for `shift = 2`).
    pub inv_w_dp: f64,
    /// The belt velocity of each wall group ([`crate::WallBelt`]; empty: none), m/s.
    pub belts: &'a [[f64; 3]],
    /// The angular velocity of each rigid carrier (world), rad/s.
    pub carrier_omega: &'a [[f64; 3]],
}

impl PassCtx<'_> {
    /// Whether fluid particle `a` is evaluated (active now or at the end of the step).
    #[inline(always)]
    pub fn evaluates_fluid(&self, a: usize) -> bool {
        self.eval.is_none_or(|e| e[a] & (ACT_NOW | ACT_NEXT) != 0)
    }
    /// Whether wall marker `w` is evaluated (listed).
    #[inline(always)]
    pub fn evaluates_wall(&self, w: usize) -> bool {
        self.eval.is_none_or(|e| e[w] & LISTED != 0)
    }
}

/// What a pair loop reads of a neighbour, packed in one record: one bounds-checked load
/// per neighbour instead of one per SoA array (the SoA arrays stay the storage; the
/// records are refreshed before each pass, a copy of `n` records against ~100 pair
/// visits per particle). Three groups of four values: the SIMD passes of
/// [`pairs`](crate::pairs) load each group of `lanes` neighbours as `lanes` rows and
/// transpose them into four columns (no per-entry column stores).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Packed {
    /// `[x, y, z, p]`: position (m) and pressure (Pa).
    pub pos_p: [f64; 4],
    /// `[vx, vy, vz, rho]`: velocity (m/s; the particle's own in the continuity pass or,
    /// for wall markers, the extrapolated no-slip velocity in the force pass, see
    /// [`PackVelocity`]) and density (kg/m^3).
    pub vel_rho: [f64; 4],
    /// `[p / rho^2, m, m / rho, fl]`: `p / rho^2` (m^5/(kg s^2)), mass (kg), volume
    /// (m^3, the same division the pair term would do), and 1 for a fluid particle, 0
    /// for a wall marker (a multiplier: the specialized passes mask fluid-only terms
    /// with it instead of branching).
    pub pr2_m_vol_fl: [f64; 4],
}

impl Packed {
    /// The record of a particle with position `pos`, velocity `vel`, density `rho`,
    /// pressure `p` and mass `mass`; `fluid`: a fluid particle (else a wall marker).
    #[inline(always)]
    pub fn new(pos: [f64; 3], vel: [f64; 3], rho: f64, p: f64, mass: f64, fluid: bool) -> Self {
        Self {
            pos_p: [pos[0], pos[1], pos[2], p],
            vel_rho: [vel[0], vel[1], vel[2], rho],
            pr2_m_vol_fl: [
                p / (rho * rho),
                mass,
                mass / rho,
                if fluid { 1.0 } else { 0.0 },
            ],
        }
    }
    /// Position, m.
    #[inline(always)]
    pub fn pos(&self) -> [f64; 3] {
        [self.pos_p[0], self.pos_p[1], self.pos_p[2]]
    }
    /// Velocity, m/s.
    #[inline(always)]
    pub fn vel(&self) -> [f64; 3] {
        [self.vel_rho[0], self.vel_rho[1], self.vel_rho[2]]
    }
    /// Density, kg/m^3.
    #[inline(always)]
    pub fn rho(&self) -> f64 {
        self.vel_rho[3]
    }
    /// Pressure, Pa.
    #[inline(always)]
    pub fn p(&self) -> f64 {
        self.pos_p[3]
    }
    /// `p / rho^2`, m^5/(kg s^2).
    #[inline(always)]
    pub fn pr2(&self) -> f64 {
        self.pr2_m_vol_fl[0]
    }
    /// Mass, kg.
    #[inline(always)]
    pub fn mass(&self) -> f64 {
        self.pr2_m_vol_fl[1]
    }
    /// Whether it is a fluid particle.
    #[inline(always)]
    pub fn fluid(&self) -> bool {
        self.pr2_m_vol_fl[3] != 0.0
    }
}

/// Which velocity of a wall marker a [`Packed`] record holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PackVelocity {
    /// The prescribed wall velocity (continuity: no flux through walls).
    Prescribed,
    /// The extrapolated no-slip velocity (the viscous term).
    NoSlip,
}

/// Refreshes the packed records of every particle from the SoA arrays.
pub(crate) fn pack(d: &ParticleData, which: PackVelocity, out: &mut Vec<Packed>) {
    out.resize(d.len(), Packed::default());
    out.par_iter_mut().enumerate().for_each(|(i, o)| {
        let fluid = d.kind[i] == FLUID;
        let vel = if !fluid && which == PackVelocity::NoSlip {
            d.wall_v[i]
        } else {
            [d.vx[i], d.vy[i], d.vz[i]]
        };
        *o = Packed::new(
            [d.x[i], d.y[i], d.z[i]],
            vel,
            d.rho[i],
            d.p[i],
            d.mass[i],
            fluid,
        );
    });
}

/// Pressure of every fluid particle from its density (Tait).
pub(crate) fn fluid_pressure(d: &mut ParticleData, eos: &Tait) {
    d.p.par_iter_mut()
        .zip(d.rho.par_iter())
        .zip(d.kind.par_iter())
        .for_each(|((p, &rho), &k)| {
            if k == FLUID {
                *p = eos.pressure(rho);
            }
        });
}

/// Wall-marker pressure, density and no-slip velocity extrapolated from the fluid
/// (Adami et al. 2012, eq. 27): `p_w = (sum_f p_f W_wf + (b - a_w) . sum_f rho_f
/// (x_w - x_f) W_wf) / sum_f W_wf`, with `b` the fluid's whole body acceleration (gravity
/// plus the settings' body force, m/s^2) and `a_w` the wall's acceleration: the normal
/// momentum balance at a no-penetration wall, `dp/dn = rho (b - a_w) . n`. `bc` is
/// scratch (one `[p, rho, vx, vy, vz]` per particle). `nb`: records packed since the last move (positions, fluid velocities and kinds are read
/// from them, one bounds-checked load per neighbour; the densities and pressures, updated
/// since, from the arrays).
pub(crate) fn wall_extrapolation(
    d: &mut ParticleData,
    nb: &[Packed],
    c: &PassCtx<'_>,
    bc: &mut Vec<[f64; 5]>,
) {
    let n = d.len();
    bc.resize(n, [0.0; 5]);
    // the body force too, not gravity alone: a fluid driven by a body force presses on
    // the walls across its flow (docs/validation-fsi.md, "The markers' pressure and the
    // driving body force")
    let b = c.accel;
    let b_minus_a = [
        b[0] - c.wall_acc[0],
        b[1] - c.wall_acc[1],
        b[2] - c.wall_acc[2],
    ];
    let support2 = c.kernel.support() * c.kernel.support();
    {
        let d = &*d;
        bc.par_iter_mut().enumerate().for_each(|(w, out)| {
            if d.kind[w] != WALL || !c.evaluates_wall(w) {
                return;
            }
            let pw = nb[w].pos();
            // carrier markers: their own rigid velocity and acceleration; tank walls: the
            // wall motion's (unchanged arithmetic)
            let carried = d.carrier[w] != NO_CARRIER;
            // a rotating rigid carrier: its velocity field is not uniform over the
            // kernel (see `rigid_omega` below)
            let omega = if carried && d.carrier[w] & POINT_CARRIER == 0 {
                c.carrier_omega
                    .get(d.carrier[w] as usize)
                    .copied()
                    .filter(|o| *o != [0.0; 3])
            } else {
                None
            };
            let (vw, b_minus_a) = if carried {
                let a = d.wall_a[w];
                (
                    [d.vx[w], d.vy[w], d.vz[w]],
                    [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                )
            } else {
                (
                    crate::system::belt_velocity(c.belts, d.group[w], c.wall_vel),
                    b_minus_a,
                )
            };
            let (mut sw, mut sp, mut sr) = (0.0, 0.0, [0.0; 3]);
            let mut sv = [0.0; 3];
            let n = d.wall_normal[w];
            let linear = c.no_slip == NoSlip::Linear && n != [0.0; 3];
            let mut sd = 0.0;
            let mut sx = [0.0; 3];
            let depth = d.wall_depth[w];
            for &f in c.list.neighbors(w) {
                let f = f as usize;
                let rf = &nb[f];
                if !rf.fluid() {
                    continue;
                }
                let x = c.grid.displacement(pw, rf.pos());
                let r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
                if r2 >= support2 {
                    continue; // W = 0: the list's skin
                }
                let wk = c.kernel.w(r2.sqrt());
                sw += wk;
                sp += d.p[f] * wk;
                let rw = d.rho[f] * wk;
                sr[0] += rw * x[0];
                sr[1] += rw * x[1];
                sr[2] += rw * x[2];
                let vf = rf.vel();
                sv[0] += vf[0] * wk;
                sv[1] += vf[1] * wk;
                sv[2] += vf[2] * wk;
                // distance of f in front of the wall surface (x = x_w - x_f)
                sd += (-(n[0] * x[0] + n[1] * x[1] + n[2] * x[2]) - depth) * wk;
                // the kernel-averaged fluid point: only a rotating carrier's mirror reads it
                if omega.is_some() {
                    sx[0] += x[0] * wk;
                    sx[1] += x[1] * wk;
                    sx[2] += x[2] * wk;
                }
            }
            if sw > 0.0 {
                let mut p =
                    (sp + b_minus_a[0] * sr[0] + b_minus_a[1] * sr[1] + b_minus_a[2] * sr[2]) / sw;
                if c.clamp_wall_pressure {
                    p = p.max(0.0);
                }
                // v_w = v_wall - ratio (v~_f - v_wall)
                let ratio = if linear {
                    depth / (sd / sw).max(0.2 * c.kernel.h())
                } else {
                    1.0
                };
                let mut v = [
                    vw[0] - ratio * (sv[0] / sw - vw[0]),
                    vw[1] - ratio * (sv[1] / sw - vw[1]),
                    vw[2] - ratio * (sv[2] / sw - vw[2]),
                ];
                if let Some(o) = omega {
                    // mirror the fluid's velocity relative to the body's rigid field:
                    // v~_f is the fluid at the kernel-averaged point x~_f, where the body
                    // moves with v_m + w x (x~_f - x_w), not v_m; the plain mirror would
                    // make the markers of a co-rotating body lag by w x (x~_f - x_w)
                    // (about w dp) and drive a torque-free body to spin too fast
                    let r = [-sx[0] / sw, -sx[1] / sw, -sx[2] / sw]; // x~_f - x_w
                    v[0] += o[1] * r[2] - o[2] * r[1];
                    v[1] += o[2] * r[0] - o[0] * r[2];
                    v[2] += o[0] * r[1] - o[1] * r[0];
                }
                *out = [p, c.eos.density(p), v[0], v[1], v[2]];
            } else {
                *out = [0.0, c.eos.rho0, vw[0], vw[1], vw[2]];
            }
        });
    }
    let vol = c.wall_volume;
    (
        d.p.par_iter_mut(),
        d.rho.par_iter_mut(),
        d.mass.par_iter_mut(),
        d.wall_v.par_iter_mut(),
        bc.par_iter(),
        d.kind.par_iter(),
    )
        .into_par_iter()
        .enumerate()
        .for_each(|(w, (p, rho, m, v, b, &k))| {
            // unlisted markers of the active domain hold their values
            if k == WALL && c.evaluates_wall(w) {
                *p = b[0];
                *rho = b[1];
                *m = b[1] * vol;
                *v = [b[2], b[3], b[4]];
            }
        });
}

/// Displacement `x_a - x_b` and distance squared of a pair.
#[inline(always)]
fn separation(c: &PassCtx<'_>, pa: &Packed, pb: &Packed) -> ([f64; 3], f64) {
    let x = c.grid.displacement(pa.pos(), pb.pos());
    (x, x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
}

/// The momentum pair terms of fluid particle `a` with neighbour `b` (pressure,
/// optional artificial viscosity, Morris viscosity), without body forces; zero outside
/// the support (`r2 >= support2`, skipped before any kernel work). Shared by the force
/// pass and the wall-force probe. `b`'s record must hold the no-slip wall velocity
/// ([`PackVelocity::NoSlip`]).
#[inline(always)]
pub(crate) fn pair_accel(c: &PassCtx<'_>, pa: &Packed, pb: &Packed, support2: f64) -> [f64; 3] {
    let (x, r2) = separation(c, pa, pb);
    if r2 >= support2 {
        return [0.0; 3];
    }
    let h = c.kernel.h();
    let fk = c.kernel.grad_factor(r2.sqrt());
    let mb = pb.mass();
    let (va, vb) = (pa.vel(), pb.vel());
    let vv = [va[0] - vb[0], va[1] - vb[1], va[2] - vb[2]];
    let rho_ab = 0.5 * (pa.rho() + pb.rho());
    let eta2 = 0.01 * h * h;
    // pressure: -m_b (p_a/rho_a^2 + p_b/rho_b^2) F x_ab
    let mut coef = -mb * (pa.pr2() + pb.pr2()) * fk;
    if c.alpha > 0.0 {
        let vx = vv[0] * x[0] + vv[1] * x[1] + vv[2] * x[2];
        if vx < 0.0 {
            let pi = -c.alpha * c.eos.sound_speed * h * vx / (rho_ab * (r2 + eta2));
            coef -= mb * pi * fk;
        }
    }
    // Morris: m_b 2 mu (x_ab . grad W) / (rho_ab^2 r^2) v_ab with x_ab . grad W = F r^2:
    // the r^2 cancels exactly (F is finite at r = 0 for both kernels), so no `eta`
    let visc = mb * 2.0 * c.mu * fk / (rho_ab * rho_ab);
    [
        coef * x[0] + visc * vv[0],
        coef * x[1] + visc * vv[1],
        coef * x[2] + visc * vv[2],
    ]
}

/// The Morris viscous factor of a pair and its displacement: `(x_ab, k)` with the pair's
/// viscous acceleration `k v_ab`, `k = m_b 2 mu F_ab / rho_ab^2` (see [`pair_accel`]);
/// `k = 0` outside the support.
#[inline(always)]
pub(crate) fn pair_visc(
    c: &PassCtx<'_>,
    pa: &Packed,
    pb: &Packed,
    support2: f64,
) -> ([f64; 3], f64) {
    let (x, r2) = separation(c, pa, pb);
    if r2 >= support2 {
        return (x, 0.0);
    }
    let fk = c.kernel.grad_factor(r2.sqrt());
    let rho_ab = 0.5 * (pa.rho() + pb.rho());
    (x, pb.mass() * 2.0 * c.mu * fk / (rho_ab * rho_ab))
}

/// The reference (scalar, one neighbour at a time) continuity pass, which the
/// specialized SIMD pass of [`pairs`](crate::pairs) must match: continuity (with density diffusion) and XSPH of every fluid particle into
/// `deriv[a].drho` and `deriv[a].xsph` (walls get zero). Wall markers enter the continuity
/// sum with their prescribed velocity and do not enter XSPH nor the diffusion (no
/// diffusive flux through walls). The diffusion reads the fluid pressures `p`, which must
/// be those of the current densities. `nb`: the records packed with
/// [`PackVelocity::Prescribed`].
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) fn continuity_pass(nb: &[Packed], c: &PassCtx<'_>, deriv: &mut [Deriv]) {
    let support2 = c.kernel.support() * c.kernel.support();
    deriv
        .par_iter_mut()
        .zip(nb.par_iter())
        .enumerate()
        .for_each(|(a, (out, pa))| {
            if !pa.fluid() {
                out.drho = 0.0;
                out.xsph = [0.0; 3];
                return;
            }
            let va = pa.vel();
            let mut sum = 0.0;
            let mut diff = 0.0;
            let mut xs = [0.0; 3];
            let (rho_a, p_a) = (pa.rho(), pa.p());
            for &b in c.list.neighbors(a) {
                let pb = &nb[b as usize];
                let (x, r2) = separation(c, pa, pb);
                if r2 >= support2 {
                    continue;
                }
                let (wk, fk) = c.kernel.w_and_grad_factor(r2.sqrt());
                let (vb, rho_b) = (pb.vel(), pb.rho());
                let vab = [va[0] - vb[0], va[1] - vb[1], va[2] - vb[2]];
                let mb = pb.mass();
                sum += mb / rho_b * fk * (vab[0] * x[0] + vab[1] * x[1] + vab[2] * x[2]);
                if pb.fluid() {
                    let k = c.xsph * mb * wk / (0.5 * (rho_a + rho_b));
                    xs[0] -= k * vab[0];
                    xs[1] -= k * vab[1];
                    xs[2] -= k * vab[2];
                    // delta-SPH: psi_ba (-F) V_b
                    let psi = match c.diffusion {
                        DensityDiffusion::None => 0.0,
                        DensityDiffusion::MolteniColagrossi => rho_b - rho_a,
                        DensityDiffusion::Fourtakas => {
                            // (p_b - p_a) minus its hydrostatic part -rho_ab g . x_ab
                            let g = c.gravity;
                            let rho_ab = 0.5 * (rho_a + rho_b);
                            (pb.p() - p_a + rho_ab * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]))
                                * c.inv_c2
                        }
                    };
                    diff -= mb / rho_b * psi * fk;
                }
            }
            out.drho = rho_a * sum + c.diffusion_coef * diff;
            out.xsph = xs;
        });
}

/// The reference force pass (see [`continuity_pass`]): accelerations of every fluid
/// particle into `deriv[a].acc` (walls get zero). `nb`: the
/// records packed with [`PackVelocity::NoSlip`].
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) fn force_pass(nb: &[Packed], c: &PassCtx<'_>, deriv: &mut [Deriv]) {
    let support2 = c.kernel.support() * c.kernel.support();
    deriv
        .par_iter_mut()
        .zip(nb.par_iter())
        .enumerate()
        .for_each(|(a, (out, pa))| {
            if !pa.fluid() {
                out.acc = [0.0; 3];
                return;
            }
            let mut acc = c.accel;
            for &b in c.list.neighbors(a) {
                let ab = pair_accel(c, pa, &nb[b as usize], support2);
                acc[0] += ab[0];
                acc[1] += ab[1];
                acc[2] += ab[2];
            }
            out.acc = acc;
        });
}

/// Shepard re-initialization of the fluid density,
/// `rho_a = sum_b m_b W_ab / sum_b (m_b / rho_b) W_ab` (self included, all neighbours),
/// through the scratch `out`.
pub(crate) fn shepard(d: &mut ParticleData, c: &PassCtx<'_>, out: &mut Vec<f64>) {
    out.resize(d.len(), 0.0);
    {
        let d = &*d;
        out.par_iter_mut().enumerate().for_each(|(a, o)| {
            // frozen particles keep their density bit for bit
            if d.kind[a] != FLUID || c.eval.is_some_and(|e| e[a] & ACT_NOW == 0) {
                *o = d.rho[a];
                return;
            }
            let w0 = c.kernel.w(0.0);
            let mut num = d.mass[a] * w0;
            let mut den = d.mass[a] / d.rho[a] * w0;
            let pa = [d.x[a], d.y[a], d.z[a]];
            for &b in c.list.neighbors(a) {
                let b = b as usize;
                let x = c.grid.displacement(pa, [d.x[b], d.y[b], d.z[b]]);
                let wk = c.kernel.w((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt());
                num += d.mass[b] * wk;
                den += d.mass[b] / d.rho[b] * wk;
            }
            *o = num / den;
        });
    }
    d.rho
        .par_iter_mut()
        .zip(out.par_iter())
        .for_each(|(r, &o)| *r = o);
}
