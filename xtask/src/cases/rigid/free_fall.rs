//! `rigid-free-fall`: a box dropped onto the ground lands at `sqrt(2 H / g)` and stays there,
//! neither bouncing (NSC contact is plastic) nor sinking.

use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape};
use serde::{Deserialize, Serialize};

use super::{VtkFrames, make_system, n_steps};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `rigid-free-fall`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FreeFallParams {
    /// Drop height of the box's bottom face above the ground, m.
    pub height: f64,
    /// Time step, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// CCP solver (`psor` or `apgd`).
    pub solver: String,
}

impl Default for FreeFallParams {
    fn default() -> Self {
        Self {
            height: 1.0,
            h: 1e-3,
            t_end: 2.0,
            solver: "psor".into(),
        }
    }
}

impl CaseParams for FreeFallParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("height", "m", "drop height of the bottom face"),
        ParamInfo::new("h", "s", "time step"),
        ParamInfo::new("t_end", "s", "simulated time"),
        ParamInfo::new(
            "solver",
            "-",
            "CCP solver: jacobi | psor | psor-sym | psor-par | apgd | bb | two-phase",
        ),
    ];
    fn apply_mode(&mut self, mode: Mode) {
        if mode == Mode::Quick {
            self.t_end = 1.0;
        }
    }
}

fn run(p: &FreeFallParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let n = n_steps(p.h, p.t_end)?;
    anyhow::ensure!(
        p.height > 0.0 && p.height.is_finite(),
        "parameter `height` must be > 0, got {}",
        p.height
    );
    let mut sys = make_system(&p.solver, 1e-9, 500)?;
    let g = sys.settings().gravity.norm();
    let t_land_exact = (2.0 * p.height / g).sqrt();
    anyhow::ensure!(
        p.t_end > t_land_exact + 0.1,
        "parameter `t_end` must exceed the landing time {t_land_exact:.3} s by 0.1 s"
    );
    let mat = ContactMaterial::with_friction(0.5);
    sys.add_body(RigidBodyBuilder::fixed().name("ground").collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        mat,
    ))?;
    let half = 0.25;
    let shape = Shape::Box {
        half_extents: Vector3::repeat(half),
    };
    let bx = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("box")
            .mass_from_shape(&shape, 500.0)?
            .position(Vector3::new(0.0, 0.0, p.height + half))
            .collider(shape, Isometry3::identity(), mat),
    )?;
    let mut series = Series::new(["t", "z_bottom", "z_exact", "vz"]);
    let mut t_land = None;
    let (mut max_bounce, mut max_sink) = (0.0f64, 0.0f64);
    let mut vtk = VtkFrames::new(ctx, (0.02 / p.h).round() as u64);
    for i in 1..=n {
        sys.step(p.h)?;
        vtk.record(i, &sys)?;
        let b = sys.body(bx)?;
        let (t, z, vz) = (sys.time(), b.position().z - half, b.linear_velocity().z);
        let z_exact = (p.height - 0.5 * g * t * t).max(0.0);
        series.push(&[t, z, z_exact, vz]);
        match t_land {
            None if vz > -1e-6 && t > 0.5 * t_land_exact => t_land = Some(t),
            Some(_) => {
                max_bounce = max_bounce.max(vz);
                max_sink = max_sink.max(-z);
            }
            None => {}
        }
        ctx.progress_steps(i, n);
    }
    let t_land = t_land.ok_or_else(|| anyhow::anyhow!("the box never came to rest"))?;
    vtk.finish()?;
    let mut out = CaseOutput::new();
    // semi-implicit Euler lands within one step of the exact time
    out.check(Check::absolute(
        "landing_time",
        t_land,
        t_land_exact,
        2.0 * p.h,
    ));
    out.check(Check::below("bounce_speed", max_bounce, 1e-3));
    out.check(Check::below("sinking", max_sink, 1e-4));
    out.series = series;
    out.plot = PlotSpec::new("free fall", "t [s]", "bottom height [m]", &["z_bottom"])
        .with_reference(&["z_exact"]);
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<FreeFallParams>::boxed(
        "rigid-free-fall",
        "rigid",
        "Box dropped on the ground: lands at sqrt(2H/g), then no bounce and no sinking.",
        run,
    )
}
