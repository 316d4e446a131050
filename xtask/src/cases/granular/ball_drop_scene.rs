//! `granular-ball-drop`'s scene: the library's [`ImpactBed`], settled once per method, and
//! one [`BallDrop`] on a rebuilt copy of it (see [`super::ball_drop`] for the case, its
//! checks and references), the case's parameters mapped onto them.

use std::ops::Deref;

use chrono_core::granular::impact::{Penetration, SettledBed};
use chrono_core::granular::{BallDrop, ImpactBed};
use chrono_core::system::{ContactMethod, SmcSettings};
use chrono_core::{ContactMaterial, System, SystemSettings};

use super::ball_drop::BallDropParams;
use super::make_system;

/// The settled bed of one method and what settling it cost.
pub(super) struct Bed {
    pub(super) bed: SettledBed,
    pub(super) wall_s: f64,
}

impl Deref for Bed {
    type Target = SettledBed;
    fn deref(&self) -> &SettledBed {
        &self.bed
    }
}

/// One drop and what it cost.
pub(super) struct Drop {
    pub(super) drop: Penetration,
    pub(super) wall_s: f64,
}

impl Deref for Drop {
    type Target = Penetration;
    fn deref(&self) -> &Penetration {
        &self.drop
    }
}

fn material(p: &BallDropParams) -> ContactMaterial {
    ContactMaterial::smc(p.young, 0.3, p.restitution, p.mu)
        .with_rolling_friction(p.rolling_friction)
}

fn settings(p: &BallDropParams, v_impact: f64) -> SystemSettings {
    SystemSettings {
        envelope: 0.05 * p.grain_diameter,
        // The step check must cover the fastest contact, the ball's impact.
        smc: SmcSettings {
            characteristic_velocity: v_impact.max(1.0),
            ..SmcSettings::default()
        },
        rolling_model: p.rolling_model,
        ..SystemSettings::default()
    }
}

/// Half width of the box (m).
pub(super) fn half_width(p: &BallDropParams) -> f64 {
    0.5 * p.bed_width * p.ball_diameter
}

/// The bed of the case.
fn impact_bed(p: &BallDropParams) -> ImpactBed {
    ImpactBed {
        seed: p.seed,
        h: p.h,
        settle_ke: p.settle_ke,
        t_settle: p.t_settle,
        ..ImpactBed::new(
            half_width(p),
            p.bed_depth * p.ball_diameter,
            p.grain_diameter,
            p.grain_density,
            material(p),
        )
    }
}

/// A system of `method` for the case's scenes (`v_max`: the fastest impact, m/s).
fn system(p: &BallDropParams, method: ContactMethod, v_max: f64) -> anyhow::Result<System> {
    let mut sys = make_system(method, settings(p, v_max), p.tolerance, p.max_iterations)?;
    sys.set_solver(crate::cases::rigid::make_solver(
        &p.solver,
        p.tolerance,
        p.max_iterations,
    )?);
    Ok(sys)
}

/// Settle the bed from a jittered lattice; the grains at rest.
pub(super) fn settle_bed(
    p: &BallDropParams,
    method: ContactMethod,
    v_max: f64,
) -> anyhow::Result<Bed> {
    let start = std::time::Instant::now();
    let mut sys = system(p, method, v_max)?;
    let bed = impact_bed(p).settle(&mut sys).map_err(|e| {
        anyhow::anyhow!("granular-ball-drop: parameter `t_settle` or `settle_ke`: {e}")
    })?;
    Ok(Bed {
        bed,
        wall_s: start.elapsed().as_secs_f64(),
    })
}

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
    progress: impl FnMut(f64),
) -> anyhow::Result<Drop> {
    let start = std::time::Instant::now();
    let mut sys = system(p, method, v_max)?;
    let ball = BallDrop {
        diameter: p.ball_diameter,
        density: p.ball_density,
        height: impact.height,
        offset: [impact.offset.0, impact.offset.1],
        t_drop: p.t_drop,
        record_dt,
    };
    let drop = ball.run(&mut sys, &impact_bed(p), &bed.bed, progress)?;
    Ok(Drop {
        drop,
        wall_s: start.elapsed().as_secs_f64(),
    })
}
