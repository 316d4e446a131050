//! A body towed through a long tank (the scene of `fsi-active-domain`): a horizontal
//! cylinder of diameter `D` spanning a quasi-2-D slab (periodic along y), submerged with
//! its centre `submergence` below the still-water level of a tank `length` diameters long
//! (walls at both ends and the floor), towed along +x by a kinematic body at the speed
//! `U(t) = U (3 s^2 - 2 s^3)`, `s = min(t / ramp, 1)` (a C1 ramp: an impulsive start
//! would send a pressure pulse `rho c_s U` through the weakly compressible fluid).
//!
//! The fluid is WCSPH with BCE markers in the cylinder ([`FsiBuilder`](crate::FsiBuilder)); with
//! [`TowedParams::active_radius`] set it runs with an active domain
//! ([`chrono_sph::ActiveDomain`]) of that radius around the cylinder, so the same scene
//! runs with and without it.
//!
//! **The radius is a length of the flow**, in cylinder diameters: what the active domain
//! must hold is the body's near field and the free surface's response to it, whose extent
//! scales with `D` (and the depth), not with the particle spacing. A radius in kernel
//! supports `2 h` is half as long in metres at half the spacing, so the same number of
//! supports reached 3.6 D at `dp = D/5` and 1.8 D at `D/10` (docs/validation-fsi.md, the
//! first `--full` run: drag -13.5 %). The radius, `active_radius * D` from the cylinder's
//! bounding sphere, must still be at least the kernel support `2 h` (the fluid touching
//! the markers must move): below it is an error naming `active_radius`.
//!
//! Read-outs: the fluid's force on the cylinder ([`TowedScene::force`]), its drag
//! coefficient per unit span `C_D = F_D / (rho U^2 D W / 2)` (`W` the slab width), and
//! the free-surface elevation at a distance from the cylinder
//! ([`TowedScene::surface_elevation`]).

use chrono_core::item::ItemHandle;
use chrono_core::math::{GRAVITY_MAGNITUDE, Isometry3, Vector3};
use chrono_core::particles::lattice::slab_layers;
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_sph::{ActiveDomain, SphSettings};

use crate::error::{FsiError, Result, check_positive};
use crate::fluid::SphFluid;
use crate::scene::{add_slab_tank, slab_water};

/// Parameters of [`towed`] (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct TowedParams {
    /// Cylinder diameter `D`, m.
    pub diameter: f64,
    /// Tow speed `U`, m/s.
    pub speed: f64,
    /// Duration of the speed ramp, s.
    pub ramp: f64,
    /// Depth of the cylinder's centre below the still-water level, m.
    pub submergence: f64,
    /// Water depth at rest, m.
    pub depth: f64,
    /// Tank length (x), in diameters.
    pub length: f64,
    /// Start of the cylinder's centre from the upstream (x = 0) wall, in diameters.
    pub start: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// `h / dp`.
    pub h_over_dp: f64,
    /// Fluid density, kg/m^3.
    pub rho0: f64,
    /// Kinematic viscosity, m^2/s.
    pub nu: f64,
    /// Sound speed over `sqrt(g depth)`.
    pub mach_factor: f64,
    /// Artificial viscosity `alpha` of the fluid (Monaghan; `>= 0`). It adds a viscosity
    /// `~ alpha c_s h / 10` m^2/s to `nu` (chrono-sph's `SphSettings::artificial_viscosity`),
    /// 1.2e-3 m^2/s at the defaults against `nu` = 1e-4: the flow's effective Reynolds number
    /// is then about 30, not `U D / nu` = 375, and it moves with the sound speed.
    pub alpha: f64,
    /// The active domain's radius around the cylinder's bounding sphere, in cylinder
    /// diameters (`active_radius * D` m, at least the kernel support `2 h`, see the
    /// [module docs](self)); `None`: the full domain is stepped.
    pub active_radius: Option<f64>,
}

impl Default for TowedParams {
    fn default() -> Self {
        Self {
            diameter: 0.125,
            speed: 0.3,
            ramp: 0.2,
            submergence: 0.125,
            depth: 0.25,
            length: 16.0,
            start: 3.0,
            spacing: 0.025,
            h_over_dp: SphSettings::default().h_over_dp,
            rho0: 1000.0,
            nu: 1e-4,
            mach_factor: 10.0,
            alpha: 0.02,
            active_radius: None,
        }
    }
}

impl TowedParams {
    /// Checks every field (the error names it).
    pub fn validate(&self) -> Result<()> {
        let pos = check_positive;
        pos("diameter", self.diameter)?;
        pos("speed", self.speed)?;
        pos("ramp", self.ramp)?;
        pos("submergence", self.submergence)?;
        pos("depth", self.depth)?;
        pos("length", self.length)?;
        pos("start", self.start)?;
        pos("spacing", self.spacing)?;
        pos("h_over_dp", self.h_over_dp)?;
        pos("rho0", self.rho0)?;
        pos("mach_factor", self.mach_factor)?;
        if !(self.nu.is_finite() && self.nu >= 0.0) {
            return Err(FsiError::invalid("nu", self.nu, "must be finite and >= 0"));
        }
        if !(self.alpha.is_finite() && self.alpha >= 0.0) {
            return Err(FsiError::invalid(
                "alpha",
                self.alpha,
                "must be finite and >= 0",
            ));
        }
        let r = 0.5 * self.diameter;
        // a layer of water (two spacings) above and below the cylinder
        if self.submergence < r + 2.0 * self.spacing {
            return Err(FsiError::invalid(
                "submergence",
                self.submergence,
                format!(
                    "must leave two spacings of water above the cylinder (>= {} m)",
                    r + 2.0 * self.spacing
                ),
            ));
        }
        // the still-water level: the depth rounded down to whole spacings
        let level = (self.depth / self.spacing + 1e-6).floor() * self.spacing;
        if level < self.submergence + r + 2.0 * self.spacing {
            return Err(FsiError::invalid(
                "depth",
                self.depth,
                format!(
                    "must leave two spacings of water below the cylinder (level {level} m >= {} m)",
                    self.submergence + r + 2.0 * self.spacing
                ),
            ));
        }
        if self.start < 1.0 || self.start > self.length - 1.0 {
            return Err(FsiError::invalid(
                "start",
                self.start,
                format!(
                    "must keep the cylinder a diameter from both end walls (1 to {})",
                    self.length - 1.0
                ),
            ));
        }
        if let Some(n) = self.active_radius {
            let support = 2.0 * self.h_over_dp * self.spacing;
            if !(n.is_finite() && n * self.diameter >= support) {
                return Err(FsiError::invalid(
                    "active_radius",
                    n,
                    format!(
                        "must be finite and at least the kernel support 2 h = {support} m = {} D \
                         (the fluid touching the markers must move)",
                        support / self.diameter
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The prescribed tow speed at time `t` (s), m/s (see the [module docs](self)).
    pub fn speed_at(&self, t: f64) -> f64 {
        let s = (t / self.ramp).clamp(0.0, 1.0);
        self.speed * s * s * (3.0 - 2.0 * s)
    }

    /// The distance towed by time `t` (s), m: the integral of [`speed_at`](Self::speed_at).
    pub fn distance_at(&self, t: f64) -> f64 {
        let tr = self.ramp;
        if t >= tr {
            // the ramp covers U tr / 2
            self.speed * (0.5 * tr + (t - tr))
        } else {
            let s = (t / tr).max(0.0);
            self.speed * tr * (s * s * s - 0.5 * s * s * s * s)
        }
    }
}

/// The towed scene: the system, the cylinder, the fluid item and the geometry.
pub struct TowedScene {
    /// The multibody system (gravity `-g z`).
    pub system: System,
    /// The towed cylinder (kinematic).
    pub body: BodyHandle,
    /// The fluid item ([`SphFluid`]).
    pub fluid: ItemHandle,
    /// Tank inner extent (x, y), m.
    pub tank: [f64; 2],
    /// Still-water level, m (the depth rounded down to whole spacings).
    pub level: f64,
    /// The cylinder's start position, m.
    pub start: Vector3<f64>,
    /// The parameters.
    pub params: TowedParams,
}

impl TowedScene {
    /// The fluid.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid")
    }

    /// One multibody step of `h` (s): the cylinder's velocity set to the tow speed at the
    /// middle of the step (the kinematic body moves with it: the position after the step
    /// is the midpoint rule of the ramp), then [`System::step`].
    pub fn step(&mut self, h: f64) -> Result<()> {
        let t = self.system.time();
        let v = self.params.speed_at(t + 0.5 * h);
        self.system
            .body_mut(self.body)?
            .set_linear_velocity(Vector3::new(v, 0.0, 0.0))?;
        self.system.step(h)?;
        Ok(())
    }

    /// The fluid's force on the cylinder over the last system step, N.
    pub fn force(&self) -> Vector3<f64> {
        self.fluid()
            .body_load(self.body)
            .map(|l| l[0])
            .unwrap_or_else(Vector3::zeros)
    }

    /// The drag coefficient of `force_x` (N, the force along the tow, negative for a
    /// drag) at the full tow speed: `C_D = -F_x / (rho U^2 D W / 2)`.
    pub fn drag_coefficient(&self, force_x: f64) -> f64 {
        let p = &self.params;
        -force_x / (0.5 * p.rho0 * p.speed * p.speed * p.diameter * self.tank[1])
    }

    /// The free-surface elevation above the still-water level (m) at `dx` (m) ahead of
    /// the cylinder's centre: the top fluid particle within half a spacing of that
    /// abscissa plus half a spacing ([`chrono_sph::SphSystem::free_surface_height`]),
    /// minus the level. `None` when no particle is there.
    pub fn surface_elevation(&self, dx: f64) -> Result<Option<f64>> {
        let x = self.system.body(self.body)?.position().x + dx;
        let h = self
            .fluid()
            .sph()
            .free_surface_height(x, 0.5 * self.params.spacing)?;
        Ok(h.map(|z| z - self.level))
    }
}

/// Builds the towed scene of `p` with the system's solver `solver` (see the
/// [module docs](self)).
pub fn towed(
    p: &TowedParams,
    solver: Box<dyn chrono_core::descriptor::CcpSolver>,
) -> Result<TowedScene> {
    p.validate()?;
    let g = GRAVITY_MAGNITUDE;
    let dp = p.spacing;
    let d = p.diameter;
    let len = (p.length * d / dp).round() * dp;
    let width = slab_layers(p.h_over_dp) as f64 * dp;
    // the lattice holds whole layers: the still-water level is `depth` rounded down
    let level = (p.depth / dp + 1e-6).floor() * dp;
    let top = level + 0.5 * p.depth.max(d) + 4.0 * dp;
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
    settings.artificial_viscosity = p.alpha;
    if let Some(n) = p.active_radius {
        settings.active_domain = Some(ActiveDomain::from_radius(&settings, n * d));
    }
    let mut system = System::new(sys_settings, solver)?;
    let shape = Shape::Cylinder {
        half_length: 0.5 * width,
        radius: 0.5 * d,
    };
    // the centre on a lattice plane in x (dp/2 off the lattice points, as the walls)
    let start = Vector3::new(
        ((p.start * d / dp).round() + 0.5) * dp,
        0.5 * width,
        level - p.submergence,
    );
    let body = system.add_body(
        RigidBodyBuilder::kinematic()
            .name("towed")
            .position(start)
            .collider(shape, Isometry3::identity(), Default::default()),
    )?;
    let fluid = add_slab_tank(
        &mut system,
        settings,
        body,
        [len, width, level, top],
        p.h_over_dp,
    )?;
    Ok(TowedScene {
        system,
        body,
        fluid,
        tank: [len, width],
        level,
        start,
        params: p.clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_distance_is_the_integral_of_the_speed() {
        let p = TowedParams::default();
        for &t in &[0.05, 0.1, 0.2, 0.5, 1.3] {
            // midpoint rule on a fine grid
            let n = 20_000;
            let h = t / n as f64;
            let s: f64 = (0..n).map(|i| p.speed_at((i as f64 + 0.5) * h) * h).sum();
            assert!((s - p.distance_at(t)).abs() < 1e-9, "t {t}: {s}");
        }
        assert_eq!(p.speed_at(0.0), 0.0);
        assert_eq!(p.speed_at(1.0), p.speed);
    }

    /// Through the fluid item: an active domain covering the tank gives the full run's
    /// body loads bit for bit; a small one steps a fraction of the fluid, centred on the
    /// towed (kinematic) cylinder.
    #[test]
    fn covering_active_domain_gives_the_full_loads_bit_for_bit() {
        let run = |active: Option<f64>| {
            let p = TowedParams {
                spacing: 0.125 / 4.0,
                length: 12.0,
                start: 3.0,
                active_radius: active,
                ..TowedParams::default()
            };
            let mut s = towed(&p, Box::new(chrono_ccp::Psor::new(Default::default()))).unwrap();
            let mut f = Vec::new();
            for _ in 0..25 {
                s.step(2e-3).unwrap();
                f.push(s.force().map(f64::to_bits));
            }
            let sph = s.fluid().sph();
            let c = s.system.body(s.body).unwrap().position();
            (
                f,
                sph.stats().active_fluid,
                sph.num_fluid(),
                sph.active_sources().to_vec(),
                c,
            )
        };
        let (full, n_full, n, _, _) = run(None);
        assert_eq!(n_full, n);
        let (cover, n_cover, _, _, _) = run(Some(1000.0));
        assert_eq!(
            full, cover,
            "a covering active domain changed the body's load"
        );
        assert_eq!(n_cover, n);
        // 1.5 D = 2 kernel supports at D / 4
        let (_, n_small, _, src, c) = run(Some(1.5));
        assert!(n_small > 0 && 2 * n_small < n, "{n_small} of {n}");
        assert_eq!(src.len(), 1);
        assert!((src[0][0] - c.x).abs() < 1e-12 && (src[0][2] - c.z).abs() < 1e-12);
    }

    /// The radius is a length of the flow: `active_radius * D` m at every spacing, and the
    /// kernel-support floor `2 h` follows the spacing (0.5 D is too short at D / 4, where
    /// `2 h` = 0.75 D, and long enough at D / 10, where `2 h` = 0.3 D).
    #[test]
    fn active_radius_is_in_diameters_at_every_spacing() {
        let radius_at = |spacing: f64, r: f64| {
            let p = TowedParams {
                spacing,
                active_radius: Some(r),
                ..TowedParams::default()
            };
            p.validate()?;
            let s = towed(&p, Box::new(chrono_ccp::Psor::new(Default::default())))?;
            let ad = s.fluid().sph().settings().active_domain.expect("active");
            Ok::<f64, FsiError>(ad.radius)
        };
        let d = TowedParams::default().diameter;
        for spacing in [d / 4.0, d / 5.0, d / 8.0] {
            assert_eq!(
                radius_at(spacing, 3.6).unwrap(),
                3.6 * d,
                "spacing {spacing}"
            );
        }
        let e = radius_at(d / 4.0, 0.5).unwrap_err().to_string();
        assert!(e.contains("active_radius") && e.contains("0.5"), "{e}");
        assert_eq!(radius_at(d / 10.0, 0.5).unwrap(), 0.5 * d);
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let p = TowedParams {
            submergence: 0.05,
            ..TowedParams::default()
        };
        let e = towed(&p, Box::new(chrono_ccp::Psor::new(Default::default())));
        assert!(e.is_err_and(|e| e.to_string().contains("submergence")));
        let p = TowedParams {
            active_radius: Some(0.5),
            ..TowedParams::default()
        };
        assert!(
            p.validate()
                .is_err_and(|e| e.to_string().contains("active_radius"))
        );
        let p = TowedParams {
            alpha: -0.1,
            ..TowedParams::default()
        };
        assert!(p.validate().is_err_and(|e| e.to_string().contains("alpha")));
    }
}
