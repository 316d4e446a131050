//! The collapse of a granular column in a slab (quasi-2-D, plane strain) by DEM: the
//! grain-scale side of `chrono-mpm`'s column (`chrono_mpm::column`, xtask's
//! `mpm-column-collapse --set method=nsc`).
//!
//! **Scene** (Z up, SI units). A column of spheres (radii uniform in
//! `[size_ratio r, r]`, `d = 2 r` the largest diameter; the spread keeps the packing from
//! crystallizing against the flat walls) of length `L0` along `x` and height `H0 = a L0`
//! stands against a frictionless back wall at `x = 0`, held by a frictionless gate at
//! `x = L0`, in a slab `W = slab_width d` wide between two frictionless walls at
//! `y = +-W/2`. Plane strain: chrono-core's rigid-body collision has no periodic axis, so
//! the slab is closed by walls without friction, which take no shear and leave the
//! grains free to move along `x` and `z`; a few grain diameters (3 by default) is what
//! quasi-2-D DEM channels use, and what the experiments' narrow channels are.
//!
//! The floor is rough: a layer of fixed spheres glued on the flat floor `z = 0` (square
//! lattice of pitch `d` along `x` and across the slab, radii uniform in
//! `[size_ratio r, r]`, their own seeded stream), of the grains' material, from the back
//! wall to `floor_length L0` (a flat floor of the grains' friction beyond it). Glued
//! grains rather than the grains' friction on a flat plate: a sphere on a flat plate rolls
//! (without rolling friction it resists nothing), so a flat floor is smoother than the
//! granular bed itself; the glued layer makes the basal friction the material's own, as
//! in Lajeunesse et al. (2005)'s and Staron & Hinch (2005)'s rough beds, and as the MPM
//! column's floor of the sand's friction angle. Heights are measured from the layer's
//! mean top `z_b = 2 mean(r_glued)` (with `rough_floor` off, `z_b = 0`).
//!
//! **Preparation** ([`GranularColumn::build`]). The grains are placed on a loose jittered
//! lattice (pitch `1.02 d` along `z`, `L0 / floor(L0 / 1.02 d)` and `W / floor(W / 1.02 d)`
//! across; a solid fraction of about 0.36), as many as fill `L0 W H0` at a solid fraction
//! of [`FILL_FRACTION`] (more than a poured packing reaches), kicked (random horizontal
//! velocities of at most 0.1 m/s, breaking the lattice's columns) and settled behind the
//! gate until the kinetic energy per grain is below `settle_ke m g d` (1e-2: rms speeds
//! below `0.15 sqrt(g d)`, against the collapse's `sqrt(g H0)`; an NSC solve whose
//! iteration cap is below the column's height in grains keeps a tall packing jittering
//! above it, hence `settle_iterations`) or for at most `t_settle`; the grains whose
//! top is above `z_b + H0` are then removed, so the column's top is at most `H0`. The
//! initial height `H0` of the measure is the highest grain top after the trim.
//!
//! **Run** ([`ColumnScene::run`]). The gate is removed at `t = 0`; the grains are stepped
//! (contact method, solver and settings of the system the caller made: NSC, DEM-C, is the
//! one this scene is meant for) until rest: the kinetic energy below
//! `rest_kinetic M g H0` for `rest_window sqrt(H0 / g)`, not before `sqrt(H0 / g)` (`M`
//! the grains' mass), the criterion of `chrono_mpm::column`; or `max_time sqrt(H0/g)`.
//!
//! **Measures** ([`Deposit::measure`]), with `x_i`, `z_i`, `r_i` the grains' centres and
//! radii:
//!
//! ```text
//! L_inf  = the front of the continuous deposit: the grains sorted by x_i - r_i, the front
//!          starts at the back wall and takes x_i + r_i while x_i - r_i <= front + g_d
//!          (g_d = detach_gap d); the first larger gap ends the deposit (grains that
//!          rolled away alone are not the deposit)
//! L_far  = max (x_i + r_i), the farthest grain (reported)
//! L_99   = the x_i + r_i below which 99 % of the mass lies (reported)
//! H_inf  = max (z_i + r_i) - z_b
//! runout ratio (L_inf - L0) / L0,   final height ratio H_inf / H0
//! ```
//!
//! (The MPM side takes its farthest marker plus half the marker spacing.)
//!
//! References: E. Lajeunesse, J. B. Monnier and G. M. Homsy, Phys. Fluids 17:103302
//! (2005) and G. Lube, H. E. Huppert, R. S. J. Sparks and A. Freundt, Phys. Rev. E
//! 72:041301 (2005) (quasi-2-D experiments); L. Staron and E. J. Hinch, J. Fluid Mech.
//! 545:1-27 (2005) (2-D DEM, contact dynamics, rough bed) and L. Lacaze, J. C. Phillips and
//! R. R. Kerswell, Phys. Fluids 20:063302 (2008) (3-D DEM in a channel); R. Zenit, Phys.
//! Fluids 17:031703 (2005) (2-D DEM). The fits are in xtask's `mpm-column-collapse`.
//!
//! The random draws are in a fixed order (glued layer from `seed ^ FLOOR_SALT`, then the
//! grains' radii and jitter, then the kick, from `seed`), so a seed and a thread count
//! give the same run.

use std::time::Instant;

use nalgebra::{Isometry3, Vector3};

use super::fill::Grain;
use super::{add_grains, step_size};
use crate::body::{BodyHandle, RigidBodyBuilder};
use crate::error::{ChronoError, Result, check_non_negative, check_positive};
use crate::material::{ContactFriction, ContactMaterial};
use crate::rng::Rng;
use crate::shape::Shape;
use crate::system::System;

/// The solid fraction the grain count is sized for: above a poured packing's (about 0.55
/// to 0.6 in a slab), so that the settled column overtops `H0` and is trimmed to it.
pub const FILL_FRACTION: f64 = 0.66;

/// The salt of the glued layer's random stream.
pub const FLOOR_SALT: u64 = 0x2545_f491_4f6c_dd1d;

/// The salt of the kick's random stream.
const KICK_SALT: u64 = 0x9e37_79b9_7f4a_7c15;

/// Largest kick speed per horizontal axis, m/s.
const KICK_SPEED: f64 = 0.1;

/// A granular column collapse in a slab (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GranularColumn {
    /// Aspect ratio `a = H0 / L0`, in (0, 100].
    pub aspect_ratio: f64,
    /// Column length `L0` from the back wall, m.
    pub column_length: f64,
    /// Largest grain diameters across `L0`, `L0 / d` (>= 2).
    pub grains_across: f64,
    /// Smallest over largest grain radius, in (0, 1].
    pub size_ratio: f64,
    /// Slab width, in largest grain diameters (>= 2).
    pub slab_width: f64,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Contact material of the grains and of the glued layer (the walls and the gate take
    /// it without friction).
    pub material: ContactMaterial,
    /// The glued layer of grains on the floor (else the flat floor, of the grains'
    /// friction).
    pub rough_floor: bool,
    /// Length of the rough floor from the back wall, in `L0` (0: [`Self::auto_floor_length`]).
    pub floor_length: f64,
    /// Seed of the glued layer, the radii, the jitter and the kick.
    pub seed: u64,
    /// Time step, s (0: [`step_size`]'s: 1 ms for NSC, the SMC stability limit for SMC).
    pub h: f64,
    /// Settled when the kinetic energy per grain is below this, in `m g d` (`m` the mass
    /// of a grain of the mean diameter).
    pub settle_ke: f64,
    /// Longest settling time, s: the gate opens then even if the column still moves
    /// ([`ColumnRun::settled`]).
    pub t_settle: f64,
    /// Sliding friction of the grains' contacts while they settle (`None`: the material's;
    /// lower: a denser column).
    pub settle_friction: Option<f64>,
    /// The solver's iteration cap while the column settles (`None`: the system's own),
    /// restored before the gate opens: an iterative NSC solve carries the weight of a tall
    /// column down its contact chains only with enough iterations (a column `H0/d` grains
    /// high needs more than `H0/d`), else the packing keeps jittering.
    pub settle_iterations: Option<usize>,
    /// At rest: kinetic energy below this fraction of `M g H0`.
    pub rest_kinetic: f64,
    /// At rest for this long, in `sqrt(H0 / g)`.
    pub rest_window: f64,
    /// Longest run after the gate opens, in `sqrt(H0 / g)`.
    pub max_time: f64,
    /// A gap along `x` wider than this (in `d`) ends the continuous deposit.
    pub detach_gap: f64,
}

impl GranularColumn {
    /// A column of aspect ratio `a` and length `column_length` (m), `grains_across`
    /// largest grains across it, of `material` and density 2500 kg/m^3: radii in
    /// `[0.8 r, r]`, a slab 3 d wide, the rough floor, seed 1, the default step, settled
    /// below 1e-2 m g d per grain (or for at most 3 s), at rest below 1e-4 `M g H0` for
    /// `sqrt(H0/g)` (the MPM column's), at most 30 `sqrt(H0/g)`, a gap of `d` detaching.
    pub fn new(
        aspect_ratio: f64,
        column_length: f64,
        grains_across: f64,
        material: ContactMaterial,
    ) -> Self {
        Self {
            aspect_ratio,
            column_length,
            grains_across,
            size_ratio: 0.8,
            slab_width: 3.0,
            density: 2500.0,
            material,
            rough_floor: true,
            floor_length: 0.0,
            seed: 1,
            h: 0.0,
            settle_ke: 1e-2,
            t_settle: 3.0,
            settle_friction: None,
            settle_iterations: None,
            rest_kinetic: 1e-4,
            rest_window: 1.0,
            max_time: 30.0,
            detach_gap: 1.0,
        }
    }

    /// Errors naming the field (`column.*`, `material.*`) unless the scene can be built.
    pub fn validate(&self) -> Result<()> {
        let a = self.aspect_ratio;
        if !(a.is_finite() && a > 0.0 && a <= 100.0) {
            return Err(ChronoError::invalid(
                "column.aspect_ratio",
                a,
                "must lie in (0, 100]",
            ));
        }
        check_positive("column.column_length", self.column_length)?;
        if !(self.grains_across.is_finite() && self.grains_across >= 2.0) {
            return Err(ChronoError::invalid(
                "column.grains_across",
                self.grains_across,
                "must be at least 2 grain diameters",
            ));
        }
        if !(self.size_ratio > 0.0 && self.size_ratio <= 1.0) {
            return Err(ChronoError::invalid(
                "column.size_ratio",
                self.size_ratio,
                "must lie in (0, 1]",
            ));
        }
        if !(self.slab_width.is_finite() && self.slab_width >= 2.0) {
            return Err(ChronoError::invalid(
                "column.slab_width",
                self.slab_width,
                "must be at least 2 grain diameters",
            ));
        }
        if a * self.grains_across < 1.5 {
            return Err(ChronoError::invalid(
                "column.aspect_ratio",
                a,
                format!(
                    "gives a column of {:.2} grain diameters: at least 1.5 needed",
                    a * self.grains_across
                ),
            ));
        }
        check_positive("column.density", self.density)?;
        self.material.validate()?;
        check_non_negative("column.floor_length", self.floor_length)?;
        if self.floor_length > 0.0 && self.floor_length < 1.0 {
            return Err(ChronoError::invalid(
                "column.floor_length",
                self.floor_length,
                "must be 0 (automatic) or at least 1 L0",
            ));
        }
        check_non_negative("column.h", self.h)?;
        check_positive("column.settle_ke", self.settle_ke)?;
        check_positive("column.t_settle", self.t_settle)?;
        if let Some(f) = self.settle_friction {
            check_non_negative("column.settle_friction", f)?;
        }
        check_positive("column.rest_kinetic", self.rest_kinetic)?;
        check_non_negative("column.rest_window", self.rest_window)?;
        check_positive("column.max_time", self.max_time)?;
        check_non_negative("column.detach_gap", self.detach_gap)?;
        Ok(())
    }

    /// The largest grain diameter `d = L0 / grains_across`, m.
    pub fn grain_diameter(&self) -> f64 {
        self.column_length / self.grains_across
    }

    /// The target height `H0 = a L0`, m.
    pub fn target_height(&self) -> f64 {
        self.aspect_ratio * self.column_length
    }

    /// The slab width `W`, m.
    pub fn width(&self) -> f64 {
        self.slab_width * self.grain_diameter()
    }

    /// The rough floor's length when `floor_length` is 0, in `L0`: `1 + 3 max(a, 2.5
    /// a^(2/3))`, about three times the largest published runout (the envelope's
    /// `max(1.8 a, 2.3 a^(2/3))`).
    pub fn auto_floor_length(&self) -> f64 {
        let a = self.aspect_ratio;
        1.0 + 3.0 * a.max(2.5 * a.powf(2.0 / 3.0))
    }

    /// The rough floor's length, m.
    pub fn rough_length(&self) -> f64 {
        let f = if self.floor_length > 0.0 {
            self.floor_length
        } else {
            self.auto_floor_length()
        };
        f * self.column_length
    }

    /// The mean volume of a grain, m^3: diameters uniform in `[q d, d]`,
    /// `pi/6 d^3 (1 - q^4) / (4 (1 - q))`.
    pub fn mean_grain_volume(&self) -> f64 {
        let (d, q) = (self.grain_diameter(), self.size_ratio);
        let m3 = if q < 1.0 {
            (1.0 - q.powi(4)) / (4.0 * (1.0 - q))
        } else {
            1.0
        };
        std::f64::consts::PI / 6.0 * d.powi(3) * m3
    }

    /// The grains poured: `FILL_FRACTION L0 W H0` over the mean grain volume.
    pub fn grain_count(&self) -> usize {
        (FILL_FRACTION * self.column_length * self.width() * self.target_height()
            / self.mean_grain_volume())
        .ceil() as usize
    }

    /// Adds the walls, the floor, the rough layer (if any) and the gate to `sys`; returns
    /// the gate and `z_b`, the base the heights are measured from.
    fn add_container(&self, sys: &mut System) -> Result<(BodyHandle, f64)> {
        let (l0, d, w) = (self.column_length, self.grain_diameter(), self.width());
        let r = 0.5 * d;
        let smooth = ContactMaterial {
            friction: 0.0,
            rolling_friction: 0.0,
            spinning_friction: 0.0,
            ..self.material
        };
        let half = |name: &str, normal: Vector3<f64>, at: Vector3<f64>, m: ContactMaterial| {
            RigidBodyBuilder::fixed().name(name).collider(
                Shape::HalfSpace { normal },
                Isometry3::translation(at.x, at.y, at.z),
                m,
            )
        };
        sys.add_body(half("floor", Vector3::z(), Vector3::zeros(), self.material))?;
        let walls = RigidBodyBuilder::fixed()
            .name("slab walls")
            .collider(
                Shape::HalfSpace {
                    normal: Vector3::x(),
                },
                Isometry3::identity(),
                smooth,
            )
            .collider(
                Shape::HalfSpace {
                    normal: Vector3::y(),
                },
                Isometry3::translation(0.0, -0.5 * w, 0.0),
                smooth,
            )
            .collider(
                Shape::HalfSpace {
                    normal: -Vector3::y(),
                },
                Isometry3::translation(0.0, 0.5 * w, 0.0),
                smooth,
            );
        sys.add_body(walls)?;
        let mut base = 0.0;
        if self.rough_floor {
            let mut rng = Rng::new(self.seed ^ FLOOR_SALT);
            let nx = (self.rough_length() / d).ceil().max(1.0) as usize;
            let ny = (w / d).floor().max(1.0) as usize;
            let mut layer = RigidBodyBuilder::fixed().name("rough floor");
            let mut tops = 0.0;
            for i in 0..nx {
                for j in 0..ny {
                    let rr = if self.size_ratio < 1.0 {
                        rng.range(self.size_ratio * r, r)
                    } else {
                        r
                    };
                    let y = -0.5 * w + (j as f64 + 0.5) * w / ny as f64;
                    layer = layer.collider(
                        Shape::Sphere { radius: rr },
                        Isometry3::translation(r + i as f64 * d, y, rr),
                        self.material,
                    );
                    tops += 2.0 * rr;
                }
            }
            sys.add_body(layer)?;
            base = tops / (nx * ny) as f64;
        }
        let gate = sys.add_body(half(
            "gate",
            -Vector3::x(),
            Vector3::new(l0, 0.0, 0.0),
            smooth,
        ))?;
        Ok((gate, base))
    }

    /// The grains on the loose lattice above `z0` (module documentation), from `rng`.
    fn lattice(&self, z0: f64, rng: &mut Rng) -> Vec<Grain> {
        let (l0, d, w) = (self.column_length, self.grain_diameter(), self.width());
        let r = 0.5 * d;
        let pz = 1.02 * d;
        let nx = ((l0 / pz).floor() as usize).max(1);
        let ny = ((w / pz).floor() as usize).max(1);
        let (px, py) = (l0 / nx as f64, w / ny as f64);
        let n = self.grain_count();
        let mut out = Vec::with_capacity(n);
        let mut k = 0usize;
        while out.len() < n {
            let (i, j, layer) = (k % nx, (k / nx) % ny, k / (nx * ny));
            k += 1;
            let rad = if self.size_ratio < 1.0 {
                rng.range(self.size_ratio * r, r)
            } else {
                r
            };
            let site = Vector3::new(
                (i as f64 + 0.5) * px,
                -0.5 * w + (j as f64 + 0.5) * py,
                z0 + (layer as f64 + 0.5) * pz,
            );
            // Jitter within the clearance of each axis: the grain stays inside its cell.
            let amp = |p: f64| 0.5 * (p - 2.0 * rad).max(0.0);
            let c = site
                + Vector3::new(
                    rng.range(-amp(px), amp(px)),
                    rng.range(-amp(py), amp(py)),
                    rng.range(-amp(pz), amp(pz)),
                );
            out.push(Grain {
                center: c,
                radius: rad,
            });
        }
        out
    }

    /// Adds the container and the grains to `sys` (an empty system the caller made:
    /// contact method, solver, settings), settles the column behind the gate and trims it
    /// to `H0`; the scene to [`ColumnScene::run`]. `on_step(sys, step)` is called after each
    /// settling step (step from 1). Errors name the field (`column.*`).
    pub fn build<E: From<ChronoError>>(
        &self,
        sys: &mut System,
        mut on_step: impl FnMut(&mut System, u64) -> std::result::Result<(), E>,
    ) -> std::result::Result<ColumnScene, E> {
        self.validate()?;
        let (gate, base) = self.add_container(sys)?;
        let d = self.grain_diameter();
        let r = 0.5 * d;
        let g = sys.settings().gravity.norm();
        check_positive("settings.gravity", g)?;
        let z0 = if self.rough_floor { d } else { 0.0 };
        let mut rng = Rng::new(self.seed);
        let grains = self.lattice(z0, &mut rng);
        let top = grains
            .iter()
            .map(|q| q.center.z + q.radius)
            .fold(z0, f64::max);
        let handles = add_grains(sys, &grains, self.density, self.material)?;
        let mut kick = Rng::new(self.seed ^ KICK_SALT);
        for &b in &handles {
            let v = Vector3::new(
                kick.range(-KICK_SPEED, KICK_SPEED),
                kick.range(-KICK_SPEED, KICK_SPEED),
                0.0,
            );
            sys.body_mut(b)?.set_linear_velocity(v)?;
        }
        let h = step_size(self.h, sys.settings().contact_method, sys);
        let h0 = self.target_height();
        // The top layer falls from `top` to about H0: no test before it has landed.
        let fall = (top - base - h0).max(d);
        let not_before = sys.time() + 1.2 * (2.0 * fall / g).sqrt();
        let m_grain = self.density * std::f64::consts::PI / 6.0 * (self.size_ratio * r + r).powi(3);
        let unit = m_grain * g * d * handles.len() as f64;
        if let Some(friction) = self.settle_friction {
            let fill = ContactFriction {
                friction,
                rolling_friction: 0.0,
                spinning_friction: 0.0,
            };
            for &b in &handles {
                sys.set_contact_friction(b, Some(fill))?;
            }
        }
        let full_iterations = sys.solver().settings().max_iterations;
        if let Some(cap) = self.settle_iterations {
            check_positive("column.settle_iterations", cap as f64)?;
            sys.solver_mut().settings_mut().max_iterations = cap;
        }
        let n_max = (self.t_settle / h).ceil() as u64;
        let every = ((0.01 / h).round() as u64).max(1);
        let (mut steps, mut settled_ke, mut settled) = (0u64, f64::INFINITY, false);
        while steps < n_max {
            sys.step(h)?;
            steps += 1;
            on_step(sys, steps)?;
            if steps.is_multiple_of(every) && sys.time() >= not_before {
                settled_ke = sys.kinetic_energy() / unit;
                if settled_ke < self.settle_ke {
                    settled = true;
                    break;
                }
            }
        }
        if !settled {
            settled_ke = sys.kinetic_energy() / unit;
        }
        sys.solver_mut().settings_mut().max_iterations = full_iterations;
        if self.settle_friction.is_some() {
            for &b in &handles {
                sys.set_contact_friction(b, None)?;
            }
        }
        let radii: Vec<f64> = grains.iter().map(|q| q.radius).collect();
        // Trim to H0.
        let mut keep = Vec::with_capacity(handles.len());
        let mut kept_radii = Vec::with_capacity(handles.len());
        let mut cut = Vec::new();
        for (&b, &rad) in handles.iter().zip(&radii) {
            if sys.body(b)?.position().z + rad > base + h0 {
                cut.push(b);
            } else {
                keep.push(b);
                kept_radii.push(rad);
            }
        }
        sys.remove_bodies(&cut)?;
        let mut scene = ColumnScene {
            spec: *self,
            gate: Some(gate),
            grains: keep,
            radii: kept_radii,
            base,
            h,
            settle_steps: steps,
            settled,
            settled_ke,
            trimmed: cut.len(),
            initial_height: 0.0,
            solid_fraction: 0.0,
            mass: 0.0,
        };
        let (mut vol, mut mass, mut height) = (0.0, 0.0, 0.0f64);
        for (&b, &rad) in scene.grains.iter().zip(&scene.radii) {
            let body = sys.body(b)?;
            vol += std::f64::consts::PI / 6.0 * (2.0 * rad).powi(3);
            mass += body.mass();
            height = height.max(body.position().z + rad - base);
        }
        if height < h0 - 1.5 * d || scene.grains.is_empty() {
            return Err(ChronoError::invalid(
                "column.aspect_ratio",
                self.aspect_ratio,
                format!(
                    "the settled column is {height:.4} m high, below H0 = {h0:.4} m less 1.5 d: too few grains poured"
                ),
            )
            .into());
        }
        scene.initial_height = height;
        scene.solid_fraction = vol / (self.column_length * self.width() * height);
        scene.mass = mass;
        Ok(scene)
    }
}

/// A settled column behind its gate ([`GranularColumn::build`]).
#[derive(Debug, Clone)]
pub struct ColumnScene {
    spec: GranularColumn,
    gate: Option<BodyHandle>,
    grains: Vec<BodyHandle>,
    radii: Vec<f64>,
    base: f64,
    h: f64,
    settle_steps: u64,
    settled: bool,
    settled_ke: f64,
    trimmed: usize,
    initial_height: f64,
    solid_fraction: f64,
    mass: f64,
}

/// The deposit's measures from the grains (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deposit {
    /// Front of the continuous deposit `L_inf`, m from the back wall.
    pub front: f64,
    /// Farthest grain front `max(x + r)`, m.
    pub farthest: f64,
    /// The front of 99 % of the mass, m.
    pub front_99: f64,
    /// Highest grain top above the base, m.
    pub height: f64,
    /// Grains ahead of the continuous deposit.
    pub detached: usize,
}

impl Deposit {
    /// The measures of grains `(centre, radius, mass)` over a base at `base` (m): the
    /// continuous deposit ends at the first gap along `x` wider than `gap` (m). `None`
    /// without grains.
    pub fn measure(grains: &[(Vector3<f64>, f64, f64)], base: f64, gap: f64) -> Option<Deposit> {
        if grains.is_empty() {
            return None;
        }
        let mut by_back: Vec<(f64, f64)> =
            grains.iter().map(|(c, r, _)| (c.x - r, c.x + r)).collect();
        by_back.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut front = 0.0f64;
        let mut inside = 0;
        for &(back, fr) in &by_back {
            if back > front + gap {
                break;
            }
            front = front.max(fr);
            inside += 1;
        }
        let mut by_front: Vec<(f64, f64)> = grains.iter().map(|(c, r, m)| (c.x + r, *m)).collect();
        by_front.sort_by(|a, b| a.0.total_cmp(&b.0));
        let total: f64 = by_front.iter().map(|q| q.1).sum();
        let mut acc = 0.0;
        let mut front_99 = by_front.last().map_or(0.0, |q| q.0);
        for &(x, m) in &by_front {
            acc += m;
            if acc >= 0.99 * total {
                front_99 = x;
                break;
            }
        }
        Some(Deposit {
            front,
            farthest: by_front.last().map_or(0.0, |q| q.0),
            front_99,
            height: grains
                .iter()
                .map(|(c, r, _)| c.z + r - base)
                .fold(f64::NEG_INFINITY, f64::max),
            detached: grains.len() - inside,
        })
    }
}

/// What a column collapse measured ([`ColumnScene::run`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnRun {
    /// The deposit at the end.
    pub deposit: Deposit,
    /// Initial height `H0` (the highest grain top after the trim), m.
    pub initial_height: f64,
    /// Column length `L0`, m.
    pub column_length: f64,
    /// `(L_inf - L0) / L0` of the continuous deposit.
    pub runout_ratio: f64,
    /// `(L_far - L0) / L0` of the farthest grain.
    pub runout_ratio_farthest: f64,
    /// `(L_99 - L0) / L0` of the 99 % mass front.
    pub runout_ratio_99: f64,
    /// `H_inf / H0`.
    pub final_height_ratio: f64,
    /// The column's aspect ratio as built, `H0 / L0`.
    pub aspect_ratio: f64,
    /// Solid fraction of the settled column, the grains' volume over `L0 W H0`.
    pub solid_fraction: f64,
    /// Whether the rest criterion was met before `max_time`.
    pub at_rest: bool,
    /// Time from the gate's removal to the end, s.
    pub time: f64,
    /// The time scale `sqrt(H0 / g)`, s.
    pub time_scale: f64,
    /// Steps after the gate's removal.
    pub steps: u64,
    /// Settling steps before it.
    pub settle_steps: u64,
    /// Whether the settling criterion was met within `t_settle` (else the gate opened at
    /// `t_settle` on a column still moving: see `settled_ke`).
    pub settled: bool,
    /// Kinetic energy per grain when the gate opened, in `m g d`.
    pub settled_ke: f64,
    /// Time step, s.
    pub h: f64,
    /// Grains in the column.
    pub grains: usize,
    /// Grains poured above `H0` and removed.
    pub trimmed: usize,
    /// The grains' mass at the end over that at the gate's removal.
    pub mass_ratio: f64,
    /// Grains outside the slab or below the floor at the end (escaped through a wall).
    pub escaped: usize,
    /// The grains' momentum at the end over `M sqrt(g H0)`.
    pub momentum: f64,
    /// Mean solver iterations per step after the gate's removal (NSC; 0 for SMC).
    pub iterations: f64,
    /// Wall time of the collapse (after the gate's removal), s.
    pub wall_s: f64,
}

impl ColumnScene {
    /// The time step, s.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The grains' bodies.
    pub fn grains(&self) -> &[BodyHandle] {
        &self.grains
    }

    /// The initial height `H0` (highest grain top after the trim above the base), m.
    pub fn initial_height(&self) -> f64 {
        self.initial_height
    }

    /// The base `z_b` the heights are measured from, m.
    pub fn base(&self) -> f64 {
        self.base
    }

    /// The deposit now.
    pub fn deposit(&self, sys: &System) -> Result<Deposit> {
        let mut q = Vec::with_capacity(self.grains.len());
        for (&b, &r) in self.grains.iter().zip(&self.radii) {
            let body = sys.body(b)?;
            q.push((body.position(), r, body.mass()));
        }
        Ok(Deposit::measure(
            &q,
            self.base,
            self.spec.detach_gap * self.spec.grain_diameter(),
        )
        .expect("a built column has grains"))
    }

    /// Removes the gate (`t = 0`) and steps `sys` until the column is at rest or
    /// `max_time sqrt(H0/g)` has passed; `on_step(sys, step)` after each step (from 1).
    pub fn run<E: From<ChronoError>>(
        &mut self,
        sys: &mut System,
        mut on_step: impl FnMut(&mut System, u64) -> std::result::Result<(), E>,
    ) -> std::result::Result<ColumnRun, E> {
        let start = Instant::now();
        if let Some(gate) = self.gate.take() {
            sys.remove_body(gate)?;
        }
        let s = self.spec;
        let g = sys.settings().gravity.norm();
        let h0 = self.initial_height;
        let tau = (h0 / g).sqrt();
        let scale = self.mass * g * h0;
        let (t0, t_max, window) = (sys.time(), s.max_time * tau, s.rest_window * tau);
        let mut quiet_since: Option<f64> = None;
        let (mut at_rest, mut steps, mut iterations) = (false, 0u64, 0u64);
        while sys.time() - t0 < t_max {
            let report = sys.step(self.h)?;
            steps += 1;
            iterations += report.solve.iterations as u64;
            on_step(sys, steps)?;
            let t = sys.time() - t0;
            if t >= tau && sys.kinetic_energy() < s.rest_kinetic * scale {
                let since = *quiet_since.get_or_insert(t);
                if t - since >= window {
                    at_rest = true;
                    break;
                }
            } else {
                quiet_since = None;
            }
        }
        let deposit = self.deposit(sys)?;
        let (half_w, l0) = (0.5 * s.width(), s.column_length);
        let (mut mass, mut momentum, mut escaped) = (0.0, Vector3::zeros(), 0usize);
        for &b in &self.grains {
            let body = sys.body(b)?;
            mass += body.mass();
            momentum += body.mass() * body.linear_velocity();
            let p = body.position();
            if p.x < 0.0 || p.y.abs() > half_w || p.z < 0.0 {
                escaped += 1;
            }
        }
        Ok(ColumnRun {
            deposit,
            initial_height: h0,
            column_length: l0,
            runout_ratio: (deposit.front - l0) / l0,
            runout_ratio_farthest: (deposit.farthest - l0) / l0,
            runout_ratio_99: (deposit.front_99 - l0) / l0,
            final_height_ratio: deposit.height / h0,
            aspect_ratio: h0 / l0,
            solid_fraction: self.solid_fraction,
            at_rest,
            time: sys.time() - t0,
            time_scale: tau,
            steps,
            settle_steps: self.settle_steps,
            settled: self.settled,
            settled_ke: self.settled_ke,
            h: self.h,
            grains: self.grains.len(),
            trimmed: self.trimmed,
            mass_ratio: mass / self.mass,
            escaped,
            momentum: momentum.norm() / (self.mass * (g * h0).sqrt()),
            iterations: iterations as f64 / steps.max(1) as f64,
            wall_s: start.elapsed().as_secs_f64(),
        })
    }
}

#[cfg(test)]
#[path = "column_tests.rs"]
mod tests;
