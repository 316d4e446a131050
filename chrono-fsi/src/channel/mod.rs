//! Rigid and flexible objects in channel flow (the scene of `fsi-channel`, after the seed's
//! "Interacting Rigid and Flexible Objects in Channel Flow": a channel 1.4 x 1 x 1 m of a
//! fluid with `rho` 1000 kg/m^3 and `mu` 1 Pa s at Re 45, 2000 free ellipsoids of
//! semi-axes (2.25, 2.25, 3) cm and density 1000 kg/m^3, 40 ANCF beams of `E` 0.2 MPa,
//! section 1.5 cm, length 64 cm, 4 elements, anchored to the floor).
//!
//! **The channel.** A box `length x width x height` (x along the flow, z up), **periodic
//! along x**, with marker walls on both sides (y) and on the floor and the ceiling (z): a
//! closed duct, so the flow's reference is the laminar duct solution ([`crate::duct`]),
//! there are no free-surface waves to resolve, and the body force that drives a given
//! mean velocity is known. (A free surface would add gravity waves and a hydrostatic
//! pressure to a scene whose bodies are neutrally buoyant; the seed's figures do not show
//! one.) No gravity: with the seed's densities (bodies as dense as the fluid) gravity and
//! buoyancy cancel on every body and gravity only adds a hydrostatic pressure, which in a
//! closed duct does not move the fluid.
//!
//! **The flow.** Driven along x by a body force `f` on the fluid, computed from the duct
//! solution so that the empty duct's mean velocity is [`ChannelParams::mean_velocity`]
//! `U` ([`crate::duct::body_force_for_mean_velocity`]); the fluid starts with that
//! developed profile (a duct this viscous takes `~ H^2 / (pi^2 nu)` to develop: 100 s at
//! the seed's size). The body force stands for the mean pressure gradient `G = rho f` of
//! a pressure-driven channel, which also pushes on the solids: every ellipsoid gets
//! `rho f V` along x as an applied force and every beam the consistent load of
//! `rho f A` per length (a pressure gradient acts on a body's volume; without it a
//! neutrally buoyant body would lag the fluid by its buoyancy share).
//!
//! **Dimensionless groups.** Channel `Re = U H / nu` (mean velocity, height `H`);
//! particle `Re_p = U d / nu` with `d = 2 a` the ellipsoid's equatorial diameter (the seed's
//! `U` = 0.045 m/s gives Re 45 on its 1 m height and `Re_p` = 2.0); the viscous Cauchy
//! (elastoviscous) number of the beams `Ca = mu U l^3 / (E I)`, the viscous load on a beam of
//! length `l` against its bending stiffness (the beams' Reynolds number `U D / nu` is 0.7 in
//! the seed: a viscous load `~ mu U` per length); the solid fraction of the ellipsoids.
//! A scaled scene holds `Re_p` and `Ca` by keeping `U`, `nu` and the ellipsoids and
//! choosing `E` for the beams; `Re` scales with the height.
//!
//! **Placement.** Beams on a regular grid over the floor, rooted at `z = 0`, standing
//! along z, the root node clamped (position and slope); ellipsoids at random centres and
//! orientations (a seeded generator), accepted when their bounding spheres keep half the
//! smallest semi-axis ([`placement_gap`]: at least a spacing) from each other, from the
//! walls and from the beams' cylinders, and clear of the periodic seam (so the fluid is carved exactly). Each body and beam is resolved by the
//! fluid spacing or the builder errors ([`FsiBuilder`], [`crate::cable`]).
//!
//! ```no_run
//! use chrono_fsi::channel::{ChannelParams, channel};
//!
//! let p = ChannelParams::default();
//! let mut scene = channel(&p, Box::new(chrono_ccp::Psor::new(Default::default()))).unwrap();
//! for _ in 0..10 {
//!     scene.step(p.coupling_step).unwrap();
//! }
//! assert_eq!(scene.fluid_inside(0.5 * p.spacing).unwrap().total(), 0);
//! ```

use std::f64::consts::PI;
use std::time::Instant;

use chrono_core::System;
use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::{slab_layers, wall_layers};
use chrono_core::shape::ellipsoid_signed_distance;
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, SystemSettings};
use chrono_fea::{BeamMaterial, CableItem, CableMesh, CableQuadrature, NodeId};
use chrono_sph::{ActiveDomain, SphSettings, sound_speed_for};

use crate::cable::{cable_distance, node_uses};
use crate::duct::{body_force_for_mean_velocity, duct_velocity};
use crate::error::{FsiError, Result, check_positive};
use crate::{FsiBuilder, SphFluid};

mod placement;
pub use placement::{beam_roots, place_ellipsoids, placement_gap};

/// Parameters of [`channel`] (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelParams {
    /// Channel length along the flow (the period), m.
    pub length: f64,
    /// Channel width (y), m.
    pub width: f64,
    /// Channel height (z), m.
    pub height: f64,
    /// Fluid particle spacing, m.
    pub spacing: f64,
    /// `h / dp`.
    pub h_over_dp: f64,
    /// Fluid density, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity, Pa s.
    pub viscosity: f64,
    /// Mean velocity of the empty duct under the driving body force, m/s.
    pub mean_velocity: f64,
    /// Number of free ellipsoids.
    pub ellipsoids: usize,
    /// Ellipsoid semi-axes (body x, y, z), m.
    pub semi_axes: [f64; 3],
    /// Ellipsoid density, kg/m^3.
    pub body_density: f64,
    /// Number of beams.
    pub beams: usize,
    /// Beam diameter (round section), m.
    pub beam_diameter: f64,
    /// Beam length, m.
    pub beam_length: f64,
    /// ANCF cable elements per beam.
    pub beam_elements: usize,
    /// Beam Young's modulus, Pa.
    pub young: f64,
    /// Beam density, kg/m^3.
    pub beam_density: f64,
    /// Multibody (coupling) step, s.
    pub coupling_step: f64,
    /// Seed of the ellipsoids' placement.
    pub seed: u64,
    /// Active domain radius in kernel supports around the moving bodies and beams
    /// ([`chrono_sph::ActiveDomain`]); `None`: the whole fluid is stepped.
    pub active_supports: Option<f64>,
}

/// The largest fluid speed expected over the duct's centre-line speed, for the sound
/// speed: the potential-flow speed-up at a sphere's equator, 3/2.
pub const SPEED_UP: f64 = 1.5;

/// The seed's mean velocity, m/s: `Re = U H / nu` = 45 on its 1 m height at
/// `nu = 1e-3 m^2/s`.
pub const SEED_MEAN_VELOCITY: f64 = 0.045;

impl Default for ChannelParams {
    /// The scaled scene run by default: the seed's fluid, velocity and ellipsoids
    /// (`Re_p` 2.0), a channel 0.24 x 0.18 x 0.18 m (`Re` 8.1) with 4 ellipsoids (solid
    /// fraction 3.3 %) and 2 beams 3 cm thick and 12 cm long (two thirds of the height,
    /// as the seed's), `E` chosen for the seed's Cauchy number (23.8); 6 spacings
    /// across an ellipsoid, 4 across a beam.
    fn default() -> Self {
        let (d, l) = (0.03, 0.12);
        Self {
            length: 0.24,
            width: 0.18,
            height: 0.18,
            spacing: 0.0075,
            h_over_dp: SphSettings::default().h_over_dp,
            rho: 1000.0,
            viscosity: 1.0,
            mean_velocity: SEED_MEAN_VELOCITY,
            ellipsoids: 4,
            semi_axes: [0.0225, 0.0225, 0.03],
            body_density: 1000.0,
            beams: 2,
            beam_diameter: d,
            beam_length: l,
            beam_elements: 4,
            young: young_for_cauchy(ChannelParams::seed().cauchy(), 1.0, 0.045, l, d),
            beam_density: 1000.0,
            coupling_step: 0.01,
            seed: 1,
            active_supports: None,
        }
    }
}

/// The Young's modulus (Pa) that gives beams of length `l` and diameter `d` (m) the
/// viscous Cauchy number `ca` at viscosity `mu` (Pa s) and velocity `u` (m/s):
/// `E = mu u l^3 / (ca I)`, `I = pi d^4 / 64`.
pub fn young_for_cauchy(ca: f64, mu: f64, u: f64, l: f64, d: f64) -> f64 {
    mu * u * l.powi(3) / (ca * PI * d.powi(4) / 64.0)
}

impl ChannelParams {
    /// The seed's scene at its full counts: 1.4 x 1 x 1 m, 2000 ellipsoids, 40 beams of
    /// 1.5 cm (round: the BCE markers of cables are on round sections) and 64 cm, `E` =
    /// 0.2 MPa, spacing 3.75 mm (4 across a beam): about 2.6e7 fluid particles.
    pub fn seed() -> Self {
        Self {
            length: 1.4,
            width: 1.0,
            height: 1.0,
            spacing: 0.00375,
            h_over_dp: SphSettings::default().h_over_dp,
            rho: 1000.0,
            viscosity: 1.0,
            mean_velocity: SEED_MEAN_VELOCITY,
            ellipsoids: 2000,
            semi_axes: [0.0225, 0.0225, 0.03],
            body_density: 1000.0,
            beams: 40,
            beam_diameter: 0.015,
            beam_length: 0.64,
            beam_elements: 4,
            young: 2e5,
            beam_density: 1000.0,
            coupling_step: 0.01,
            seed: 1,
            active_supports: None,
        }
    }

    /// Kinematic viscosity, m^2/s.
    pub fn nu(&self) -> f64 {
        self.viscosity / self.rho
    }

    /// Channel Reynolds number `U H / nu` (mean velocity, height).
    pub fn reynolds(&self) -> f64 {
        self.mean_velocity * self.height / self.nu()
    }

    /// Nominal particle Reynolds number `U d / nu`, `d` twice the smaller equatorial
    /// semi-axis.
    pub fn particle_reynolds(&self) -> f64 {
        self.mean_velocity * self.equatorial_diameter() / self.nu()
    }

    /// The ellipsoids' equatorial diameter `2 min(a, b)`, m.
    pub fn equatorial_diameter(&self) -> f64 {
        2.0 * self.semi_axes[0].min(self.semi_axes[1])
    }

    /// Viscous Cauchy number of the beams, `mu U l^3 / (E I)`.
    pub fn cauchy(&self) -> f64 {
        let i = PI * self.beam_diameter.powi(4) / 64.0;
        self.viscosity * self.mean_velocity * self.beam_length.powi(3) / (self.young * i)
    }

    /// Volume fraction of the ellipsoids in the channel.
    pub fn solid_fraction(&self) -> f64 {
        let [a, b, c] = self.semi_axes;
        self.ellipsoids as f64 * 4.0 / 3.0 * PI * a * b * c
            / (self.length * self.width * self.height)
    }

    /// The coupling step's limit from the ellipsoids' viscous relaxation (s): the
    /// explicit coupling is an explicit Euler step of the body's relaxation to the fluid
    /// (docs/validation-fsi.md, `fsi-sphere-settling`), unstable above twice its time.
    /// The spin time of a sphere of the equatorial radius `a`, `m / (20 pi mu a)` (the
    /// shorter one; the translation's is `m / (6 pi mu a)`), halved.
    pub fn coupling_step_limit(&self) -> f64 {
        let [a, b, c] = self.semi_axes;
        let m = self.body_density * 4.0 / 3.0 * PI * a * b * c;
        let r = a.min(b).min(c);
        0.5 * m / (20.0 * PI * self.viscosity * r)
    }

    /// Checks every field (the error names it and the value).
    pub fn validate(&self) -> Result<()> {
        let pos = check_positive;
        pos("length", self.length)?;
        pos("width", self.width)?;
        pos("height", self.height)?;
        pos("spacing", self.spacing)?;
        pos("h_over_dp", self.h_over_dp)?;
        pos("rho", self.rho)?;
        pos("viscosity", self.viscosity)?;
        pos("mean_velocity", self.mean_velocity)?;
        for (i, s) in self.semi_axes.iter().enumerate() {
            pos(&format!("semi_axes[{i}]"), *s)?;
        }
        pos("body_density", self.body_density)?;
        pos("beam_diameter", self.beam_diameter)?;
        pos("beam_length", self.beam_length)?;
        pos("young", self.young)?;
        pos("beam_density", self.beam_density)?;
        pos("coupling_step", self.coupling_step)?;
        if self.beam_elements == 0 {
            return Err(FsiError::invalid("beam_elements", 0, "must be >= 1"));
        }
        if let Some(n) = self.active_supports
            && !(n.is_finite() && n >= 1.0)
        {
            return Err(FsiError::invalid(
                "active_supports",
                n,
                "must be finite and >= 1 (the fluid touching the markers must move)",
            ));
        }
        let support = 2.0 * self.h_over_dp * self.spacing;
        // the fluid needs a few supports across the channel and above the beams
        for (f, v) in [("width", self.width), ("height", self.height)] {
            if v < 4.0 * support {
                return Err(FsiError::invalid(
                    f,
                    v,
                    format!("must be at least 4 kernel supports ({} m)", 4.0 * support),
                ));
            }
        }
        // the period holds two neighbour-list radii (chrono-sph's minimum image)
        let period = slab_layers(self.h_over_dp) as f64 * self.spacing;
        if self.length < period - 1e-9 * self.spacing {
            return Err(FsiError::invalid(
                "length",
                self.length,
                format!(
                    "must be at least two neighbour-list radii ({period} m) for the periodic images"
                ),
            ));
        }
        if self.beams > 0 && self.beam_length > self.height - support {
            return Err(FsiError::invalid(
                "beam_length",
                self.beam_length,
                format!(
                    "must leave a kernel support below the ceiling (<= {} m)",
                    self.height - support
                ),
            ));
        }
        let limit = self.coupling_step_limit();
        if self.ellipsoids > 0 && self.coupling_step > limit {
            return Err(FsiError::invalid(
                "coupling_step",
                self.coupling_step,
                format!(
                    "must be at most half the ellipsoids' viscous spin relaxation time ({limit:.3e} s): the explicit coupling is unstable above it"
                ),
            ));
        }
        Ok(())
    }
}

/// The channel scene: the system, the fluid item (which owns the beams), the ellipsoids.
pub struct ChannelScene {
    /// The multibody system (no gravity).
    pub system: System,
    /// The fluid item ([`SphFluid`]; the beams are its cables `0..beams`).
    pub fluid: ItemHandle,
    /// The free ellipsoids.
    pub bodies: Vec<BodyHandle>,
    /// The beams' roots (on the floor), m.
    pub roots: Vec<Vector3<f64>>,
    /// The driving body force on the fluid along x, m/s^2.
    pub body_force: f64,
    /// The fluid's sound speed, m/s.
    pub sound_speed: f64,
    /// The parameters.
    pub params: ChannelParams,
    /// Wall time of [`step`](Self::step) so far (the system's steps only), s.
    pub step_time: f64,
}

/// Fluid particles found inside the solids (see [`ChannelScene::fluid_inside`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Inside {
    /// Below an ellipsoid's surface by more than the depth.
    pub ellipsoids: usize,
    /// Below a beam's surface by more than the depth.
    pub beams: usize,
}

impl Inside {
    /// Both counts.
    pub fn total(&self) -> usize {
        self.ellipsoids + self.beams
    }
}

impl ChannelScene {
    /// The fluid item.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid")
    }

    /// One multibody step of `h` (s) ([`System::step`], timed into
    /// [`step_time`](Self::step_time)); then every ellipsoid whose centre left the
    /// period `[0, length)` along x is moved back by one period (its markers are on the
    /// periodic fluid's axis already; this keeps the bodies near their contacts).
    pub fn step(&mut self, h: f64) -> Result<()> {
        let t0 = Instant::now();
        self.system.step(h)?;
        self.step_time += t0.elapsed().as_secs_f64();
        let l = self.params.length;
        for &b in &self.bodies {
            let body = self.system.body_mut(b)?;
            let (x, q) = (body.position(), body.rotation());
            if !(0.0..l).contains(&x.x) && x.x.is_finite() {
                let xw = Vector3::new(x.x.rem_euclid(l), x.y, x.z);
                body.set_pose(xw, q)?;
            }
        }
        Ok(())
    }

    /// The tip displacement of beam `k` from its straight position, m.
    pub fn tip_displacement(&self, k: usize) -> Option<Vector3<f64>> {
        let c = self.fluid().cable(k)?;
        let n = c.mesh().nodes().len() - 1;
        c.mesh().node(NodeId(n)).ok().map(|n| n.displacement())
    }

    /// Number of ellipsoids whose centre is outside the channel's cross-section (or not
    /// finite): `y` outside `[0, width]` or `z` outside `[0, height]`.
    pub fn bodies_outside(&self) -> Result<usize> {
        let p = &self.params;
        let mut n = 0;
        for &b in &self.bodies {
            let x = self.system.body(b)?.position();
            let inside = (0.0..=p.width).contains(&x.y) && (0.0..=p.height).contains(&x.z);
            if !inside || !x.x.is_finite() {
                n += 1;
            }
        }
        Ok(n)
    }

    /// Fluid particles more than `depth` (m) below the surface of an ellipsoid or a beam
    /// (minimum image along the periodic x). With `depth = dp / 2` a particle counted has
    /// passed the outer marker layer.
    pub fn fluid_inside(&self, depth: f64) -> Result<Inside> {
        let p = &self.params;
        let l = p.length;
        let image = |dx: f64| dx - l * (dx / l).round();
        let f = self.fluid();
        let d = f.sph().data();
        let mut out = Inside::default();
        let e = Vector3::from(p.semi_axes);
        let r_max = e.max();
        let poses: Vec<Isometry3<f64>> = (self.bodies.iter())
            .map(|&b| self.system.body(b).map(|b| b.pose()))
            .collect::<std::result::Result<_, _>>()?;
        // the beams' bounding boxes (nodes and slopes span the centre line's hull
        // closely enough at these deflections; padded by the radius and a length)
        let mut beams = Vec::new();
        for k in 0..f.num_cables() {
            let mesh = f.cable(k).expect("beam").mesh();
            let (mut lo, mut hi) = (
                Vector3::repeat(f64::INFINITY),
                Vector3::repeat(-f64::INFINITY),
            );
            for n in mesh.nodes() {
                lo = lo.inf(&n.position);
                hi = hi.sup(&n.position);
            }
            let pad = 0.5 * p.beam_diameter + p.beam_length / p.beam_elements as f64;
            beams.push((
                mesh,
                node_uses(mesh),
                lo.add_scalar(-pad),
                hi.add_scalar(pad),
            ));
        }
        for i in 0..d.len() {
            if d.kind[i] != chrono_sph::data::FLUID {
                continue;
            }
            let x = Vector3::new(d.x[i], d.y[i], d.z[i]);
            for pose in &poses {
                let c = pose.translation.vector;
                let r = Vector3::new(image(x.x - c.x), x.y - c.y, x.z - c.z);
                if r.norm_squared() >= r_max * r_max {
                    continue;
                }
                let local = pose.rotation.inverse() * r;
                if local.component_div(&e).norm_squared() < 1.0
                    && ellipsoid_signed_distance(&e, &local) < -depth
                {
                    out.ellipsoids += 1;
                }
            }
            for (mesh, uses, lo, hi) in &beams {
                // the particle's image nearest the box's centre along x
                let cx = 0.5 * (lo.x + hi.x);
                let y = Vector3::new(cx + image(x.x - cx), x.y, x.z);
                if (0..3).any(|a| y[a] < lo[a] || y[a] > hi[a]) {
                    continue;
                }
                if cable_distance(mesh, uses, &y) < -depth {
                    out.beams += 1;
                }
            }
        }
        Ok(out)
    }

    /// Each ellipsoid's slip velocity (m/s): its velocity minus the mean velocity of the
    /// fluid at its lateral position, the fluid particles within one bounding radius of its
    /// centre in y and z and farther than two bounding radii from it along x (minimum
    /// image): the flow the body sees, without its own disturbance. `None` for a body with
    /// no such fluid.
    pub fn slip_velocities(&self) -> Result<Vec<Option<Vector3<f64>>>> {
        let p = &self.params;
        let l = p.length;
        let r = p.semi_axes.iter().copied().fold(0.0, f64::max);
        let d = self.fluid().sph().data();
        let centres: Vec<(Vector3<f64>, Vector3<f64>)> = (self.bodies.iter())
            .map(|&b| {
                self.system
                    .body(b)
                    .map(|b| (b.position(), b.linear_velocity()))
            })
            .collect::<std::result::Result<_, _>>()?;
        let mut sums = vec![(Vector3::zeros(), 0.0); centres.len()];
        for i in 0..d.len() {
            if d.kind[i] != chrono_sph::data::FLUID {
                continue;
            }
            for ((c, _), s) in centres.iter().zip(sums.iter_mut()) {
                let dx = d.x[i] - c.x;
                let dx = dx - l * (dx / l).round();
                if (d.y[i] - c.y).abs() < r && (d.z[i] - c.z).abs() < r && dx.abs() > 2.0 * r {
                    s.0 += d.mass[i] * Vector3::new(d.vx[i], d.vy[i], d.vz[i]);
                    s.1 += d.mass[i];
                }
            }
        }
        Ok(centres
            .iter()
            .zip(sums)
            .map(|((_, v), (m, w))| (w > 0.0).then(|| v - m / w))
            .collect())
    }

    /// The fluid's mean velocity along x (m/s): momentum over mass.
    pub fn mean_fluid_velocity(&self) -> f64 {
        let d = self.fluid().sph().data();
        let (mut m, mut mv) = (0.0, 0.0);
        for i in 0..d.len() {
            if d.kind[i] == chrono_sph::data::FLUID {
                m += d.mass[i];
                mv += d.mass[i] * d.vx[i];
            }
        }
        mv / m
    }
}

/// Builds the channel scene of `p` with the multibody `solver` (see the
/// [module docs](self)).
pub fn channel(p: &ChannelParams, solver: Box<dyn CcpSolver>) -> Result<ChannelScene> {
    p.validate()?;
    let dp = p.spacing;
    let (hy, hz) = (0.5 * p.width, 0.5 * p.height);
    let f = body_force_for_mean_velocity(p.mean_velocity, p.rho, p.viscosity, hy, hz)?;
    let g_over_mu = p.rho * f / p.viscosity;
    let u_max = duct_velocity(g_over_mu, hy, hz, 0.0, 0.0)?;
    let nu = p.nu();
    // the smallest body scale sets the viscous pressure term (Morris et al. 1997); the
    // fluid passing a body is faster than the duct's centre line: 1.5 U at a sphere's
    // equator in potential flow, the margin taken on the largest speed (measured: the
    // duct's own maximum as the speed gave Mach warnings at the limit 0.1)
    let scale = p.equatorial_diameter().min(if p.beams > 0 {
        p.beam_diameter
    } else {
        f64::INFINITY
    });
    let cs = sound_speed_for(SPEED_UP * u_max, scale, f, nu, 0.01)?;
    let mut settings = SphSettings {
        spacing: dp,
        h_over_dp: p.h_over_dp,
        rho0: p.rho,
        viscosity: p.viscosity,
        sound_speed: cs,
        // a viscous flow (Re_p ~ 2): no artificial viscosity, no XSPH (they act as added
        // viscosity and added mass; docs/validation-fsi.md)
        artificial_viscosity: 0.0,
        xsph: 0.0,
        // no free surface: the gauge pressure may be negative on a body's lee side
        clamp_wall_pressure: false,
        gravity: [0.0; 3],
        body_force: [f, 0.0, 0.0],
        domain_lower: [0.0; 3],
        domain_upper: [p.length, p.width, p.height],
        periodic: [true, false, false],
        ..SphSettings::default()
    };
    if let Some(n) = p.active_supports {
        settings.active_domain = Some(ActiveDomain::from_supports(&settings, n));
    }
    let sys_settings = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut system = System::new(sys_settings, solver)?;
    let profile = |x: &Vector3<f64>| duct_velocity(g_over_mu, hy, hz, x.y - hy, x.z - hz);
    // collision walls for the ellipsoids (fixed boxes outside the fluid: the fluid's
    // walls are markers; these keep a body that reaches a wall from passing it)
    let t = p.width.max(p.height);
    for (k, (c, half)) in [
        (
            Vector3::new(0.5 * p.length, hy, -0.5 * t),
            Vector3::new(p.length, hy + t, 0.5 * t),
        ),
        (
            Vector3::new(0.5 * p.length, hy, p.height + 0.5 * t),
            Vector3::new(p.length, hy + t, 0.5 * t),
        ),
        (
            Vector3::new(0.5 * p.length, -0.5 * t, hz),
            Vector3::new(p.length, 0.5 * t, hz + t),
        ),
        (
            Vector3::new(0.5 * p.length, p.width + 0.5 * t, hz),
            Vector3::new(p.length, 0.5 * t, hz + t),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        system.add_body(
            RigidBodyBuilder::fixed()
                .name(format!("wall {k}"))
                .position(c)
                .collider(
                    Shape::Box { half_extents: half },
                    Isometry3::identity(),
                    Default::default(),
                ),
        )?;
    }
    let roots = beam_roots(p);
    let placed = place_ellipsoids(p, &roots)?;
    let shape = Shape::Ellipsoid {
        semi_axes: Vector3::from(p.semi_axes),
    };
    let [a, b, c] = p.semi_axes;
    let volume = 4.0 / 3.0 * PI * a * b * c;
    let mut bodies = Vec::new();
    for (k, (centre, q)) in placed.iter().enumerate() {
        let v = profile(centre)?;
        let h = system.add_body(
            RigidBodyBuilder::dynamic()
                .name(format!("ellipsoid {k}"))
                .mass_from_shape(&shape, p.body_density)?
                .position(*centre)
                .rotation(*q)
                .linear_velocity(Vector3::new(v, 0.0, 0.0))
                .collider(shape.clone(), Isometry3::identity(), Default::default()),
        )?;
        // the mean pressure gradient the body force stands for acts on the volume
        system
            .body_mut(h)?
            .set_applied_force(Vector3::new(p.rho * f * volume, 0.0, 0.0))?;
        bodies.push(h);
    }
    let mut fsi = FsiBuilder::new(settings)?;
    fsi.add_fluid_box([0.0; 3], [p.length, p.width, p.height], None)?;
    // side walls and floor and ceiling; open (periodic) along x
    fsi.sph().add_tank(
        [0.0; 3],
        [p.length, p.width, p.height],
        wall_layers(p.h_over_dp),
        [false, false, true, true, true, true],
        0,
    )?;
    for &h in &bodies {
        fsi.add_body(&system, h)?;
    }
    let d = p.beam_diameter;
    let material = BeamMaterial::new(
        p.young,
        p.beam_density,
        0.25 * PI * d * d,
        PI * d.powi(4) / 64.0,
        0.0,
    )
    .map_err(|e| FsiError::invalid("young", p.young, e.to_string()))?;
    // rho f A per length as a load of density rho_b: the "gravity" f rho / rho_b
    let push = Vector3::new(f * p.rho / p.beam_density, 0.0, 0.0);
    for (k, root) in roots.iter().enumerate() {
        let mut mesh = CableMesh::straight(
            *root,
            root + Vector3::z() * p.beam_length,
            p.beam_elements,
            material,
            CableQuadrature::default(),
        )
        .map_err(|e| FsiError::invalid("beam_elements", p.beam_elements, e.to_string()))?;
        mesh.clamp(NodeId(0))
            .map_err(|e| FsiError::invalid("beam clamp", k, e.to_string()))?;
        let mut load = vec![0.0; mesh.ndof()];
        for el in mesh.elements() {
            let q = el.gravity_force(&push);
            for (a, v) in q.iter().enumerate() {
                load[6 * el.nodes[a / 6] + a % 6] += v;
            }
        }
        mesh.set_coordinate_load(&load)
            .map_err(|e| FsiError::invalid("body force on the beams", f, e.to_string()))?;
        let mut cable = CableItem::new(format!("beam {k}"), mesh)
            .map_err(|e| FsiError::invalid("beam", k, e.to_string()))?;
        cable.set_contact_enabled(false);
        fsi.add_cable(cable)?;
    }
    let fluid = system.add_item(Box::new(fsi.build("fluid", 10)?));
    let item = system
        .item_mut::<SphFluid>(fluid)
        .expect("the fluid item just added");
    item.sph_mut().set_fluid_velocity(|x| {
        let u = duct_velocity(g_over_mu, hy, hz, x[1] - hy, x[2] - hz).unwrap_or(0.0);
        [u, 0.0, 0.0]
    })?;
    Ok(ChannelScene {
        system,
        fluid,
        bodies,
        roots,
        body_force: f,
        sound_speed: cs,
        params: p.clone(),
        step_time: 0.0,
    })
}
