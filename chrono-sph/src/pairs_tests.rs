//! Tests of the specialized pair passes against the reference arithmetic of `interact`.

use chrono_core::particles::{CellGrid, GridConfig, Kernel, KernelKind, NeighborList};
use proptest::prelude::*;

use super::*;
use crate::eos::Tait;
use crate::interact;
use crate::settings::NoSlip;

/// A random cloud: `(records, grid, list)` with `h = 1`, particles in a `[0, 4]^3`
/// box (two-thirds fluid), list radius `2.2 h` (a skin as in the solver).
struct Cloud {
    nb: Vec<Packed>,
    grid: CellGrid,
    periodic: bool,
    list: NeighborList,
}

fn cloud(seed: u64, n: usize, periodic: bool) -> Cloud {
    // a small LCG: the proptest picks the seed
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let l = 4.5;
    let mut nb = Vec::with_capacity(n);
    let (mut xs, mut ys, mut zs) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let pos = [l * next(), l * next(), l * next()];
        let rho = 1000.0 * (1.0 + 0.02 * (next() - 0.5));
        let p = 2e4 * (next() - 0.3);
        let mass = 1.0 + 0.1 * next();
        let fluid = next() < 0.67;
        let vel = [next() - 0.5, next() - 0.5, next() - 0.5];
        nb.push(Packed::new(pos, vel, rho, p, mass, fluid));
        xs.push(pos[0]);
        ys.push(pos[1]);
        zs.push(pos[2]);
    }
    let radius = 2.2;
    let config =
        GridConfig::bounded(radius, [0.0; 3], [l; 3]).with_periodic([periodic, false, periodic]);
    let mut grid = CellGrid::new(config).unwrap();
    grid.build([&xs, &ys, &zs]).unwrap();
    let mut list = NeighborList::new();
    grid.neighbor_list([&xs, &ys, &zs], radius, &mut list)
        .unwrap();
    Cloud {
        nb,
        grid,
        periodic,
        list,
    }
}

fn ctx<'a>(
    cl: &'a Cloud,
    kernel: &'a Kernel,
    eos: &'a Tait,
    diffusion: DensityDiffusion,
    alpha: f64,
) -> PassCtx<'a> {
    PassCtx {
        kernel,
        eos,
        grid: &cl.grid,
        periodic: cl.periodic,
        list: &cl.list,
        mu: 1e-3,
        alpha,
        xsph: 0.5,
        accel: [0.1, -0.2, -9.81],
        gravity: [0.0, 0.0, -9.81],
        wall_acc: [0.0; 3],
        wall_vel: [0.0; 3],
        clamp_wall_pressure: true,
        wall_volume: 1e-3,
        diffusion,
        diffusion_coef: 2.0 * 0.1 * kernel.h() * eos.sound_speed,
        inv_c2: 1.0 / (eos.sound_speed * eos.sound_speed),
        no_slip: NoSlip::Linear,
        eval: None,
        shift: 0,
        inv_w_dp: 1.0 / kernel.w(0.01),
        belts: &[],
        carrier_omega: &[],
    }
}

/// The fields a pass writes, flattened: `[acc x3, drho, xsph x3]` per particle.
fn flat(d: &[Deriv]) -> Vec<f64> {
    d.iter()
        .flat_map(|v| {
            [
                v.acc[0], v.acc[1], v.acc[2], v.drho, v.xsph[0], v.xsph[1], v.xsph[2],
            ]
        })
        .collect()
}

/// Both passes, by the reference and by the specialized path (`simd`).
fn both(c: &PassCtx<'_>, nb: &[Packed], simd: bool) -> (Vec<f64>, Vec<f64>) {
    let mut r = vec![Deriv::default(); nb.len()];
    interact::continuity_pass(nb, c, &mut r);
    interact::force_pass(nb, c, &mut r);
    let mut f = vec![Deriv::default(); nb.len()];
    let mut sup = Support::default();
    continuity_pass(nb, c, &mut f, &mut sup, simd);
    // the kept sequences hold every in-support entry (and padding only)
    assert!(sup.total() >= in_support(c, nb));
    force_pass(nb, c, &mut f, &mut [], &mut sup, simd);
    (flat(&r), flat(&f))
}

/// Directed list entries within the support of fluid particles.
fn in_support(c: &PassCtx<'_>, nb: &[Packed]) -> usize {
    let s2 = c.kernel.support() * c.kernel.support();
    (0..nb.len())
        .filter(|&a| nb[a].fluid())
        .map(|a| {
            c.list
                .neighbors(a)
                .iter()
                .filter(|&&b| {
                    let d = c.grid.displacement(nb[a].pos(), nb[b as usize].pos());
                    d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < s2
                })
                .count()
        })
        .sum()
}

fn diffusion(k: u8) -> DensityDiffusion {
    match k {
        0 => DensityDiffusion::None,
        1 => DensityDiffusion::MolteniColagrossi,
        _ => DensityDiffusion::Fourtakas,
    }
}

/// The shifting's concentration gradient of each fluid particle by a plain loop over the
/// list (`grad C_a = sum_b V_b (1 + f_ab) F_ab x_ab`, [`crate::shifting`]), the reference
/// of the force pass's sums.
fn reference_gradients(c: &PassCtx<'_>, nb: &[Packed], delta_plus: bool) -> Vec<[f64; 3]> {
    let s2 = c.kernel.support() * c.kernel.support();
    (0..nb.len())
        .map(|a| {
            let mut g = [0.0; 3];
            if !nb[a].fluid() {
                return g;
            }
            for &b in c.list.neighbors(a) {
                let x = c.grid.displacement(nb[a].pos(), nb[b as usize].pos());
                let r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
                if r2 >= s2 {
                    continue;
                }
                let r = r2.sqrt();
                let mut f = nb[b as usize].pr2_m_vol_fl[2] * c.kernel.grad_factor(r);
                if delta_plus {
                    let q = c.kernel.w(r) * c.inv_w_dp;
                    f *= 1.0 + crate::shifting::CLUMP_R * (q * q) * (q * q);
                }
                for k in 0..3 {
                    g[k] += f * x[k];
                }
            }
            g
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// One lane without FMA (the baseline x86-64 path) is the reference arithmetic:
    /// bit for bit.
    #[test]
    fn one_lane_path_is_the_reference_bit_for_bit(
        seed in any::<u64>(), n in 2usize..400, cubic in any::<bool>(),
        diff in 0u8..3, av in any::<bool>(), periodic in any::<bool>(),
    ) {
        let cl = cloud(seed, n, periodic);
        let kind = if cubic { KernelKind::CubicSpline } else { KernelKind::WendlandC2 };
        let kernel = Kernel::new(kind, 1.0, 3).unwrap();
        let eos = Tait::new(1000.0, 7.0, 20.0).unwrap();
        let c = ctx(&cl, &kernel, &eos, diffusion(diff), if av { 0.02 } else { 0.0 });
        let (r, f) = both(&c, &cl.nb, false);
        for (i, (a, b)) in r.iter().zip(&f).enumerate() {
            prop_assert!(a.to_bits() == b.to_bits() || (*a == 0.0 && *b == 0.0),
                "entry {i}: reference {a:e}, one lane {b:e}");
        }
    }

    /// The dispatched path (AVX2 + FMA where present: 4 per-lane partial sums, fused
    /// products) matches the reference to rounding: each quantity within `1e-12` of
    /// the largest magnitude of that quantity over the cloud (a few hundred terms of
    /// relative rounding 1.1e-16 each, with cancellation between them).
    #[test]
    fn simd_path_matches_the_reference_to_rounding(
        seed in any::<u64>(), n in 2usize..400, cubic in any::<bool>(),
        diff in 0u8..3, av in any::<bool>(), periodic in any::<bool>(),
    ) {
        let cl = cloud(seed, n, periodic);
        let kind = if cubic { KernelKind::CubicSpline } else { KernelKind::WendlandC2 };
        let kernel = Kernel::new(kind, 1.0, 3).unwrap();
        let eos = Tait::new(1000.0, 7.0, 20.0).unwrap();
        let c = ctx(&cl, &kernel, &eos, diffusion(diff), if av { 0.02 } else { 0.0 });
        let (r, f) = both(&c, &cl.nb, true);
        let mut scale = [0.0f64; 7];
        for (i, a) in r.iter().enumerate() {
            scale[i % 7] = scale[i % 7].max(a.abs());
        }
        for (i, (a, b)) in r.iter().zip(&f).enumerate() {
            let tol = 1e-12 * scale[i % 7];
            prop_assert!((a - b).abs() <= tol,
                "entry {i}: reference {a:e}, simd {b:e}, tolerance {tol:e}");
        }
    }

    /// The shifting's concentration gradients summed in the force pass (both forms, both
    /// paths) match a plain loop to rounding, and leave the accelerations bit for bit.
    #[test]
    fn force_pass_sums_the_shifting_gradient(
        seed in any::<u64>(), n in 2usize..400, cubic in any::<bool>(),
        delta_plus in any::<bool>(), simd in any::<bool>(), periodic in any::<bool>(),
    ) {
        let cl = cloud(seed, n, periodic);
        let kind = if cubic { KernelKind::CubicSpline } else { KernelKind::WendlandC2 };
        let kernel = Kernel::new(kind, 1.0, 3).unwrap();
        let eos = Tait::new(1000.0, 7.0, 20.0).unwrap();
        let mut c = ctx(&cl, &kernel, &eos, DensityDiffusion::None, 0.0);
        let (_, plain) = both(&c, &cl.nb, simd);
        c.shift = if delta_plus { 2 } else { 1 };
        let mut f = vec![Deriv::default(); cl.nb.len()];
        let mut g = vec![[f64::NAN; 3]; cl.nb.len()];
        let mut sup = Support::default();
        continuity_pass(&cl.nb, &c, &mut f, &mut sup, simd);
        force_pass(&cl.nb, &c, &mut f, &mut g, &mut sup, simd);
        let shifted = flat(&f);
        for (i, (a, b)) in plain.iter().zip(&shifted).enumerate() {
            prop_assert!(a.to_bits() == b.to_bits(), "entry {i}: {a:e} without, {b:e} with");
        }
        let r = reference_gradients(&c, &cl.nb, delta_plus);
        let scale = r.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, (ra, ga)) in r.iter().zip(&g).enumerate() {
            for k in 0..3 {
                prop_assert!((ra[k] - ga[k]).abs() <= 1e-12 * scale,
                    "particle {a} axis {k}: reference {:e}, pass {:e}", ra[k], ga[k]);
            }
        }
    }
}
