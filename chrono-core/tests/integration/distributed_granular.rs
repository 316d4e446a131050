//! SMC granular material over ranks (`chrono_core::distributed::granular`), ranks as
//! threads ([`LocalTransport`]): the same grains, energies and heights as one process.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::contact::smc::RollingModel;
use chrono_core::distributed::granular::{GrainRankSettings, GrainRanks, GrainSummary};
use chrono_core::distributed::{LocalTransport, Transport};
use chrono_core::granular::KickedBox;
use chrono_core::math::Vector3;
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System};

const R: f64 = 0.01;

/// The kicked box, 24 x 4 x 10 pitches; `(system, step)`.
fn scene(n: usize, method: ContactMethod) -> (System, f64) {
    scene_with(n, method, RollingModel::Relative, 0.0)
}

/// The kicked box with rolling friction `mu_r` under `rolling_model`.
fn scene_with(
    n: usize,
    method: ContactMethod,
    rolling_model: RollingModel,
    mu_r: f64,
) -> (System, f64) {
    let d = KickedBox::default();
    KickedBox {
        grains: n,
        radius: R,
        pitches: [24, 4, 10],
        method,
        material: d.material.with_rolling_friction(mu_r),
        rolling_model,
        ..d
    }
    .build(Box::new(Apgd::new(SolverSettings::default())))
    .unwrap()
}

/// Runs `f` on `r` in-process ranks (one thread each), results in rank order.
fn on_ranks<T: Send>(r: usize, f: impl Fn(LocalTransport) -> T + Sync) -> Vec<T> {
    std::thread::scope(|s| {
        let hs: Vec<_> = LocalTransport::ranks(r)
            .into_iter()
            .map(|t| s.spawn(|| f(t)))
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// Per step the summary; at the end `(id, position, velocity)` of every grain.
type Run = (Vec<GrainSummary>, Vec<(u64, Vector3<f64>, Vector3<f64>)>);

fn whole(n: usize, steps: usize, rolling: (RollingModel, f64)) -> Run {
    let (mut sys, h) = scene_with(n, ContactMethod::Smc, rolling.0, rolling.1);
    let first = sys.bodies().iter().position(|b| b.is_dynamic()).unwrap();
    let summary = |sys: &System| GrainSummary {
        grains: sys.bodies().len() - first,
        kinetic_energy: sys.bodies()[first..]
            .iter()
            .map(|b| b.kinetic_energy())
            .sum(),
        top: sys.bodies()[first..]
            .iter()
            .map(|b| b.position().z + b.colliders()[0].shape.curvature_radius())
            .fold(f64::NEG_INFINITY, f64::max),
    };
    let mut hist = Vec::new();
    for _ in 0..steps {
        sys.step(h).unwrap();
        hist.push(summary(&sys));
    }
    let end = sys.bodies()[first..]
        .iter()
        .enumerate()
        .map(|(g, b)| (g as u64, b.position(), b.linear_velocity()))
        .collect();
    (hist, end)
}

fn ranks(
    n: usize,
    steps: usize,
    r: usize,
    settings: GrainRankSettings,
    rolling: (RollingModel, f64),
) -> (Run, Vec<chrono_core::distributed::granular::GrainRankStats>) {
    let out = on_ranks(r, |mut t| {
        let (sys, h) = scene_with(n, ContactMethod::Smc, rolling.0, rolling.1);
        let mut g = GrainRanks::new(sys, settings, &mut t).unwrap();
        let mut hist = Vec::new();
        for _ in 0..steps {
            g.step(h, &mut t).unwrap();
            hist.push(g.summary(&mut t).unwrap());
        }
        assert_eq!(g.rank(), t.rank());
        let end: Vec<_> = g
            .owned()
            .map(|(id, b)| (id, b.position(), b.linear_velocity()))
            .collect();
        (hist, end, g.stats())
    });
    let hist = out[0].0.clone();
    for o in &out[1..] {
        assert_eq!(o.0, hist, "every rank reads the same sums");
    }
    let mut end: Vec<_> = out.iter().flat_map(|o| o.1.clone()).collect();
    end.sort_by_key(|e| e.0);
    let stats = out.iter().map(|o| o.2).collect();
    ((hist, end), stats)
}

fn compare(a: &Run, b: &Run) -> f64 {
    assert_eq!(a.0.len(), b.0.len());
    let mut worst = 0.0f64;
    for (x, y) in a.0.iter().zip(&b.0) {
        assert_eq!(x.grains, y.grains, "a grain lost or duplicated");
        worst = worst.max((x.kinetic_energy - y.kinetic_energy).abs() / x.kinetic_energy.abs());
        worst = worst.max((x.top - y.top).abs() / x.top.abs());
    }
    assert_eq!(a.1.len(), b.1.len());
    for (x, y) in a.1.iter().zip(&b.1) {
        assert_eq!(x.0, y.0, "every grain owned once");
        worst = worst.max((x.1 - y.1).norm() / R);
        worst = worst.max((x.2 - y.2).norm() / 1.0);
    }
    worst
}

#[test]
fn two_to_four_ranks_reproduce_one_process() {
    let (n, steps) = (600, 200);
    let plain = (RollingModel::Relative, 0.0);
    let reference = whole(n, steps, plain);
    let settings = GrainRankSettings {
        skin_radii: 0.05,
        rebalance_every: 2,
        ..GrainRankSettings::default()
    };
    for r in [1, 2, 3, 4] {
        let (run, stats) = ranks(n, steps, r, settings, plain);
        let worst = compare(&reference, &run);
        let rebuilds = stats[0].rebuilds;
        let migrated: u64 = stats.iter().map(|s| s.migrated_in).sum();
        let ghosts: usize = stats.iter().map(|s| s.ghosts).sum();
        eprintln!(
            "{r} ranks: worst relative difference {worst:.3e}, {rebuilds} rebuilds, {migrated} migrations, {ghosts} ghosts at the end"
        );
        assert!(worst <= 1e-9, "{r} ranks: {worst:e}");
        if r > 1 {
            assert!(rebuilds >= 3 && migrated > 0 && ghosts > 0, "{stats:?}");
        }
    }
}

#[test]
fn horizontal_slabs_reproduce_one_process_while_grains_fall_through_them() {
    // cut along z: the falling grains migrate down through the cuts
    let (n, steps) = (600, 200);
    let plain = (RollingModel::Relative, 0.0);
    let reference = whole(n, steps, plain);
    let settings = GrainRankSettings {
        axis: 2,
        skin_radii: 0.05,
        rebalance_every: 3,
        ..GrainRankSettings::default()
    };
    let (run, stats) = ranks(n, steps, 3, settings, plain);
    let worst = compare(&reference, &run);
    let migrated: u64 = stats.iter().map(|s| s.migrated_in).sum();
    eprintln!(
        "3 ranks along z: worst relative difference {worst:.3e}, {} rebuilds, {migrated} migrations",
        stats[0].rebuilds
    );
    assert!(worst <= 1e-9, "{worst:e}");
    assert!(migrated > 0, "{stats:?}");
}

/// The rolling spring's angle is contact history: it must travel with the tangential
/// displacement when grains migrate and ghosts are made, or the ranks part from the whole
/// run (checked to fail with the angle dropped on import).
#[test]
fn the_rolling_springs_angles_travel_between_ranks() {
    let (n, steps) = (600, 200);
    let spring = (RollingModel::Spring, 0.2);
    let reference = whole(n, steps, spring);
    let settings = GrainRankSettings {
        skin_radii: 0.05,
        rebalance_every: 2,
        ..GrainRankSettings::default()
    };
    for r in [2, 3] {
        let (run, stats) = ranks(n, steps, r, settings, spring);
        let worst = compare(&reference, &run);
        eprintln!("rolling spring, {r} ranks: worst relative difference {worst:.3e}");
        assert!(worst <= 1e-9, "{r} ranks: {worst:e}");
        assert!(
            stats.iter().map(|s| s.migrated_in).sum::<u64>() > 0,
            "{stats:?}"
        );
    }
}

#[test]
fn bad_input_is_named() {
    let one = || LocalTransport::ranks(1).pop().unwrap();
    // NSC
    let (sys, _) = scene(50, ContactMethod::Nsc);
    let e = GrainRanks::new(sys, GrainRankSettings::default(), &mut one())
        .unwrap_err()
        .to_string();
    assert!(e.contains("contact_method"), "{e}");
    // a dynamic box among the grains would be cut
    let (mut sys, _) = scene(50, ContactMethod::Smc);
    let s = Shape::Box {
        half_extents: Vector3::new(0.05, 0.02, 0.02),
    };
    sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("plank")
            .mass_from_shape(&s, 500.0)
            .unwrap()
            .position(Vector3::new(0.2, 0.04, 0.15))
            .collider(s, Default::default(), ContactMaterial::default()),
    )
    .unwrap();
    let e = GrainRanks::new(sys, GrainRankSettings::default(), &mut one())
        .unwrap_err()
        .to_string();
    assert!(e.contains("plank") && e.contains("cut"), "{e}");
    // more ranks than slabs: 30 ranks on a box 24 grains long
    let errs = on_ranks(30, |mut t| {
        let (sys, _) = scene(50, ContactMethod::Smc);
        GrainRanks::new(sys, GrainRankSettings::default(), &mut t)
            .unwrap_err()
            .to_string()
    });
    assert!(errs.iter().all(|e| e.contains("ranks")), "{errs:?}");
    // settings
    let (sys, _) = scene(50, ContactMethod::Smc);
    let e = GrainRanks::new(
        sys,
        GrainRankSettings {
            skin_radii: -1.0,
            ..GrainRankSettings::default()
        },
        &mut one(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("skin_radii"), "{e}");
    // stepped with another decomposition's transport
    let (sys, h) = scene(50, ContactMethod::Smc);
    let mut g = GrainRanks::new(sys, GrainRankSettings::default(), &mut one()).unwrap();
    let mut other = LocalTransport::ranks(2).swap_remove(0);
    let e = g.step(h, &mut other).unwrap_err().to_string();
    assert!(e.contains("transport"), "{e}");
}

#[test]
fn a_failing_rank_is_named_by_the_others() {
    let errs = on_ranks(3, |mut t| {
        let (sys, h) = scene(300, ContactMethod::Smc);
        let mut g = GrainRanks::new(sys, GrainRankSettings::default(), &mut t).unwrap();
        let me = t.rank();
        for k in 0..20 {
            if k == 5 && me == 1 {
                let id = g.owned().next().unwrap().0;
                g.grain_mut(id)
                    .unwrap()
                    .set_linear_velocity(Vector3::new(1e9, 0.0, 0.0))
                    .unwrap();
            }
            if let Err(e) = g.step(h, &mut t) {
                return format!("rank {me}: {e}");
            }
        }
        format!("rank {me}: no error")
    });
    assert!(errs[1].contains("grain"), "{errs:?}");
    for e in [&errs[0], &errs[2]] {
        assert!(e.contains("rank 1") && e.contains("step 5"), "{errs:?}");
    }
}
