//! `granular-vs-rapier` bench (cargo feature `rapier`): the `granular-settle` pour run by
//! our NSC step and by rapier3d-f64 0.36.1 in the same process, on the same rayon pool.
//!
//! The scene is `granular-settle`'s (`settle::scene`: `GrainBed` jittered lattice, radii
//! uniform in `[0.8 r, r]`, open box `add_box_container`). Rapier gets the same centres,
//! radii and density, friction `mu` and restitution 0 on every collider (its default
//! combine rule, the average, so every pair has `mu`), the same gravity, the box as five
//! fixed thick cuboids whose inner faces are the half-spaces' planes, and its default
//! integration parameters except `dt = h` and `length_unit` = the grain diameter `2 r`.
//!
//! Both engines are measured the same way from positions and radii only (not from either
//! engine's contact list): the deepest sphere–sphere and sphere–wall overlap at the end
//! (and its maximum over the last quarter, sampled every 10 steps) over the smallest
//! radius `0.8 r` (`granular-settle`'s `max_penetration_over_r`), the kinetic energy per
//! grain in units of `m g d` with `granular-settle`'s `m` and `d` (its largest value over
//! the last quarter against `ke_bound`: at rest or not), and the grains that left the box.
//! Steps/s: steps over the summed wall time of the step calls, and one over the median
//! step time; the measurements above are outside the timed calls.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::time::Instant;

use chrono_core::math::Vector3;
use chrono_core::system::ContactMethod;
use chrono_core::{BodyHandle, Shape, System};
use rapier3d_f64::prelude::{
    ColliderBuilder, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, Vector as RVector,
};
use serde::{Deserialize, Serialize};

use super::settle::{SettleParams, scene};
use crate::case::{Case, CaseOutput, Mode, RunContext};
use crate::params::{CaseParams, ParamCase, ParamInfo, ensure_positive};

/// Parameters of `granular-vs-rapier`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct VsRapierParams {
    /// Number of grains.
    pub n: usize,
    /// Largest grain radius, m (radii uniform in [0.8 r, r]).
    pub radius: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Friction coefficient (both engines).
    pub mu: f64,
    /// Time step, s (both engines).
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Worker threads of the rayon pool both engines run in (0: rayon's default).
    pub threads: usize,
    /// Bound on the kinetic energy per grain over the last quarter, in units of `m g d`.
    pub ke_bound: f64,
    /// Our NSC step's CCP solver, by name (`chrono_ccp::SOLVER_NAMES`).
    pub solver: String,
    /// Our solver's tolerance, m/s.
    pub tolerance: f64,
    /// Our solver's iteration cap.
    pub max_iterations: usize,
    /// Seed of the packing.
    pub seed: u64,
}

impl Default for VsRapierParams {
    fn default() -> Self {
        // Issue 23's scene: 10 000 grains, r = 1 cm, h = 1/240 s, 1 s, 2 threads; the
        // material, the rest bound and our solver settings are granular-settle's own.
        let settle = SettleParams::default();
        Self {
            n: 10_000,
            radius: 0.01,
            density: settle.density,
            mu: settle.mu,
            h: 1.0 / 240.0,
            t_end: 1.0,
            threads: 2,
            ke_bound: settle.ke_bound,
            solver: settle.solver,
            tolerance: settle.tolerance,
            max_iterations: settle.max_iterations,
            seed: settle.seed,
        }
    }
}

const INFO: &[ParamInfo] = &[
    ParamInfo::new("n", "-", "number of grains"),
    ParamInfo::new("radius", "m", "largest grain radius (radii in [0.8 r, r])"),
    ParamInfo::new("density", "kg/m^3", "grain density"),
    ParamInfo::new("mu", "-", "friction coefficient (both engines)"),
    ParamInfo::new("h", "s", "time step (both engines)"),
    ParamInfo::new("t_end", "s", "simulated time"),
    ParamInfo::new(
        "threads",
        "-",
        "rayon pool size for both engines (0: default)",
    ),
    ParamInfo::new(
        "ke_bound",
        "m g d",
        "bound on the kinetic energy per grain (at rest)",
    ),
    ParamInfo::new("solver", "-", "our CCP solver: apgd | apsor | ..."),
    ParamInfo::new("tolerance", "m/s", "our solver's tolerance"),
    ParamInfo::new("max_iterations", "-", "our solver's iteration cap"),
    ParamInfo::new("seed", "-", "seed of the packing"),
];

impl CaseParams for VsRapierParams {
    const INFO: &'static [ParamInfo] = INFO;
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.n = 500;
            self.t_end = 0.25;
        }
    }
}

/// The grains and box every measurement reads (centres, radii, the box's planes) and
/// the units of the reported figures.
struct Meter<'a> {
    radii: &'a [f64],
    lower: Vector3<f64>,
    upper: Vector3<f64>,
    /// `m g d`, J: the unit of the kinetic energy per grain.
    ke_unit: f64,
    /// `0.8 r`, m: the unit of the penetration.
    pen_unit: f64,
}

impl Meter<'_> {
    /// Deepest overlaps (m, 0 if none), `[walls, spheres]`: of the spheres `centers` (radii
    /// `self.radii`) with the box's floor and four side planes, and among them. A cell grid of pitch
    /// `2 r_max` finds the sphere pairs.
    fn deepest_penetrations(&self, centers: &[Vector3<f64>]) -> [f64; 2] {
        let (lo, hi) = (self.lower, self.upper);
        let mut deepest = 0.0f64;
        for (c, &r) in centers.iter().zip(self.radii) {
            let gaps = [c.z - lo.z, c.x - lo.x, hi.x - c.x, c.y - lo.y, hi.y - c.y];
            for g in gaps {
                deepest = deepest.max(r - g);
            }
        }
        let walls = deepest;
        deepest = 0.0;
        let pitch = 2.0 * self.radii.iter().copied().fold(0.0, f64::max);
        if pitch <= 0.0 {
            return [walls, 0.0];
        }
        let cell = |c: &Vector3<f64>| -> [i64; 3] {
            [0, 1, 2].map(|a| ((c[a] - lo[a]) / pitch).floor() as i64)
        };
        let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (i, c) in centers.iter().enumerate() {
            grid.entry(cell(c)).or_default().push(i);
        }
        for (i, ci) in centers.iter().enumerate() {
            let k = cell(ci);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(others) = grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) else {
                            continue;
                        };
                        for &j in others.iter().filter(|&&j| j > i) {
                            let d = (centers[j] - ci).norm();
                            deepest = deepest.max(self.radii[i] + self.radii[j] - d);
                        }
                    }
                }
            }
        }
        [walls, deepest]
    }

    /// Grains out of the box by `granular-settle`'s definition (below the floor, or out
    /// through a side; the top is open).
    fn escaped(&self, centers: &[Vector3<f64>]) -> usize {
        let (lo, hi) = (self.lower, self.upper);
        centers
            .iter()
            .filter(|x| (0..3).any(|a| x[a] < lo[a]) || x.x > hi.x || x.y > hi.y)
            .count()
    }
}

/// What one engine's run gave.
#[derive(Debug, Default)]
struct EngineRun {
    /// Wall time of each step call, s.
    step_s: Vec<f64>,
    /// Kinetic energy per grain over `m g d`, largest over the last quarter.
    ke_late_max: f64,
    /// Deepest penetration over `0.8 r`, largest of the samples over the last quarter.
    pen_late_max: f64,
    /// Deepest penetration over `0.8 r` at the end.
    pen_end: f64,
    /// The same against the walls only, and between spheres only.
    pen_end_split: [f64; 2],
    /// Grains out of the box at the end.
    escaped: usize,
}

impl EngineRun {
    fn steps_per_s(&self) -> f64 {
        self.step_s.len() as f64 / self.step_s.iter().sum::<f64>()
    }

    fn steps_per_s_median(&self) -> f64 {
        let mut t = self.step_s.clone();
        t.sort_by(f64::total_cmp);
        let m = t.len() / 2;
        let median = if t.len().is_multiple_of(2) {
            0.5 * (t[m - 1] + t[m])
        } else {
            t[m]
        };
        1.0 / median
    }
}

/// One engine stepping the scene.
trait Engine {
    /// Advances one step.
    fn step(&mut self) -> anyhow::Result<()>;
    /// The grains' centres (grain order) and their total kinetic energy, J.
    fn state(&self) -> (Vec<Vector3<f64>>, f64);
}

/// Our NSC system of `granular-settle`'s scene.
struct Ours<'a> {
    sys: &'a mut System,
    grains: &'a [BodyHandle],
    h: f64,
}

impl Engine for Ours<'_> {
    fn step(&mut self) -> anyhow::Result<()> {
        self.sys.step(self.h)?;
        Ok(())
    }
    fn state(&self) -> (Vec<Vector3<f64>>, f64) {
        let c = self
            .grains
            .iter()
            .map(|&b| self.sys.body(b).map(|b| b.position()).unwrap_or_default())
            .collect();
        (c, self.sys.kinetic_energy())
    }
}

/// Rapier's world with the grains' bodies in grain order.
struct Rapier {
    world: PhysicsWorld,
    grains: Vec<RigidBodyHandle>,
}

impl Engine for Rapier {
    fn step(&mut self) -> anyhow::Result<()> {
        self.world.step();
        Ok(())
    }
    fn state(&self) -> (Vec<Vector3<f64>>, f64) {
        let mut ke = 0.0;
        let c = self
            .grains
            .iter()
            .map(|&h| {
                let b = &self.world.bodies[h];
                ke += b.kinetic_energy();
                let x = b.translation();
                Vector3::new(x.x, x.y, x.z)
            })
            .collect();
        (c, ke)
    }
}

/// Runs `steps` steps of `engine`, reporting progress from `done` of `total`. Only the
/// step calls are timed.
fn drive(
    engine: &mut dyn Engine,
    steps: u64,
    meter: &Meter,
    ctx: &RunContext,
    (done, total): (u64, u64),
) -> anyhow::Result<EngineRun> {
    let n = meter.radii.len() as f64;
    let mut run = EngineRun {
        step_s: Vec::with_capacity(steps as usize),
        ..EngineRun::default()
    };
    for i in 1..=steps {
        let t = Instant::now();
        engine.step()?;
        run.step_s.push(t.elapsed().as_secs_f64());
        if i * 4 >= 3 * steps {
            let (centers, ke) = engine.state();
            run.ke_late_max = run.ke_late_max.max(ke / n / meter.ke_unit);
            if i % 10 == 0 || i == steps {
                let split = meter
                    .deepest_penetrations(&centers)
                    .map(|d| d / meter.pen_unit);
                let pen = split[0].max(split[1]);
                run.pen_late_max = run.pen_late_max.max(pen);
                if i == steps {
                    run.pen_end = pen;
                    run.pen_end_split = split;
                    run.escaped = meter.escaped(&centers);
                }
            }
        }
        ctx.progress_steps(done + i, total);
    }
    Ok(run)
}

/// Rapier's world for the grains (`centers`, `radii`) in the open box `[lower, upper]`.
fn rapier_world(
    p: &VsRapierParams,
    centers: &[Vector3<f64>],
    meter: &Meter,
    gravity: Vector3<f64>,
    h: f64,
) -> Rapier {
    let (lower, upper) = (meter.lower, meter.upper);
    let v = |x: Vector3<f64>| RVector::new(x.x, x.y, x.z);
    let mut world = PhysicsWorld::new();
    world.gravity = v(gravity);
    world.integration_parameters.dt = h;
    world.integration_parameters.length_unit = 2.0 * p.radius;
    let mut grains = Vec::with_capacity(centers.len());
    for (c, &r) in centers.iter().zip(meter.radii) {
        let (body, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(v(*c)),
            ColliderBuilder::ball(r)
                .density(p.density)
                .friction(p.mu)
                .restitution(0.0),
        );
        grains.push(body);
    }
    // Walls as cuboids `t` thick (ten diameters: nothing tunnels through), their inner
    // faces on the half-spaces' planes; the side walls reach a box height above the top
    // (the half-spaces are unbounded, but no grain rises that far).
    let t = 20.0 * p.radius;
    let size = upper - lower;
    let mid = 0.5 * (lower + upper);
    let (z_lo, z_hi) = (lower.z - t, upper.z + size.z);
    let zc = 0.5 * (z_lo + z_hi);
    let hz = 0.5 * (z_hi - z_lo);
    let walls = [
        // Floor.
        (
            Vector3::new(0.5 * size.x + t, 0.5 * size.y + t, 0.5 * t),
            Vector3::new(mid.x, mid.y, lower.z - 0.5 * t),
        ),
        // x = lower.x and x = upper.x.
        (
            Vector3::new(0.5 * t, 0.5 * size.y + t, hz),
            Vector3::new(lower.x - 0.5 * t, mid.y, zc),
        ),
        (
            Vector3::new(0.5 * t, 0.5 * size.y + t, hz),
            Vector3::new(upper.x + 0.5 * t, mid.y, zc),
        ),
        // y = lower.y and y = upper.y.
        (
            Vector3::new(0.5 * size.x + t, 0.5 * t, hz),
            Vector3::new(mid.x, lower.y - 0.5 * t, zc),
        ),
        (
            Vector3::new(0.5 * size.x + t, 0.5 * t, hz),
            Vector3::new(mid.x, upper.y + 0.5 * t, zc),
        ),
    ];
    for (half, at) in walls {
        world.insert_collider(
            ColliderBuilder::cuboid(half.x, half.y, half.z)
                .translation(v(at))
                .friction(p.mu)
                .restitution(0.0),
            None,
        );
    }
    Rapier { world, grains }
}

fn run(p: &VsRapierParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    anyhow::ensure!(p.n > 0, "parameter `n` must be > 0, got {}", p.n);
    ensure_positive("radius", p.radius)?;
    ensure_positive("h", p.h)?;
    ensure_positive("t_end", p.t_end)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(p.threads)
        .build()
        .map_err(|e| anyhow::anyhow!("parameter `threads` = {}: {e}", p.threads))?;
    pool.install(|| run_in_pool(p, ctx))
}

fn run_in_pool(p: &VsRapierParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let settle = SettleParams {
        n: p.n,
        method: ContactMethod::Nsc,
        radius: p.radius,
        density: p.density,
        mu: p.mu,
        h: p.h,
        t_end: p.t_end,
        solver: p.solver.clone(),
        tolerance: p.tolerance,
        max_iterations: p.max_iterations,
        seed: p.seed,
        ..SettleParams::default()
    };
    let mut s = scene(&settle)?;
    let steps = (p.t_end / s.h).round().max(1.0) as u64;
    let mut radii = Vec::with_capacity(s.grains.len());
    let mut centers = Vec::with_capacity(s.grains.len());
    for &b in &s.grains {
        let body = s.sys.body(b)?;
        let r = match body.colliders().first().map(|c| &c.shape) {
            Some(Shape::Sphere { radius }) => *radius,
            other => anyhow::bail!("a grain of granular-settle is not a sphere: {other:?}"),
        };
        radii.push(r);
        centers.push(body.position());
    }
    let gravity = s.sys.settings().gravity;
    // granular-settle's units: m of a grain of radius 0.9 r, d = 2 r; penetration over 0.8 r.
    let m_grain = p.density * 4.0 / 3.0 * std::f64::consts::PI * (0.9 * p.radius).powi(3);
    let meter = Meter {
        radii: &radii,
        lower: s.lower,
        upper: s.upper,
        ke_unit: m_grain * gravity.norm() * 2.0 * p.radius,
        pen_unit: 0.8 * p.radius,
    };
    let mut rapier = rapier_world(p, &centers, &meter, gravity, s.h);
    let total = 2 * steps;
    ctx.note(format!(
        "granular-vs-rapier: {} grains, {steps} steps of {} s, {} threads; ours first",
        p.n,
        s.h,
        rayon::current_num_threads()
    ));
    let mut ours = Ours {
        sys: &mut s.sys,
        grains: &s.grains,
        h: s.h,
    };
    let ours = drive(&mut ours, steps, &meter, ctx, (0, total))?;
    let theirs = drive(&mut rapier, steps, &meter, ctx, (steps, total))?;

    let mut out = CaseOutput::new();
    out.metric("grains", p.n as f64)
        .metric("h", s.h)
        .metric("steps", steps as f64)
        .metric("threads", rayon::current_num_threads() as f64);
    for (name, r) in [("ours", &ours), ("rapier", &theirs)] {
        out.metric(format!("{name}_steps_per_s"), r.steps_per_s())
            .metric(format!("{name}_steps_per_s_median"), r.steps_per_s_median())
            .metric(format!("{name}_max_penetration_over_r_end"), r.pen_end)
            .metric(
                format!("{name}_max_penetration_over_r_end_walls"),
                r.pen_end_split[0],
            )
            .metric(
                format!("{name}_max_penetration_over_r_end_spheres"),
                r.pen_end_split[1],
            )
            .metric(
                format!("{name}_max_penetration_over_r_late"),
                r.pen_late_max,
            )
            .metric(format!("{name}_ke_per_grain_late_max"), r.ke_late_max)
            .metric(
                format!("{name}_at_rest"),
                f64::from(u8::from(r.ke_late_max < p.ke_bound)),
            )
            .metric(format!("{name}_escaped_grains"), r.escaped as f64);
    }
    out.metric(
        "ratio_steps_per_s_ours_over_rapier",
        ours.steps_per_s() / theirs.steps_per_s(),
    )
    .metric(
        "ratio_steps_per_s_median_ours_over_rapier",
        ours.steps_per_s_median() / theirs.steps_per_s_median(),
    );
    let table = markdown(p, s.h, steps, &ours, &theirs);
    std::fs::write(ctx.out_dir.join("comparison.md"), &table)?;
    ctx.note(table);
    Ok(out)
}

/// The two engines side by side, as a markdown table.
fn markdown(
    p: &VsRapierParams,
    h: f64,
    steps: u64,
    ours: &EngineRun,
    rapier: &EngineRun,
) -> String {
    let mut t = format!(
        "granular-settle pour: {} grains, r = {} m, h = {h} s, {steps} steps, {} threads\n\n\
         | engine | steps/s (total) | steps/s (median) | deepest penetration / 0.8 r, end (walls / spheres) | \
         same, last quarter max | KE per grain / (m g d), last quarter max | at rest | escaped |\n\
         |---|---|---|---|---|---|---|---|\n",
        p.n,
        p.radius,
        rayon::current_num_threads()
    );
    for (name, r) in [("chrono-rs NSC", ours), ("rapier3d-f64 0.36.1", rapier)] {
        let _ = writeln!(
            t,
            "| {name} | {:.3} | {:.3} | {:.4} ({:.4} / {:.4}) | {:.4} | {:.3e} | {} | {} |",
            r.steps_per_s(),
            r.steps_per_s_median(),
            r.pen_end,
            r.pen_end_split[0],
            r.pen_end_split[1],
            r.pen_late_max,
            r.ke_late_max,
            if r.ke_late_max < p.ke_bound {
                "yes"
            } else {
                "no"
            },
            r.escaped
        );
    }
    let _ = writeln!(
        t,
        "\nours / rapier: {:.3} (total), {:.3} (median)",
        ours.steps_per_s() / rapier.steps_per_s(),
        ours.steps_per_s_median() / rapier.steps_per_s_median()
    );
    t
}

/// The bench.
pub fn bench() -> Box<dyn Case> {
    ParamCase::<VsRapierParams>::boxed(
        "granular-vs-rapier",
        "granular",
        "The granular-settle pour by our NSC step and by rapier3d-f64 0.36.1 in one run: steps/s, deepest penetration, rest, ratio.",
        run,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn penetration_of_spheres_and_walls() {
        let radii = [0.01, 0.008, 0.01];
        let geo = Meter {
            radii: &radii,
            lower: Vector3::zeros(),
            upper: Vector3::new(1.0, 1.0, 1.0),
            ke_unit: 1.0,
            pen_unit: 1.0,
        };
        let centers = [
            Vector3::new(0.5, 0.5, 0.5),
            Vector3::new(0.517, 0.5, 0.5),
            Vector3::new(0.2, 0.2, 0.2),
        ];
        let d = geo.deepest_penetrations(&centers);
        assert!(d[0] == 0.0 && (d[1] - 0.001).abs() < 1e-12, "{d:?}");
        let on_floor = [
            Vector3::new(0.5, 0.5, 0.5),
            Vector3::new(0.8, 0.5, 0.5),
            Vector3::new(0.2, 0.2, 0.0075),
        ];
        let d = geo.deepest_penetrations(&on_floor);
        assert!((d[0] - 0.0025).abs() < 1e-12 && d[1] == 0.0, "{d:?}");
        let out = [
            Vector3::new(0.5, 0.5, -0.1),
            Vector3::new(1.1, 0.5, 0.5),
            Vector3::new(0.5, 0.5, 3.0),
        ];
        assert_eq!(geo.escaped(&out), 2);
    }

    #[test]
    fn rapier_has_the_scene_and_both_run() {
        let p = VsRapierParams {
            n: 60,
            t_end: 0.05,
            threads: 1,
            ..VsRapierParams::default()
        };
        let dir = crate::tests::temp_dir("vs-rapier");
        std::fs::create_dir_all(&dir).unwrap();
        let ctx = RunContext::new(Mode::Quick, &dir, false);
        let out = run(&p, &ctx).unwrap();
        for k in [
            "ours_steps_per_s",
            "rapier_steps_per_s",
            "ratio_steps_per_s_ours_over_rapier",
        ] {
            assert!(out.metrics[k].is_finite() && out.metrics[k] > 0.0, "{k}");
        }
        assert_eq!(out.metrics["rapier_escaped_grains"], 0.0);
        assert!(dir.join("comparison.md").exists());
        // The grains' masses agree (same density and radii).
        let s = scene(&SettleParams {
            n: 5,
            radius: p.radius,
            ..SettleParams::default()
        })
        .unwrap();
        let b = s.sys.body(s.grains[0]).unwrap();
        let Some(&Shape::Sphere { radius }) = b.colliders().first().map(|c| &c.shape) else {
            panic!("not a sphere");
        };
        let meter = Meter {
            radii: &[radius],
            lower: s.lower,
            upper: s.upper,
            ke_unit: 1.0,
            pen_unit: 1.0,
        };
        let r = rapier_world(&p, &[b.position()], &meter, s.sys.settings().gravity, 1e-3);
        let rb = &r.world.bodies[r.grains[0]];
        assert!(
            (rb.mass() / b.mass() - 1.0).abs() < 1e-12,
            "{} {}",
            rb.mass(),
            b.mass()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
