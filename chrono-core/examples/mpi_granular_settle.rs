//! SMC grains kicked in a long box (`chrono_core::granular::KickedBox`) stepped over MPI
//! ranks, or in one process without a decomposition (`--whole`), writing the whole
//! system's figures of every step; `--compare` checks them against another run's file.
//!
//! ```text
//! cargo build --release -p chrono-core --features mpi --example mpi_granular_settle
//! target/release/examples/mpi_granular_settle --whole --out whole.csv
//! RAYON_NUM_THREADS=1 mpirun -n 2 target/release/examples/mpi_granular_settle --compare whole.csv
//! RAYON_NUM_THREADS=1 mpirun --oversubscribe -n 4 target/release/examples/mpi_granular_settle --compare whole.csv
//! ```
//!
//! The box is 6 x 14 lattice pitches across and `grains / 60` long (the grains fill its
//! lower 10 layers). Options: `--grains N` (2000), `--steps N` (200), `--out FILE` (rank 0 writes step,
//! time, grains, kinetic energy, top), `--compare FILE` (rank 0 checks the grain count of
//! every step exactly and the kinetic energy and top within `--tol`, default 1e-9
//! relative; exit status 1 on a mismatch), `--skin S` (the Verlet skin in grain radii,
//! 0.5), `--rebalance K` (cuts moved every K rebuilds), `--rolling-friction MU` (0),
//! `--spring` (the rolling spring, `RollingModel::Spring`, whose angle the ranks exchange
//! with the tangential history). Each rank prints its counters at
//! the end. A rank whose step fails prints the error and exits with status 1.

use std::io::Write;
use std::time::Instant;

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::contact::smc::RollingModel;
use chrono_core::distributed::granular::{GrainRankSettings, GrainRanks, GrainSummary};
use chrono_core::distributed::{MpiTransport, Transport};
use chrono_core::granular::KickedBox;
use chrono_core::{Result, System};

struct Args {
    grains: usize,
    steps: usize,
    whole: bool,
    out: Option<String>,
    compare: Option<String>,
    tol: f64,
    skin: f64,
    rebalance: u32,
    rolling_friction: f64,
    spring: bool,
}

fn args() -> Args {
    let d = GrainRankSettings::default();
    let mut r = Args {
        grains: 2000,
        steps: 200,
        whole: false,
        out: None,
        compare: None,
        tol: 1e-9,
        skin: d.skin_radii,
        rebalance: d.rebalance_every,
        rolling_friction: 0.0,
        spring: false,
    };
    let v: Vec<String> = std::env::args().skip(1).collect();
    let val = |i: usize| -> String {
        v.get(i + 1).cloned().unwrap_or_else(|| {
            eprintln!("option {} needs a value", v[i]);
            std::process::exit(2)
        })
    };
    let num = |s: String, name: &str| -> f64 {
        s.parse().unwrap_or_else(|_| {
            eprintln!("option {name}: not a number: {s}");
            std::process::exit(2)
        })
    };
    let mut i = 0;
    while i < v.len() {
        match v[i].as_str() {
            "--whole" => {
                r.whole = true;
                i += 1;
                continue;
            }
            "--spring" => {
                r.spring = true;
                i += 1;
                continue;
            }
            "--rolling-friction" => r.rolling_friction = num(val(i), "--rolling-friction"),
            "--grains" => r.grains = num(val(i), "--grains") as usize,
            "--steps" => r.steps = num(val(i), "--steps") as usize,
            "--out" => r.out = Some(val(i)),
            "--compare" => r.compare = Some(val(i)),
            "--tol" => r.tol = num(val(i), "--tol"),
            "--skin" => r.skin = num(val(i), "--skin"),
            "--rebalance" => r.rebalance = num(val(i), "--rebalance") as u32,
            o => {
                eprintln!("unknown option {o}");
                std::process::exit(2)
            }
        }
        i += 2;
    }
    r
}

fn scene(a: &Args) -> Result<(System, f64)> {
    // 6 x 14 pitches across; long enough for the grains in the lower 10 layers
    let across = 6 * 10;
    let d = KickedBox::default();
    KickedBox {
        grains: a.grains,
        pitches: [a.grains.div_ceil(across).max(8), 6, 14],
        material: d.material.with_rolling_friction(a.rolling_friction),
        rolling_model: if a.spring {
            RollingModel::Spring
        } else {
            RollingModel::Relative
        },
        ..d
    }
    .build(Box::new(Apgd::new(SolverSettings::default())))
}

fn fail(rank: usize, e: impl std::fmt::Display) -> ! {
    eprintln!("rank {rank}: {e}");
    std::process::exit(1)
}

fn row(k: usize, t: f64, s: &GrainSummary) -> String {
    format!(
        "{k},{t:.17e},{},{:.17e},{:.17e}",
        s.grains, s.kinetic_energy, s.top
    )
}

/// The whole scene in one process: the same figures a decomposition reduces.
fn whole(a: &Args) -> Vec<String> {
    let (mut sys, h) = scene(a).unwrap_or_else(|e| fail(0, e));
    let first = sys
        .bodies()
        .iter()
        .position(|b| b.is_dynamic())
        .unwrap_or(0);
    let t0 = Instant::now();
    let mut rows = Vec::new();
    for k in 0..a.steps {
        sys.step(h).unwrap_or_else(|e| fail(0, e));
        let g = &sys.bodies()[first..];
        let s = GrainSummary {
            grains: g.len(),
            kinetic_energy: g.iter().map(|b| b.kinetic_energy()).sum(),
            top: g
                .iter()
                .map(|b| b.position().z + b.colliders()[0].shape.curvature_radius())
                .fold(f64::NEG_INFINITY, f64::max),
        };
        rows.push(row(k + 1, sys.time(), &s));
    }
    println!(
        "1 process (whole, no decomposition): {} steps in {:.3} s",
        a.steps,
        t0.elapsed().as_secs_f64()
    );
    rows
}

fn main() {
    let a = args();
    let universe = mpi::initialize().unwrap_or_else(|| fail(0, "MPI could not be initialized"));
    let mut t = MpiTransport::new(universe.world());
    let me = t.rank();
    let rows = if a.whole {
        if t.size() > 1 {
            fail(me, "--whole runs in one process (no mpirun -n > 1)");
        }
        whole(&a)
    } else {
        let (sys, h) = scene(&a).unwrap_or_else(|e| fail(me, e));
        let settings = GrainRankSettings {
            skin_radii: a.skin,
            rebalance_every: a.rebalance,
            ..GrainRankSettings::default()
        };
        let mut g = GrainRanks::new(sys, settings, &mut t).unwrap_or_else(|e| fail(me, e));
        let t0 = Instant::now();
        let mut rows = Vec::new();
        for k in 0..a.steps {
            g.step(h, &mut t).unwrap_or_else(|e| fail(me, e));
            let s = g.summary(&mut t).unwrap_or_else(|e| fail(me, e));
            rows.push(row(k + 1, g.system().time(), &s));
        }
        let st = g.stats();
        println!(
            "rank {me} of {}: {} steps in {:.3} s; owned {}, ghosts {}, rebuilds {}, rebalances {}, migrated in {}, values sent {} ({:.1} kB per step); rebuilds {:.3} s, refreshes {:.3} s",
            t.size(),
            a.steps,
            t0.elapsed().as_secs_f64(),
            st.owned,
            st.ghosts,
            st.rebuilds,
            st.rebalances,
            st.migrated_in,
            st.values_sent,
            8.0 * st.values_sent as f64 / a.steps.max(1) as f64 / 1e3,
            st.rebuild_seconds,
            st.refresh_seconds
        );
        rows
    };
    if me != 0 {
        return;
    }
    if let Some(path) = &a.out {
        let mut f = std::fs::File::create(path).unwrap_or_else(|e| fail(me, e));
        writeln!(f, "step,time,grains,kinetic_energy,top").unwrap_or_else(|e| fail(me, e));
        for r in &rows {
            writeln!(f, "{r}").unwrap_or_else(|e| fail(me, e));
        }
    }
    if let Some(path) = &a.compare {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| fail(me, e));
        let theirs: Vec<&str> = text.lines().skip(1).collect();
        if theirs.len() != rows.len() {
            fail(
                me,
                format!("{path} has {} steps, this run {}", theirs.len(), rows.len()),
            );
        }
        let mut worst = 0.0f64;
        for (k, (x, y)) in rows.iter().zip(&theirs).enumerate() {
            let x: Vec<f64> = x
                .split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect();
            let y: Vec<f64> = y
                .split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect();
            if x.len() != 5 || y.len() != 5 {
                fail(
                    me,
                    format!("{path}: step {} is not step,time,grains,ke,top", k + 1),
                );
            }
            if x[2] != y[2] {
                fail(
                    me,
                    format!("step {}: {} grains against {}", k + 1, x[2], y[2]),
                );
            }
            for c in [1, 3, 4] {
                let d = (x[c] - y[c]).abs() / y[c].abs().max(f64::MIN_POSITIVE);
                if d.is_nan() || d > a.tol {
                    fail(
                        me,
                        format!(
                            "step {}: column {c} differs by {d:.3e} relative (tolerance {:.1e})",
                            k + 1,
                            a.tol
                        ),
                    );
                }
                worst = worst.max(d);
            }
        }
        println!(
            "compare: {} steps against {path}: grain counts equal, worst relative difference {worst:.3e} (tolerance {:.1e})",
            rows.len(),
            a.tol
        );
    }
}
