//! Tests of the particle shifting ([`crate::shifting`]).

use crate::data::FLUID;
use crate::{Shifting, SphBuilder, SphError, SphSettings, SphSystem};

const DP: f64 = 0.01;
const N: usize = 8;

/// A triply periodic box of `N^3` fluid particles, each moved off its lattice point by
/// up to `0.2 dp` per axis (a fixed pseudo-random sequence), all translating at `v`.
fn box_with(shifting: Option<Shifting>, v: f64) -> SphSystem {
    let l = N as f64 * DP;
    let s = SphSettings {
        spacing: DP,
        sound_speed: 1.0,
        gravity: [0.0; 3],
        viscosity: 1e-3,
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        shifting,
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(s).unwrap();
    b.add_fluid_box([0.0; 3], [l; 3], None).unwrap();
    let mut sys = b.build().unwrap();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let d = &mut sys.data;
    for i in 0..d.len() {
        d.x[i] += 0.4 * DP * next();
        d.y[i] += 0.4 * DP * next();
        d.z[i] += 0.4 * DP * next();
        d.vx[i] = v;
    }
    sys.initialize().unwrap();
    sys
}

/// Mean and standard deviation of the nearest-neighbour distance over the spacing.
fn nearest_neighbours(sys: &SphSystem) -> (f64, f64) {
    let d = sys.data();
    let l = N as f64 * DP;
    let (mut s, mut s2, mut n) = (0.0, 0.0, 0.0);
    for a in 0..d.len() {
        let mut best = f64::MAX;
        for b in 0..d.len() {
            if a == b {
                continue;
            }
            let mut r = [d.x[a] - d.x[b], d.y[a] - d.y[b], d.z[a] - d.z[b]];
            for x in &mut r {
                *x -= l * (*x / l).round();
            }
            best = best.min((r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt() / DP);
        }
        s += best;
        s2 += best * best;
        n += 1.0;
    }
    let m = s / n;
    (m, (s2 / n - m * m).max(0.0).sqrt())
}

fn centroid(sys: &SphSystem) -> [f64; 3] {
    let d = sys.data();
    let n = d.len() as f64;
    [
        d.x.iter().sum::<f64>() / n,
        d.y.iter().sum::<f64>() / n,
        d.z.iter().sum::<f64>() / n,
    ]
}

#[test]
fn shifting_restores_the_particle_order_of_a_translating_fluid() {
    let (m0, s0) = nearest_neighbours(&box_with(None, 0.2));
    let mut plain = box_with(None, 0.2);
    let mut shifted = box_with(
        Some(Shifting {
            coefficient: 2.0,
            ..Shifting::default()
        }),
        0.2,
    );
    for _ in 0..300 {
        plain.step().unwrap();
        shifted.step().unwrap();
    }
    assert_eq!(
        plain.time(),
        shifted.time(),
        "same steps: shifting leaves dt alone"
    );
    let (mp, sp) = nearest_neighbours(&plain);
    let (ms, ss) = nearest_neighbours(&shifted);
    // a lattice has std 0 and mean 1; the start is disordered
    assert!(s0 > 0.05, "start: mean {m0}, std {s0}");
    assert!(
        ss < 0.5 * sp && ms > mp,
        "shifting should order the fluid: plain mean {mp} std {sp}, shifted mean {ms} std {ss}"
    );
}

#[test]
fn shifting_needs_motion_and_keeps_the_centroid() {
    // D = A h |v| dt: a fluid at rest is not shifted
    let mut still = box_with(
        Some(Shifting {
            coefficient: 2.0,
            ..Shifting::default()
        }),
        0.0,
    );
    let mut plain = box_with(None, 0.0);
    for _ in 0..20 {
        still.step().unwrap();
        plain.step().unwrap();
    }
    assert_eq!(still.data().x, plain.data().x);
    assert_eq!(still.data().z, plain.data().z);
    // the shifts of a uniformly moving fluid cancel pairwise (grad_a W_ab = -grad_b W_ba):
    // only the translation moves the centroid (no particle wrapped here: v t < the box)
    let mut a = box_with(
        Some(Shifting {
            coefficient: 2.0,
            ..Shifting::default()
        }),
        0.05,
    );
    let mut b = box_with(None, 0.05);
    for _ in 0..20 {
        a.step().unwrap();
        b.step().unwrap();
    }
    let (ca, cb) = (centroid(&a), centroid(&b));
    for k in 0..3 {
        assert!(
            (ca[k] - cb[k]).abs() < 1e-4 * DP,
            "axis {k}: centroid {} vs {}",
            ca[k],
            cb[k]
        );
    }
    let moved = (0..a.data().len())
        .filter(|&i| a.data().kind[i] == FLUID && a.data().x[i] != b.data().x[i])
        .count();
    assert!(moved > 0, "no particle shifted");
}

#[test]
fn a_bad_shifting_coefficient_is_named() {
    for c in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let s = SphSettings {
            shifting: Some(Shifting {
                coefficient: c,
                ..Shifting::default()
            }),
            ..SphSettings::default()
        };
        match SphBuilder::new(s) {
            Err(SphError::InvalidParameter { field, .. }) => {
                assert_eq!(field, "settings.shifting.coefficient")
            }
            other => panic!("coefficient {c}: {other:?}"),
        }
    }
    assert_eq!(SphSettings::default().shifting, None);
}

/// The disordered box of [`box_with`] in a periodic shear flow `v_x = v sin(2 pi (z -
/// dp / 2) / l)`: the particles of the layers at `z = dp / 2` and `l / 2 + dp / 2` hardly
/// move (below `0.16 v`: their jitter).
fn sheared_box(shifting: Option<Shifting>, v: f64) -> SphSystem {
    let mut sys = box_with(shifting, 0.0);
    let l = N as f64 * DP;
    let d = &mut sys.data;
    for i in 0..d.len() {
        d.vx[i] = v * (2.0 * std::f64::consts::PI * (d.z[i] - 0.5 * DP) / l).sin();
    }
    sys.initialize().unwrap();
    sys
}

/// Per particle: its speed at the start and the length of its shift over one step (the
/// shifted run's position against the plain run's; both runs take the same step).
fn one_step_shifts(shifting: Shifting) -> Vec<(f64, f64)> {
    let mut a = sheared_box(Some(shifting), 0.2);
    let mut b = sheared_box(None, 0.2);
    let speed: Vec<f64> = a.data().vx.iter().map(|v| v.abs()).collect();
    a.step().unwrap();
    b.step().unwrap();
    assert_eq!(a.time(), b.time());
    let (da, db) = (a.data(), b.data());
    (0..da.len())
        .map(|i| {
            let r = [da.x[i] - db.x[i], da.y[i] - db.y[i], da.z[i] - db.z[i]];
            (speed[i], (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt())
        })
        .collect()
}

#[test]
fn the_delta_plus_form_shifts_slow_particles_in_a_moving_fluid() {
    // mean shift of the slow (|v| < 0.2 U) and of the fast (|v| > 0.9 U) particles
    let means = |s: &[(f64, f64)]| {
        let pick = |slow: bool| {
            let v: Vec<f64> = s
                .iter()
                .filter(|(u, _)| if slow { *u < 0.04 } else { *u > 0.18 })
                .map(|(_, r)| *r)
                .collect();
            assert!(v.len() > 10, "too few particles in the class");
            v.iter().sum::<f64>() / v.len() as f64
        };
        (pick(true), pick(false))
    };
    let (slow_l, fast_l) = means(&one_step_shifts(Shifting {
        coefficient: 4.0,
        ..Shifting::default()
    }));
    let (slow_d, fast_d) = means(&one_step_shifts(Shifting::delta_plus()));
    // Skillen's form scales each shift by the particle's own speed, Sun's by the flow's
    assert!(
        slow_l < 0.25 * fast_l,
        "local speed: slow {slow_l:e} m against fast {fast_l:e} m"
    );
    assert!(
        slow_d > 0.5 * fast_d && fast_d > 0.0,
        "delta plus: slow {slow_d:e} m against fast {fast_d:e} m"
    );
    // both are diffusions of the same size where the particle moves at U_max, but the
    // anti-clumping weight adds to the delta-plus shift
    assert!(fast_d > fast_l, "fast: {fast_d:e} vs {fast_l:e}");
}

#[test]
fn delta_plus_shifting_orders_the_fluid_and_leaves_a_fluid_at_rest() {
    let mut plain = sheared_box(None, 0.2);
    let mut shifted = sheared_box(Some(Shifting::delta_plus()), 0.2);
    for _ in 0..300 {
        plain.step().unwrap();
        shifted.step().unwrap();
    }
    let (mp, sp) = nearest_neighbours(&plain);
    let (ms, ss) = nearest_neighbours(&shifted);
    assert!(
        ss < 0.5 * sp && ms > mp,
        "plain mean {mp} std {sp}, shifted mean {ms} std {ss}"
    );
    // U_max = 0: no shift at all
    let mut still = box_with(Some(Shifting::delta_plus()), 0.0);
    let mut rest = box_with(None, 0.0);
    for _ in 0..20 {
        still.step().unwrap();
        rest.step().unwrap();
    }
    assert_eq!(still.data().x, rest.data().x);
    assert_eq!(still.data().y, rest.data().y);
}

#[test]
fn delta_plus_shifting_gives_the_same_bits_on_any_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut s = sheared_box(Some(Shifting::delta_plus()), 0.2);
            for _ in 0..30 {
                s.step().unwrap();
            }
            (s.data().x.clone(), s.data().z.clone(), s.data().vx.clone())
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}
