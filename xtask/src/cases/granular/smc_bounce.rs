//! `smc-bounce`: one sphere dropped on a plate with SMC contact.
//!
//! Reference: the coefficient of restitution set in the material. The measured value is
//! the ratio of the sphere's normal speed after and before the impact. Gravity is off by
//! default so the ratio is the contact's alone (with gravity on, the impact speed changes
//! by `g t_c` during the contact, a bias of `g t_c / v` that is not the model's error).
//! The step is `t_c / steps_per_contact` with `t_c` the undamped contact duration at the
//! impact speed (Johnson 1985, eq. 11.24, for Hertz; `pi sqrt(m/k)` for Hooke).
//!
//! Besides the run with the set parameters, the case checks both force laws at
//! `e = 0.1, 0.3, 0.5, 0.7, 0.9` (the acceptance: within 2 %), reported as a sweep.

use chrono_core::contact::smc::{RollingModel, SmcPair, contact_duration};
use chrono_core::material::effective_young_modulus;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::system::{ContactMethod, SmcModel, SmcSettings};
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, SystemSettings};
use serde::{Deserialize, Serialize};

use super::make_system;
use crate::case::{Case, CaseOutput, Check, PlotSpec, RunContext, Series, SweepPoint};
use crate::params::{CaseParams, ParamCase, ParamInfo};

/// Parameters of `smc-bounce`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BounceParams {
    /// Coefficient of restitution of the material (sphere and plate).
    pub restitution: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Poisson ratio.
    pub poisson: f64,
    /// Impact speed, m/s.
    pub impact_velocity: f64,
    /// Normal force law: `hooke` or `hertz`.
    pub model: SmcModel,
    /// Sphere radius, m.
    pub radius: f64,
    /// Sphere density, kg/m^3.
    pub density: f64,
    /// Steps per (undamped) contact duration.
    pub steps_per_contact: f64,
    /// Gravity magnitude, m/s^2 (0: the contact alone).
    pub gravity: f64,
    /// Tolerance on the relative restitution error.
    pub tolerance: f64,
}

impl Default for BounceParams {
    fn default() -> Self {
        Self {
            restitution: 0.5,
            young: 1e7,
            poisson: 0.3,
            impact_velocity: 1.0,
            model: SmcModel::Hertz,
            radius: 0.01,
            density: 2500.0,
            steps_per_contact: 200.0,
            gravity: 0.0,
            tolerance: 0.02,
        }
    }
}

impl CaseParams for BounceParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "restitution",
            "-",
            "coefficient of restitution set in the material",
        ),
        ParamInfo::new("young", "Pa", "Young's modulus"),
        ParamInfo::new("poisson", "-", "Poisson ratio"),
        ParamInfo::new("impact_velocity", "m/s", "impact speed"),
        ParamInfo::new("model", "-", "normal force law: hooke | hertz"),
        ParamInfo::new("radius", "m", "sphere radius"),
        ParamInfo::new("density", "kg/m^3", "sphere density"),
        ParamInfo::new("steps_per_contact", "-", "steps per contact duration"),
        ParamInfo::new(
            "gravity",
            "m/s^2",
            "gravity magnitude (0 isolates the contact)",
        ),
        ParamInfo::new("tolerance", "-", "relative tolerance on the restitution"),
    ];
}

/// What one bounce measured.
struct Bounce {
    restitution: f64,
    contact_time: f64,
    contact_time_undamped: f64,
    steps: u64,
    series: Series,
}

fn bounce(p: &BounceParams, model: SmcModel, e: f64) -> anyhow::Result<Bounce> {
    anyhow::ensure!(
        p.impact_velocity.is_finite() && p.impact_velocity > 0.0,
        "parameter `impact_velocity` must be > 0, got {}",
        p.impact_velocity
    );
    anyhow::ensure!(
        p.steps_per_contact >= 10.0,
        "parameter `steps_per_contact` must be >= 10, got {}",
        p.steps_per_contact
    );
    anyhow::ensure!(
        p.radius > 0.0 && p.density > 0.0,
        "parameters `radius` and `density` must be > 0"
    );
    let mat = ContactMaterial::smc(p.young, p.poisson, e, 0.5);
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -p.gravity),
        envelope: 0.0,
        smc: SmcSettings {
            model,
            characteristic_velocity: p.impact_velocity,
            ..SmcSettings::default()
        },
        ..SystemSettings::default()
    };
    let mut sys = make_system(ContactMethod::Smc, settings, 1e-8, 100)?;
    sys.add_body(RigidBodyBuilder::fixed().name("plate").collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        mat,
    ))?;
    let shape = Shape::Sphere { radius: p.radius };
    let builder = RigidBodyBuilder::dynamic()
        .name("ball")
        .mass_from_shape(&shape, p.density)?;
    let mass = builder.clone().build()?.mass();
    let pair = SmcPair {
        radius: p.radius,
        mass,
        inertia: 0.0,
        rolling_inertia: 0.0,
        young: effective_young_modulus(&mat, &mat),
        shear: 0.0,
        alpha: 0.0,
        friction: 0.0,
        rolling_friction: 0.0,
        spinning_friction: 0.0,
        rolling_model: RollingModel::Relative,
        rolling_damping: 0.0,
    };
    let tc = contact_duration(model, &pair, p.impact_velocity);
    let h = tc / p.steps_per_contact;
    // Half a step of free flight inside the first contact step: the entry phase of an
    // impact is random in a real scene; 1/2 is its mean (at phase 0 or 1 the linear
    // model's damping force, which jumps at first touch, is over- or under-counted by
    // one step, an O(h / t_c) bias).
    let gap = 5.5 * h * p.impact_velocity;
    let ball = sys.add_body(
        builder
            .position(Vector3::new(0.0, 0.0, p.radius + gap))
            .linear_velocity(Vector3::new(0.0, 0.0, -p.impact_velocity))
            .collider(shape, Isometry3::identity(), mat),
    )?;
    let mut series = Series::new(["t", "overlap_over_r", "vz"]);
    let (mut v_in, mut v_out, mut touching_steps, mut touched) = (None, None, 0u64, false);
    let max_steps = (20.0 * p.steps_per_contact) as u64 + 100;
    let mut steps = 0;
    for _ in 0..max_steps {
        let before = sys.body(ball)?.linear_velocity().z;
        sys.step(h)?;
        steps += 1;
        let b = sys.body(ball)?;
        let overlap = p.radius - b.position().z;
        series.push(&[sys.time(), overlap / p.radius, b.linear_velocity().z]);
        if overlap > 0.0 {
            if !touched {
                v_in = Some(-before);
                touched = true;
            }
            touching_steps += 1;
        } else if touched {
            v_out = Some(b.linear_velocity().z);
            break;
        }
    }
    let (Some(v_in), Some(v_out)) = (v_in, v_out) else {
        anyhow::bail!(
            "the sphere did not bounce off within {max_steps} steps (e = {e}, {model:?})"
        );
    };
    Ok(Bounce {
        restitution: v_out / v_in,
        contact_time: touching_steps as f64 * h,
        contact_time_undamped: tc,
        steps,
        series,
    })
}

fn run(p: &BounceParams, ctx: &RunContext) -> anyhow::Result<CaseOutput> {
    let model = p.model;
    anyhow::ensure!(
        (0.0..=1.0).contains(&p.restitution),
        "parameter `restitution` must be in [0, 1], got {}",
        p.restitution
    );
    let main = bounce(p, model, p.restitution)?;
    let mut out = CaseOutput::new();
    out.check(Check::relative(
        "restitution_measured",
        main.restitution,
        p.restitution,
        p.tolerance,
    ));
    out.metric("contact_time", main.contact_time);
    out.metric("contact_time_undamped_theory", main.contact_time_undamped);
    let mut steps = main.steps;
    let values = [0.1, 0.3, 0.5, 0.7, 0.9];
    for (k, (m, name)) in [(SmcModel::Hooke, "hooke"), (SmcModel::Hertz, "hertz")]
        .into_iter()
        .enumerate()
    {
        for (j, e) in values.into_iter().enumerate() {
            let start = std::time::Instant::now();
            let b = bounce(p, m, e)?;
            let wall = start.elapsed().as_secs_f64().max(1e-9);
            steps += b.steps;
            out.check(Check::relative(
                format!("restitution_{name}_{e}"),
                b.restitution,
                e,
                p.tolerance,
            ));
            out.sweep.push(SweepPoint {
                label: format!("{name} e={e}"),
                error: (b.restitution - e).abs() / e,
                wall_s: wall,
            });
            ctx.progress((k * values.len() + j + 1) as f64 / (2 * values.len()) as f64);
        }
    }
    out.series = main.series;
    out.plot = PlotSpec::new(
        "sphere bouncing on a plate (SMC)",
        "t [s]",
        "vz [m/s]",
        &["vz"],
    );
    out.steps = steps;
    Ok(out)
}

/// The case.
pub fn case() -> Box<dyn Case> {
    ParamCase::<BounceParams>::boxed(
        "smc-bounce",
        "granular",
        "One sphere dropped on a plate with SMC contact (Hooke or Hertz); measured restitution against the material's, for e = 0.1..0.9 and both force laws.",
        run,
    )
}
