//! Tests of the active domain ([`crate::system::active`]).

use chrono_core::math::{UnitQuaternion, Vector3};
use chrono_core::particles::lattice::{Fit, Lattice};

use crate::data::FLUID;
use crate::{ActiveDomain, RigidMotion, SphBuilder, SphSettings, SphSystem};

const DP: f64 = 0.04;
const LEN: f64 = 40.0 * DP;
const LY: f64 = 7.0 * DP;
const DEPTH: f64 = 8.0 * DP;
/// The block's half extents (x, z) and its start centre.
const HALF: [f64; 2] = [2.0 * DP, 1.5 * DP];
const C0: [f64; 3] = [0.4, 0.5 * LY, 0.5 * DEPTH];
const SPEED: f64 = 0.4;

/// A long slab tank of still water with a submerged block of markers (a rigid carrier)
/// towed along x at `SPEED`; `active`: the active domain.
fn towed_block(active: Option<ActiveDomain>) -> SphSystem {
    let settings = SphSettings {
        spacing: DP,
        sound_speed: 10.0 * (9.81 * DEPTH).sqrt(),
        domain_lower: [0.0; 3],
        domain_upper: [LEN, LY, 1.5 * DEPTH],
        periodic: [false, true, false],
        active_domain: active,
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(settings).unwrap();
    let inside = |p: &[f64; 3]| {
        (p[0] - C0[0]).abs() <= HALF[0] + 0.5 * DP && (p[2] - C0[2]).abs() <= HALF[1] + 0.5 * DP
    };
    let fluid: Vec<[f64; 3]> = Lattice::new([0.0; 3], DP)
        .unwrap()
        .fill([0.0; 3], [LEN, LY, DEPTH], Fit::Floor)
        .unwrap()
        .into_iter()
        .filter(|p| !inside(p))
        .collect();
    b.add_fluid_points(&fluid, Some(DEPTH));
    b.add_tank(
        [0.0; 3],
        [LEN, LY, 1.5 * DEPTH],
        3,
        [true, true, false, false, true, false],
        0,
    )
    .unwrap();
    // markers on the lattice of the fluid inside the block, as body-frame offsets
    let lo = [C0[0] - HALF[0], 0.0, C0[2] - HALF[1]];
    let hi = [C0[0] + HALF[0], LY, C0[2] + HALF[1]];
    let local: Vec<[f64; 3]> = Lattice::new(lo, DP)
        .unwrap()
        .fill(lo, hi, Fit::Floor)
        .unwrap()
        .into_iter()
        .map(|p| [p[0] - C0[0], p[1] - C0[1], p[2] - C0[2]])
        .collect();
    let c = Vector3::new(C0[0], C0[1], C0[2]);
    let motion = RigidMotion {
        velocity: Vector3::new(SPEED, 0.0, 0.0),
        ..RigidMotion::at_rest(c, UnitQuaternion::identity())
    };
    b.add_rigid_markers(motion, &local, 9).unwrap();
    b.build().unwrap()
}

/// Positions, velocities and densities of every particle by id (bits).
fn state(sys: &SphSystem) -> Vec<[u64; 7]> {
    let d = sys.data();
    let mut out = vec![[0u64; 7]; d.len()];
    for i in 0..d.len() {
        out[d.id[i] as usize] =
            [d.x[i], d.y[i], d.z[i], d.vx[i], d.vy[i], d.vz[i], d.rho[i]].map(f64::to_bits);
    }
    out
}

fn radius(supports: f64) -> ActiveDomain {
    let s = SphSettings {
        spacing: DP,
        ..SphSettings::default()
    };
    ActiveDomain::from_supports(&s, supports)
}

#[test]
fn active_domain_covering_the_tank_gives_the_full_run_bit_for_bit() {
    let mut full = towed_block(None);
    // every particle within the radius at every step: every mask passes
    let mut act = towed_block(Some(ActiveDomain {
        radius: 10.0 * LEN,
        margin: 0.1,
    }));
    for _ in 0..150 {
        full.step().unwrap();
        act.step().unwrap();
    }
    assert!(full.stats().list_builds > 3, "the run must rebuild lists");
    assert_eq!(act.stats().active_fluid, act.num_fluid());
    assert_eq!(act.stats().fluid_steps, full.stats().fluid_steps);
    assert_eq!(
        state(&full),
        state(&act),
        "the covering active domain changed bits"
    );
    assert_eq!(full.time().to_bits(), act.time().to_bits());
    let (fa, fb) = (full.carrier_load(0), act.carrier_load(0));
    assert_eq!(fa[0], fb[0]);
}

#[test]
fn frozen_particles_hold_their_state_and_activity_follows_the_distance_rule() {
    let ad = radius(2.0);
    let mut sys = towed_block(Some(ad));
    sys.initialize().unwrap();
    let s0 = state(&sys);
    let n = sys.len();
    let mut ever = vec![false; n];
    let mut fluid = vec![false; n];
    for (i, &id) in sys.data().id.iter().enumerate() {
        fluid[id as usize] = sys.data().kind[i] == FLUID;
    }
    let mut min_active = usize::MAX;
    let mut held = 0;
    for _ in 0..300 {
        // the particles active so far moved; every other one holds its state bit for bit,
        // also in the step that activates it (it starts from its held state)
        let s = state(&sys);
        let d = sys.data();
        for (id, (a, b)) in s.iter().zip(&s0).enumerate() {
            if fluid[id] && !ever[id] {
                assert_eq!(a, b, "frozen particle {id} changed");
                held += 1;
            }
        }
        for i in 0..d.len() {
            if sys.is_active(i) {
                ever[d.id[i] as usize] = true;
            }
        }
        min_active = min_active.min(sys.stats().active_fluid);
        sys.step().unwrap();
    }
    // the rule: active iff within the radius of the block's bounding sphere, now
    let src = sys.active_sources()[0];
    let centre = sys.carrier_centre(0);
    assert_eq!([src[0], src[1], src[2]], [centre.x, centre.y, centre.z]);
    assert!(
        centre.x > C0[0] + 0.05,
        "the block must have moved: {}",
        centre.x
    );
    let d = sys.data();
    let mut active = 0;
    for i in 0..d.len() {
        if d.kind[i] != FLUID {
            continue;
        }
        let e = [d.x[i] - src[0], d.y[i] - src[1], d.z[i] - src[2]];
        let dist = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt() - src[3];
        assert_eq!(
            sys.is_active(i),
            dist <= ad.radius,
            "slot {i} at distance {dist}"
        );
        active += sys.is_active(i) as usize;
    }
    assert_eq!(active, sys.stats().active_fluid);
    // a minority stepped, and the set moved with the block (more ids than one set)
    assert!(
        2 * min_active < sys.num_fluid(),
        "{min_active} of {}",
        sys.num_fluid()
    );
    let ever_fluid = ever.iter().filter(|&&e| e).count();
    assert!(
        ever_fluid > active,
        "{ever_fluid} ever active, {active} now"
    );
    assert!(sys.stats().fluid_steps < sys.steps() * sys.num_fluid() as u64 / 2);
    assert!(held > 0);
}

/// The active run's state after `steps` steps on `threads` threads.
fn active_state(threads: usize, steps: usize) -> Vec<[u64; 7]> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut sys = towed_block(Some(radius(2.0)));
        for _ in 0..steps {
            sys.step().unwrap();
        }
        state(&sys)
    })
}

#[test]
fn active_domain_is_deterministic_for_any_thread_count() {
    let one = active_state(1, 120);
    assert_eq!(one, active_state(1, 120), "1 thread, run to run");
    assert_eq!(one, active_state(2, 120), "1 vs 2 threads");
    assert_eq!(one, active_state(3, 120), "1 vs 3 threads");
}

#[test]
fn active_domain_bad_input_names_the_field() {
    // a radius below the kernel support
    let s = SphSettings {
        spacing: DP,
        sound_speed: 10.0,
        active_domain: Some(ActiveDomain {
            radius: 0.5 * DP,
            margin: DP,
        }),
        ..SphSettings::default()
    };
    let e = SphBuilder::new(s).unwrap_err().to_string();
    assert!(e.contains("settings.active_domain.radius"), "{e}");
    let s = SphSettings {
        spacing: DP,
        sound_speed: 10.0,
        active_domain: Some(ActiveDomain {
            radius: 1.0,
            margin: f64::NAN,
        }),
        ..SphSettings::default()
    };
    let e = SphBuilder::new(s).unwrap_err().to_string();
    assert!(e.contains("settings.active_domain.margin"), "{e}");
    // no moving carrier: every particle would freeze
    let mut sys = towed_block(Some(radius(2.0)));
    sys.set_carrier_source(0, false).unwrap();
    let e = sys.step().unwrap_err().to_string();
    assert!(
        e.contains("settings.active_domain") && e.contains("source"),
        "{e}"
    );
    assert!(sys.set_carrier_source(3, true).is_err());
}
