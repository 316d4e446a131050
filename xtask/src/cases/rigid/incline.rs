//! `rigid-incline`: a box on an inclined plane, sliding or sticking.
//!
//! Reference: Coulomb friction on an incline of angle `a`: the acceleration along the slope
//! is `g (sin a - mu cos a)` when `tan a > mu`, else the box sticks (0).

use chrono_core::math::{Isometry3, UnitQuaternion, Vector3};
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape};
use serde::{Deserialize, Serialize};

use super::{VtkFrames, make_system, n_steps};
use crate::case::{Case, CaseOutput, Check, Mode, PlotSpec, RunContext, Series};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `rigid-incline`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct InclineParams {
    /// Incline angle, degrees.
    pub angle_deg: f64,
    /// Friction coefficient between box and plane.
    pub mu: f64,
    /// Time step, s.
    pub h: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// CCP solver (`psor` or `apgd`).
    pub solver: String,
}

impl Default for InclineParams {
    fn default() -> Self {
        Self {
            angle_deg: 25.0,
            mu: 0.3,
            h: 1e-3,
            t_end: 1.0,
            solver: "psor".into(),
        }
    }
}

impl CaseParams for InclineParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new("angle_deg", "deg", "incline angle"),
        ParamInfo::new("mu", "-", "friction coefficient"),
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
            self.t_end = 0.5;
        }
    }
}

fn run(p: &InclineParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let n = n_steps(p.h, p.t_end)?;
    anyhow::ensure!(
        p.t_end > 0.2,
        "parameter `t_end` must exceed 0.2 s (the fit starts at 0.1 s), got {}",
        p.t_end
    );
    anyhow::ensure!(
        (0.0..90.0).contains(&p.angle_deg),
        "parameter `angle_deg` must be in [0, 90), got {}",
        p.angle_deg
    );
    let a = p.angle_deg.to_radians();
    let mut sys = make_system(&p.solver, 1e-9, 500)?;
    let g = sys.settings().gravity.norm();
    let tilt = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -a); // the plane rises along +x
    let normal = tilt * Vector3::z();
    let down_slope = -(tilt * Vector3::x());
    let mat = ContactMaterial::with_friction(p.mu);
    sys.add_body(RigidBodyBuilder::fixed().name("incline").collider(
        Shape::HalfSpace { normal },
        Isometry3::identity(),
        mat,
    ))?;
    let half = 0.1;
    let shape = Shape::Box {
        half_extents: Vector3::repeat(half),
    };
    let bx = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("box")
            .mass_from_shape(&shape, 1000.0)?
            .position(normal * half)
            .rotation(tilt)
            .collider(shape, Isometry3::identity(), mat),
    )?;
    let mut series = Series::new(["t", "s", "v", "v_exact"]);
    let a_exact = if a.tan() > p.mu {
        g * (a.sin() - p.mu * a.cos())
    } else {
        0.0
    };
    let (mut t1, mut s1, mut v1) = (None, 0.0, 0.0);
    let mut vtk = VtkFrames::new(ctx, (0.02 / p.h).round() as u64);
    for i in 1..=n {
        sys.step(p.h)?;
        vtk.record(i, &sys)?;
        let b = sys.body(bx)?;
        let t = sys.time();
        let s = b.position().dot(&down_slope);
        let v = b.linear_velocity().dot(&down_slope);
        series.push(&[t, s, v, a_exact * t]);
        if t1.is_none() && t >= 0.1 - 1e-12 {
            t1 = Some(t);
            s1 = s;
            v1 = v;
        }
        ctx.progress_steps(i, n);
    }
    let b = sys.body(bx)?;
    let (t_end, v_end) = (sys.time(), b.linear_velocity().dot(&down_slope));
    let t1 = t1.unwrap_or(0.0);
    let accel = (v_end - v1) / (t_end - t1);
    vtk.finish()?;
    let mut out = CaseOutput::new();
    if a_exact > 0.0 {
        out.check(Check::relative("accel", accel, a_exact, 0.02));
    } else {
        out.check(Check::absolute("accel", accel, 0.0, 1e-3));
    }
    out.metric("slide_distance", b.position().dot(&down_slope) - s1);
    out.series = series;
    out.plot = PlotSpec::new("box on an incline", "t [s]", "v along slope [m/s]", &["v"])
        .with_reference(&["v_exact"]);
    out.steps = n;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<InclineParams>::boxed(
        "rigid-incline",
        "rigid",
        "Box on an incline; acceleration along the slope against g (sin a - mu cos a), or 0 when tan a <= mu (sticking).",
        run,
    )
}
