//! Unit tests of the density diffusion, the no-slip extrapolation and the lattice
//! stability at the default smoothing length (small lattices, one evaluation each).

use crate::data::{FLUID, WALL};
use crate::{DensityDiffusion, NoSlip, SphBuilder, SphSettings, SphSystem};

/// A still-water tank, `n` particles deep, `[walls x, walls z, lid]` as asked, slab
/// periodic in y, started from the builder's hydrostatic density.
fn tank(settings: SphSettings, n: usize, side_walls: bool) -> SphSystem {
    let dp = settings.spacing;
    let h = n as f64 * dp;
    let ly = 7.0 * dp;
    let top = h + 3.0 * dp;
    let settings = SphSettings {
        sound_speed: 10.0 * (2.0 * -chrono_core::math::GRAVITY.z * h).sqrt(),
        domain_lower: [0.0; 3],
        domain_upper: [h, ly, top],
        periodic: [!side_walls, true, false],
        ..settings
    };
    let mut b = SphBuilder::new(settings).unwrap();
    b.add_fluid_box([0.0; 3], [h, ly, h], Some(h)).unwrap();
    b.add_tank(
        [0.0; 3],
        [h, ly, top],
        3,
        [side_walls, side_walls, false, false, true, false],
        0,
    )
    .unwrap();
    b.build().unwrap()
}

fn settings(diffusion: DensityDiffusion) -> SphSettings {
    SphSettings {
        spacing: 0.04,
        density_diffusion: diffusion,
        ..SphSettings::default()
    }
}

/// `(max |d rho/dt|, sum_a V_a d rho_a/dt, sum_a |V_a d rho_a/dt|)` over the fluid.
fn rates(sys: &SphSystem) -> (f64, f64, f64) {
    let d = sys.data();
    let (mut m, mut s, mut sa) = (0.0f64, 0.0, 0.0);
    for i in 0..d.len() {
        if d.kind[i] == FLUID {
            let r = d.deriv[i].drho;
            let v = d.mass[i] / d.rho[i];
            m = m.max(r.abs());
            s += v * r;
            sa += (v * r).abs();
        }
    }
    (m, s, sa)
}

#[test]
fn hydrostatic_diffusion_leaves_a_fluid_at_rest_unchanged() {
    // v = 0: continuity gives 0, so d rho/dt is the diffusion alone
    let mut fourtakas = tank(settings(DensityDiffusion::Fourtakas), 10, true);
    fourtakas.initialize().unwrap();
    let mut plain = tank(settings(DensityDiffusion::MolteniColagrossi), 10, true);
    plain.initialize().unwrap();
    let (m_f, _, _) = rates(&fourtakas);
    let (m_p, s_p, sa_p) = rates(&plain);
    // the plain form diffuses the hydrostatic gradient (kg/m^3/s of order
    // delta c_s (d rho/dz) ~ 0.1 * 28 * 1 = 3); the corrected one only the trapezoidal
    // error of its hydrostatic step, ~1e-6 of it (with rho_0 instead of rho_ab in the
    // correction the residual would be ~5e-3 of it)
    assert!(
        m_p > 0.1,
        "Molteni-Colagrossi flux on the hydrostatic lattice: {m_p}"
    );
    assert!(
        m_f < 1e-5 * m_p,
        "hydrostatic form leaves a flux {m_f} (plain {m_p})"
    );
    // the plain form is conservative: it moves density, it does not create it
    assert!(s_p.abs() < 1e-12 * sa_p, "{s_p} vs {sa_p}");
    // and smooths: the top layer (lighter than the fluid below) gains density
    let d = plain.data();
    let zmax = (0..d.len())
        .filter(|&i| d.kind[i] == FLUID)
        .map(|i| d.z[i])
        .fold(f64::MIN, f64::max);
    for i in 0..d.len() {
        if d.kind[i] == FLUID && d.z[i] > zmax - 1e-9 {
            assert!(
                d.deriv[i].drho > 0.0,
                "top particle {i}: {}",
                d.deriv[i].drho
            );
        }
    }
    // with the diffusion off, d rho/dt is exactly 0 at rest
    let mut none = tank(settings(DensityDiffusion::None), 10, true);
    none.initialize().unwrap();
    assert_eq!(rates(&none).0, 0.0);
}

#[test]
fn linear_no_slip_extrapolates_a_shear_flow_through_the_wall_surface() {
    // periodic channel with walls at z = 0 and z = L, velocity v_x = S z imposed
    let dp = 0.1;
    let l = 1.0;
    let per = 7.0 * dp;
    let make = |no_slip| {
        let s = SphSettings {
            spacing: dp,
            sound_speed: 1.0,
            gravity: [0.0; 3],
            no_slip,
            domain_lower: [0.0; 3],
            domain_upper: [per, per, l],
            periodic: [true, true, false],
            ..SphSettings::default()
        };
        let mut b = SphBuilder::new(s).unwrap();
        b.add_fluid_box([0.0; 3], [per, per, l], None).unwrap();
        b.add_tank(
            [0.0; 3],
            [per, per, l],
            3,
            [false, false, false, false, true, true],
            0,
        )
        .unwrap();
        let mut sys = b.build().unwrap();
        sys.initialize().unwrap();
        for i in 0..sys.data.len() {
            if sys.data.kind[i] == FLUID {
                sys.data.vx[i] = 2.0 * sys.data.z[i];
            }
        }
        sys.density_update(0.0);
        sys
    };
    let lin = make(NoSlip::Linear);
    let adami = make(NoSlip::Adami);
    let (mut worst_lin, mut worst_adami) = (0.0f64, 0.0f64);
    for (sys, worst) in [(&lin, &mut worst_lin), (&adami, &mut worst_adami)] {
        let d = &sys.data;
        for i in 0..d.len() {
            // lower-wall markers that see fluid: the exact mirror is v = S z = 2 z
            if d.kind[i] == WALL && d.z[i] < 0.0 && d.z[i] > -2.0 * dp {
                let exact = 2.0 * d.z[i];
                *worst = worst.max((d.wall_v[i][0] - exact).abs() / exact.abs());
            }
        }
    }
    assert!(worst_lin < 1e-9, "linear extrapolation error {worst_lin}");
    assert!(
        worst_adami > 0.3,
        "Adami's mirror should miss deep layers: {worst_adami}"
    );
}

#[test]
fn cubic_lattice_resists_column_sliding_at_the_default_smoothing_length() {
    // Shift one fluid column down by 0.02 dp under hydrostatic pressure: the change of its
    // vertical acceleration must be restoring (upward). With Wendland C2 at h = 1.3 dp it
    // is not, and still water develops convection cells (docs/validation-sph.md).
    let column_response = |h_over_dp: f64| {
        let s = SphSettings {
            h_over_dp,
            ..settings(DensityDiffusion::Fourtakas)
        };
        let dp = s.spacing;
        let mut base = tank(s.clone(), 10, false);
        base.initialize().unwrap();
        let mut shifted = tank(s, 10, false);
        for i in 0..shifted.data.len() {
            if shifted.data.kind[i] == FLUID && shifted.data.x[i] < dp {
                shifted.data.z[i] -= 0.02 * dp;
            }
        }
        shifted.initialize().unwrap();
        let acc = |sys: &SphSystem| {
            let d = &sys.data;
            let (mut a, mut n) = (0.0, 0.0);
            for i in 0..d.len() {
                let z = d.z[i] + if d.x[i] < dp { 0.02 * dp } else { 0.0 };
                if d.kind[i] == FLUID && d.x[i] < dp && z > 0.12 && z < 0.28 {
                    a += d.deriv[i].acc[2];
                    n += 1.0;
                }
            }
            a / n
        };
        acc(&shifted) - acc(&base)
    };
    let default = column_response(SphSettings::default().h_over_dp);
    assert!(default > 0.0, "anti-restoring column force {default} m/s^2");
    assert!(
        column_response(1.3) < 0.0,
        "h = 1.3 dp is expected anti-restoring"
    );
}

/// Positions, velocities and densities by particle id after `steps` steps of a small
/// dam break (list rebuilds and re-sorts included) on a pool of `threads` threads.
fn dam_break_state(threads: usize, steps: usize) -> Vec<u64> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let dp = 0.05;
        let s = SphSettings {
            spacing: dp,
            sound_speed: 20.0,
            domain_lower: [0.0; 3],
            domain_upper: [0.6, 7.0 * dp, 0.6],
            periodic: [false, true, false],
            ..SphSettings::default()
        };
        let mut b = SphBuilder::new(s).unwrap();
        b.add_fluid_box([0.0; 3], [0.3, 7.0 * dp, 0.4], Some(0.4))
            .unwrap();
        b.add_tank(
            [0.0; 3],
            [0.6, 7.0 * dp, 0.6],
            3,
            [true, true, false, false, true, false],
            0,
        )
        .unwrap();
        let mut sys = b.build().unwrap();
        for _ in 0..steps {
            sys.step().unwrap();
        }
        assert!(sys.stats().list_builds > 3, "the window must rebuild lists");
        let d = sys.data();
        let mut out = vec![0u64; 7 * d.len()];
        for i in 0..d.len() {
            let id = d.id[i] as usize;
            for (k, v) in [d.x[i], d.y[i], d.z[i], d.vx[i], d.vy[i], d.vz[i], d.rho[i]]
                .into_iter()
                .enumerate()
            {
                out[7 * id + k] = v.to_bits();
            }
        }
        out
    })
}

#[test]
fn steps_are_bit_reproducible_and_independent_of_the_thread_count() {
    // the pair passes reduce per particle in a fixed order and the list is built in
    // a fixed order: same bits on 1, 2 and 3 threads, and run to run
    let one = dam_break_state(1, 150);
    assert_eq!(one, dam_break_state(1, 150), "1 thread, run to run");
    assert_eq!(one, dam_break_state(2, 150), "1 vs 2 threads");
    assert_eq!(one, dam_break_state(3, 150), "1 vs 3 threads");
}

/// A rigid carrier at rest is a fixed wall: the same markers added as a carrier (centre
/// at the origin, so their positions are the same bits) or as a wall box give the same
/// fluid, bit for bit; the carrier's load is the probe's wall force; `advance_exactly`
/// ends on its time and refuses one in the past.
#[test]
fn carrier_at_rest_is_a_fixed_wall() {
    use crate::RigidMotion;
    use chrono_core::math::{UnitQuaternion, Vector3};
    let build = |carried: bool| {
        let dp = 0.04;
        let h = 8.0 * dp;
        let ly = 7.0 * dp;
        let settings = SphSettings {
            spacing: dp,
            sound_speed: 10.0 * (2.0 * 9.81 * h).sqrt(),
            domain_lower: [0.0; 3],
            domain_upper: [2.0 * h, ly, 2.0 * h],
            periodic: [false, true, false],
            ..SphSettings::default()
        };
        let mut b = SphBuilder::new(settings).unwrap();
        b.add_fluid_box([0.0; 3], [h, ly, h], Some(h)).unwrap();
        b.add_tank(
            [0.0; 3],
            [2.0 * h, ly, 2.0 * h],
            3,
            [true, true, false, false, true, false],
            0,
        )
        .unwrap();
        // an obstacle block on the floor, right of the water column
        let (lo, hi) = ([1.25 * h, 0.0, 0.0], [1.5 * h, ly, 0.25 * h]);
        if carried {
            use chrono_core::particles::lattice::{Fit, Lattice};
            let pts = Lattice::new(lo, dp)
                .unwrap()
                .fill(lo, hi, Fit::Floor)
                .unwrap();
            let rest = RigidMotion::at_rest(Vector3::zeros(), UnitQuaternion::identity());
            b.add_rigid_markers(rest, &pts, 9).unwrap();
        } else {
            b.add_wall_box(lo, hi, 9).unwrap();
        }
        b.build().unwrap()
    };
    let (mut a, mut b) = (build(false), build(true));
    assert_eq!(a.len(), b.len());
    for _ in 0..60 {
        a.step().unwrap();
        b.step().unwrap();
    }
    let (da, db) = (a.data(), b.data());
    let key = |d: &crate::ParticleData, i: usize| {
        (
            d.id[i],
            d.x[i].to_bits(),
            d.z[i].to_bits(),
            d.vx[i].to_bits(),
        )
    };
    let mut ka: Vec<_> = (0..da.len())
        .filter(|&i| da.kind[i] == FLUID)
        .map(|i| key(da, i))
        .collect();
    let mut kb: Vec<_> = (0..db.len())
        .filter(|&i| db.kind[i] == FLUID)
        .map(|i| key(db, i))
        .collect();
    ka.sort_unstable();
    kb.sort_unstable();
    assert_eq!(ka, kb, "the carried block changed the fluid");
    // the water reached the block and pushes it
    let load = b.carrier_load(0)[0];
    let probe = b.wall_force(9);
    assert!(load.x > 1e-3, "no load on the block: {load}");
    assert!(
        (load - probe).norm() <= 1e-12 * load.norm(),
        "{load} vs {probe}"
    );
    // exact end time, and no way back
    let t_end = b.time() + 1.234e-3;
    let n = b.advance_exactly(t_end).unwrap();
    assert!(n >= 1);
    assert_eq!(b.time(), t_end);
    assert!(b.advance_exactly(t_end - 1e-3).is_err());
}

/// A rank whose particle turns non-finite stops with the particle named; the other
/// ranks stop at the same step with an error naming that rank (no hang).
#[test]
fn a_failing_rank_is_named_by_the_others() {
    use crate::distributed::{DistributedSettings, LocalTransport, Transport};
    let build = || {
        let tank =
            chrono_core::particles::lattice::SlabTank::dam_break(0.02, 1.3, [0.4, 0.2], 0.8, 0.25);
        let settings = SphSettings {
            sound_speed: 20.0,
            ..SphSettings::default()
        };
        crate::scene::slab_tank(settings, &tank).unwrap()
    };
    let errors: Vec<String> = std::thread::scope(|s| {
        let hs: Vec<_> = LocalTransport::ranks(2)
            .into_iter()
            .map(|mut t| {
                s.spawn(move || {
                    let mut sys = build();
                    sys.distribute(t.rank(), t.size(), DistributedSettings::default())
                        .unwrap();
                    for k in 0..20 {
                        if k == 5 && t.rank() == 0 {
                            // the owned fluid particle farthest from the cuts: its NaN
                            // reaches no other rank within the step
                            let cuts = sys.slabs().unwrap().cuts.clone();
                            let gap = |x: f64| {
                                cuts.iter()
                                    .map(|c| (x - c).abs())
                                    .fold(f64::INFINITY, f64::min)
                            };
                            let i = (0..sys.data.len())
                                .filter(|&i| sys.data.kind[i] == FLUID && sys.is_owned(i))
                                .max_by(|&a, &b| gap(sys.data.x[a]).total_cmp(&gap(sys.data.x[b])))
                                .unwrap();
                            assert!(
                                gap(sys.data.x[i]) > 3.0 * sys.kernel.support(),
                                "slab too thin for the test: {} m from a cut, cuts {cuts:?}",
                                gap(sys.data.x[i])
                            );
                            sys.data.vx[i] = f64::NAN;
                        }
                        if let Err(e) = sys.step_on(&mut t) {
                            return format!("step {k}: {e}");
                        }
                    }
                    "finished".to_string()
                })
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert!(errors[0].starts_with("step 5: non-finite"), "{errors:?}");
    assert!(errors[1].starts_with("step 5: rank 0:"), "{errors:?}");
}

/// `set_fluid_velocity` sets every fluid particle from the field and no wall marker; a
/// field that is not finite somewhere is an error naming the particle.
#[test]
fn fluid_velocity_field_sets_the_fluid_only() {
    let mut sys = tank(settings(DensityDiffusion::default()), 6, true);
    sys.set_fluid_velocity(|x| [x[2], 0.0, -x[0]]).unwrap();
    let d = sys.data();
    let mut n = 0;
    for i in 0..d.len() {
        if d.kind[i] == FLUID {
            assert_eq!((d.vx[i], d.vy[i], d.vz[i]), (d.z[i], 0.0, -d.x[i]));
            n += 1;
        } else {
            assert_eq!((d.vx[i], d.vy[i], d.vz[i]), (0.0, 0.0, 0.0));
        }
    }
    assert_eq!(n, sys.num_fluid());
    let e = sys
        .set_fluid_velocity(|x| [if x[2] > 0.1 { f64::NAN } else { 0.0 }, 0.0, 0.0])
        .unwrap_err()
        .to_string();
    assert!(e.contains("fluid velocity of particle"), "{e}");
}
