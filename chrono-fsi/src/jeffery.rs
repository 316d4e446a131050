//! A neutrally buoyant spheroid in simple shear flow against Jeffery's (1922) orbit: the
//! reference, the orbit fit and the scene of `fsi-jeffery`.
//!
//! # Reference
//!
//! Jeffery (1922, "The motion of ellipsoidal particles immersed in a viscous fluid", Proc.
//! R. Soc. Lond. A 102:161-179): a torque- and force-free spheroid of aspect ratio `r`
//! (symmetry semi-axis over equatorial semi-axis) in the unbounded Stokes shear flow
//! `u = gamma z e_x` whose symmetry axis lies in the shear plane (x-z) stays in it and
//! turns about the vorticity axis (y) as
//!
//! ```text
//! d theta / dt = gamma (cos^2 theta + r^2 sin^2 theta) / (r^2 + 1)
//! tan theta    = (1 / r) tan(2 pi t / T),      T = (2 pi / gamma) (r + 1 / r)
//! ```
//!
//! with `theta` the axis' angle from the flow direction (+x), turning towards `-z` (the
//! sense of the vorticity `+gamma e_y`; [`jeffery_angle`], [`jeffery_period`]). The axis
//! lingers along the flow (rate `gamma / (r^2 + 1)`) and flips across it (rate
//! `gamma r^2 / (r^2 + 1)`); a quarter period takes it from the flow direction to the
//! gradient direction.
//!
//! # The shear cell
//!
//! Fluid periodic along the flow (x) and across it (y), bounded in z by two plane walls
//! `H` apart that move at `-U` (bottom) and `+U` (top) along x, `gamma = 2 U / H`. A
//! plane wall translating along a periodic direction of its own plane is invariant, so the
//! walls are tank markers that keep their places and carry the velocity
//! ([`chrono_sph::WallBelt`], a "moving belt"; its Couette test is in chrono-sph). The
//! walls are at least [`MIN_GAP_MAJOR_AXES`] major axes apart (confinement slows the
//! rotation by a few per cent at that gap; the case reports the gap). The spheroid's
//! centre is on the mid-plane, where the fluid is at rest: it should neither translate
//! nor migrate.
//!
//! # Start
//!
//! The fluid starts on the developed linear profile `u = gamma (z - H / 2)` (the Couette
//! flow needs `H^2 / (pi^2 nu)` to develop from rest, longer than the measured window),
//! the spheroid at rest with its axis along the flow. Its spin-up takes its rotational
//! relaxation time `tau_r` ([`JefferyParams::spin_time`]), about `Re / (100 gamma)`,
//! negligible against `T`; the orbit fit leaves the start time `t0` free.
//!
//! # Particle Reynolds number and cost
//!
//! `Re = gamma a^2 / nu` with `a` the largest semi-axis ([`JefferyParams::reynolds`]). The
//! walls' speed `U = gamma H / 2` sets the sound speed, `c_s = max(10 U, sqrt(nu gamma /
//! 0.01))` (1 % density variation by the shear's speed or its viscous stress,
//! [`chrono_sph::sound_speed_for`]), so the acoustic step `0.2 h / (c_s + U)` is
//! `~ 5e-3 (dp / a) / gamma` at `H` = 5 major axes; at `Re <= 0.1` the viscous step
//! `0.125 h^2 / nu` is of the same order at `a` = 4-8 spacings. A quarter period at
//! `r = 2` (`3.9 / gamma`) is 3 000-10 000 fluid steps.

use std::f64::consts::PI;

use chrono_core::descriptor::CcpSolver;
use chrono_core::item::ItemHandle;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::wall_layers;
use chrono_core::{BodyHandle, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_sph::{SphSettings, WallBelt, sound_speed_for};

use crate::error::{FsiError, Result, check_positive};
use crate::{FsiBuilder, SphFluid};

/// The smallest wall gap, in major axes (the spheroid's largest diameter), the scene
/// accepts: the issue's "at least ~5 major axes apart".
pub const MIN_GAP_MAJOR_AXES: f64 = 5.0;

/// Wall groups of the shear cell: the tank's faces (`-z` = 4, `+z` = 5) and the spheroid.
const BOTTOM: u16 = 4;
const TOP: u16 = 5;
const BODY_GROUP: u16 = 10;

/// Jeffery's period `T = (2 pi / gamma) (r + 1 / r)` (s) of a spheroid of aspect ratio
/// `r` in simple shear of rate `gamma` (1/s) (Jeffery 1922; see the [module docs](self)).
pub fn jeffery_period(aspect_ratio: f64, shear_rate: f64) -> f64 {
    2.0 * PI / shear_rate * (aspect_ratio + 1.0 / aspect_ratio)
}

/// Jeffery's orbit angle `theta(t)` (rad) of the symmetry axis from the flow direction,
/// for an orbit of period `period` (s) and aspect ratio `r` passing the flow direction at
/// `t = 0`: `tan theta = tan(psi) / r`, `psi = 2 pi t / T`, continuous in `t` (written
/// `theta = psi + atan((1 - r) sin psi cos psi / (r cos^2 psi + sin^2 psi))`, whose
/// denominator never vanishes). `theta(T / 4) = pi / 2`, `theta(T / 2) = pi`.
pub fn jeffery_angle(t: f64, period: f64, aspect_ratio: f64) -> f64 {
    let r = aspect_ratio;
    let psi = 2.0 * PI * t / period;
    let (s, c) = psi.sin_cos();
    psi + ((1.0 - r) * s * c / (r * c * c + s * s)).atan()
}

/// A fit of Jeffery's orbit to a record of the axis angle ([`fit_jeffery_orbit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitFit {
    /// The period `T`, s.
    pub period: f64,
    /// The orbit's aspect ratio (fitted, or the one given when held).
    pub aspect_ratio: f64,
    /// The time the axis passes the flow direction, s.
    pub t0: f64,
    /// The root-mean-square residual of the angle, rad.
    pub residual: f64,
    /// The angle the record spans, rad.
    pub span: f64,
    /// Parameters fitted: 3 (`T`, `r`, `t0`) or 2 (`T`, `t0`, `r` held).
    pub parameters: usize,
}

/// The smallest angle span (rad) [`fit_jeffery_orbit`] accepts when it fits the aspect
/// ratio too: a quarter orbit's shape (the slow start and the flip) pins `r` and `T`
/// apart; below it only their combination, the starting rate `2 pi / (r T)`, is known.
pub const MIN_SPAN_FOR_ASPECT_RATIO: f64 = 0.4 * PI;

/// Fits Jeffery's orbit `theta(t) = jeffery_angle(t - t0, T, r)` to the axis angles
/// `theta` (rad, unwrapped) at the times `t` (s, increasing) by least squares
/// (Levenberg-Marquardt with central-difference derivatives, from the period
/// `period_guess` (s), the aspect ratio `aspect_ratio` and `t0 = t[0]`): `T`, `r` and
/// `t0` when `fit_aspect_ratio` and the record spans at least
/// [`MIN_SPAN_FOR_ASPECT_RATIO`], else `T` and `t0` with `r` held. Fitting a partial orbit
/// is legitimate: the closed form is the whole orbit, and a quarter of it (the axis from
/// the flow to the gradient direction) already fixes its period. Errors name `record`
/// (fewer than 8 samples, times not increasing, a value not finite, a span under 0.05 rad)
/// or the guess.
pub fn fit_jeffery_orbit(
    t: &[f64],
    theta: &[f64],
    period_guess: f64,
    aspect_ratio: f64,
    fit_aspect_ratio: bool,
) -> Result<OrbitFit> {
    if t.len() != theta.len() || t.len() < 8 {
        return Err(FsiError::invalid(
            "record",
            t.len(),
            format!(
                "needs at least 8 samples and as many angles ({})",
                theta.len()
            ),
        ));
    }
    if t.iter().chain(theta).any(|v| !v.is_finite()) || t.windows(2).any(|w| w[1] <= w[0]) {
        return Err(FsiError::invalid(
            "record",
            t.len(),
            "times must increase and every value be finite",
        ));
    }
    for (f, v) in [
        ("period_guess", period_guess),
        ("aspect_ratio", aspect_ratio),
    ] {
        check_positive(f, v)?;
    }
    let (lo, hi) = theta
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = hi - lo;
    if span < 0.05 {
        return Err(FsiError::invalid(
            "record",
            span,
            "the angle spans less than 0.05 rad: no rotation to fit",
        ));
    }
    let three = fit_aspect_ratio && span >= MIN_SPAN_FOR_ASPECT_RATIO;
    // parameters: [T, t0] or [T, t0, r]
    let mut p = vec![period_guess, t[0]];
    if three {
        p.push(aspect_ratio);
    }
    let model = |p: &[f64], ti: f64| {
        let r = if p.len() == 3 { p[2] } else { aspect_ratio };
        jeffery_angle(ti - p[1], p[0], r)
    };
    let cost = |p: &[f64]| -> f64 {
        t.iter()
            .zip(theta)
            .map(|(&ti, &th)| (th - model(p, ti)).powi(2))
            .sum()
    };
    let n = p.len();
    let mut lambda = 1e-3;
    let mut c = cost(&p);
    for _ in 0..200 {
        // Jacobian of the residuals (central differences) and the normal equations
        let mut jtj = vec![vec![0.0; n]; n];
        let mut jte = vec![0.0; n];
        let steps: Vec<f64> = p.iter().map(|v| 1e-6 * v.abs().max(1e-3)).collect();
        for (&ti, &th) in t.iter().zip(theta) {
            let e = th - model(&p, ti);
            let mut g = vec![0.0; n];
            for k in 0..n {
                let (mut a, mut b) = (p.clone(), p.clone());
                a[k] += steps[k];
                b[k] -= steps[k];
                g[k] = (model(&a, ti) - model(&b, ti)) / (2.0 * steps[k]);
            }
            for i in 0..n {
                jte[i] += g[i] * e;
                for j in 0..n {
                    jtj[i][j] += g[i] * g[j];
                }
            }
        }
        let mut improved = false;
        while lambda < 1e12 {
            let mut a = jtj.clone();
            for (i, row) in a.iter_mut().enumerate() {
                row[i] += lambda * jtj[i][i].max(1e-300);
            }
            let Some(d) = solve(a, jte.clone()) else {
                lambda *= 10.0;
                continue;
            };
            let q: Vec<f64> = p.iter().zip(&d).map(|(v, dv)| v + dv).collect();
            // the period and the aspect ratio stay positive
            let valid = q[0] > 0.0 && (n < 3 || q[2] > 0.0);
            let cq = if valid { cost(&q) } else { f64::INFINITY };
            if cq < c {
                let rel = d
                    .iter()
                    .zip(&p)
                    .map(|(dv, v)| (dv / v.abs().max(1e-3)).abs())
                    .fold(0.0, f64::max);
                p = q;
                c = cq;
                lambda = (lambda * 0.3).max(1e-12);
                improved = rel > 1e-13;
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    Ok(OrbitFit {
        period: p[0],
        aspect_ratio: if three { p[2] } else { aspect_ratio },
        t0: p[1],
        residual: (c / t.len() as f64).sqrt(),
        span,
        parameters: n,
    })
}

/// Solves the small dense system `a x = b` by Gaussian elimination with partial pivoting;
/// `None` when it is singular.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for k in 0..n {
        let piv = (k..n).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        if a[piv][k].abs() < 1e-300 || !a[piv][k].is_finite() {
            return None;
        }
        a.swap(k, piv);
        b.swap(k, piv);
        for i in k + 1..n {
            let f = a[i][k] / a[k][k];
            for j in k..n {
                a[i][j] -= f * a[k][j];
            }
            b[i] -= f * b[k];
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    Some(x)
}

/// Parameters of [`jeffery_scene`] (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct JefferyParams {
    /// Aspect ratio `r` (symmetry semi-axis over equatorial semi-axis; > 1 prolate).
    pub aspect_ratio: f64,
    /// Shear rate `gamma = 2 U / H`, 1/s.
    pub shear_rate: f64,
    /// Dynamic viscosity `mu`, Pa s.
    pub viscosity: f64,
    /// Fluid (and spheroid) density, kg/m^3.
    pub rho: f64,
    /// The spheroid's largest semi-axis `a`, m.
    pub semi_axis: f64,
    /// Wall gap `H` in major axes (`2 a`), at least [`MIN_GAP_MAJOR_AXES`].
    pub gap: f64,
    /// The cell's period along the flow in major axes.
    pub length: f64,
    /// The cell's period across the flow (along the vorticity) in major axes.
    pub width: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Smoothing length over spacing.
    pub h_over_dp: f64,
}

impl Default for JefferyParams {
    /// `r = 2`, `gamma = 1 1/s`, `mu = 1 Pa s`, water's density, `a = 0.01 m`
    /// (`Re = 0.1`), gap 5, length 2 and width 1.5 major axes, `dp = a / 4`, `h = 1.5 dp`.
    fn default() -> Self {
        Self {
            aspect_ratio: 2.0,
            shear_rate: 1.0,
            viscosity: 1.0,
            rho: 1000.0,
            semi_axis: 0.01,
            gap: MIN_GAP_MAJOR_AXES,
            length: 2.0,
            width: 1.5,
            spacing: 0.0025,
            h_over_dp: SphSettings::default().h_over_dp,
        }
    }
}

impl JefferyParams {
    /// Checks every field; the error names it and its value.
    pub fn validate(&self) -> Result<()> {
        for (f, v) in [
            ("aspect_ratio", self.aspect_ratio),
            ("shear_rate", self.shear_rate),
            ("viscosity", self.viscosity),
            ("rho", self.rho),
            ("semi_axis", self.semi_axis),
            ("length", self.length),
            ("width", self.width),
            ("spacing", self.spacing),
            ("h_over_dp", self.h_over_dp),
        ] {
            check_positive(f, v)?;
        }
        if !(self.gap.is_finite() && self.gap >= MIN_GAP_MAJOR_AXES - 1e-12) {
            return Err(FsiError::invalid(
                "gap",
                self.gap,
                format!("must be at least {MIN_GAP_MAJOR_AXES} major axes"),
            ));
        }
        // the periodic images must not touch: a kernel support between neighbours (the
        // body turns in the x-z plane, so along x it reaches its largest diameter)
        let support = 2.0 * self.h_over_dp * self.spacing;
        for (f, v, extent) in [
            ("length", self.length, 2.0 * self.semi_axis),
            ("width", self.width, 2.0 * self.semi_axes().y),
        ] {
            if v * 2.0 * self.semi_axis < extent + support {
                return Err(FsiError::invalid(
                    f,
                    v,
                    format!(
                        "the cell must exceed the spheroid ({extent} m) by a kernel support ({support} m)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The semi-axes in the body frame (m): the symmetry axis along x, `(a, a/r, a/r)`
    /// for a prolate spheroid, `(a r, a, a)` for an oblate one.
    pub fn semi_axes(&self) -> Vector3<f64> {
        let (a, r) = (self.semi_axis, self.aspect_ratio);
        if r >= 1.0 {
            Vector3::new(a, a / r, a / r)
        } else {
            Vector3::new(a * r, a, a)
        }
    }

    /// The particle Reynolds number `Re = gamma a^2 / nu` (`a` the largest semi-axis).
    pub fn reynolds(&self) -> f64 {
        self.shear_rate * self.semi_axis.powi(2) * self.rho / self.viscosity
    }

    /// Jeffery's period of this spheroid and shear rate, s ([`jeffery_period`]).
    pub fn period(&self) -> f64 {
        jeffery_period(self.aspect_ratio, self.shear_rate)
    }

    /// `n dp` for the whole count `n` (rounded to even, so the cell is symmetric about
    /// its centre on the lattice) nearest to `len` (m).
    fn rounded(&self, len: f64) -> f64 {
        2.0 * (0.5 * len / self.spacing).round().max(1.0) * self.spacing
    }

    /// The cell (x, y, z) = (length, width, gap), m, rounded to even counts of spacings.
    pub fn cell(&self) -> [f64; 3] {
        let major = 2.0 * self.semi_axis;
        [
            self.rounded(self.length * major),
            self.rounded(self.width * major),
            self.rounded(self.gap * major),
        ]
    }

    /// The walls' speed `U = gamma H / 2` (m/s) of the rounded cell.
    pub fn wall_speed(&self) -> f64 {
        0.5 * self.shear_rate * self.cell()[2]
    }

    /// The spheroid's rotational relaxation time about the vorticity axis, s: its moment
    /// of inertia `m (a_1^2 + a_2^2) / 5` over the rotational drag of the sphere of
    /// radius `a` around it, `8 pi mu a^3` (more than the spheroid's, so this is a lower
    /// bound). The fluid's torque reaches the body once per coupling step with the body's
    /// spin frozen: an explicit step of this relaxation, unstable above `2 tau_r`.
    pub fn spin_time(&self) -> f64 {
        let e = self.semi_axes();
        let m = self.rho * 4.0 / 3.0 * PI * e.x * e.y * e.z;
        let inertia = m * (e.x * e.x + e.z * e.z) / 5.0;
        inertia / (8.0 * PI * self.viscosity * self.semi_axis.powi(3))
    }

    /// The fluid's step (s) by its CFL and viscous limits at the walls' speed
    /// ([`SphSettings`]: `cfl h / (c_s + U)`, `visc_coef h^2 rho / mu`, `max_dt`).
    pub fn fluid_step(&self) -> Result<f64> {
        let s = self.fluid_settings()?;
        let h = s.h();
        Ok((s.cfl * h / (s.sound_speed + self.wall_speed()))
            .min(s.visc_coef * h * h * s.rho0 / s.viscosity)
            .min(s.max_dt))
    }

    /// The multibody (coupling) step, s: the fluid's step ([`fluid_step`](Self::fluid_step),
    /// less 0.1 %, so each coupling step is one fluid step) or the spheroid's spin time
    /// ([`spin_time`](Self::spin_time)), the shorter.
    pub fn coupling_step(&self) -> Result<f64> {
        Ok((0.999 * self.fluid_step()?).min(self.spin_time()))
    }

    /// The fluid's settings: the shear cell (periodic in x and y, belts at `z = 0`
    /// and `z = H`), no gravity, no artificial viscosity or XSPH (a resolved viscous
    /// flow), sound speed `max(10 U, sqrt(nu gamma / 0.01))`.
    pub fn fluid_settings(&self) -> Result<SphSettings> {
        let cell = self.cell();
        let u = self.wall_speed();
        let nu = self.viscosity / self.rho;
        let a = self.semi_axis;
        // the shear's speed, and the viscous stress mu gamma at the body (speed gamma a
        // over length a)
        let cs = sound_speed_for(u, a, 0.0, 0.0, 0.01)?.max(sound_speed_for(
            self.shear_rate * a,
            a,
            0.0,
            nu,
            0.01,
        )?);
        Ok(SphSettings {
            spacing: self.spacing,
            h_over_dp: self.h_over_dp,
            rho0: self.rho,
            viscosity: self.viscosity,
            sound_speed: cs,
            artificial_viscosity: 0.0,
            xsph: 0.0,
            gravity: [0.0; 3],
            domain_lower: [0.0; 3],
            domain_upper: cell,
            periodic: [true, true, false],
            // no free surface: the gauge pressure is negative on the spheroid's lee sides
            clamp_wall_pressure: false,
            wall_belts: vec![
                WallBelt {
                    group: BOTTOM,
                    velocity: [-u, 0.0, 0.0],
                },
                WallBelt {
                    group: TOP,
                    velocity: [u, 0.0, 0.0],
                },
            ],
            ..SphSettings::default()
        })
    }
}

/// The scene: the system with the free spheroid and the fluid item.
pub struct Jeffery {
    /// The multibody system (no gravity).
    pub system: System,
    /// The fluid item.
    pub fluid: ItemHandle,
    /// The spheroid.
    pub body: BodyHandle,
    /// The cell (x, y, z), m.
    pub cell: [f64; 3],
    /// The spheroid's centre at the start, m.
    pub centre0: Vector3<f64>,
}

impl Jeffery {
    /// The fluid item.
    pub fn fluid(&self) -> &SphFluid {
        self.system
            .item::<SphFluid>(self.fluid)
            .expect("the scene's fluid item")
    }

    /// The symmetry axis (world, unit).
    pub fn axis(&self) -> Vector3<f64> {
        self.system
            .body(self.body)
            .map_or(Vector3::x(), |b| b.rotation() * Vector3::x())
    }

    /// The axis' angle in the shear plane from the flow direction towards `-z` (rad, in
    /// `(-pi, pi]`; unwrap a record): `atan2(-e_z, e_x)`.
    pub fn angle(&self) -> f64 {
        let e = self.axis();
        (-e.z).atan2(e.x)
    }

    /// The axis' component out of the shear plane (along y; 0 on Jeffery's orbit here).
    pub fn out_of_plane(&self) -> f64 {
        self.axis().y
    }

    /// The spheroid's centre, m.
    pub fn centre(&self) -> Vector3<f64> {
        self.system
            .body(self.body)
            .map_or(Vector3::zeros(), |b| b.position())
    }

    /// The spheroid's angular velocity (world), rad/s.
    pub fn angular_velocity(&self) -> Vector3<f64> {
        self.system
            .body(self.body)
            .map_or(Vector3::zeros(), |b| b.angular_velocity())
    }

    /// The mean shear stress the fluid puts on the two walls, along the walls' motion
    /// (Pa): `(F_top - F_bottom) . e_x / (2 L_x L_y)` opposing the motion, `mu gamma` in
    /// undisturbed Couette flow (the spheroid adds a little).
    pub fn wall_shear_stress(&self) -> f64 {
        let s = self.fluid().sph();
        let (top, bottom) = (s.wall_force(TOP), s.wall_force(BOTTOM));
        -(top.x - bottom.x) / (2.0 * self.cell[0] * self.cell[1])
    }
}

/// Builds the scene of `p` (see the [module docs](self)) with the multibody `solver`: the
/// spheroid at the cell's centre with its axis along the flow, at rest, the fluid carved
/// around it on the linear Couette profile. Errors name the parameter
/// ([`JefferyParams::validate`]) or the body (a spheroid not resolved by the spacing,
/// [`FsiBuilder::add_body`]).
pub fn jeffery_scene(p: &JefferyParams, solver: Box<dyn CcpSolver>) -> Result<Jeffery> {
    p.validate()?;
    let settings = p.fluid_settings()?;
    let cell = p.cell();
    let mut system = System::new(
        SystemSettings {
            gravity: Vector3::zeros(),
            ..SystemSettings::default()
        },
        solver,
    )?;
    let shape = Shape::Ellipsoid {
        semi_axes: p.semi_axes(),
    };
    let centre = Vector3::new(0.5 * cell[0], 0.5 * cell[1], 0.5 * cell[2]);
    let body = system.add_body(
        RigidBodyBuilder::dynamic()
            .name("spheroid")
            .mass_from_shape(&shape, p.rho)?
            .position(centre)
            .collider(shape, Isometry3::identity(), Default::default()),
    )?;
    let layers = wall_layers(settings.h_over_dp);
    let mut fsi = FsiBuilder::new(settings)?;
    fsi.add_fluid_box([0.0; 3], cell, None)?;
    fsi.sph().add_tank(
        [0.0; 3],
        cell,
        layers,
        [false, false, false, false, true, true],
        0,
    )?;
    fsi.add_body(&system, body)?;
    let mut fluid = fsi.build("fluid", BODY_GROUP)?;
    let (gamma, zc) = (p.shear_rate, centre.z);
    fluid
        .sph_mut()
        .set_fluid_velocity(|x| [gamma * (x[2] - zc), 0.0, 0.0])?;
    let fluid = system.add_item(Box::new(fluid));
    Ok(Jeffery {
        system,
        fluid,
        body,
        cell,
        centre0: centre,
    })
}
