//! A sphere settling under gravity in a viscous fluid: one cell of a simple cubic array
//! of spheres (edge `L`), WCSPH fluid, triply periodic, the sphere a free rigid body with
//! BCE markers (the scene of `fsi-sphere-settling`).
//!
//! # Why a fully periodic cell, and its forces
//!
//! The reference problem of the periodic corrections (Hasimoto 1959; Zick & Homsy 1982)
//! is a simple cubic array of spheres, i.e. exactly a triply periodic cell; a laterally
//! periodic box with a floor would add the floor's and the free surface's effects and
//! need a column many diameters tall to reach the terminal speed. A periodic cell has no
//! hydrostatic pressure: in a settling suspension the mean pressure gradient balances the
//! weight of the mixture, `grad <p> = rho_mix g`, `rho_mix = c rho_s + (1 - c) rho_f`, and
//! acts on the fluid and on the sphere's volume alike. Its periodic part is what the SPH
//! fluid computes; the mean part enters as body forces: per unit volume, the fluid gets
//! `(rho_f - rho_mix) g = -c (rho_s - rho_f) g` and the sphere `(rho_s - rho_mix) g`, so
//! the sphere is pulled by
//!
//! ```text
//! F_s = (1 - c) W,     W = (rho_s - rho_f) V_s g     (the net weight)
//! ```
//!
//! and the fluid by `-F_s` in total. The external forces cancel, so the total momentum of
//! fluid plus sphere stays zero (to round-off) from a start at rest, which is the frame of
//! a closed container. Gravity itself is then zero in the system and in the fluid (its
//! hydrostatic part has no periodic counterpart): the sphere gets `F_s` as an applied
//! force, the fluid a body force `b = -F_s / m_f` per unit mass (`m_f` the fluid's actual
//! mass after carving). Gravity in the fluid would be wrong here: the markers' pressure is
//! extrapolated from the fluid with the fluid's body acceleration (Adami et al. 2012), and
//! the fluid would be given a gradient it does not have (measured before this form: the error grew
//! as the density ratio fell, +14 % at 3 to +22 % at 0.5, `D / dp = 8`). The markers'
//! pressure is not clamped at zero either: a periodic cell has no free surface, and its
//! gauge pressure is negative on one side of the sphere.
//!
//! # What is measured, and the references
//!
//! The settling speed is the sphere's velocity relative to the mean fluid velocity, as a
//! volume flux: `U = (1 - c) (u_s - <u_f>)` along `F_s` ([`SphereSettling::settling_velocity`]).
//! It is the sphere's speed in the frame of zero volume flux (a container's frame), and,
//! seen from the sphere, the superficial velocity of the fixed array, the `U` of Zick &
//! Homsy: in steady Stokes flow the sphere's drag `F_s` is
//!
//! ```text
//! W = 6 pi mu a K(c) U,   i.e.   F_s = (1 - c) 6 pi mu a K(c) U
//! ```
//!
//! with `K` the drag factor of the pressure-driven array ([`periodic_drag_factor`]: the
//! table of Zick & Homsy 1982 for `c >= 0.027`, the dilute series of Hasimoto 1959 /
//! Sangani & Acrivos 1982 below). At Reynolds numbers 1-20 the isolated sphere's drag of
//! Schiller & Naumann (1933, [`schiller_naumann_cd`]) is the reference, for a sphere at
//! most a tenth of the cell ([`schiller_naumann_terminal_velocity`]; the periodic
//! correction at finite Reynolds number is discussed in docs/validation-fsi.md).
//!
//! ```
//! use chrono_fsi::sphere_settling::{SphereSettlingParams, sphere_settling};
//!
//! let p = SphereSettlingParams { spacing: 0.004, ..SphereSettlingParams::default() };
//! let solver = chrono_ccp::Psor::new(Default::default());
//! let mut scene = sphere_settling(&p, Box::new(solver)).unwrap();
//! for _ in 0..5 {
//!     scene.system.step(p.coupling_step_limit().min(2e-3)).unwrap();
//! }
//! // the heavy sphere starts to sink through the fluid, and the total momentum stays 0
//! assert!(scene.settling_velocity() > 0.0);
//! assert!(scene.total_momentum().norm() < 1e-9 * scene.sphere_mass() * scene.settling_velocity());
//! ```

use std::f64::consts::PI;

use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_sph::{SphSettings, sound_speed_for};

use crate::error::{FsiError, Result, check_positive};
use crate::{FsiBuilder, SphFluid};

/// Zick & Homsy (1982, "Stokes flow through periodic arrays of spheres", J. Fluid Mech.
/// 115:13-26), Table 2, simple cubic array: solid fraction `c` and the drag factor
/// `K = F / (6 pi mu a U)` (`F` the force on a sphere of the pressure-driven array, `U`
/// the superficial velocity). The last row, their `c = 0.5236`, is the close packing
/// `pi / 6`.
pub const ZICK_HOMSY_SIMPLE_CUBIC: [(f64, f64); 7] = [
    (0.027, 2.008),
    (0.064, 2.810),
    (0.125, 4.292),
    (0.216, 7.442),
    (0.343, 15.4),
    (0.45, 28.1),
    (std::f64::consts::FRAC_PI_6, 42.1),
];

/// The dilute expansion of the simple cubic array's drag factor,
///
/// ```text
/// 1 / K = 1 - 1.7601 c^(1/3) + c - 1.5593 c^2 + 3.9799 c^(8/3) - 3.0734 c^(10/3)
/// ```
///
/// (Hasimoto 1959, J. Fluid Mech. 5:317, the terms up to `c`; Sangani & Acrivos 1982,
/// Int. J. Multiphase Flow 8:343, the higher ones). The `c^(1/3)` term is the periodic
/// images' Stokeslets: at a sphere a tenth of the cell (`c = 5.2e-4`) it still slows the
/// sphere by 14 %. Within 0.2 % of Zick & Homsy's table at `c` = 0.027 and 0.064.
pub fn hasimoto_simple_cubic(c: f64) -> f64 {
    let s = c.cbrt();
    1.0 / (1.0 - 1.7601 * s + c - 1.5593 * c * c + 3.9799 * c * c * s * s - 3.0734 * c.powi(3) * s)
}

/// `K(c)` of the simple cubic array: Zick & Homsy's table ([`ZICK_HOMSY_SIMPLE_CUBIC`])
/// interpolated linearly in `(c, ln K)` for `c` in `[0.027, pi / 6]`, the dilute series
/// ([`hasimoto_simple_cubic`]) in `(0, 0.027)`; `None` otherwise.
pub fn periodic_drag_factor(c: f64) -> Option<f64> {
    crate::periodic::drag_factor_from_table(&ZICK_HOMSY_SIMPLE_CUBIC, c, hasimoto_simple_cubic)
}

/// Schiller & Naumann's (1933) drag coefficient of an isolated sphere,
/// `C_D = 24 / Re (1 + 0.15 Re^0.687)` (`Re = rho U D / mu`; within about 5 % of the
/// standard drag curve up to `Re ~ 800`, Clift, Grace & Weber 1978).
pub fn schiller_naumann_cd(re: f64) -> f64 {
    24.0 / re * (1.0 + 0.15 * re.powf(0.687))
}

/// The terminal speed (m/s) of an isolated sphere of radius `a` (m) whose net weight is
/// `w` (N) in a fluid of density `rho` (kg/m^3) and viscosity `mu` (Pa s) by Schiller &
/// Naumann: the root of `w = 3 pi mu D U (1 + 0.15 Re^0.687)`, `Re = rho U D / mu`
/// (monotone in `U`; bisection to round-off). Stokes' `w / (6 pi mu a)` when `Re -> 0`.
pub fn schiller_naumann_terminal_velocity(a: f64, w: f64, rho: f64, mu: f64) -> f64 {
    let d = 2.0 * a;
    let drag = |u: f64| 3.0 * PI * mu * d * u * (1.0 + 0.15 * (rho * u * d / mu).powf(0.687));
    let (mut lo, mut hi) = (0.0, w.abs() / (3.0 * PI * mu * d));
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if drag(mid) < w.abs() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Parameters of [`sphere_settling`] (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct SphereSettlingParams {
    /// Sphere radius `a`, m.
    pub radius: f64,
    /// Sphere over fluid density `rho_s / rho_f` (positive, not 1; below 1 the sphere rises).
    pub density_ratio: f64,
    /// Fluid density `rho_f`, kg/m^3.
    pub rho: f64,
    /// Dynamic viscosity `mu`, Pa s.
    pub viscosity: f64,
    /// Cell edge `L` (the spacing of the array), m; rounded to whole particle spacings.
    pub container_size: f64,
    /// Gravitational acceleration, m/s^2 (along -z).
    pub gravity: f64,
    /// Particle spacing `dp`, m.
    pub spacing: f64,
    /// Smoothing length over spacing `h / dp`.
    pub h_over_dp: f64,
}

impl Default for SphereSettlingParams {
    /// `a = 0.01 m`, density ratio 1.5, water's density, `mu = 5 Pa s`, `L = 0.05 m`
    /// (`c = 0.034`, `K = 2.31`), `g = 9.81`, `dp = a / 4`, `h = 1.3 dp`: Stokes' speed in
    /// the array 10.2 mm/s, `Re = 0.041`.
    fn default() -> Self {
        Self {
            radius: 0.01,
            density_ratio: 1.5,
            rho: 1000.0,
            viscosity: 5.0,
            container_size: 0.05,
            gravity: -GRAVITY.z,
            spacing: 0.0025,
            h_over_dp: SphSettings::default().h_over_dp,
        }
    }
}

impl SphereSettlingParams {
    /// Checks every field; the error names it and its value.
    pub fn validate(&self) -> Result<()> {
        for (f, v) in [
            ("sphere_radius", self.radius),
            ("density_ratio", self.density_ratio),
            ("rho", self.rho),
            ("viscosity", self.viscosity),
            ("container_size", self.container_size),
            ("gravity", self.gravity),
            ("spacing", self.spacing),
            ("h_over_dp", self.h_over_dp),
        ] {
            check_positive(f, v)?;
        }
        if (self.density_ratio - 1.0).abs() < 1e-6 {
            return Err(FsiError::invalid(
                "density_ratio",
                self.density_ratio,
                "must differ from 1 (a neutrally buoyant sphere does not settle)",
            ));
        }
        let d = 2.0 * self.radius;
        let support = 2.0 * self.h_over_dp * self.spacing;
        if self.container_size < d + support {
            return Err(FsiError::invalid(
                "container_size",
                self.container_size,
                format!("must exceed the sphere's diameter {d} m by a kernel support {support} m"),
            ));
        }
        Ok(())
    }

    /// The cell edge rounded to whole spacings, m.
    pub fn cell(&self) -> f64 {
        (self.container_size / self.spacing).round().max(1.0) * self.spacing
    }

    /// The sphere's volume `4/3 pi a^3`, m^3.
    pub fn sphere_volume(&self) -> f64 {
        4.0 / 3.0 * PI * self.radius.powi(3)
    }

    /// The solid fraction of the rounded cell, `c = V_s / L^3`.
    pub fn solid_fraction(&self) -> f64 {
        self.sphere_volume() / self.cell().powi(3)
    }

    /// The net weight `W = (rho_s - rho_f) V_s g` (N; negative for a light sphere).
    pub fn net_weight(&self) -> f64 {
        (self.density_ratio - 1.0) * self.rho * self.sphere_volume() * self.gravity
    }

    /// The Stokes terminal speed in the array, `W / (6 pi mu a K(c))` (m/s, along the net
    /// weight; `None` where `K` is not known, [`periodic_drag_factor`]).
    pub fn stokes_array_velocity(&self) -> Option<f64> {
        let k = periodic_drag_factor(self.solid_fraction())?;
        Some(self.net_weight().abs() / (6.0 * PI * self.viscosity * self.radius * k))
    }

    /// The isolated sphere's terminal speed by Schiller & Naumann (m/s, along the net
    /// weight; [`schiller_naumann_terminal_velocity`]).
    pub fn schiller_naumann_velocity(&self) -> f64 {
        schiller_naumann_terminal_velocity(self.radius, self.net_weight(), self.rho, self.viscosity)
    }

    /// An estimate of the settling speed (m/s): the smaller of the two references (both
    /// bound it from above where the other effect matters).
    pub fn speed_estimate(&self) -> f64 {
        let sn = self.schiller_naumann_velocity();
        self.stokes_array_velocity().map_or(sn, |s| s.min(sn))
    }

    /// The largest stable multibody (coupling) step, s: half the shortest viscous
    /// relaxation time of the sphere, its spin `tau_r = I / (8 pi mu a^3) = m_s / (20 pi
    /// mu a)` or its translation in the array `tau_t = m_s / (6 pi mu a K)`. The fluid's
    /// force reaches the body once per step, computed with the body's velocity frozen: an
    /// explicit Euler step of the viscous relaxation, unstable above `2 tau` (measured:
    /// a sphere of density ratio 0.4 at `h = 3.8 tau_r` spun and drifted sideways as fast
    /// as it rose). The terminal speed itself does not depend on the step.
    pub fn coupling_step_limit(&self) -> f64 {
        let m = self.density_ratio * self.rho * self.sphere_volume();
        let mu_a = self.viscosity * self.radius;
        let k = periodic_drag_factor(self.solid_fraction()).unwrap_or(1.0);
        0.5 * (m / (20.0 * PI * mu_a)).min(m / (6.0 * PI * mu_a * k))
    }

    /// The time (s) the settling takes to become steady: the longer of the sphere's
    /// relaxation, its momentum with the added mass over the drag at the estimated
    /// speed, `(rho_s + rho_f / 2) V_s U / (1 - c) W`, and the viscous time of the cell's
    /// longest periodic mode, `rho L^2 / (4 pi^2 mu)`.
    pub fn relaxation_time(&self) -> f64 {
        let c = self.solid_fraction();
        let m = (self.density_ratio + 0.5) * self.rho * self.sphere_volume();
        let t_sphere = m * self.speed_estimate() / ((1.0 - c) * self.net_weight().abs());
        let l = self.cell();
        let t_cell = self.rho * l * l / (4.0 * PI * PI * self.viscosity);
        t_sphere.max(t_cell)
    }
}

/// The scene: the system with the free sphere and the fluid item.
pub struct SphereSettling {
    /// The multibody system (no gravity: the sphere's applied force is `F_s`, see the
    /// [module docs](self)).
    pub system: System,
    /// The fluid item.
    pub fluid: ItemHandle,
    /// The sphere.
    pub sphere: BodyHandle,
    /// The cell edge actually used, m.
    pub cell: f64,
    /// The solid fraction of the cell.
    pub solid_fraction: f64,
    /// The force that drives the sphere, `F_s = (1 - c) W` (N, world; down for a heavy
    /// sphere).
    pub driving_force: Vector3<f64>,
    /// The fluid's total mass, kg.
    pub fluid_mass: f64,
}

impl SphereSettling {
    /// The fluid item.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid item")
    }

    /// The unit vector along the driving force (down for a heavy sphere).
    pub fn direction(&self) -> Vector3<f64> {
        self.driving_force.normalize()
    }

    /// The sphere's mass, kg.
    pub fn sphere_mass(&self) -> f64 {
        self.system.body(self.sphere).map_or(0.0, |b| b.mass())
    }

    /// The sphere's velocity, m/s.
    pub fn sphere_velocity(&self) -> Vector3<f64> {
        self.system
            .body(self.sphere)
            .map_or(Vector3::zeros(), |b| b.linear_velocity())
    }

    /// The fluid's mean velocity (momentum over mass), m/s.
    pub fn fluid_velocity(&self) -> Vector3<f64> {
        self.fluid().sph().fluid_momentum() / self.fluid_mass
    }

    /// The settling speed `U = (1 - c) (u_s - <u_f>) . e` along the driving force `e`
    /// (m/s): the sphere's speed in the frame of zero volume flux (see the
    /// [module docs](self)).
    pub fn settling_velocity(&self) -> f64 {
        (1.0 - self.solid_fraction)
            * (self.sphere_velocity() - self.fluid_velocity()).dot(&self.direction())
    }

    /// The fluid's force on the sphere along `-e` over the last step (the drag, N);
    /// `F_s` in steady state.
    pub fn drag(&self) -> f64 {
        self.fluid()
            .body_load(self.sphere)
            .map_or(0.0, |l| -l[0].dot(&self.direction()))
    }

    /// The total linear momentum of fluid and sphere, kg m/s (zero from a start at rest).
    pub fn total_momentum(&self) -> Vector3<f64> {
        self.fluid().sph().fluid_momentum() + self.sphere_mass() * self.sphere_velocity()
    }

    /// The sphere's centre, m (not wrapped into the cell).
    pub fn sphere_position(&self) -> Vector3<f64> {
        self.system
            .body(self.sphere)
            .map_or(Vector3::zeros(), |b| b.position())
    }
}

/// The fluid's settings for the cell of `p` with the body force `b` along z (m/s^2).
fn fluid_settings(p: &SphereSettlingParams, b: f64) -> Result<SphSettings> {
    let l = p.cell();
    let d = 2.0 * p.radius;
    let nu = p.viscosity / p.rho;
    let c = p.solid_fraction();
    // the pressure difference across the sphere, ~ F_s / (pi a^2), as a force per unit
    // mass at length D (the force term of sound_speed_for)
    let force = (1.0 - c) * p.net_weight().abs() / (p.rho * PI * p.radius * p.radius * d);
    let cs = sound_speed_for(1.5 * p.speed_estimate(), d, force, nu, 0.01)?;
    Ok(SphSettings {
        spacing: p.spacing,
        h_over_dp: p.h_over_dp,
        rho0: p.rho,
        viscosity: p.viscosity,
        sound_speed: cs,
        artificial_viscosity: 0.0,
        xsph: 0.0,
        gravity: [0.0; 3],
        body_force: [0.0, 0.0, b],
        // no free surface: the gauge pressure is negative on one side of the sphere
        clamp_wall_pressure: false,
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        ..SphSettings::default()
    })
}

/// Builds the scene of `p` (see the [module docs](self)): the sphere at rest at the
/// cell's centre, the fluid at rest carved around it, with the multibody `solver`.
/// Errors name the parameter ([`SphereSettlingParams::validate`]) or the body (a sphere
/// not resolved by the spacing, [`FsiBuilder::add_body`]).
pub fn sphere_settling(
    p: &SphereSettlingParams,
    solver: Box<dyn CcpSolver>,
) -> Result<SphereSettling> {
    p.validate()?;
    let l = p.cell();
    let c = p.solid_fraction();
    let shape = Shape::Sphere { radius: p.radius };
    let rho_s = p.density_ratio * p.rho;
    // F_s = (1 - c) W along -z, an applied force on the sphere; no gravity (see the
    // module docs)
    let f_s = -(1.0 - c) * p.net_weight();
    let mut system = System::new(
        SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        },
        solver,
    )?;
    let sphere = system.add_body(
        RigidBodyBuilder::dynamic()
            .name("sphere")
            .mass_from_shape(&shape, rho_s)?
            .position(Vector3::repeat(0.5 * l))
            .collider(shape, Isometry3::identity(), Default::default()),
    )?;
    let carve = |settings: SphSettings, system: &System| -> Result<SphFluid> {
        let mut fsi = FsiBuilder::new(settings)?;
        fsi.add_fluid_box([0.0; 3], [l; 3], None)?;
        fsi.add_body(system, sphere)?;
        fsi.build("fluid", 1)
    };
    system
        .body_mut(sphere)?
        .set_applied_force(Vector3::new(0.0, 0.0, f_s))?;
    // the fluid's actual mass (the lattice carved around the sphere) sets the body force
    // that cancels F_s exactly
    let m_f = carve(fluid_settings(p, 0.0)?, &system)?.sph().fluid_mass();
    let fluid = system.add_item(Box::new(carve(fluid_settings(p, -f_s / m_f)?, &system)?));
    Ok(SphereSettling {
        system,
        fluid,
        sphere,
        cell: l,
        solid_fraction: c,
        driving_force: Vector3::new(0.0, 0.0, f_s),
        fluid_mass: m_f,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use chrono_ccp::Psor;

    #[test]
    fn the_dilute_series_matches_zick_and_homsy_where_both_apply() {
        // two independent results for the same array: the series (Hasimoto; Sangani &
        // Acrivos) and the integral-equation solution (Zick & Homsy, Table 2)
        for (c, k) in &ZICK_HOMSY_SIMPLE_CUBIC[..2] {
            let s = hasimoto_simple_cubic(*c);
            assert!((s / k - 1.0).abs() < 2e-3, "c {c}: series {s} table {k}");
        }
        // the isolated sphere in the limit, and Hasimoto's leading correction
        let c = 1e-9;
        assert!((hasimoto_simple_cubic(c) - 1.0 - 1.7601 * c.cbrt()).abs() < 1e-5);
    }

    #[test]
    fn the_table_is_interpolated_between_its_rows() {
        for (c, k) in ZICK_HOMSY_SIMPLE_CUBIC {
            let v = periodic_drag_factor(c).unwrap();
            assert!((v / k - 1.0).abs() < 1e-12, "{c}: {v}");
        }
        let k = periodic_drag_factor(0.1).unwrap();
        assert!(k > 2.810 && k < 4.292, "{k}");
        assert_eq!(
            periodic_drag_factor(0.01),
            Some(hasimoto_simple_cubic(0.01))
        );
        assert_eq!(periodic_drag_factor(0.6), None);
        assert_eq!(periodic_drag_factor(0.0), None);
        assert_eq!(periodic_drag_factor(f64::NAN), None);
    }

    #[test]
    fn schiller_naumann_balances_the_weight_and_tends_to_stokes() {
        let (a, rho, mu) = (0.005, 1000.0, 0.05);
        for w in [1e-6, 1e-3, 0.05] {
            let u = schiller_naumann_terminal_velocity(a, w, rho, mu);
            let re = rho * u * 2.0 * a / mu;
            // C_D (1/2) rho U^2 pi a^2 = W
            let drag = schiller_naumann_cd(re) * 0.5 * rho * u * u * PI * a * a;
            assert!((drag / w - 1.0).abs() < 1e-9, "w {w}: {drag}");
        }
        let w = 1e-9;
        let u = schiller_naumann_terminal_velocity(a, w, rho, mu);
        assert!((u / (w / (6.0 * PI * mu * a)) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn bad_parameters_are_named() {
        let base = SphereSettlingParams::default();
        for (field, p) in [
            (
                "sphere_radius",
                SphereSettlingParams {
                    radius: 0.0,
                    ..base.clone()
                },
            ),
            (
                "sphere_radius",
                SphereSettlingParams {
                    radius: -0.01,
                    ..base.clone()
                },
            ),
            (
                "density_ratio",
                SphereSettlingParams {
                    density_ratio: -2.0,
                    ..base.clone()
                },
            ),
            (
                "density_ratio",
                SphereSettlingParams {
                    density_ratio: 1.0,
                    ..base.clone()
                },
            ),
            (
                "viscosity",
                SphereSettlingParams {
                    viscosity: f64::NAN,
                    ..base.clone()
                },
            ),
            // smaller than the sphere, and not a kernel support larger
            (
                "container_size",
                SphereSettlingParams {
                    container_size: 0.015,
                    ..base.clone()
                },
            ),
            (
                "container_size",
                SphereSettlingParams {
                    container_size: 0.022,
                    ..base.clone()
                },
            ),
            (
                "spacing",
                SphereSettlingParams {
                    spacing: 0.0,
                    ..base.clone()
                },
            ),
        ] {
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{field}: {e}");
            let s = sphere_settling(&p, Box::new(Psor::new(Default::default())));
            assert!(s.is_err(), "{field}");
        }
        // a spacing that does not resolve the sphere: an error naming the body
        let p = SphereSettlingParams {
            spacing: 0.006,
            ..base
        };
        let e = sphere_settling(&p, Box::new(Psor::new(Default::default())))
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("sphere"), "{e}");
    }

    /// A coarse cell (`D / dp = 5`) with a heavy and a light sphere: the external forces
    /// cancel, so the total momentum of fluid and sphere stays zero to round-off while
    /// the sphere settles (rises); the sphere moves along its driving force only.
    #[test]
    fn the_total_momentum_stays_zero_while_the_sphere_settles() {
        for ratio in [3.0, 0.4] {
            let p = SphereSettlingParams {
                spacing: 0.004,
                density_ratio: ratio,
                ..SphereSettlingParams::default()
            };
            let mut s = sphere_settling(&p, Box::new(Psor::new(Default::default()))).unwrap();
            // the cancelling body force puts exactly -F_s on the fluid
            let sph = s.fluid().sph();
            let on_fluid =
                Vector3::from(sph.settings().gravity) + Vector3::from(sph.settings().body_force);
            let err = (on_fluid * s.fluid_mass + s.driving_force).norm() / s.driving_force.norm();
            assert!(err < 1e-12, "{err:e}");
            let mut drift: f64 = 0.0;
            let h = p.coupling_step_limit().min(2e-3);
            for _ in 0..(0.12 / h).ceil() as usize {
                s.system.step(h).unwrap();
                drift = drift.max(s.total_momentum().norm());
            }
            let u = s.settling_velocity();
            // relative to the impulse each of sphere and fluid got from its external force
            let scale = s.driving_force.norm() * s.system.time();
            assert!(u > 0.1 * p.speed_estimate(), "ratio {ratio}: U {u}");
            assert!(
                drift < 1e-12 * scale,
                "ratio {ratio}: drift {:e}",
                drift / scale
            );
            // along the driving force: the sideways drift is the markers' Fibonacci layout,
            // which is not mirror-symmetric (measured 1e-3 of the settling speed)
            let v = s.sphere_velocity();
            assert!(v.xy().norm() < 1e-2 * v.z.abs(), "ratio {ratio}: {v}");
            assert!(v.z * (ratio - 1.0) < 0.0, "ratio {ratio}: {v}");
            eprintln!(
                "ratio {ratio}: U {u:.5}, momentum drift {:e}",
                drift / scale
            );
        }
    }
}
