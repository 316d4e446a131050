//! The dam break of `sph-dam-break` (its default set-up) stepped over MPI ranks, or in
//! one process without a decomposition (`--whole`), writing the whole-system figures of
//! every step; `--compare` checks them against another run's file.
//!
//! ```text
//! cargo build --release -p chrono-sph --features mpi --example mpi_dam_break
//! target/release/examples/mpi_dam_break --whole --out whole.csv
//! RAYON_NUM_THREADS=1 mpirun -n 2 target/release/examples/mpi_dam_break --compare whole.csv
//! RAYON_NUM_THREADS=1 mpirun --oversubscribe -n 4 target/release/examples/mpi_dam_break --compare whole.csv
//! ```
//!
//! Options: `--steps N` (200), `--warmup N` (steps before the timed ones, 0),
//! `--scene case | dualsph` (issue 23's DualSPHysics tank, 128 310 fluid particles), `--spacing DP` (m; the case's a/24), `--out FILE`
//! (rank 0 writes the series), `--compare FILE` (rank 0 checks the particle counts
//! exactly and the time step, kinetic energy and front within `--tol`, default 1e-9
//! relative; exit status 1 on a mismatch), `--rebalance K` (cuts moved every K list
//! builds, 0 = never), `--wall-weight W` (a wall marker's work against a fluid
//! particle's in the balance), `--vtk DIR` (each rank writes its particles every `--vtk-every`
//! steps, 50, as `dam_<step>_r<rank>.vtp`; rank 0 writes `dam.pvd` listing each frame's
//! rank files as its parts). Each rank prints its decomposition counters at the end. A rank
//! whose step fails prints the error and exits with status 1 (mpirun then stops the
//! others).

use std::io::Write;
use std::time::Instant;

use chrono_core::particles::lattice::SlabTank;
use chrono_sph::distributed::MpiTransport;
use chrono_sph::{
    DistributedSettings, GlobalSummary, NoSlip, SphBuilder, SphSettings, SphSystem, Transport,
};

const G: f64 = 9.81;

struct Args {
    steps: usize,
    warmup: usize,
    dualsph: bool,
    spacing: f64,
    whole: bool,
    out: Option<String>,
    compare: Option<String>,
    tol: f64,
    rebalance: u32,
    vtk: Option<String>,
    vtk_every: usize,
    wall_weight: f64,
}

fn args() -> Args {
    let a = 0.05715;
    let mut r = Args {
        steps: 200,
        warmup: 0,
        dualsph: false,
        spacing: a / 24.0,
        whole: false,
        out: None,
        compare: None,
        tol: 1e-9,
        rebalance: DistributedSettings::default().rebalance_every,
        vtk: None,
        vtk_every: 50,
        wall_weight: DistributedSettings::default().wall_weight,
    };
    let v: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
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
    while i < v.len() {
        match v[i].as_str() {
            "--steps" => r.steps = num(val(i), "--steps") as usize,
            "--warmup" => r.warmup = num(val(i), "--warmup") as usize,
            "--scene" => match val(i).as_str() {
                "case" => r.dualsph = false,
                "dualsph" => {
                    r.dualsph = true;
                    if r.spacing == 0.05715 / 24.0 {
                        r.spacing = 0.0085;
                    }
                }
                o => {
                    eprintln!("--scene: case | dualsph, not {o}");
                    std::process::exit(2)
                }
            },
            "--spacing" => r.spacing = num(val(i), "--spacing"),
            "--out" => r.out = Some(val(i)),
            "--compare" => r.compare = Some(val(i)),
            "--vtk" => r.vtk = Some(val(i)),
            "--vtk-every" => r.vtk_every = (num(val(i), "--vtk-every") as usize).max(1),
            "--tol" => r.tol = num(val(i), "--tol"),
            "--rebalance" => r.rebalance = num(val(i), "--rebalance") as u32,
            "--wall-weight" => r.wall_weight = num(val(i), "--wall-weight"),
            "--whole" => {
                r.whole = true;
                i += 1;
                continue;
            }
            o => {
                eprintln!("unknown option {o}");
                std::process::exit(2)
            }
        }
        i += 2;
    }
    r
}

/// Issue 23's DualSPHysics dam break (its `01_DamBreak`: tank 1.6 x 0.67 x 0.4 m, column
/// 0.4 x 0.67 x 0.3 m, `h = 1.732 dp`; `cargo xtask bench sph-dam-break` with the issue's
/// settings) at spacing `dp` (0.0085 m: 128 310 fluid particles).
fn dualsph(dp: f64) -> SphSystem {
    let upper = [1.6, 0.67, 0.4];
    let settings = SphSettings {
        spacing: dp,
        h_over_dp: 1.732,
        sound_speed: 10.0 * (2.0 * G * 0.3f64).sqrt(),
        domain_lower: [0.0; 3],
        domain_upper: upper,
        ..SphSettings::default()
    };
    let layers = chrono_core::particles::lattice::wall_layers(1.732);
    let built = SphBuilder::new(settings).and_then(|mut b| {
        b.add_fluid_box([0.0; 3], [0.4, 0.67, 0.3], Some(0.3))?;
        b.add_tank(
            [0.0; 3],
            upper,
            layers,
            [true, true, true, true, true, false],
            0,
        )?;
        b.build()
    });
    built.unwrap_or_else(|e| {
        eprintln!("scene: {e}");
        std::process::exit(2)
    })
}

/// `sph-dam-break`'s default scene at spacing `dp`.
fn scene(dp: f64) -> SphSystem {
    let a = 0.05715;
    let (hc, length) = (a, 5.0 * a);
    let tank = SlabTank::dam_break(
        dp,
        SphSettings::default().h_over_dp,
        [a, hc],
        length,
        1.25 * hc,
    );
    let settings = SphSettings {
        sound_speed: 10.0 * (2.0 * G * hc).sqrt(),
        artificial_viscosity: 0.03,
        diffusion_delta: 0.1,
        xsph: 0.5,
        no_slip: NoSlip::Linear,
        ..SphSettings::default()
    };
    chrono_sph::scene::slab_tank(settings, &tank).unwrap_or_else(|e| {
        eprintln!("scene: {e}");
        std::process::exit(2)
    })
}

/// A transport that times its collectives (the communication share of the step).
#[derive(Debug)]
struct Timed<T: Transport> {
    inner: T,
    seconds: f64,
    calls: u64,
}

impl<T: Transport> Transport for Timed<T> {
    fn rank(&self) -> usize {
        self.inner.rank()
    }
    fn size(&self) -> usize {
        self.inner.size()
    }
    fn all_to_all(&mut self, send: &[Vec<f64>], recv: &mut [Vec<f64>]) -> chrono_core::Result<()> {
        let t = Instant::now();
        let r = self.inner.all_to_all(send, recv);
        self.seconds += t.elapsed().as_secs_f64();
        self.calls += 1;
        r
    }
    fn all_max(&mut self, v: &mut [f64]) -> chrono_core::Result<()> {
        let t = Instant::now();
        let r = self.inner.all_max(v);
        self.seconds += t.elapsed().as_secs_f64();
        self.calls += 1;
        r
    }
    fn all_sum(&mut self, v: &mut [f64]) -> chrono_core::Result<()> {
        let t = Instant::now();
        let r = self.inner.all_sum(v);
        self.seconds += t.elapsed().as_secs_f64();
        self.calls += 1;
        r
    }
}

fn row(k: usize, t: f64, dt: f64, g: &GlobalSummary) -> String {
    format!(
        "{k},{t:.17e},{dt:.17e},{},{},{:.17e},{:.17e},{:.17e}",
        g.fluid, g.particles, g.kinetic_energy, g.fluid_max[0], g.fluid_max[2]
    )
}

fn fail(rank: usize, e: impl std::fmt::Display) -> ! {
    eprintln!("rank {rank}: {e}");
    std::process::exit(1)
}

fn main() {
    let a = args();
    let universe = mpi::initialize().unwrap_or_else(|| fail(0, "MPI was already initialized"));
    let mut net = Timed {
        inner: MpiTransport::new(universe.world()),
        seconds: 0.0,
        calls: 0,
    };
    let (rank, size) = (net.rank(), net.size());
    if a.whole && size > 1 {
        fail(rank, "--whole runs one process: start it without mpirun -n");
    }
    let mut sys = if a.dualsph {
        dualsph(a.spacing)
    } else {
        scene(a.spacing)
    };
    if !a.whole {
        let settings = DistributedSettings {
            rebalance_every: a.rebalance,
            wall_weight: a.wall_weight,
            ..Default::default()
        };
        sys.distribute(rank, size, settings)
            .unwrap_or_else(|e| fail(rank, e));
    }
    let mut lines = vec!["step,t,dt,fluid,particles,kinetic_energy,front_x,top_z".to_string()];
    if let Some(dir) = &a.vtk {
        std::fs::create_dir_all(dir).unwrap_or_else(|e| fail(rank, format!("{dir}: {e}")));
    }
    let mut frames: Vec<(f64, String)> = Vec::new();
    let mut t0 = Instant::now();
    let mut fluid_steps = 0u64;
    for k in 0..a.warmup + a.steps {
        if k == a.warmup {
            sys.reset_timings();
            t0 = Instant::now();
            fluid_steps = 0;
            (net.seconds, net.calls) = (0.0, 0);
        }
        let (dt, g) = if a.whole {
            let dt = sys.step().unwrap_or_else(|e| fail(rank, e));
            (
                dt,
                sys.global_summary(None).unwrap_or_else(|e| fail(rank, e)),
            )
        } else {
            let dt = sys.step_on(&mut net).unwrap_or_else(|e| fail(rank, e));
            let g = sys
                .global_summary(Some(&mut net))
                .unwrap_or_else(|e| fail(rank, e));
            (dt, g)
        };
        fluid_steps += g.fluid as u64;
        lines.push(row(k, sys.time(), dt, &g));
        if let Some(dir) = &a.vtk
            && (k + 1) % a.vtk_every == 0
        {
            let name = format!("dam_{:05}_r{rank}.vtp", k + 1);
            sys.write_vtk(std::path::Path::new(dir).join(&name), true)
                .unwrap_or_else(|e| fail(rank, e));
            frames.push((sys.time(), name));
        }
    }
    if let Some(dir) = &a.vtk
        && rank == 0
    {
        // every rank wrote its part of each frame under the same names
        let parts: Vec<(f64, usize, String)> = frames
            .iter()
            .flat_map(|(t, name)| {
                (0..size).map(move |r| (*t, r, name.replace("_r0.vtp", &format!("_r{r}.vtp"))))
            })
            .collect();
        let refs: Vec<(f64, usize, &str)> =
            parts.iter().map(|(t, r, n)| (*t, *r, n.as_str())).collect();
        chrono_core::io::write_pvd_parts(std::path::Path::new(dir).join("dam.pvd"), &refs)
            .unwrap_or_else(|e| fail(rank, e));
    }
    let wall = t0.elapsed().as_secs_f64();
    let tm = sys.timings();
    eprintln!(
        "rank {rank}: neighbour search {:.3} s, density {:.3} s, forces {:.3} s, integration {:.3} s",
        tm.neighbor_search, tm.density, tm.forces, tm.integration
    );
    if let Some(s) = sys.halo_stats() {
        eprintln!(
            "rank {rank} of {size}: collectives {:.3} s in {} calls over the timed steps ({:.1} % of {wall:.3} s); owned {}, ghosts {}, list builds {}, rebalances {}, migrated in {}, values sent {} ({:.1} kB per step)",
            net.seconds,
            net.calls,
            100.0 * net.seconds / wall,
            s.owned,
            s.ghosts,
            s.builds,
            s.rebalances,
            s.migrated_in,
            s.values_sent,
            s.values_sent as f64 * 8.0 / 1e3 / (a.warmup + a.steps) as f64
        );
    }
    if rank != 0 {
        return;
    }
    println!(
        "{size} rank(s){}: {} steps in {wall:.3} s, {:.3e} fluid particle-steps/s",
        if a.whole {
            " (whole, no decomposition)"
        } else {
            ""
        },
        a.steps,
        fluid_steps as f64 / wall
    );
    if let Some(path) = &a.out {
        let mut f = std::fs::File::create(path).unwrap_or_else(|e| fail(0, format!("{path}: {e}")));
        for l in &lines {
            writeln!(f, "{l}").unwrap_or_else(|e| fail(0, e));
        }
    }
    if let Some(path) = &a.compare {
        let text =
            std::fs::read_to_string(path).unwrap_or_else(|e| fail(0, format!("{path}: {e}")));
        let reference: Vec<&str> = text.lines().collect();
        if reference.len() != lines.len() {
            fail(
                0,
                format!(
                    "{path} has {} rows, this run {}",
                    reference.len(),
                    lines.len()
                ),
            );
        }
        let mut worst: f64 = 0.0;
        for (k, (r, l)) in reference.iter().zip(&lines).enumerate().skip(1) {
            let p = |s: &str| -> Vec<f64> {
                s.split(',')
                    .map(|x| x.parse().unwrap_or(f64::NAN))
                    .collect()
            };
            let (r, l) = (p(r), p(l));
            if r[3] != l[3] || r[4] != l[4] {
                fail(
                    0,
                    format!(
                        "step {}: {} fluid / {} particles against {} / {}",
                        k - 1,
                        l[3],
                        l[4],
                        r[3],
                        r[4]
                    ),
                );
            }
            for c in [1, 2, 5, 6, 7] {
                let e = (r[c] - l[c]).abs() / r[c].abs().max(l[c].abs()).max(1e-300);
                worst = worst.max(e);
                if e.is_nan() || e > a.tol {
                    fail(
                        0,
                        format!(
                            "step {}: column {c} {} against {} (relative {e:.3e} > {})",
                            k - 1,
                            l[c],
                            r[c],
                            a.tol
                        ),
                    );
                }
            }
        }
        println!(
            "matches {path}: counts exact at every step, worst relative difference {worst:.3e} (tolerance {})",
            a.tol
        );
    }
}
