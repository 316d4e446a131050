//! A ball dropped into a settled granular bed, and how deep it goes.
//!
//! The reference is the penetration law of J. S. Uehara, M. A. Ambroso, R. P. Ojha and
//! D. J. Durian, "Low-speed impact craters in loose granular media", Phys. Rev. Lett. 90,
//! 194301 (2003) (erratum Phys. Rev. Lett. 91, 149902):
//!
//! `d = 0.14 / mu (rho_b / rho_g)^(1/2) D^(2/3) H^(1/3)`,
//!
//! the depth `d` of the ball's bottom below the initial surface once it has stopped, for a
//! ball of diameter `D` and density `rho_b` in a medium of bulk density `rho_g` and angle
//! of repose `atan(mu)`, from a total drop distance `H` (free fall plus penetration).
//!
//! An [`ImpactBed`] settles a bed in a square box once ([`ImpactBed::settle`]); its grains
//! ([`SettledBed`]) are rebuilt in a fresh system for every drop, so each drop starts from
//! the same bed (a [`System`] is not `Clone`; rebuilding is deterministic). A [`BallDrop`]
//! lets the rebuilt bed find its contacts again, measures the surface and the bulk
//! density, puts the ball just above the surface at its free-fall speed (the free fall
//! itself is not simulated) and runs until the ball has been at rest for [`REST_TIME`]
//! ([`BallDrop::run`], a [`Penetration`]).

use nalgebra::{Isometry3, Vector3};

use super::bed::{GrainBed, Settle};
use super::fill::{Grain, Region};
use super::probe::{bulk_density, surface_height};
use super::{add_box_container, add_grains, step_size};
use crate::body::{BodyHandle, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_non_negative, check_positive};
use crate::material::ContactMaterial;
use crate::shape::Shape;
use crate::system::{ContactMethod, System};

/// Under NSC with the automatic step ([`ImpactBed::h`] = 0), the drop's step is at most
/// the time in which the ball, at its impact speed, travels this fraction of a grain
/// diameter: `h = min(1 ms, NSC_IMPACT_TRAVEL d / v)`. An NSC step sees only the contacts
/// found at its start (within the envelope, 0.05 d in the case), so a ball that travels a
/// large part of a grain per step overruns the grains ahead and the stabilization pushes
/// it back: at 0.5 m (3.1 m/s, 0.63 d per 1 ms step) the depth was 0.65-0.8 of the
/// resolved one and fell as the solver converged; at 0.16 d per step it is within 3 % of
/// the depth at 0.08 d (docs/validation-granular.md, "The NSC step of an impact").
pub const NSC_IMPACT_TRAVEL: f64 = 0.2;

/// The rest window, s: a drop ends once the ball has stayed below 1 % of its impact speed
/// for this long, and [`Penetration::late_drift`] is the depth's change over it.
pub const REST_TIME: f64 = 0.01;

/// A bed of grains (diameters uniform in `[0.9 d, d]`) settled in a square open box
/// `|x|, |y| < half_width` with its floor at `z = 0` (Z up), from a loose jittered lattice
/// 2.6 times the wanted depth (sites 1.25 d apart, solid fraction ~0.23, settling to
/// ~0.6), until its kinetic energy per grain is below `settle_ke m g d`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactBed {
    /// Half the side of the square box, m.
    pub half_width: f64,
    /// Depth of the settled bed wanted, m.
    pub depth: f64,
    /// Largest grain diameter `d`, m.
    pub grain_diameter: f64,
    /// Grain density, kg/m^3.
    pub grain_density: f64,
    /// Contact material of the grains, the box and the ball.
    pub material: ContactMaterial,
    /// Seed of the packing (radii, jitter, kick).
    pub seed: u64,
    /// Time step, s (0: [`step_size`]'s, 1 ms for NSC, the SMC stability limit for SMC).
    pub h: f64,
    /// The bed counts as settled when its kinetic energy per grain is below this, in units
    /// of `m g d`.
    pub settle_ke: f64,
    /// Longest settling time, s (an error past it).
    pub t_settle: f64,
}

/// A settled bed: the grains at rest, to rebuild for each drop.
#[derive(Debug, Clone, PartialEq)]
pub struct SettledBed {
    /// The grains (centre, radius) at rest.
    pub grains: Vec<Grain>,
    /// Steps the settling took.
    pub steps: u64,
    /// Simulated time of the settling, s.
    pub time: f64,
}

impl ImpactBed {
    /// A bed `depth` (m) deep in a box `2 half_width` (m) wide of grains of diameter `d`
    /// (m), density and material; seed 1, the default step, settled below `1e-4 m g d`
    /// within 1.5 s.
    pub fn new(
        half_width: f64,
        depth: f64,
        grain_diameter: f64,
        grain_density: f64,
        material: ContactMaterial,
    ) -> Self {
        Self {
            half_width,
            depth,
            grain_diameter,
            grain_density,
            material,
            seed: 1,
            h: 0.0,
            settle_ke: 1e-4,
            t_settle: 1.5,
        }
    }

    /// Errors naming the field (`impact_bed.*`) unless the bed can be built.
    pub fn validate(&self) -> Result<()> {
        check_positive("impact_bed.half_width", self.half_width)?;
        check_positive("impact_bed.depth", self.depth)?;
        check_positive("impact_bed.grain_diameter", self.grain_diameter)?;
        check_positive("impact_bed.grain_density", self.grain_density)?;
        check_positive("impact_bed.settle_ke", self.settle_ke)?;
        check_positive("impact_bed.t_settle", self.t_settle)?;
        check_non_negative("impact_bed.h", self.h)?;
        self.material.validate()
    }

    /// Adds the box (a floor at `z = 0` and four walls, one fixed body "bed box") to `sys`.
    pub fn add_box(&self, sys: &mut System) -> Result<BodyHandle> {
        self.validate()?;
        let (hw, d) = (self.half_width, self.grain_diameter);
        let top = 3.0 * self.depth + 4.0 * d;
        add_box_container(
            sys,
            "bed box",
            Vector3::new(-hw, -hw, 0.0),
            Vector3::new(hw, hw, top + 2.0 * d),
            self.material,
        )
    }

    /// Adds the box to `sys` (an empty system the caller made: contact method, solver,
    /// settings), pours the grains and settles them; the grains at rest. An error names
    /// `settle.timeout` if the bed did not settle within `t_settle`.
    pub fn settle(&self, sys: &mut System) -> Result<SettledBed> {
        self.add_box(sys)?;
        let d = self.grain_diameter;
        let (hw, depth) = (self.half_width, self.depth);
        let r = 0.5 * d;
        let g = sys.settings().gravity.norm();
        let spec = GrainBed {
            seed: self.seed,
            // The bed falls ~1.6 depths: no test before it has landed.
            settle: Settle::KineticEnergy {
                below: self.settle_ke,
                check_every: 0.01,
                not_before: 2.0 * (2.0 * 1.6 * depth / g).sqrt(),
                timeout: self.t_settle,
            },
            ..GrainBed::new(
                Region::Box {
                    lower: Vector3::new(-hw, -hw, 0.5 * r),
                    upper: Vector3::new(hw, hw, 2.6 * depth),
                },
                0.9 * r,
                r,
                self.grain_density,
                self.material,
            )
        };
        let bed = spec.pour(sys)?;
        let h = step_size(self.h, sys.settings().contact_method, sys);
        let settled = spec.settle(sys, &bed, h, |_, _| Ok::<(), ChronoError>(()))?;
        Ok(SettledBed {
            grains: bed.grains(sys)?,
            steps: settled.steps,
            time: sys.time(),
        })
    }

    /// Adds the box and the `grains` of a settled bed to `sys` (an empty system); their
    /// handles, in order.
    pub fn rebuild(&self, sys: &mut System, grains: &[Grain]) -> Result<Vec<BodyHandle>> {
        self.add_box(sys)?;
        add_grains(sys, grains, self.grain_density, self.material)
    }
}

/// One drop of a ball onto a settled bed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallDrop {
    /// Ball diameter `D`, m.
    pub diameter: f64,
    /// Ball density `rho_b`, kg/m^3.
    pub density: f64,
    /// Free-fall height `h` of the ball's bottom above the bed's surface, m (more than
    /// half a grain diameter: the ball starts `d / 2` above the surface).
    pub height: f64,
    /// Horizontal offset `(x, y)` of the impact point from the bed's centre, m.
    pub offset: [f64; 2],
    /// Longest simulated time after release, s (the drop ends once the ball is at rest).
    pub t_drop: f64,
    /// Interval of the recorded depth ([`Penetration::series`]), s.
    pub record_dt: f64,
}

/// What one drop measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Penetration {
    /// Depth of the ball's bottom below the surface at the end, m.
    pub depth: f64,
    /// Deepest depth reached, m.
    pub max_depth: f64,
    /// The bed's surface before the impact, m: the mean, over `d x d` columns `2 d` from
    /// the walls, of the top of the highest grain ([`surface_height`]).
    pub surface: f64,
    /// Standard deviation of the columns' tops, m.
    pub roughness: f64,
    /// Bulk density `rho_g` of the bed, kg/m^3: the grains' mass in the band of centres
    /// from `2 d` above the floor to `2 d` below the surface, `2 d` from the walls, over its
    /// volume ([`bulk_density`]).
    pub bulk_density: f64,
    /// Ball speed at the end, m/s.
    pub end_speed: f64,
    /// How much the depth changed over the last [`REST_TIME`] of the drop, m (infinite if
    /// the drop was shorter).
    pub late_drift: f64,
    /// Impact speed `sqrt(2 g h)`, m/s.
    pub impact_speed: f64,
    /// Time after which the depth stays within `d / 10` of its end value, s.
    pub stop_time: f64,
    /// Steps taken (the rebuilt bed's relaxation and the drop).
    pub steps: u64,
    /// Depth (m) every `record_dt` from release to `t_drop` (held at the end value once
    /// the ball has stopped).
    pub series: Vec<f64>,
}

impl BallDrop {
    /// The automatic NSC step of the drop on grains of diameter `d` (m) under gravity `g`
    /// (m/s^2): `min(1 ms, NSC_IMPACT_TRAVEL d / sqrt(2 g h))`, s (see
    /// [`NSC_IMPACT_TRAVEL`]).
    pub fn nsc_step(&self, d: f64, g: f64) -> f64 {
        let v = (2.0 * g * self.height).sqrt();
        if v > 0.0 {
            (NSC_IMPACT_TRAVEL * d / v).min(1e-3)
        } else {
            1e-3
        }
    }

    /// Errors naming the field (`ball_drop.*`) unless the drop can run on beds of grains
    /// of diameter `d` (m).
    pub fn validate(&self, d: f64) -> Result<()> {
        check_positive("ball_drop.diameter", self.diameter)?;
        check_positive("ball_drop.density", self.density)?;
        check_positive("ball_drop.t_drop", self.t_drop)?;
        check_positive("ball_drop.record_dt", self.record_dt)?;
        if !(self.height.is_finite() && self.height > 0.5 * d) {
            return Err(ChronoError::invalid(
                "ball_drop.height",
                self.height,
                format!("must exceed half a grain diameter ({})", 0.5 * d),
            ));
        }
        Ok(())
    }

    /// Rebuilds `settled` from `bed` in `sys` (an empty system the caller made), lets it
    /// find its contacts again for 20 ms (a rebuilt bed has no tangential history (SMC) or
    /// warm start (NSC)), measures the surface `z_s` and `rho_g`, puts the ball with its
    /// bottom `d / 2` above `z_s` falling at `sqrt(2 g (h - d / 2))` and steps until it
    /// has stayed below 1 % of its impact speed for [`REST_TIME`], at most `t_drop`.
    /// `progress(f)` gets the fraction of `t_drop` done after each step of the drop.
    ///
    /// The step is the bed's ([`ImpactBed::h`]; by default SMC's stability limit, taken
    /// again once the ball is in): under SMC, give `sys` a
    /// [`SmcSettings::characteristic_velocity`](crate::system::SmcSettings::characteristic_velocity) of at least the
    /// impact speed, so the limit covers the ball's impact.
    pub fn run(
        &self,
        sys: &mut System,
        bed: &ImpactBed,
        settled: &SettledBed,
        mut progress: impl FnMut(f64),
    ) -> Result<Penetration> {
        let d = bed.grain_diameter;
        self.validate(d)?;
        let hw = bed.half_width;
        let handles = bed.rebuild(sys, &settled.grains)?;
        let g = sys.settings().gravity.norm();
        let h = step_size(bed.h, sys.settings().contact_method, sys);
        let relax = (0.02 / h).round().max(1.0) as u64;
        for _ in 0..relax {
            sys.step(h)?;
        }
        let now = handles
            .iter()
            .zip(&settled.grains)
            .map(|(&b, g)| Ok((sys.body(b)?.position(), g.radius)))
            .collect::<Result<Vec<(Vector3<f64>, f64)>>>()?;
        let (zs, roughness) = surface_height(&now, hw, d, 2.0 * d);
        let inner = hw - 2.0 * d;
        let band = Region::Box {
            lower: Vector3::new(-inner, -inner, 2.0 * d),
            upper: Vector3::new(inner, inner, zs - 2.0 * d),
        };
        let rho_g = bulk_density(
            now.iter().map(|&(x, r)| {
                (
                    x,
                    bed.grain_density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3),
                )
            }),
            &band,
        );
        let radius = 0.5 * self.diameter;
        let gap = 0.5 * d;
        let v0 = (2.0 * g * (self.height - gap)).sqrt();
        let shape = Shape::Sphere { radius };
        let ball = sys.add_body(
            RigidBodyBuilder::dynamic()
                .name("ball")
                .mass_from_shape(&shape, self.density)?
                .position(Vector3::new(
                    self.offset[0],
                    self.offset[1],
                    zs + gap + radius,
                ))
                .linear_velocity(Vector3::new(0.0, 0.0, -v0))
                .collider(shape, Isometry3::identity(), bed.material),
        )?;
        // The ball's contacts are the fastest: SMC's limit may have changed; under NSC
        // the automatic step resolves the impact (`NSC_IMPACT_TRAVEL`).
        let method = sys.settings().contact_method;
        let mut h = step_size(bed.h, method, sys);
        if method == ContactMethod::Nsc && bed.h <= 0.0 {
            h = h.min(self.nsc_step(d, g));
        }
        let n = (self.t_drop / h).round().max(1.0) as u64;
        let every = ((self.record_dt / h).round() as u64).max(1);
        let rest_speed = 0.01 * (2.0 * g * self.height).sqrt();
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
        let (late_drift, stop_time) = close_record(
            &mut series,
            depth,
            (n / every) as usize,
            back,
            d,
            self.record_dt,
        );
        Ok(Penetration {
            depth,
            stop_time,
            max_depth,
            surface: zs,
            roughness,
            bulk_density: rho_g,
            end_speed: b.linear_velocity().norm(),
            late_drift,
            impact_speed: (2.0 * g * self.height).sqrt(),
            steps: relax + taken,
            series,
        })
    }
}

/// Closes a drop's depth record `series` (m, one sample per record interval `record_dt`,
/// s) whose end depth is `depth` (m): the late drift (the depth's change over the last
/// `back` samples; infinite with fewer), the stop time (s, after which the depth stays
/// within `d / 10` of `depth`, `d` the grain diameter, m), and the record held at `depth`
/// up to `len` samples.
fn close_record(
    series: &mut Vec<f64>,
    depth: f64,
    len: usize,
    back: usize,
    d: f64,
    record_dt: f64,
) -> (f64, f64) {
    let late_drift = series
        .len()
        .checked_sub(back + 1)
        .map_or(f64::INFINITY, |i| (depth - series[i]).abs());
    // At rest the depth stays, so the record runs on to `t_drop` (equal lengths).
    series.resize(len, depth);
    let stopped = series
        .iter()
        .rposition(|z| (z - depth).abs() > 0.1 * d)
        .map_or(0, |i| i + 1);
    (late_drift, stopped as f64 * record_dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_of_a_ball_that_stops() {
        // Sinks 1 mm per sample to 6 mm, creeps 0.1 mm more in 4 samples, then stops: the
        // drift over the last 3 samples, the stop after the last move past d / 10 = 0.5 mm
        // from the end, the record held at the end depth.
        let mut series = vec![0.001, 0.002, 0.003, 0.004, 0.005, 0.006];
        series.extend([0.006025, 0.00605, 0.006075, 0.0061]);
        let (drift, stop) = close_record(&mut series, 0.0061, 20, 3, 0.005, 1e-3);
        assert!((drift - 0.000075).abs() < 1e-12, "{drift}");
        assert!((stop - 0.005).abs() < 1e-12, "{stop}");
        assert_eq!(series.len(), 20);
        assert_eq!(series[19], 0.0061);
        // Shorter than the rest window: no drift measured.
        let (drift, _) = close_record(&mut vec![0.001], 0.001, 2, 3, 0.005, 1e-3);
        assert!(drift.is_infinite());
    }

    #[test]
    fn nsc_step_resolves_the_impact() {
        let drop = |height| BallDrop {
            diameter: 0.03,
            density: 2500.0,
            height,
            offset: [0.0; 2],
            t_drop: 0.15,
            record_dt: 1e-3,
        };
        let (d, g) = (0.005, 9.81);
        // Low drops keep the bed's 1 ms; at 0.5 m the ball travels 0.2 d per step.
        assert_eq!(drop(0.03).nsc_step(d, g), 1e-3);
        let h = drop(0.5).nsc_step(d, g);
        assert!((h * (2.0 * g * 0.5f64).sqrt() / d - NSC_IMPACT_TRAVEL).abs() < 1e-12);
        assert!(drop(0.24).nsc_step(d, g) > h);
    }

    #[test]
    fn bad_fields_are_named() {
        let mat = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
        let bed = ImpactBed::new(0.05, 0.05, 0.005, 2500.0, mat);
        assert!(bed.validate().is_ok());
        let e = ImpactBed { depth: 0.0, ..bed }
            .validate()
            .unwrap_err()
            .to_string();
        assert!(e.contains("impact_bed.depth"), "{e}");
        let ball = BallDrop {
            diameter: 0.02,
            density: 2500.0,
            height: 0.002,
            offset: [0.0, 0.0],
            t_drop: 0.1,
            record_dt: 1e-3,
        };
        let e = ball.validate(0.005).unwrap_err().to_string();
        assert!(e.contains("ball_drop.height") && e.contains("0.002"), "{e}");
        assert!(
            BallDrop {
                height: 0.05,
                ..ball
            }
            .validate(0.005)
            .is_ok()
        );
    }
}
