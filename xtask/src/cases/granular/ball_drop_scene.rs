//! `granular-ball-drop`'s scene: the bed settled once per method, and one drop of the ball
//! on a rebuilt copy of it (see [`super::ball_drop`] for the case, its checks and references).

use chrono_core::granular::probe::{bulk_density, surface_height};
use chrono_core::granular::{Grain, GrainBed, Region, Settle, add_box_container, add_grains};
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::system::{ContactMethod, SmcSettings};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

use super::ball_drop::BallDropParams;
use super::make_system;

/// The settled bed of one method: grain positions at rest and what was measured on it.
pub(super) struct Bed {
    pub(super) grains: Vec<Grain>,
    pub(super) steps: u64,
    pub(super) settle_time: f64,
    pub(super) wall_s: f64,
}

/// One drop: the depth at the end and over time.
pub(super) struct Drop {
    pub(super) depth: f64,
    pub(super) max_depth: f64,
    pub(super) surface: f64,
    pub(super) roughness: f64,
    pub(super) bulk_density: f64,
    pub(super) end_speed: f64,
    /// How much the depth changed over the last `REST_TIME` of the drop, m.
    pub(super) late_drift: f64,
    pub(super) impact_speed: f64,
    pub(super) stop_time: f64,
    pub(super) steps: u64,
    pub(super) wall_s: f64,
    pub(super) series: Vec<f64>,
}

pub(super) fn material(p: &BallDropParams) -> anyhow::Result<ContactMaterial> {
    let mat = ContactMaterial::smc(p.young, 0.3, p.restitution, p.mu)
        .with_rolling_friction(p.rolling_friction);
    mat.validate()?;
    Ok(mat)
}

pub(super) fn settings(p: &BallDropParams, v_impact: f64) -> anyhow::Result<SystemSettings> {
    Ok(SystemSettings {
        envelope: 0.05 * p.grain_diameter,
        // The step check must cover the fastest contact, the ball's impact.
        smc: SmcSettings {
            characteristic_velocity: v_impact.max(1.0),
            ..SmcSettings::default()
        },
        rolling_model: p.rolling_model,
        ..SystemSettings::default()
    })
}

/// Half width of the box (m).
pub(super) fn half_width(p: &BallDropParams) -> f64 {
    0.5 * p.bed_width * p.ball_diameter
}

pub(super) fn step_size(p: &BallDropParams, sys: &System, method: ContactMethod) -> f64 {
    super::step_size(p.h, method, sys)
}

/// Settle the bed from a jittered lattice; the grains at rest.
pub(super) fn settle_bed(
    p: &BallDropParams,
    method: ContactMethod,
    v_max: f64,
) -> anyhow::Result<Bed> {
    let start = std::time::Instant::now();
    let d = p.grain_diameter;
    let hw = half_width(p);
    let depth = p.bed_depth * p.ball_diameter;
    let mut sys = make_system(method, settings(p, v_max)?, p.tolerance, p.max_iterations)?;
    let mat = material(p)?;
    let top = 3.0 * depth + 4.0 * d;
    let (lower, upper) = (
        Vector3::new(-hw, -hw, 0.0),
        Vector3::new(hw, hw, top + 2.0 * d),
    );
    add_box_container(&mut sys, "bed box", lower, upper, mat)?;
    // A loose lattice (sites 1.25 d apart, solid fraction ~0.23) settles to ~0.6: fill
    // 2.6x deeper (as `granular-hopper`).
    let r = 0.5 * d;
    let g = sys.settings().gravity.norm();
    let spec = GrainBed {
        seed: p.seed,
        // The bed falls ~1.6 depths: do not test before it has landed.
        settle: Settle::KineticEnergy {
            below: p.settle_ke,
            check_every: 0.01,
            not_before: 2.0 * (2.0 * 1.6 * depth / g).sqrt(),
            timeout: p.t_settle,
        },
        ..GrainBed::new(
            Region::Box {
                lower: Vector3::new(-hw, -hw, 0.5 * r),
                upper: Vector3::new(hw, hw, 2.6 * depth),
            },
            0.9 * r,
            r,
            p.grain_density,
            mat,
        )
    };
    let bed = spec.pour(&mut sys)?;
    let h = step_size(p, &sys, method);
    let settled = spec
        .settle(&mut sys, &bed, h, |_, _| Ok::<(), anyhow::Error>(()))
        .map_err(|e| {
            anyhow::anyhow!("granular-ball-drop: parameter `t_settle` or `settle_ke`: {e}")
        })?;
    let grains = bed.grains(&sys)?;
    let steps = settled.steps;
    Ok(Bed {
        grains,
        steps,
        settle_time: sys.time(),
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// The rest window: a drop ends once the ball has stayed below 1 % of its impact speed for
/// this long, and at the end the depth must not have changed over it, s.
pub(super) const REST_TIME: f64 = 0.01;

/// Where and from how high the ball falls.
#[derive(Clone, Copy, Debug)]
pub(super) struct Impact {
    /// Free-fall height of the ball's bottom above the surface, m.
    pub(super) height: f64,
    /// Horizontal offset of the impact point from the bed's centre, m.
    pub(super) offset: (f64, f64),
}

/// Impact point `k` of `p.impact_points` from free-fall height `height`: the centre, then
/// `impact_points - 1` points evenly on a circle of radius `impact_spread d`.
pub(super) fn impact(p: &BallDropParams, height: f64, k: usize) -> Impact {
    let offset = if k == 0 || p.impact_points < 2 {
        (0.0, 0.0)
    } else {
        let a = std::f64::consts::TAU * (k - 1) as f64 / (p.impact_points - 1) as f64;
        let r = p.impact_spread * p.grain_diameter;
        (r * a.cos(), r * a.sin())
    };
    Impact { height, offset }
}

/// One drop on the settled `bed`.
pub(super) fn drop_ball(
    p: &BallDropParams,
    method: ContactMethod,
    bed: &Bed,
    impact: Impact,
    v_max: f64,
    record_dt: f64,
    mut progress: impl FnMut(f64),
) -> anyhow::Result<Drop> {
    let start = std::time::Instant::now();
    let d = p.grain_diameter;
    let hw = half_width(p);
    let mut sys = make_system(method, settings(p, v_max)?, p.tolerance, p.max_iterations)?;
    let mat = material(p)?;
    let top = 3.0 * p.bed_depth * p.ball_diameter + 4.0 * d;
    add_box_container(
        &mut sys,
        "bed box",
        Vector3::new(-hw, -hw, 0.0),
        Vector3::new(hw, hw, top + 2.0 * d),
        mat,
    )?;
    let handles = add_grains(&mut sys, &bed.grains, p.grain_density, mat)?;
    // The rebuilt bed has no tangential history (SMC) or warm start (NSC): let it find
    // its contacts again before measuring the surface.
    let g = sys.settings().gravity.norm();
    let h = step_size(p, &sys, method);
    let relax = (0.02 / h).round().max(1.0) as u64;
    for _ in 0..relax {
        sys.step(h)?;
    }
    let state = |sys: &System, hs: &[BodyHandle]| -> anyhow::Result<Vec<(Vector3<f64>, f64)>> {
        hs.iter()
            .zip(&bed.grains)
            .map(|(&b, g)| Ok((sys.body(b)?.position(), g.radius)))
            .collect()
    };
    let now = state(&sys, &handles)?;
    let (zs, roughness) = surface_height(&now, hw, d, 2.0 * d);
    // Bulk density in the band of centres `[2 d, z_s - 2 d]`, `2 d` from the walls.
    let inner = hw - 2.0 * d;
    let band = Region::Box {
        lower: Vector3::new(-inner, -inner, 2.0 * d),
        upper: Vector3::new(inner, inner, zs - 2.0 * d),
    };
    let rho_g = bulk_density(
        now.iter().map(|&(x, r)| {
            (
                x,
                p.grain_density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3),
            )
        }),
        &band,
    );
    let radius = 0.5 * p.ball_diameter;
    let gap = 0.5 * d;
    let v0 = (2.0 * g * (impact.height - gap)).sqrt();
    let shape = Shape::Sphere { radius };
    let ball = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("ball")
            .mass_from_shape(&shape, p.ball_density)?
            .position(Vector3::new(
                impact.offset.0,
                impact.offset.1,
                zs + gap + radius,
            ))
            .linear_velocity(Vector3::new(0.0, 0.0, -v0))
            .collider(shape, Isometry3::identity(), mat),
    )?;
    let h = step_size(p, &sys, method);
    let n = (p.t_drop / h).round().max(1.0) as u64;
    let every = ((record_dt / h).round() as u64).max(1);
    // The drop ends early once the ball has stayed below 1 % of its impact speed for
    // `REST_TIME`.
    let rest_speed = 0.01 * (2.0 * g * impact.height).sqrt();
    let rest_steps = (REST_TIME / h).ceil() as u64;
    let mut still = 0;
    let mut series = Vec::new();
    let mut max_depth = f64::NEG_INFINITY;
    let mut taken = 0;
    for i in 1..=n {
        sys.step(h)?;
        taken = i;
        let b = sys.body(ball)?;
        let z = b.position().z - radius;
        max_depth = max_depth.max(zs - z);
        if i % every == 0 {
            series.push(zs - z);
        }
        progress(i as f64 / n as f64);
        still = if b.linear_velocity().norm() < rest_speed {
            still + 1
        } else {
            0
        };
        if still >= rest_steps {
            break;
        }
    }
    let b = sys.body(ball)?;
    let depth = zs - (b.position().z - radius);
    let back = (REST_TIME / (every as f64 * h)).round() as usize;
    let late_drift = series
        .len()
        .checked_sub(back + 1)
        .map_or(f64::INFINITY, |i| (depth - series[i]).abs());
    // At rest: the depth stays, so the record runs on to `t_drop` (equal lengths to plot).
    series.resize((n / every) as usize, depth);
    // The time after which the depth stays within a tenth of a grain diameter of its end
    // value: how much of `t_drop` the stop took.
    let settled = series
        .iter()
        .rposition(|z| (z - depth).abs() > 0.1 * d)
        .map_or(0, |i| i + 1);
    Ok(Drop {
        depth,
        stop_time: settled as f64 * record_dt,
        max_depth,
        surface: zs,
        roughness,
        bulk_density: rho_g,
        end_speed: b.linear_velocity().norm(),
        late_drift,
        impact_speed: (2.0 * g * impact.height).sqrt(),
        steps: relax + taken,
        wall_s: start.elapsed().as_secs_f64(),
        series,
    })
}
