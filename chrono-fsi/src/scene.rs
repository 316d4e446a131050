//! Ready-made coupled scenes: a body floating in a tank ([`floating`]), with the
//! Archimedes drafts it is checked against ([`archimedes_draft`]).
//!
//! The box and the horizontal cylinder float in a quasi-2-D slab tank (periodic along y,
//! the body spanning the slab: the physics is the 2-D section's, per unit length); the
//! sphere floats in a 3-D tank, periodic along y with a period of [`FloatingParams::width`]
//! body sizes (a row of spheres that far apart: the draft is a static, local quantity).
//! Walls at both ends in x and the floor; the fluid at rest, hydrostatic, filled to
//! `depth` and carved around the body, which starts `offset` above its Archimedes
//! position.

use chrono_core::item::ItemHandle;
use chrono_core::math::{GRAVITY_MAGNITUDE, Isometry3, UnitQuaternion, Vector3};
use chrono_core::particles::lattice::{SLAB_SIDES, slab_layers, wall_layers};
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_sph::SphSettings;

use crate::builder::FsiBuilder;
use crate::error::{FsiError, Result, check_positive};
use crate::fluid::SphFluid;

/// The floating body's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FloatShape {
    /// A box of height `size` and width [`BOX_ASPECT`]` size` spanning the slab.
    Box,
    /// A horizontal cylinder of diameter `size` along y, spanning the slab.
    Cylinder,
    /// A sphere of diameter `size`.
    Sphere,
}

impl std::str::FromStr for FloatShape {
    type Err = FsiError;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "box" => Ok(Self::Box),
            "cylinder" => Ok(Self::Cylinder),
            "sphere" => Ok(Self::Sphere),
            other => Err(FsiError::invalid("shape", other, "box | cylinder | sphere")),
        }
    }
}

/// Parameters of [`floating`] (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct FloatingParams {
    /// The body's shape.
    pub shape: FloatShape,
    /// Body density, kg/m^3 (below the fluid's to float).
    pub body_density: f64,
    /// Body size (box side, cylinder or sphere diameter), m.
    pub body_size: f64,
    /// Water depth at rest, m.
    pub depth: f64,
    /// Tank length (x), in body sizes.
    pub length: f64,
    /// Sphere only: the period along y, in body sizes.
    pub width: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// `h / dp`.
    pub h_over_dp: f64,
    /// Fluid density, kg/m^3.
    pub rho0: f64,
    /// Kinematic viscosity, m^2/s.
    pub nu: f64,
    /// Start of the body above its Archimedes position, m.
    pub offset: f64,
    /// Sound speed over `sqrt(g depth)`.
    pub mach_factor: f64,
    /// Monaghan's artificial viscosity `alpha` of the fluid
    /// ([`SphSettings::artificial_viscosity`]; it acts as a kinematic viscosity
    /// `~ alpha c_s h / 10`).
    pub artificial_viscosity: f64,
    /// XSPH coefficient of the fluid ([`SphSettings::xsph`]: particles drift with their
    /// velocity plus this fraction of the kernel-averaged velocity difference).
    pub xsph: f64,
}

impl Default for FloatingParams {
    fn default() -> Self {
        Self {
            shape: FloatShape::Box,
            body_density: 500.0,
            body_size: 0.1,
            depth: 0.2,
            length: 10.0,
            width: 3.0,
            spacing: 0.0125,
            h_over_dp: SphSettings::default().h_over_dp,
            rho0: 1000.0,
            nu: 1e-6,
            offset: 0.01,
            mach_factor: 10.0,
            artificial_viscosity: SphSettings::default().artificial_viscosity,
            xsph: SphSettings::default().xsph,
        }
    }
}

impl FloatingParams {
    /// Checks every field (the error names it).
    pub fn validate(&self) -> Result<()> {
        let pos = check_positive;
        pos("body_density", self.body_density)?;
        pos("body_size", self.body_size)?;
        pos("depth", self.depth)?;
        pos("spacing", self.spacing)?;
        pos("h_over_dp", self.h_over_dp)?;
        pos("rho0", self.rho0)?;
        pos("mach_factor", self.mach_factor)?;
        if !(self.artificial_viscosity.is_finite() && self.artificial_viscosity >= 0.0) {
            return Err(FsiError::invalid(
                "artificial_viscosity",
                self.artificial_viscosity,
                "must be finite and >= 0",
            ));
        }
        if !(self.xsph.is_finite() && (0.0..=1.0).contains(&self.xsph)) {
            return Err(FsiError::invalid("xsph", self.xsph, "must be in [0, 1]"));
        }
        if !(self.nu.is_finite() && self.nu >= 0.0) {
            return Err(FsiError::invalid("nu", self.nu, "must be finite and >= 0"));
        }
        if self.body_density >= self.rho0 {
            return Err(FsiError::invalid(
                "body_density",
                self.body_density,
                format!(
                    "must be below the fluid density {} kg/m^3 to float",
                    self.rho0
                ),
            ));
        }
        if !(self.length.is_finite() && self.length >= 2.0) {
            return Err(FsiError::invalid(
                "length",
                self.length,
                "must be >= 2 body sizes",
            ));
        }
        if !(self.width.is_finite() && self.width >= 1.5) {
            return Err(FsiError::invalid(
                "width",
                self.width,
                "must be >= 1.5 body sizes",
            ));
        }
        if !self.offset.is_finite() || self.offset.abs() > 0.25 * self.body_size {
            return Err(FsiError::invalid(
                "offset",
                self.offset,
                "must be finite and at most a quarter of the body size",
            ));
        }
        let d = archimedes_draft(self.shape, self.body_size, self.body_density / self.rho0);
        let below = (0.5 * self.body_size).max(4.0 * self.spacing);
        if self.depth < d + below - 1e-9 {
            return Err(FsiError::invalid(
                "depth",
                self.depth,
                format!("must leave {below} m of water below the draft {d} m"),
            ));
        }
        Ok(())
    }
}

/// The draft (m) at which a body of `shape`, size `size` (m; the height of the box) and
/// density ratio `ratio` to the fluid floats upright (Archimedes): box `d = ratio s`;
/// cylinder (per unit length) the circular segment
/// `R^2 acos((R - d)/R) - (R - d) sqrt(2 R d - d^2) = ratio pi R^2`; sphere the cap
/// `pi d^2 (3 R - d) / 3 = ratio 4/3 pi R^3`; solved by bisection.
pub fn archimedes_draft(shape: FloatShape, size: f64, ratio: f64) -> f64 {
    let full = submerged_area_or_volume(shape, size, size);
    let (mut lo, mut hi) = (0.0, size);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if submerged_area_or_volume(shape, size, mid) < ratio * full {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The floating scene: the system, the body, the fluid item and the geometry.
pub struct FloatingScene {
    /// The multibody system (gravity `-g z`).
    pub system: System,
    /// The floating body.
    pub body: BodyHandle,
    /// The fluid item ([`SphFluid`]).
    pub fluid: ItemHandle,
    /// Tank inner extent (x, y), m.
    pub tank: [f64; 2],
    /// Archimedes draft, m.
    pub draft_archimedes: f64,
}

impl FloatingScene {
    /// The fluid.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid")
    }

    /// The body's draft (m): the still-water level minus the body's lowest point. The
    /// level `L` is the one at which the fluid's actual volume `sum_f m_f / rho_f` (its
    /// compression included) fills the tank around the body:
    /// `A L - V_sub(L) = sum_f m_f / rho_f`, with `A` the tank's plan area and `V_sub`
    /// the body's volume below `L` (by bisection). A reading free of the ragged top
    /// particle layer.
    pub fn draft(&self, p: &FloatingParams) -> f64 {
        let b = self.system.body(self.body).expect("the scene's body");
        let c = b.position();
        let d = self.fluid().sph().data();
        let vol: f64 = (0..d.len())
            .filter(|&i| d.kind[i] == chrono_sph::data::FLUID)
            .map(|i| d.mass[i] / d.rho[i])
            .sum();
        volume_draft(p.shape, p.body_size, self.tank, vol, c.z)
    }
}

/// The draft (m) of a body of `shape` and `size` (m) centred at height `centre` (m; its
/// lowest point `bottom = centre - size / 2`) in a tank of plan `tank = [length, width]` (m) holding the fluid volume `vol`
/// (m^3): the level `L` with `A L - V_sub(L) = vol` (`A` the plan area, `V_sub` the
/// body's volume below `L`: the section times the slab width for the slab shapes), by
/// bisection, minus `bottom`.
pub fn volume_draft(shape: FloatShape, size: f64, tank: [f64; 2], vol: f64, centre: f64) -> f64 {
    let bottom = centre - 0.5 * size;
    let area = tank[0] * tank[1];
    let sub = |level: f64| {
        let dd = (level - bottom).clamp(0.0, size);
        submerged_area_or_volume(shape, size, dd)
            * match shape {
                FloatShape::Sphere => 1.0,
                _ => tank[1],
            }
    };
    let (mut lo, mut hi) = (0.0, 2.0 * (vol / area) + 2.0 * size + centre.abs());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if area * mid - sub(mid) < vol {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) - bottom
}

/// A floating scene by either fluid model (WCSPH: [`FloatingScene`]; constraint fluid:
/// [`crate::cfluid::CfluidFloatingScene`]): what the heave scene
/// ([`crate::heave::HeaveScene`]) needs of it.
pub trait FloatingSystem {
    /// The multibody system.
    fn system(&self) -> &System;
    /// The multibody system, mutable.
    fn system_mut(&mut self) -> &mut System;
    /// The floating body.
    fn body(&self) -> BodyHandle;
    /// Tank inner extent (x, y), m.
    fn tank(&self) -> [f64; 2];
    /// Relax the fluid's velocities at `rate` (1/s; 0: off).
    fn set_fluid_damping(&mut self, rate: f64) -> Result<()>;
    /// One multibody step of `h` (s).
    fn step(&mut self, h: f64) -> Result<()>;
    /// The fluid's vertical force on the body over the last step, N.
    fn fluid_force_z(&self) -> f64;
    /// The fluid's steps so far (SPH: its sub-steps; constraint fluid: the system's).
    fn fluid_steps(&self) -> u64;
}

impl FloatingSystem for FloatingScene {
    fn system(&self) -> &System {
        &self.system
    }
    fn system_mut(&mut self) -> &mut System {
        &mut self.system
    }
    fn body(&self) -> BodyHandle {
        self.body
    }
    fn tank(&self) -> [f64; 2] {
        self.tank
    }
    fn set_fluid_damping(&mut self, rate: f64) -> Result<()> {
        let fluid = self.fluid;
        self.system
            .item_mut::<SphFluid>(fluid)
            .expect("the scene's fluid")
            .sph_mut()
            .set_damping(rate)?;
        Ok(())
    }
    fn step(&mut self, h: f64) -> Result<()> {
        self.system.step(h)?;
        Ok(())
    }
    fn fluid_force_z(&self) -> f64 {
        self.fluid()
            .body_load(self.body)
            .map_or(f64::NAN, |[f, _]| f.z)
    }
    fn fluid_steps(&self) -> u64 {
        self.fluid().substeps()
    }
}

impl FloatingScene {
    /// The body's draft (m) from the hydrostatic level: the level `L` where the pressure
    /// of the far fluid extrapolates to zero, `L = z_f + p_f / (g (rho_f + rho_0) / 2)`
    /// averaged over the fluid particles in the lower half of the water farther than one
    /// body size (horizontally) from the body and than the support from the end walls;
    /// minus the body's lowest point (NaN when no particle qualifies). Archimedes' level (the buoyancy is the weight of the
    /// fluid displaced below the zero-pressure level).
    pub fn draft_pressure(&self, p: &FloatingParams) -> f64 {
        let b = self.system.body(self.body).expect("the scene's body");
        let c = b.position();
        let sph = self.fluid().sph();
        let d = sph.data();
        let g = -sph.settings().gravity[2];
        let rho0 = sph.settings().rho0;
        let margin = sph.kernel().support();
        let level0 = (p.depth / p.spacing + 1e-6).floor() * p.spacing;
        let (mut sum, mut n) = (0.0, 0usize);
        for i in 0..d.len() {
            if d.kind[i] != chrono_sph::data::FLUID || d.z[i] > 0.5 * level0 {
                continue;
            }
            let (dx, dy) = (d.x[i] - c.x, d.y[i] - c.y);
            let dist = match p.shape {
                FloatShape::Sphere => (dx * dx + dy * dy).sqrt(),
                _ => dx.abs(),
            };
            if dist > p.body_size && d.x[i] > margin && d.x[i] < self.tank[0] - margin {
                sum += d.z[i] + d.p[i] / (g * 0.5 * (d.rho[i] + rho0));
                n += 1;
            }
        }
        if n == 0 {
            return f64::NAN;
        }
        sum / n as f64 - (c.z - 0.5 * p.body_size)
    }
}

/// The body's submerged cross-section area (box, cylinder: m^2, per unit length) or
/// volume (sphere: m^3) at draft `d` (m), `0 <= d <= size`.
pub fn submerged_area_or_volume(shape: FloatShape, size: f64, d: f64) -> f64 {
    let r = 0.5 * size;
    match shape {
        FloatShape::Box => BOX_ASPECT * size * d,
        FloatShape::Cylinder => {
            r * r * ((r - d) / r).clamp(-1.0, 1.0).acos()
                - (r - d) * (2.0 * r * d - d * d).max(0.0).sqrt()
        }
        FloatShape::Sphere => std::f64::consts::PI * d * d * (3.0 * r - d) / 3.0,
    }
}

/// Width over height of the floating box: 2, so it floats upright (metacentric height
/// `B^2 / (12 d) - (H - d) / 2 > 0` for every density ratio), where a square box capsizes
/// for density ratios between 0.21 and 0.79.
pub const BOX_ASPECT: f64 = 2.0;

/// Moment of inertia factor on the axes a slab body may not turn about (roll about x, yaw
/// about z): the body is a slice of an infinitely long one.
pub const PLANAR_INERTIA: f64 = 1e6;

/// Builds the floating scene of `p` with the system's solver `solver` (see the
/// [module docs](self)).
pub fn floating(
    p: &FloatingParams,
    solver: Box<dyn chrono_core::descriptor::CcpSolver>,
) -> Result<FloatingScene> {
    p.validate()?;
    let g = GRAVITY_MAGNITUDE;
    let dp = p.spacing;
    let s = p.body_size;
    let len = (p.length * s / dp).round() * dp;
    let width = match p.shape {
        FloatShape::Sphere => (p.width * s / dp).round() * dp,
        _ => slab_layers(p.h_over_dp) as f64 * dp,
    };
    // the lattice holds whole layers (`Fit::Floor`): the still-water level is `depth`
    // rounded down to a multiple of `dp`
    let level = (p.depth / dp + 1e-6).floor() * dp;
    let top = level + s + 4.0 * dp;
    let draft = archimedes_draft(p.shape, s, p.body_density / p.rho0);
    let sys_settings = SystemSettings::default();
    let mut settings = slab_water(
        &sys_settings,
        dp,
        p.h_over_dp,
        p.rho0,
        p.mach_factor * (g * p.depth).sqrt(),
        p.nu,
        [len, width, top],
    );
    settings.artificial_viscosity = p.artificial_viscosity;
    settings.xsph = p.xsph;
    let mut system = System::new(sys_settings, solver)?;
    // the body along y spans the slab (one period) exactly
    let (shape, rot) = match p.shape {
        FloatShape::Box => (
            Shape::Box {
                half_extents: Vector3::new(0.5 * BOX_ASPECT * s, 0.5 * width, 0.5 * s),
            },
            UnitQuaternion::identity(),
        ),
        FloatShape::Cylinder => (
            Shape::Cylinder {
                half_length: 0.5 * width,
                radius: 0.5 * s,
            },
            UnitQuaternion::identity(),
        ),
        FloatShape::Sphere => (
            Shape::Sphere { radius: 0.5 * s },
            UnitQuaternion::identity(),
        ),
    };
    let centre = Vector3::new(0.5 * len, 0.5 * width, level - draft + 0.5 * s + p.offset);
    let mut builder = RigidBodyBuilder::dynamic()
        .name("float")
        .mass_from_shape(&shape, p.body_density)?;
    if p.shape != FloatShape::Sphere {
        let (m, r) = (
            p.body_density * submerged_area_or_volume(p.shape, s, s) * width,
            0.5 * s,
        );
        // pitch about y: the shape's own; roll and yaw blocked (a slice of a long body)
        let iy = match p.shape {
            FloatShape::Box => m * (BOX_ASPECT * BOX_ASPECT + 1.0) * s * s / 12.0,
            _ => 0.5 * m * r * r,
        };
        builder =
            builder.inertia_diagonal(Vector3::new(PLANAR_INERTIA * iy, iy, PLANAR_INERTIA * iy));
    }
    let body = system.add_body(builder.position(centre).rotation(rot).collider(
        shape,
        Isometry3::identity(),
        Default::default(),
    ))?;
    let fluid = add_slab_tank(
        &mut system,
        settings,
        body,
        [len, width, level, top],
        p.h_over_dp,
    )?;
    Ok(FloatingScene {
        system,
        body,
        fluid,
        tank: [len, width],
        draft_archimedes: draft,
    })
}

/// The fluid settings of a slab scene (periodic along y, walls elsewhere): spacing `dp`
/// (m), `h_over_dp`, rest density `rho0` (kg/m^3), sound speed (m/s), kinematic viscosity
/// `nu` (m^2/s; the dynamic one is `rho0 nu`), the domain `[0, len] x [0, width] x [0, top]`
/// and the system's gravity. Shared by the floating and the towed scenes.
pub(crate) fn slab_water(
    system: &SystemSettings,
    dp: f64,
    h_over_dp: f64,
    rho0: f64,
    sound_speed: f64,
    nu: f64,
    [len, width, top]: [f64; 3],
) -> SphSettings {
    let gz = system.gravity;
    SphSettings {
        spacing: dp,
        h_over_dp,
        rho0,
        sound_speed,
        viscosity: rho0 * nu,
        gravity: [gz.x, gz.y, gz.z],
        domain_lower: [0.0; 3],
        domain_upper: [len, width, top],
        periodic: [false, true, false],
        ..SphSettings::default()
    }
}

/// The water of a slab scene as an item of `system`: the box `[0, len] x [0, width]` filled
/// to `level` (m), its marker walls (floor and the slab's sides, open above `top`) and
/// `body`'s markers; `dims = [len, width, level, top]`, `h_over_dp` the kernel's
/// smoothing length over the spacing. Shared by the floating and the towed scenes.
pub(crate) fn add_slab_tank(
    system: &mut System,
    settings: SphSettings,
    body: BodyHandle,
    dims: [f64; 4],
    h_over_dp: f64,
) -> Result<ItemHandle> {
    let [len, width, level, top] = dims;
    let mut fsi = FsiBuilder::new(settings)?;
    fsi.add_fluid_box([0.0; 3], [len, width, level], Some(level))?;
    fsi.sph().add_tank(
        [0.0; 3],
        [len, width, top],
        wall_layers(h_over_dp),
        SLAB_SIDES,
        0,
    )?;
    fsi.add_body(system, body)?;
    Ok(system.add_item(Box::new(fsi.build("water", 10)?)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn archimedes_drafts_satisfy_their_equations() {
        // half-density cylinder and sphere float at half their diameter (symmetry)
        for shape in [FloatShape::Cylinder, FloatShape::Sphere] {
            let d = archimedes_draft(shape, 0.2, 0.5);
            assert!((d - 0.1).abs() < 1e-12, "{shape:?} {d}");
        }
        assert!((archimedes_draft(FloatShape::Box, 0.2, 0.3) - 0.06).abs() < 1e-15);
        // sphere at ratio 0.3: cap volume pi d^2 (3R - d)/3 = 0.3 * 4/3 pi R^3
        let (r, d) = (0.1, archimedes_draft(FloatShape::Sphere, 0.2, 0.3));
        let v = std::f64::consts::PI * d * d * (3.0 * r - d) / 3.0;
        assert!((v / (0.4 * std::f64::consts::PI * r.powi(3)) - 1.0).abs() < 1e-12);
    }
}
