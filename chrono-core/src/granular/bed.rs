//! Bed preparation: the "loose lattice and settle" recipe of granular scenes.
//!
//! A [`GrainBed`] places grains on a jittered lattice ([`LatticeFill`]) in a region of a
//! container the caller has already added, optionally gives them small random horizontal
//! velocities (a [`Kick`]: it breaks the lattice's vertical columns, which frictional
//! contacts would otherwise keep standing, a settled solid fraction of ~0.45 instead of a
//! random packing's ~0.6), and lets them settle under gravity by a [`Settle`] criterion.
//! A lattice with sites `1.25 d` apart (solid fraction ~0.23) settles to ~0.6: fill a region
//! about 2.6 times the height of the bed wanted.
//!
//! The order of the random draws and of the bodies is fixed (lattice, then grains in
//! lattice order, then one kick per grain from its own stream), so a seed gives the same
//! bed on every platform.

use nalgebra::Vector3;

use super::fill::{Grain, LatticeFill, Region};
use super::{add_grains, step_size};
use crate::body::BodyHandle;
use crate::error::{ChronoError, Result, check_non_negative, check_positive};
use crate::material::{ContactFriction, ContactMaterial};
use crate::rng::Rng;
use crate::system::System;

/// The default salt of the kick's random stream (the 64-bit golden ratio).
pub const KICK_SALT: u64 = 0x9e37_79b9_7f4a_7c15;

/// Random horizontal velocities given to the grains once placed: each axis uniform in
/// `[-speed, speed]` (m/s), from the generator seeded by `bed seed ^ salt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kick {
    /// Largest speed per horizontal axis, m/s.
    pub speed: f64,
    /// Mixed into the bed's seed for the kick's own stream.
    pub salt: u64,
}

impl Kick {
    /// A kick of `speed` (m/s) with the default salt [`KICK_SALT`].
    pub fn new(speed: f64) -> Self {
        Self {
            speed,
            salt: KICK_SALT,
        }
    }
}

/// When the placed grains count as settled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Settle {
    /// Do not step: the grains stay where the lattice put them (the scene's own run lets
    /// them fall).
    None,
    /// A fixed number of steps.
    Steps(u64),
    /// A fixed simulated time (s): `round(t / h)` steps.
    Duration(f64),
    /// Until the kinetic energy of the system per grain is below `below` in units of
    /// `m g d` (`m` the mass of a grain of the mean diameter `r_min + r_max`, `g` the
    /// gravity's magnitude, `d = 2 r_max`), tested every `check_every` seconds from
    /// `not_before` seconds on (a bed still falling passes through rest at its start);
    /// an error past `timeout` seconds.
    KineticEnergy {
        /// Bound on the kinetic energy per grain, in `m g d`.
        below: f64,
        /// Interval between the tests, s.
        check_every: f64,
        /// No test before this time, s.
        not_before: f64,
        /// Longest settling time, s.
        timeout: f64,
    },
}

/// A bed of grains poured from a loose jittered lattice into a container and settled.
///
/// Add the container first (for example [`super::add_box_container`]), then
/// [`GrainBed::pour`] the grains and [`GrainBed::settle`] them, or both at once with
/// [`GrainBed::build`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrainBed {
    /// Where the lattice sites are (m). Grains lie wholly inside.
    pub region: Region,
    /// Smallest grain radius (m); radii are uniform in `[r_min, r_max]`.
    pub r_min: f64,
    /// Largest grain radius (m).
    pub r_max: f64,
    /// Clearance between the largest spheres of neighbouring sites (m); the lattice pitch
    /// is `2 r_max + gap`.
    pub gap: f64,
    /// Jitter of the centres as a fraction of the clearance, in `[0, 1]`.
    pub jitter: f64,
    /// `Some(n)`: exactly `n` grains (the first `n` sites, bottom layer first; an error if
    /// the region holds fewer); `None`: every site of the region.
    pub count: Option<usize>,
    /// Grain density, kg/m^3.
    pub density: f64,
    /// Contact material of the grains.
    pub material: ContactMaterial,
    /// Seed of the radii, the jitter and the kick.
    pub seed: u64,
    /// Random horizontal velocities at placement, if any.
    pub kick: Option<Kick>,
    /// When the bed counts as settled.
    pub settle: Settle,
    /// Sliding friction of every grain contact while settling (no rolling or spinning
    /// friction), restored to the materials' afterwards: the usual way to set a DEM
    /// sample's density (0: a dense sample; `None`: settle with the materials).
    pub settle_friction: Option<f64>,
}

/// The grains of a poured bed.
#[derive(Debug, Clone)]
pub struct Bed {
    /// The grains' bodies, in lattice order (bottom layer first).
    pub handles: Vec<BodyHandle>,
    /// Their radii (m), in the same order.
    pub radii: Vec<f64>,
    /// The kick's generator after its draws: a scene that draws more random numbers (for
    /// example re-insertion positions) continues this stream, so one seed fixes the run.
    pub rng: Rng,
}

impl Bed {
    /// Number of grains.
    pub fn len(&self) -> usize {
        self.handles.len()
    }

    /// Whether the bed has no grain.
    pub fn is_empty(&self) -> bool {
        self.handles.is_empty()
    }

    /// The grains as they are now in `sys` (centre and radius): a settled bed to rebuild
    /// in another system with [`super::add_grains`].
    pub fn grains(&self, sys: &System) -> Result<Vec<Grain>> {
        self.handles
            .iter()
            .zip(&self.radii)
            .map(|(&b, &radius)| {
                Ok(Grain {
                    center: sys.body(b)?.position(),
                    radius,
                })
            })
            .collect()
    }

    /// The grains' masses (kg), in order.
    pub fn masses(&self, sys: &System) -> Result<Vec<f64>> {
        self.handles
            .iter()
            .map(|&b| sys.body(b).map(|b| b.mass()))
            .collect()
    }
}

/// What settling took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settled {
    /// Steps taken.
    pub steps: u64,
    /// Simulated time at the end, s.
    pub time: f64,
}

impl GrainBed {
    /// The usual loose bed: radii in `[r_min, r_max]`, clearance `r_max / 2` (sites
    /// `2.5 r_max` apart), full jitter, every site of `region`, a kick of 0.1 m/s, seed 1,
    /// no settling.
    pub fn new(
        region: Region,
        r_min: f64,
        r_max: f64,
        density: f64,
        material: ContactMaterial,
    ) -> Self {
        Self {
            region,
            r_min,
            r_max,
            gap: 0.5 * r_max,
            jitter: 1.0,
            count: None,
            density,
            material,
            seed: 1,
            kick: Some(Kick::new(0.1)),
            settle: Settle::None,
            settle_friction: None,
        }
    }

    /// The lattice of the grains.
    pub fn lattice(&self) -> LatticeFill {
        LatticeFill {
            region: self.region,
            r_min: self.r_min,
            r_max: self.r_max,
            gap: self.gap,
            jitter: self.jitter,
            max_count: self.count.unwrap_or(usize::MAX),
            seed: self.seed,
        }
    }

    /// Places the grains in `sys` (after the bodies already there) and kicks them. Errors
    /// name the bad field (`bed.count` when the region holds too few sites, `fill.*`,
    /// `grain density`, `kick.speed`).
    pub fn pour(&self, sys: &mut System) -> Result<Bed> {
        let grains = self.lattice().generate()?;
        if let Some(n) = self.count
            && grains.len() != n
        {
            return Err(ChronoError::invalid(
                "bed.count",
                n,
                format!("the region holds only {} grains", grains.len()),
            ));
        }
        if let Some(k) = self.kick {
            check_non_negative("kick.speed", k.speed)?;
        }
        let handles = add_grains(sys, &grains, self.density, self.material)?;
        let salt = self.kick.map_or(KICK_SALT, |k| k.salt);
        let mut rng = Rng::new(self.seed ^ salt);
        if let Some(k) = self.kick {
            for &b in &handles {
                let v = Vector3::new(
                    rng.range(-k.speed, k.speed),
                    rng.range(-k.speed, k.speed),
                    0.0,
                );
                sys.body_mut(b)?.set_linear_velocity(v)?;
            }
        }
        Ok(Bed {
            handles,
            radii: grains.iter().map(|g| g.radius).collect(),
            rng,
        })
    }

    /// Steps `sys` at `h` (s) until `bed` is settled by [`GrainBed::settle`]'s criterion,
    /// calling `on_step(sys, step)` after each step (step counted from 1; frames, progress).
    /// With `settle_friction` the grains' contacts use it meanwhile.
    pub fn settle<E: From<ChronoError>>(
        &self,
        sys: &mut System,
        bed: &Bed,
        h: f64,
        mut on_step: impl FnMut(&mut System, u64) -> std::result::Result<(), E>,
    ) -> std::result::Result<Settled, E> {
        check_positive("h", h)?;
        if let Some(friction) = self.settle_friction {
            check_non_negative("bed.settle_friction", friction)?;
            let fill = ContactFriction {
                friction,
                rolling_friction: 0.0,
                spinning_friction: 0.0,
            };
            for &b in &bed.handles {
                sys.set_contact_friction(b, Some(fill))?;
            }
        }
        let mut steps = 0u64;
        match self.settle {
            Settle::None => {}
            Settle::Steps(n) => {
                for _ in 0..n {
                    sys.step(h)?;
                    steps += 1;
                    on_step(sys, steps)?;
                }
            }
            Settle::Duration(t) => {
                check_non_negative("settle.duration", t)?;
                for _ in 0..(t / h).round() as u64 {
                    sys.step(h)?;
                    steps += 1;
                    on_step(sys, steps)?;
                }
            }
            Settle::KineticEnergy {
                below,
                check_every,
                not_before,
                timeout,
            } => {
                check_positive("settle.below", below)?;
                check_positive("settle.timeout", timeout)?;
                let g = sys.settings().gravity.norm();
                let d = 2.0 * self.r_max;
                let m_grain =
                    self.density * std::f64::consts::PI / 6.0 * (self.r_min + self.r_max).powi(3);
                let unit = m_grain * g * d * bed.len() as f64;
                let n_max = (timeout / h).ceil() as u64;
                let every = ((check_every / h).round() as u64).max(1);
                loop {
                    sys.step(h)?;
                    steps += 1;
                    on_step(sys, steps)?;
                    if steps.is_multiple_of(every)
                        && sys.time() >= not_before
                        && sys.kinetic_energy() / unit < below
                    {
                        break;
                    }
                    if steps >= n_max {
                        return Err(ChronoError::invalid(
                            "settle.timeout",
                            timeout,
                            format!(
                                "the bed did not settle (kinetic energy per grain {:.2e} m g d, bound {below:.2e})",
                                sys.kinetic_energy() / unit
                            ),
                        )
                        .into());
                    }
                }
            }
        }
        if self.settle_friction.is_some() {
            for &b in &bed.handles {
                sys.set_contact_friction(b, None)?;
            }
        }
        Ok(Settled {
            steps,
            time: sys.time(),
        })
    }

    /// [`GrainBed::pour`] then [`GrainBed::settle`] at the step of [`step_size`] (1 ms for
    /// NSC, the SMC stability limit for SMC).
    pub fn build(&self, sys: &mut System) -> Result<(Bed, Settled)> {
        let bed = self.pour(sys)?;
        let h = step_size(0.0, sys.settings().contact_method, sys);
        let settled = self.settle(sys, &bed, h, |_, _| Ok::<(), ChronoError>(()))?;
        Ok((bed, settled))
    }
}
