//! A rigid wheel driven at fixed slip on a granular bed (DEM-P, SMC contact): the
//! single-wheel test of terramechanics (J. Y. Wong, "Theory of Ground Vehicles", 4th ed.,
//! Wiley 2008, ch. 2) on grains instead of a continuum.
//!
//! The bin is a slab: `[0, L]` along the travel `x`, `slab_thickness` across (`y`, between
//! two frictionless walls), a floor at `z = 0` (the grains' own friction) and frictionless
//! end walls; its length leaves `R` behind the wheel, its forward travel and `2 R` ahead
//! (the lay-out of the MPM soil bin of `chrono-mpm`). The grains (diameters uniform in
//! `[size_ratio d, d]`) are poured from a jittered lattice and settled; their solid fraction
//! `phi` is measured, and the bed is rebuilt with the grain density `rho_bulk / phi`, so
//! that its bulk density is the one asked for ([`WheelBin::prepare`]).
//!
//! The wheel is a kinematic cylinder of radius `R` across the slab (axis along `y`), in
//! SMC contact with the grains at the rim friction `tan(delta)`. Its spin `omega` (about
//! `+y`, rolling towards `+x`) and forward speed are prescribed at the slip
//!
//! ```text
//! s = 1 - v / (omega R),   omega R = U (the rim speed),   v = (1 - s) U
//! ```
//!
//! and its height is free under the load: the slab's share of the wheel (mass
//! `M = W / g` times `t / b`, `t` the slab thickness, `b` the wheel width) obeys
//!
//! ```text
//! M dv_z/dt = F_z - f(t) W t / b
//! ```
//!
//! with `F_z` the grains' vertical force on the rim (the SMC contact forces of the step) and
//! `f` the load's ramp, integrated by symplectic Euler with the grains' step. The run
//! ([`WheelBin::run`]): the load ramps up over `load_time` with the wheel at rest (the
//! static sinkage), stays on for `hold_time` (0 by default), the rim speed ramps up over
//! `ramp_time`, then the wheel drives for
//! `rim_travel R` of rim travel; the steady values are the means over the last
//! `average_fraction` of the drive, scaled to the full width by `b / t` (plane strain: the
//! slab stands for a slice of a wide wheel):
//!
//! - sinkage `z`: the rim's lowest point below the bed's initial surface, m;
//! - drawbar pull `DP = F_x`, the grains' force on the wheel along the travel, N;
//! - driving torque `T`, the torque the drive applies about the axle to hold `omega`
//!   against the grains (minus their torque on the rim), N m.

use nalgebra::{Isometry3, Vector3};

use super::bed::{GrainBed, Kick, Settle};
use super::fill::{Grain, Region};
use super::{add_grains, step_size};
use crate::body::{BodyHandle, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_non_negative, check_positive};
use crate::material::ContactMaterial;
use crate::shape::Shape;
use crate::system::{ContactMethod, System};

/// The time (s) a rebuilt bed is stepped before it is measured: a rebuilt bed has no
/// tangential contact history and finds its contacts again.
pub const RELAX_TIME: f64 = 0.02;

/// The smooth ramp `(1 - cos(pi t / T)) / 2` from 0 at `t = 0` to 1 at `t >= T` (1 at
/// once for `T = 0`): no jerk at either end.
pub fn smooth_ramp(t: f64, ramp_time: f64) -> f64 {
    if t < ramp_time {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp_time).cos())
    } else {
        1.0
    }
}

/// The single-wheel test on a granular slab (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelBin {
    /// Wheel radius `R`, m.
    pub wheel_radius: f64,
    /// Wheel width `b`, m: the full-width forces are the slab's times `b / t`.
    pub wheel_width: f64,
    /// Vertical load `W` on the full wheel, N (> 0; the wheel's weight).
    pub load: f64,
    /// Slip `s = 1 - v / (omega R)`, in `[-1, 1]`.
    pub slip: f64,
    /// Rim speed `U = omega R`, m/s.
    pub rim_speed: f64,
    /// Rim–grain Coulomb friction coefficient `tan(delta)` (overrides the minimum rule of
    /// [`ContactMaterial::combine`] for the rim's contacts).
    pub rim_friction: f64,
    /// Largest grain diameter `d`, m.
    pub grain_diameter: f64,
    /// Smallest over largest grain diameter, in (0, 1] (a spread keeps the packing from
    /// ordering against the flat walls).
    pub size_ratio: f64,
    /// Bulk density of the bed wanted, kg/m^3 (the grain density is set to it over the
    /// measured solid fraction).
    pub bulk_density: f64,
    /// The grains' contact material (also the rim's stiffness; the walls take it with no
    /// friction).
    pub material: ContactMaterial,
    /// Slab thickness `t` across the travel, m (at least two grain diameters).
    pub slab_thickness: f64,
    /// Bed depth wanted, m (the settled depth is measured: [`WheelRun::surface`]).
    pub soil_depth: f64,
    /// Time over which the load ramps up (wheel at rest), s.
    pub load_time: f64,
    /// Time the wheel stays at rest under the full load after the ramp, s.
    pub hold_time: f64,
    /// Time over which the rim speed ramps up, s.
    pub ramp_time: f64,
    /// Rim travel after the ramp, in radii.
    pub rim_travel: f64,
    /// The steady values are the means over this last fraction of the drive, in (0, 1].
    pub average_fraction: f64,
    /// Seed of the packing (radii, jitter, kick).
    pub seed: u64,
    /// Time step, s (0: the SMC stability limit, [`step_size`]).
    pub h: f64,
    /// The poured bed counts as settled when its kinetic energy per grain is below this,
    /// in units of `m g d`.
    pub settle_ke: f64,
    /// Longest settling time, s (an error past it).
    pub t_settle: f64,
    /// Restitution of the grains while the bed settles ([`WheelBin::prepare`]; the run
    /// uses `material`'s): bouncy grains take long to come to rest, and the packing is
    /// set by their friction.
    pub settle_restitution: f64,
}

impl WheelBin {
    /// The test at slip `slip` with the wheel (`R`, `b`, `W`) and grains of diameter `d`
    /// (m) of `material`, matching `bulk_density` (kg/m^3); a slab `4 d` thick and `1.5 R`
    /// deep, rim speed 0.5 m/s, rim friction `material.friction`, the MPM wheel's
    /// schedule (load 0.2 s, ramp 0.1 s, 2 R of rim travel, means over the last 40 %).
    pub fn new(
        wheel_radius: f64,
        wheel_width: f64,
        load: f64,
        slip: f64,
        grain_diameter: f64,
        bulk_density: f64,
        material: ContactMaterial,
    ) -> Self {
        Self {
            wheel_radius,
            wheel_width,
            load,
            slip,
            rim_speed: 0.5,
            rim_friction: material.friction,
            grain_diameter,
            size_ratio: 0.8,
            bulk_density,
            material,
            slab_thickness: 4.0 * grain_diameter,
            soil_depth: 1.5 * wheel_radius,
            load_time: 0.2,
            hold_time: 0.0,
            ramp_time: 0.1,
            rim_travel: 2.0,
            average_fraction: 0.4,
            seed: 1,
            h: 0.0,
            settle_ke: 1e-3,
            t_settle: 3.0,
            settle_restitution: 0.3,
        }
    }

    /// Errors naming the field (`wheel_bin.*`) unless the test can be built.
    pub fn validate(&self) -> Result<()> {
        check_positive("wheel_bin.wheel_radius", self.wheel_radius)?;
        check_positive("wheel_bin.wheel_width", self.wheel_width)?;
        check_positive("wheel_bin.load", self.load)?;
        if !(self.slip.is_finite() && (-1.0..=1.0).contains(&self.slip)) {
            return Err(ChronoError::invalid(
                "wheel_bin.slip",
                self.slip,
                "must lie in [-1, 1]",
            ));
        }
        check_positive("wheel_bin.rim_speed", self.rim_speed)?;
        check_non_negative("wheel_bin.rim_friction", self.rim_friction)?;
        check_positive("wheel_bin.grain_diameter", self.grain_diameter)?;
        if !(self.size_ratio > 0.0 && self.size_ratio <= 1.0) {
            return Err(ChronoError::invalid(
                "wheel_bin.size_ratio",
                self.size_ratio,
                "must lie in (0, 1]",
            ));
        }
        check_positive("wheel_bin.bulk_density", self.bulk_density)?;
        self.material.validate()?;
        let d = self.grain_diameter;
        if !(self.slab_thickness.is_finite() && self.slab_thickness >= 2.0 * d) {
            return Err(ChronoError::invalid(
                "wheel_bin.slab_thickness",
                self.slab_thickness,
                format!("must be at least two grain diameters ({})", 2.0 * d),
            ));
        }
        // The density band leaves 2 d at the floor and at the surface: at least 2 d of it.
        if !(self.soil_depth.is_finite() && self.soil_depth >= 6.0 * d) {
            return Err(ChronoError::invalid(
                "wheel_bin.soil_depth",
                self.soil_depth,
                format!("must be at least six grain diameters ({})", 6.0 * d),
            ));
        }
        if self.wheel_radius < 2.0 * d {
            return Err(ChronoError::invalid(
                "wheel_bin.wheel_radius",
                self.wheel_radius,
                format!("must be at least two grain diameters ({})", 2.0 * d),
            ));
        }
        check_non_negative("wheel_bin.load_time", self.load_time)?;
        check_non_negative("wheel_bin.hold_time", self.hold_time)?;
        check_non_negative("wheel_bin.ramp_time", self.ramp_time)?;
        check_non_negative("wheel_bin.rim_travel", self.rim_travel)?;
        if !(self.average_fraction > 0.0 && self.average_fraction <= 1.0) {
            return Err(ChronoError::invalid(
                "wheel_bin.average_fraction",
                self.average_fraction,
                "must lie in (0, 1]",
            ));
        }
        check_non_negative("wheel_bin.h", self.h)?;
        check_positive("wheel_bin.settle_ke", self.settle_ke)?;
        check_positive("wheel_bin.t_settle", self.t_settle)?;
        if !(0.0..=1.0).contains(&self.settle_restitution) {
            return Err(ChronoError::invalid(
                "wheel_bin.settle_restitution",
                self.settle_restitution,
                "must lie in [0, 1]",
            ));
        }
        Ok(())
    }

    /// The slab's length `L`, m: `R` behind the wheel's start, its forward travel
    /// `(1 - s)(U ramp_time / 2 + rim_travel R)` (none when it moves backwards) and `2 R`
    /// ahead.
    pub fn length(&self) -> f64 {
        let r = self.wheel_radius;
        let drive =
            (1.0 - self.slip) * (0.5 * self.ramp_time * self.rim_speed + self.rim_travel * r);
        r + drive.max(0.0) + 2.0 * r
    }

    /// The end of the run, s.
    pub fn t_end(&self) -> f64 {
        self.start_time() + self.ramp_time + self.rim_travel * self.wheel_radius / self.rim_speed
    }

    /// When the rim speed starts to ramp up, s.
    fn start_time(&self) -> f64 {
        self.load_time + self.hold_time
    }

    /// The start of the steady window, s: the last `average_fraction` of the drive after
    /// the ramp, or of the hold when there is no drive (`rim_travel` 0).
    pub fn window_start(&self) -> f64 {
        let t_end = self.t_end();
        let from = if self.rim_travel > 0.0 {
            self.start_time() + self.ramp_time
        } else {
            self.load_time
        };
        t_end - self.average_fraction * (t_end - from)
    }

    /// The full-width forces per slab force, `b / t`.
    pub fn scale(&self) -> f64 {
        self.wheel_width / self.slab_thickness
    }

    fn check_smc(sys: &System) -> Result<()> {
        if sys.settings().contact_method != ContactMethod::Smc {
            return Err(ChronoError::invalid(
                "settings.contact_method",
                format!("{:?}", sys.settings().contact_method),
                "the wheel bin reads the SMC contact forces: must be Smc",
            ));
        }
        Ok(())
    }

    /// Adds the bin to `sys`: the floor (the grains' material) and four frictionless walls,
    /// one fixed body "wheel bin".
    pub fn add_bin(&self, sys: &mut System) -> Result<BodyHandle> {
        let (l, t) = (self.length(), 0.5 * self.slab_thickness);
        let wall = ContactMaterial {
            friction: 0.0,
            rolling_friction: 0.0,
            spinning_friction: 0.0,
            ..self.material
        };
        let walls = [
            (Vector3::z(), Vector3::zeros(), self.material),
            (Vector3::x(), Vector3::zeros(), wall),
            (-Vector3::x(), Vector3::new(l, 0.0, 0.0), wall),
            (Vector3::y(), Vector3::new(0.0, -t, 0.0), wall),
            (-Vector3::y(), Vector3::new(0.0, t, 0.0), wall),
        ];
        let mut b = RigidBodyBuilder::fixed().name("wheel bin");
        for (normal, at, m) in walls {
            b = b.collider(
                Shape::HalfSpace { normal },
                Isometry3::translation(at.x, at.y, at.z),
                m,
            );
        }
        sys.add_body(b)
    }

    /// The number of grains that fill the bin to `soil_depth` at a solid fraction of 0.58
    /// (a settled packing between walls; the depth reached is measured).
    pub fn grain_count(&self) -> usize {
        let d = self.grain_diameter;
        let q = self.size_ratio;
        // Mean volume of a sphere of diameter uniform in [q d, d]: pi/6 (d^4 - (qd)^4) / (4 (d - qd)).
        let v = if q < 1.0 {
            std::f64::consts::PI / 6.0 * d.powi(3) * (1.0 - q.powi(4)) / (4.0 * (1.0 - q))
        } else {
            std::f64::consts::PI / 6.0 * d.powi(3)
        };
        (0.58 * self.length() * self.slab_thickness * self.soil_depth / v).round() as usize
    }

    /// Pours the bed into `sys` (an empty SMC system the caller made: solver, settings,
    /// threads), settles it and measures its solid fraction; the grains at rest, to
    /// [`WheelBin::run`] with. Errors name the field (`wheel_bin.*`, `settle.timeout` if
    /// the bed did not settle within `t_settle`).
    pub fn prepare(&self, sys: &mut System) -> Result<PreparedBed> {
        self.validate()?;
        Self::check_smc(sys)?;
        self.add_bin(sys)?;
        let d = self.grain_diameter;
        let r = 0.5 * d;
        let (l, t) = (self.length(), 0.5 * self.slab_thickness);
        let g = sys.settings().gravity.norm();
        let n = self.grain_count();
        // Sites 2.2 r apart (solid fraction ~0.4 for equal spheres, less in a thin slab):
        // as many layers as the grains need, and one more (jitter and the edges).
        let pitch = 2.2 * r;
        let sites = |w: f64| (w / pitch).floor().max(1.0);
        let layers = (n as f64 / (sites(l) * sites(2.0 * t))).ceil() + 1.0;
        let top = layers * pitch;
        // A nominal grain density while settling: the packing does not depend on it (rigid
        // limit); the bed is rebuilt with the matching one.
        let density = self.bulk_density / 0.6;
        let spec = GrainBed {
            gap: pitch - 2.0 * r,
            count: Some(n),
            seed: self.seed,
            kick: Some(Kick::new(0.1)),
            settle: Settle::KineticEnergy {
                below: self.settle_ke,
                check_every: 0.01,
                // The top layer falls from `top` to about the depth: no test before it
                // has landed.
                not_before: 1.2 * (2.0 * (top - self.soil_depth).max(0.0) / g).sqrt(),
                timeout: self.t_settle,
            },
            ..GrainBed::new(
                Region::Box {
                    lower: Vector3::new(0.0, -t, 0.0),
                    upper: Vector3::new(l, t, top),
                },
                self.size_ratio * r,
                r,
                density,
                ContactMaterial {
                    restitution: self.settle_restitution,
                    ..self.material
                },
            )
        };
        let bed = spec.pour(sys)?;
        let h = step_size(self.h, ContactMethod::Smc, sys);
        let settled = spec.settle(sys, &bed, h, |_, _| Ok::<(), ChronoError>(()))?;
        let grains = bed.grains(sys)?;
        let (surface, _) = self.surface(grains.iter().map(|g| (g.center, g.radius)));
        let rho = self.band_density(
            grains
                .iter()
                .map(|g| (g.center, density * sphere_volume(g.radius))),
            surface,
        );
        let solid_fraction = rho / density;
        if !(solid_fraction.is_finite() && solid_fraction > 0.0) {
            return Err(ChronoError::invalid(
                "wheel_bin.soil_depth",
                self.soil_depth,
                "the settled bed is too shallow to measure its solid fraction",
            ));
        }
        Ok(PreparedBed {
            grains,
            solid_fraction,
            grain_density: self.bulk_density / solid_fraction,
            steps: settled.steps,
            time: settled.time,
        })
    }

    /// The bed's surface: the mean and the standard deviation, over columns one grain
    /// diameter long along `x` (across the whole slab), `2 d` from the end walls, of the top
    /// of the highest grain in the column, m. `grains` are `(centre, radius)`.
    pub fn surface(&self, grains: impl IntoIterator<Item = (Vector3<f64>, f64)>) -> (f64, f64) {
        let d = self.grain_diameter;
        let (x0, x1) = (2.0 * d, self.length() - 2.0 * d);
        let n = (((x1 - x0) / d).floor() as usize).max(1);
        let mut top = vec![f64::NEG_INFINITY; n];
        for (c, r) in grains {
            if c.x < x0 || c.x >= x1 {
                continue;
            }
            let i = (((c.x - x0) / d) as usize).min(n - 1);
            top[i] = top[i].max(c.z + r);
        }
        let filled: Vec<f64> = top.into_iter().filter(|t| t.is_finite()).collect();
        let k = filled.len().max(1) as f64;
        let mean = filled.iter().sum::<f64>() / k;
        let var = filled.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / k;
        (mean, var.sqrt())
    }

    /// Bulk density (kg/m^3) of the slab's band of centres `2 d` from the end walls, from
    /// `2 d` above the floor to `2 d` below `surface` (across the whole slab: the walls'
    /// looser layers count, as they do under the wheel). `grains` are `(centre, mass)`.
    fn band_density(
        &self,
        grains: impl IntoIterator<Item = (Vector3<f64>, f64)>,
        surface: f64,
    ) -> f64 {
        let d = self.grain_diameter;
        let (x0, x1, z0, z1) = (2.0 * d, self.length() - 2.0 * d, 2.0 * d, surface - 2.0 * d);
        // Every centre lies between the walls: the band spans the slab.
        let mass: f64 = grains
            .into_iter()
            .filter(|(x, _)| x.x > x0 && x.x < x1 && x.z >= z0 && x.z < z1)
            .map(|(_, m)| m)
            .sum();
        let volume = (x1 - x0) * self.slab_thickness * (z1 - z0);
        if volume > 0.0 {
            mass / volume
        } else {
            f64::NAN
        }
    }

    /// Rebuilds `bed` in `sys` (an empty SMC system the caller made) with the grain density
    /// that gives the bulk density asked for, lets it find its contacts for [`RELAX_TIME`],
    /// puts the wheel on it and runs the test (module documentation). `progress(f)` gets
    /// the fraction of the run's time done.
    pub fn run(
        &self,
        sys: &mut System,
        bed: &PreparedBed,
        mut progress: impl FnMut(f64),
    ) -> Result<WheelRun> {
        self.validate()?;
        Self::check_smc(sys)?;
        self.add_bin(sys)?;
        let handles = add_grains(sys, &bed.grains, bed.grain_density, self.material)?;
        let h = step_size(self.h, ContactMethod::Smc, sys);
        let relax = (RELAX_TIME / h).round().max(1.0) as u64;
        for _ in 0..relax {
            sys.step(h)?;
        }
        let now = handles
            .iter()
            .zip(&bed.grains)
            .map(|(&b, g)| Ok((sys.body(b)?.position(), g.radius)))
            .collect::<Result<Vec<(Vector3<f64>, f64)>>>()?;
        let (surface, roughness) = self.surface(now.iter().copied());
        let rho = self.band_density(
            now.iter()
                .map(|&(x, r)| (x, bed.grain_density * sphere_volume(r))),
            surface,
        );
        // The wheel just clear of every grain: its axis at least R + r from each centre
        // in the x-z plane.
        let r_w = self.wheel_radius;
        let x0 = r_w;
        let mut zc = surface + r_w;
        for &(c, r) in &now {
            let dx = (c.x - x0).abs();
            if dx < r_w + r {
                zc = zc.max(c.z + ((r_w + r).powi(2) - dx * dx).sqrt());
            }
        }
        let clearance = 0.05 * self.grain_diameter;
        let shape = Shape::Cylinder {
            half_length: 0.5 * self.slab_thickness - clearance,
            radius: r_w,
        };
        let wheel = sys.add_body(
            RigidBodyBuilder::kinematic()
                .name("wheel")
                .position(Vector3::new(x0, 0.0, zc + 1e-3 * self.grain_diameter))
                .collider(shape, Isometry3::identity(), self.material),
        )?;
        sys.set_contact_friction(
            wheel,
            Some(crate::material::ContactFriction {
                friction: self.rim_friction,
                rolling_friction: 0.0,
                spinning_friction: 0.0,
            }),
        )?;
        let wheel_index = sys
            .body_set()
            .dense_index(wheel)
            .ok_or(ChronoError::StaleBody { handle: wheel })? as u32;
        // The grains' contacts with the rim may set a smaller step.
        let h = step_size(self.h, ContactMethod::Smc, sys);
        let g = sys.settings().gravity.norm();
        let scale = self.scale();
        let load = self.load / scale;
        let mass = load / g;
        let t0 = sys.time();
        let t_end = self.t_end();
        let t_avg = self.window_start();
        let n = (t_end / h).ceil() as u64;
        let every = (n / 200).max(1);
        let mut vz = 0.0;
        let mut samples = Vec::with_capacity(201);
        let mut sum = Sums::default();
        let mut window = Sums::default();
        let mut static_sinkage = f64::NAN;
        let sinkage =
            |sys: &System| -> Result<f64> { Ok(surface - (sys.body(wheel)?.position().z - r_w)) };
        for k in 1..=n {
            let t = (k - 1) as f64 * h;
            let f = smooth_ramp(t, self.load_time);
            let u = if t < self.start_time() {
                0.0
            } else {
                self.rim_speed * smooth_ramp(t - self.start_time(), self.ramp_time)
            };
            {
                let b = sys.body_mut(wheel)?;
                b.set_linear_velocity(Vector3::new((1.0 - self.slip) * u, 0.0, vz))?;
                b.set_angular_velocity(Vector3::new(0.0, u / r_w, 0.0))?;
            }
            let before = sinkage(sys)?;
            sys.step(h)?;
            let c = sys.body(wheel)?.position();
            // The grains' force and torque on the rim in this step.
            let (mut force, mut torque) = (Vector3::zeros(), Vector3::zeros());
            for ct in sys.smc_contacts() {
                let (on_wheel, couple) = if ct.owner_b == wheel_index {
                    (ct.force, ct.torque)
                } else if ct.owner_a == wheel_index {
                    (-ct.force, -ct.torque)
                } else {
                    continue;
                };
                force += on_wheel;
                torque += (ct.point - c).cross(&on_wheel) + couple;
            }
            vz += (force.z - f * load) / mass * h;
            let now = sinkage(sys)?;
            let tk = k as f64 * h;
            let step = Sums {
                time: h,
                sinkage: 0.5 * (before + now) * h,
                force: force * h,
                drive_torque: -torque.y * h,
            };
            sum.add(&step);
            if tk > t_avg {
                window.add(&step);
            }
            if static_sinkage.is_nan() && tk >= self.load_time {
                static_sinkage = now;
            }
            if k % every == 0 || k == n {
                samples.push(WheelBinSample {
                    t: tk,
                    travel: c.x - x0,
                    sinkage: now,
                    drawbar_pull: sum.force.x / sum.time * scale,
                    torque: sum.drive_torque / sum.time * scale,
                    vertical_force: sum.force.z / sum.time * scale,
                });
                sum = Sums::default();
                progress((tk / t_end).min(1.0));
            }
        }
        let span = window.time.max(f64::MIN_POSITIVE);
        Ok(WheelRun {
            static_sinkage,
            sinkage: window.sinkage / span,
            drawbar_pull: window.force.x / span * scale,
            torque: window.drive_torque / span * scale,
            vertical_force: window.force.z / span * scale,
            surface,
            roughness,
            bulk_density: rho,
            grains: handles.len(),
            h,
            samples,
            steps: relax + n,
            time: sys.time() - t0,
        })
    }
}

fn sphere_volume(r: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
}

/// Time integrals over a stretch of the run.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    time: f64,
    sinkage: f64,
    force: Vector3<f64>,
    drive_torque: f64,
}

impl Sums {
    fn add(&mut self, o: &Sums) {
        self.time += o.time;
        self.sinkage += o.sinkage;
        self.force += o.force;
        self.drive_torque += o.drive_torque;
    }
}

/// A settled bed of the wheel bin, to rebuild for each run.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedBed {
    /// The grains (centre, radius) at rest.
    pub grains: Vec<Grain>,
    /// The measured solid fraction of the settled bed (its band, [`WheelBin::surface`]).
    pub solid_fraction: f64,
    /// The grain density of the rebuilt bed, `rho_bulk / phi`, kg/m^3.
    pub grain_density: f64,
    /// Steps the settling took.
    pub steps: u64,
    /// Simulated time of the settling, s.
    pub time: f64,
}

/// One sample of the wheel run (full-width values, means over the interval since the last
/// sample).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelBinSample {
    /// Time since the wheel was placed, s.
    pub t: f64,
    /// Forward travel of the axle, m.
    pub travel: f64,
    /// Sinkage, m.
    pub sinkage: f64,
    /// Drawbar pull, N.
    pub drawbar_pull: f64,
    /// Driving torque, N m.
    pub torque: f64,
    /// Vertical force of the grains on the wheel, N.
    pub vertical_force: f64,
}

/// What a wheel run measured (full-width values).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelRun {
    /// Sinkage at the end of the static loading, m.
    pub static_sinkage: f64,
    /// Mean sinkage over the steady window, m.
    pub sinkage: f64,
    /// Mean drawbar pull over the window, N.
    pub drawbar_pull: f64,
    /// Mean driving torque over the window, N m.
    pub torque: f64,
    /// Mean vertical force of the grains over the window (the load at steady state), N.
    pub vertical_force: f64,
    /// The bed's initial surface height above the floor (its depth), m.
    pub surface: f64,
    /// The standard deviation of its column tops, m.
    pub roughness: f64,
    /// The rebuilt bed's bulk density, kg/m^3.
    pub bulk_density: f64,
    /// Number of grains.
    pub grains: usize,
    /// Time step, s.
    pub h: f64,
    /// The samples (about 200 over the run).
    pub samples: Vec<WheelBinSample>,
    /// Steps taken (relaxation and run).
    pub steps: u64,
    /// Simulated time, s.
    pub time: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> WheelBin {
        WheelBin::new(
            0.25,
            0.15,
            400.0,
            0.2,
            0.025,
            1500.0,
            ContactMaterial::smc(4e7, 0.22, 0.87, 0.18),
        )
    }

    #[test]
    fn bad_input_names_the_field() {
        assert!(spec().validate().is_ok());
        let bad = |s: WheelBin, field: &str| {
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{e} should name {field}");
        };
        bad(
            WheelBin {
                wheel_radius: -0.25,
                ..spec()
            },
            "wheel_bin.wheel_radius",
        );
        bad(
            WheelBin {
                slip: 1.5,
                ..spec()
            },
            "wheel_bin.slip",
        );
        bad(
            WheelBin {
                slip: -1.2,
                ..spec()
            },
            "wheel_bin.slip",
        );
        bad(
            WheelBin {
                load: 0.0,
                ..spec()
            },
            "wheel_bin.load",
        );
        bad(
            WheelBin {
                slab_thickness: 0.03,
                ..spec()
            },
            "wheel_bin.slab_thickness",
        );
        bad(
            WheelBin {
                size_ratio: 0.0,
                ..spec()
            },
            "wheel_bin.size_ratio",
        );
        bad(
            WheelBin {
                average_fraction: 0.0,
                ..spec()
            },
            "wheel_bin.average_fraction",
        );
    }

    #[test]
    fn lay_out_follows_the_slip() {
        let s = spec();
        // R behind, (1 - s)(U T/2 + 2 R) of travel, 2 R ahead.
        let drive = 0.8 * (0.5 * 0.1 * 0.5 + 2.0 * 0.25);
        assert!((s.length() - (0.25 + drive + 0.5)).abs() < 1e-12);
        // Spinning in place: no travel.
        assert!((WheelBin { slip: 1.0, ..s }.length() - 0.75).abs() < 1e-12);
        assert!((s.t_end() - (0.2 + 0.1 + 1.0)).abs() < 1e-12);
        // The window: the last 40 % of the drive after the ramp; without a drive, of the
        // hold.
        assert!((s.window_start() - (1.3 - 0.4 * 1.0)).abs() < 1e-12);
        let held = WheelBin {
            hold_time: 0.1,
            ramp_time: 0.0,
            rim_travel: 0.0,
            ..s
        };
        assert!((held.window_start() - (0.3 - 0.4 * 0.1)).abs() < 1e-12);
        assert!((s.scale() - 1.5).abs() < 1e-12);
        assert_eq!(smooth_ramp(0.0, 0.2), 0.0);
        assert!((smooth_ramp(0.1, 0.2) - 0.5).abs() < 1e-12);
        assert_eq!(smooth_ramp(0.3, 0.2), 1.0);
        assert_eq!(smooth_ramp(0.0, 0.0), 1.0);
    }
}
