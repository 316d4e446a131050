//! Free heave of a floating hemisphere: the reference of Hulme (1982) and the scene.
//!
//! A sphere of radius `a` and half the fluid's density floats with its centre on the
//! still-water level (a floating hemisphere). Released from an offset `z0`, it heaves
//! about that level; linear potential theory gives, per unit heave `z`, the buoyancy
//! stiffness `C = rho g pi a^2` (waterplane area), the added mass `A33(omega)` and the
//! radiation damping `B33(omega)`, so that
//!
//! `(m + A33) z'' + B33 z' + C z = 0`, `m = (2/3) pi rho a^3` (the displaced mass).
//!
//! Hulme (1982) tabulates `mu = A33 / m` and `nu = B33 / (m omega)` against
//! `K a = omega^2 a / g` ([`HULME_HEAVE`]). The natural frequency is the root of
//! `omega^2 (m + A33(omega)) = C`, i.e. in these variables `K a = 3 / (2 (1 + mu(K a)))`
//! (a fixed point, [`hemisphere_heave`]): `K a = 1.054`, `mu = 0.422`, for every radius
//! and gravity. The damping ratio there, `zeta = nu / (2 (1 + mu))` = 0.084, lengthens the
//! period by `1 / sqrt(1 - zeta^2)` = 0.35 % (the damped period is the reference); the
//! amplitude falls by `exp(-2 pi zeta / sqrt(1 - zeta^2))` = 0.59 per cycle.
//!
//! [`fit_damped_oscillation`] reads a period and a damping rate from a record `z(t)`
//! (least squares over a damped sinusoid about a free mean); [`sphere_heave`] builds the
//! scene: the sphere in a 3-D tank of walls at both ends in x, periodic along y with the
//! tank's length as period (the sphere and its images form a square array of pitch `L`;
//! a wall is a mirror image), filled to its centre's level. The sphere is held at its
//! offset while the fluid settles ([`HeaveScene::hold`]), then released
//! ([`HeaveScene::step`]). The radiated waves of the natural frequency come back from the
//! nearest image after `2 (L - 2 a) omega / g` (the deep-water group velocity
//! `g / (2 omega)` over the gap between the two surfaces, [`HeaveScene::return_time`]);
//! the record is read before that.
//!
//! Numerics that matter here (measured, docs/validation-fsi.md): Hulme's fluid is
//! inviscid, so [`HeaveParams`] sets no artificial viscosity, and no XSPH: XSPH moves the
//! particles with a kernel-averaged velocity, which slows the free surface on the scale
//! of the radiated waves (12-24 spacings long) and of the sphere's near field and acts
//! as extra added mass (the period at 4 spacings per diameter +16 % with XSPH 0.5,
//! +8.5 % without).

use chrono_core::descriptor::CcpSolver;
use chrono_core::math::{GRAVITY_MAGNITUDE, Vector3};

use crate::cfluid::{CfluidFloat, CfluidFloatingScene, floating_cfluid};
use crate::error::{FsiError, Result, check_positive};
use crate::scene::{FloatShape, FloatingParams, FloatingScene, FloatingSystem, floating};

/// Hulme's (1982) heave coefficients of a floating hemisphere in deep water,
/// `(K a, mu, nu)`: `K a = omega^2 a / g`, `mu = A33 / ((2/3) pi rho a^3)`,
/// `nu = B33 / ((2/3) pi rho a^3 omega)`.
///
/// Source: A. Hulme (1982), "The wave forces acting on a floating hemisphere undergoing
/// forced periodic oscillations", J. Fluid Mech. 121, 443-463, the heave table; numbers
/// as tabulated in the LHEEA (Ecole Centrale de Nantes) repository
/// `Hulme_Heaving_Sphere`, `comparison/HulmeResult.dat`. The limits agree with the
/// known asymptotes: `mu(0)` = 0.8310, `mu -> 1/2` as `K a -> inf` (the rigid-lid limit,
/// half the added mass of a deeply submerged sphere), `nu -> 0` at both ends.
pub const HULME_HEAVE: [(f64, f64, f64); 26] = [
    (0.0, 0.8310, 0.0000),
    (0.05, 0.8764, 0.1036),
    (0.1, 0.8627, 0.1816),
    (0.2, 0.7938, 0.2793),
    (0.3, 0.7157, 0.3254),
    (0.4, 0.6452, 0.3410),
    (0.5, 0.5861, 0.3391),
    (0.6, 0.5381, 0.3271),
    (0.7, 0.4999, 0.3098),
    (0.8, 0.4698, 0.2899),
    (0.9, 0.4464, 0.2691),
    (1.0, 0.4284, 0.2484),
    (1.2, 0.4047, 0.2096),
    (1.4, 0.3924, 0.1756),
    (1.6, 0.3871, 0.1469),
    (1.8, 0.3864, 0.1229),
    (2.0, 0.3884, 0.1031),
    (2.5, 0.3988, 0.0674),
    (3.0, 0.4111, 0.0452),
    (4.0, 0.4322, 0.0219),
    (5.0, 0.4471, 0.0116),
    (6.0, 0.4574, 0.0066),
    (7.0, 0.4647, 0.0040),
    (8.0, 0.4700, 0.0026),
    (9.0, 0.4740, 0.0017),
    (10.0, 0.4771, 0.0012),
];

/// `(mu, nu)` of [`HULME_HEAVE`] at `ka` (linear interpolation; near the natural
/// frequency the table's second differences change the period by under 0.05 %). An error
/// outside the table, `0 <= K a <= 10`.
pub fn hulme_heave_coefficients(ka: f64) -> Result<(f64, f64)> {
    let last = HULME_HEAVE[HULME_HEAVE.len() - 1].0;
    if !(ka.is_finite() && (0.0..=last).contains(&ka)) {
        return Err(FsiError::invalid(
            "ka",
            ka,
            format!("outside Hulme's table (0 to {last})"),
        ));
    }
    let i = HULME_HEAVE
        .windows(2)
        .position(|w| ka <= w[1].0)
        .expect("ka within the table");
    let (k0, m0, n0) = HULME_HEAVE[i];
    let (k1, m1, n1) = HULME_HEAVE[i + 1];
    let s = (ka - k0) / (k1 - k0);
    Ok((m0 + s * (m1 - m0), n0 + s * (n1 - n0)))
}

/// The heave estimate of a floating hemisphere from [`HULME_HEAVE`]: see
/// [`hemisphere_heave`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeaveEstimate {
    /// `K a = omega_n^2 a / g` at the natural frequency.
    pub ka: f64,
    /// `A33 / m` there.
    pub mu: f64,
    /// `B33 / (m omega_n)` there.
    pub nu: f64,
    /// Natural angular frequency `omega_n`, rad/s.
    pub omega: f64,
    /// Damping ratio `zeta = B33 / (2 omega_n (m + A33)) = nu / (2 (1 + mu))`.
    pub zeta: f64,
    /// Undamped period `2 pi / omega_n`, s.
    pub period_undamped: f64,
    /// Damped period `2 pi / (omega_n sqrt(1 - zeta^2))`, s (the reference).
    pub period: f64,
}

/// Hulme's estimate for a sphere of radius `radius` (m) at half the fluid's density
/// (floating at half draft) under gravity `g` (m/s^2): the natural frequency is the root
/// of `omega^2 (m + A33(omega)) = rho g pi a^2`, `m = (2/3) pi rho a^3`, i.e. the fixed
/// point `K a = 3 / (2 (1 + mu(K a)))` (a contraction: `|d/dKa| < 0.1` there), with the
/// damping ratio and damped period of [`HeaveEstimate`].
pub fn hemisphere_heave(radius: f64, g: f64) -> Result<HeaveEstimate> {
    check_positive("radius", radius)?;
    check_positive("g", g)?;
    let mut ka = 1.0;
    for _ in 0..200 {
        let (mu, _) = hulme_heave_coefficients(ka)?;
        let next = 1.5 / (1.0 + mu);
        let done = (next - ka).abs() < 1e-15;
        ka = next;
        if done {
            break;
        }
    }
    let (mu, nu) = hulme_heave_coefficients(ka)?;
    let omega = (ka * g / radius).sqrt();
    let zeta = nu / (2.0 * (1.0 + mu));
    let tau = std::f64::consts::TAU;
    Ok(HeaveEstimate {
        ka,
        mu,
        nu,
        omega,
        zeta,
        period_undamped: tau / omega,
        period: tau / (omega * (1.0 - zeta * zeta).sqrt()),
    })
}

/// A damped oscillation `z(t) = z_mean + e^(-sigma (t - t0)) (p cos w (t - t0) + q sin w (t - t0))`
/// fitted to a record ([`fit_damped_oscillation`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedFit {
    /// The mean `z_mean` (the equilibrium), m.
    pub mean: f64,
    /// Amplitude at the record's start `sqrt(p^2 + q^2)`, m.
    pub amplitude: f64,
    /// Damped angular frequency `w`, rad/s.
    pub omega: f64,
    /// Decay rate `sigma`, 1/s.
    pub sigma: f64,
    /// Period `2 pi / w`, s.
    pub period: f64,
    /// Damping ratio `sigma / sqrt(sigma^2 + w^2)`.
    pub zeta: f64,
    /// RMS residual of the fit over the amplitude.
    pub residual: f64,
}

/// Least-squares fit of [`DampedFit`]'s model to samples `(t_i, z_i)` (at least 8, over at
/// least half a period). For given `(w, sigma)` the model is linear in `(z_mean, p, q)`
/// (solved exactly); `(w, sigma)` minimize the residual by a grid search over
/// `w` from `pi / 4` per record length to half the sampling rate (log-spaced) and
/// `sigma` from 0 to `2 w`, refined by successive finer grids around the best point. No
/// initial guess is taken from outside the record. `None` if the record is too short or
/// flat.
pub fn fit_damped_oscillation(t: &[f64], z: &[f64]) -> Option<DampedFit> {
    let n = t.len().min(z.len());
    if n < 8 {
        return None;
    }
    let (t0, span) = (t[0], t[n - 1] - t[0]);
    if span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // a flat record (to round-off) has no oscillation to fit
    let (lo, hi) = z[..n]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let range = hi - lo;
    if range.is_nan() || range <= 1e-12 * hi.abs().max(lo.abs()) {
        return None;
    }
    let w_lo = 0.25 * std::f64::consts::PI / span;
    let w_hi = std::f64::consts::PI * (n - 1) as f64 / span;
    let residual = |w: f64, s: f64| -> Option<(f64, [f64; 3])> {
        // normal equations of the three basis functions
        let mut a = [[0.0; 3]; 3];
        let mut b = [0.0; 3];
        for i in 0..n {
            let dt = t[i] - t0;
            let e = (-s * dt).exp();
            let f = [1.0, e * (w * dt).cos(), e * (w * dt).sin()];
            for r in 0..3 {
                b[r] += f[r] * z[i];
                for c in 0..3 {
                    a[r][c] += f[r] * f[c];
                }
            }
        }
        let x = solve3(a, b)?;
        let mut r2 = 0.0;
        for i in 0..n {
            let dt = t[i] - t0;
            let e = (-s * dt).exp();
            let m = x[0] + e * (x[1] * (w * dt).cos() + x[2] * (w * dt).sin());
            r2 += (z[i] - m).powi(2);
        }
        Some((r2, x))
    };
    // coarse grid: log w, sigma / w
    let (nw, ns) = (240usize, 40usize);
    let mut best = (f64::INFINITY, w_lo, 0.0);
    for i in 0..nw {
        let w = w_lo * (w_hi / w_lo).powf(i as f64 / (nw - 1) as f64);
        for j in 0..ns {
            let s = 2.0 * w * j as f64 / (ns - 1) as f64;
            if let Some((r2, _)) = residual(w, s)
                && r2 < best.0
            {
                best = (r2, w, s);
            }
        }
    }
    // refine: grids of half-width one cell around the best point, shrinking
    let mut dw = best.1 * ((w_hi / w_lo).powf(1.0 / (nw - 1) as f64) - 1.0);
    let mut ds = 2.0 * best.1 / (ns - 1) as f64;
    for _ in 0..40 {
        let (_, w0, s0) = best;
        for i in -4i32..=4 {
            for j in -4i32..=4 {
                let w = w0 + dw * i as f64 / 4.0;
                let s = (s0 + ds * j as f64 / 4.0).max(0.0);
                if w <= 0.0 {
                    continue;
                }
                if let Some((r2, _)) = residual(w, s)
                    && r2 < best.0
                {
                    best = (r2, w, s);
                }
            }
        }
        dw *= 0.5;
        ds *= 0.5;
    }
    let (r2, w, s) = best;
    let (_, x) = residual(w, s)?;
    let amplitude = (x[1] * x[1] + x[2] * x[2]).sqrt();
    if !(amplitude > 0.0 && amplitude.is_finite()) {
        return None;
    }
    Some(DampedFit {
        mean: x[0],
        amplitude,
        omega: w,
        sigma: s,
        period: std::f64::consts::TAU / w,
        zeta: s / (s * s + w * w).sqrt(),
        residual: (r2 / n as f64).sqrt() / amplitude,
    })
}

/// Solves the symmetric 3x3 system `a x = b` (Gaussian elimination with partial pivoting);
/// `None` if singular.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    let scale = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for c in 0..3 {
        let p = (c..3).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() <= 1e-13 * scale {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..3 {
            let f = a[r][c] / a[c][c];
            for k in c..3 {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 3];
    for r in (0..3).rev() {
        let s: f64 = (r + 1..3).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    Some(x)
}

/// Parameters of [`sphere_heave`] (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct HeaveParams {
    /// Sphere radius `a`, m.
    pub radius: f64,
    /// Body density over the fluid's (0.5: Hulme's hemisphere; other values float at
    /// another draft, for which [`HULME_HEAVE`] does not hold).
    pub density_ratio: f64,
    /// Tank side `L` (length in x, period in y), in diameters.
    pub tank: f64,
    /// Water depth at rest, m.
    pub depth: f64,
    /// Start of the centre above its Archimedes position, in radii (negative: below).
    pub offset: f64,
    /// Particle spacing, m.
    pub spacing: f64,
    /// Fluid density, kg/m^3.
    pub rho0: f64,
    /// Kinematic viscosity, m^2/s.
    pub nu: f64,
    /// Sound speed over `sqrt(g depth)`.
    pub mach_factor: f64,
    /// Monaghan's artificial viscosity `alpha` (a kinematic viscosity
    /// `~ alpha c_s h / 10`: Hulme's fluid is inviscid, see the module docs).
    pub artificial_viscosity: f64,
    /// XSPH coefficient of the fluid (see the module docs: it slows the short waves).
    pub xsph: f64,
}

impl Default for HeaveParams {
    fn default() -> Self {
        Self {
            radius: 0.05,
            density_ratio: 0.5,
            tank: 4.0,
            depth: 0.15,
            offset: 0.2,
            spacing: 0.02,
            rho0: 1000.0,
            nu: 1e-6,
            mach_factor: 10.0,
            artificial_viscosity: 0.0,
            xsph: 0.0,
        }
    }
}

impl HeaveParams {
    /// The floating scene's parameters (sphere of diameter `2 a` in an `L` square).
    pub fn floating(&self) -> FloatingParams {
        FloatingParams {
            shape: FloatShape::Sphere,
            body_density: self.density_ratio * self.rho0,
            body_size: 2.0 * self.radius,
            depth: self.depth,
            length: self.tank,
            width: self.tank,
            spacing: self.spacing,
            rho0: self.rho0,
            nu: self.nu,
            offset: self.offset * self.radius,
            mach_factor: self.mach_factor,
            artificial_viscosity: self.artificial_viscosity,
            xsph: self.xsph,
            ..FloatingParams::default()
        }
    }

    /// Checks every field (the error names it); the rest is checked by
    /// [`FloatingParams::validate`].
    pub fn validate(&self) -> Result<()> {
        check_positive("radius", self.radius)?;
        if !(self.density_ratio.is_finite() && self.density_ratio > 0.0 && self.density_ratio < 1.0)
        {
            return Err(FsiError::invalid(
                "density_ratio",
                self.density_ratio,
                "must be in (0, 1) to float",
            ));
        }
        if !(self.offset.is_finite() && self.offset.abs() <= 0.5) {
            return Err(FsiError::invalid(
                "offset",
                self.offset,
                "must be finite and at most half a radius (linear heave)",
            ));
        }
        if !(self.tank.is_finite() && self.tank >= 2.0) {
            return Err(FsiError::invalid(
                "tank",
                self.tank,
                "must be >= 2 diameters",
            ));
        }
        self.floating().validate()
    }
}

/// The heave scene: a floating scene of either fluid model ([`FloatingSystem`]: WCSPH by
/// default, [`sphere_heave_cfluid`] for the constraint fluid) with the sphere's hold and
/// release.
pub struct HeaveScene<S: FloatingSystem = FloatingScene> {
    /// The floating scene (system, body, fluid, tank).
    pub scene: S,
    /// Its parameters.
    pub params: FloatingParams,
    /// Height of the sphere's centre at its Archimedes position, m.
    pub z_equilibrium: f64,
    start: Vector3<f64>,
}

impl<S: FloatingSystem> HeaveScene<S> {
    /// One multibody step of `h` (s) with the sphere held at its start (position reset,
    /// velocities zero after the step) and the fluid's velocity relaxed at `damping`
    /// (1/s): the fluid settles around the displaced sphere.
    pub fn hold(&mut self, h: f64, damping: f64) -> Result<()> {
        self.scene.set_fluid_damping(damping)?;
        self.scene.step(h)?;
        let body = self.scene.body();
        let b = self.scene.system_mut().body_mut(body)?;
        let rot = b.rotation();
        b.set_pose(self.start, rot)?;
        b.set_linear_velocity(Vector3::zeros())?;
        b.set_angular_velocity(Vector3::zeros())?;
        Ok(())
    }

    /// One free multibody step of `h` (s), the fluid undamped.
    pub fn step(&mut self, h: f64) -> Result<()> {
        self.scene.set_fluid_damping(0.0)?;
        self.scene.step(h)?;
        Ok(())
    }

    /// The sphere's heave: its centre's height above the Archimedes position, m.
    pub fn heave(&self) -> Result<f64> {
        Ok(self.scene.system().body(self.scene.body())?.position().z - self.z_equilibrium)
    }

    /// The sphere's mass, kg.
    pub fn mass(&self) -> Result<f64> {
        Ok(self.scene.system().body(self.scene.body())?.mass())
    }

    /// The fluid's vertical force on the sphere over the last multibody step, N.
    pub fn fluid_force_z(&self) -> f64 {
        self.scene.fluid_force_z()
    }

    /// The fluid's steps so far ([`FloatingSystem::fluid_steps`]).
    pub fn fluid_steps(&self) -> u64 {
        self.scene.fluid_steps()
    }

    /// The buoyancy stiffness `C = rho g pi a^2` of linear theory (N/m): the waterplane
    /// area times `rho g`.
    pub fn stiffness(&self) -> f64 {
        let a = 0.5 * self.params.body_size;
        self.params.rho0 * GRAVITY_MAGNITUDE * std::f64::consts::PI * a * a
    }

    /// Time (s, after the release) at which waves of angular frequency `omega` (rad/s)
    /// radiated by the nearest image (its centre at the tank side `L`: the periodic
    /// neighbour along y, the mirror image in an end wall) reach the sphere at the
    /// deep-water group velocity `g / (2 omega)`, counted from surface to surface:
    /// `2 (L - 2 a) omega / g`.
    pub fn return_time(&self, omega: f64) -> f64 {
        let tank = self.scene.tank();
        let gap = tank[0].min(tank[1]) - self.params.body_size;
        2.0 * gap * omega / GRAVITY_MAGNITUDE
    }
}

/// Builds the heave scene of `p` with the system's solver `solver` (see the
/// [module docs](self)).
pub fn sphere_heave(p: &HeaveParams, solver: Box<dyn CcpSolver>) -> Result<HeaveScene> {
    p.validate()?;
    let params = p.floating();
    let scene = floating(&params, solver)?;
    Ok(heave_scene(scene, params))
}

/// The heave scene of `p` in a constraint fluid set by `c` (the SPH-only fields of `p`
/// are not used), solved by `solver` (one CCP per step for the fluid and the sphere;
/// [`crate::cfluid`]).
pub fn sphere_heave_cfluid(
    p: &HeaveParams,
    c: &CfluidFloat,
    solver: Box<dyn CcpSolver>,
) -> Result<HeaveScene<CfluidFloatingScene>> {
    p.validate()?;
    let params = p.floating();
    let scene = floating_cfluid(&params, c, solver)?;
    Ok(heave_scene(scene, params))
}

fn heave_scene<S: FloatingSystem>(scene: S, params: FloatingParams) -> HeaveScene<S> {
    let start = scene
        .system()
        .body(scene.body())
        .expect("the scene's body")
        .position();
    let z_equilibrium = start.z - params.offset;
    HeaveScene {
        scene,
        params,
        z_equilibrium,
        start,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_ordered_and_interpolated() {
        assert!(HULME_HEAVE.windows(2).all(|w| w[1].0 > w[0].0));
        for &(ka, mu, nu) in &HULME_HEAVE {
            let (m, n) = hulme_heave_coefficients(ka).unwrap();
            assert!((m - mu).abs() < 1e-15 && (n - nu).abs() < 1e-15, "{ka}");
        }
        let (m, n) = hulme_heave_coefficients(1.1).unwrap();
        assert!((m - 0.5 * (0.4284 + 0.4047)).abs() < 1e-15);
        assert!((n - 0.5 * (0.2484 + 0.2096)).abs() < 1e-15);
        for bad in [-0.1, 10.5, f64::NAN] {
            let e = hulme_heave_coefficients(bad).unwrap_err().to_string();
            assert!(e.contains("`ka`"), "{e}");
        }
    }

    #[test]
    fn natural_frequency_solves_the_dispersion_equation() {
        // omega^2 (m + A33(omega)) = rho g pi a^2, for any radius and gravity
        for (a, g) in [(0.05, 9.81), (1.0, 9.80665), (0.2, 1.62)] {
            let e = hemisphere_heave(a, g).unwrap();
            let (rho, pi) = (1000.0, std::f64::consts::PI);
            let m = 2.0 / 3.0 * pi * rho * a * a * a;
            let (mu, nu) = hulme_heave_coefficients(e.omega * e.omega * a / g).unwrap();
            let lhs = e.omega * e.omega * m * (1.0 + mu);
            assert!(
                (lhs / (rho * g * pi * a * a) - 1.0).abs() < 1e-12,
                "{a} {g}"
            );
            assert!((e.nu - nu).abs() < 1e-12);
            // the table's neighbourhood: K a between 1.0 and 1.2, mu about 0.42
            assert!(e.ka > 1.0 && e.ka < 1.2 && (e.mu - 0.422).abs() < 0.002);
            assert!(e.zeta > 0.08 && e.zeta < 0.09);
            assert!(e.period > e.period_undamped);
        }
        assert!(hemisphere_heave(0.0, 9.81).is_err());
    }

    #[test]
    fn fit_recovers_a_damped_oscillation() {
        // 1.5 cycles sampled every 1 ms, with a deterministic wiggle at 2 % of the amplitude
        let (w, s, mean, p, q) = (14.4, 1.2, -0.0013, 0.01, 0.0007);
        let t: Vec<f64> = (0..660).map(|i| 1e-3 * i as f64).collect();
        let z: Vec<f64> = t
            .iter()
            .map(|&t| {
                mean + (-s * t).exp() * (p * (w * t).cos() + q * (w * t).sin())
                    + 2e-4 * (173.0 * t).sin()
            })
            .collect();
        let f = fit_damped_oscillation(&t, &z).unwrap();
        assert!((f.omega / w - 1.0).abs() < 2e-3, "{f:?}");
        assert!((f.sigma / s - 1.0).abs() < 0.05, "{f:?}");
        assert!((f.mean - mean).abs() < 1e-4, "{f:?}");
        // exact data: exact parameters
        let z: Vec<f64> = t
            .iter()
            .map(|&t| mean + (-s * t).exp() * (p * (w * t).cos() + q * (w * t).sin()))
            .collect();
        let f = fit_damped_oscillation(&t, &z).unwrap();
        assert!((f.omega / w - 1.0).abs() < 1e-8 && (f.sigma / s - 1.0).abs() < 1e-6);
        assert!(f.residual < 1e-8);
        assert!(fit_damped_oscillation(&t[..5], &z[..5]).is_none());
        assert!(fit_damped_oscillation(&t, &vec![0.3; t.len()]).is_none());
    }

    #[test]
    fn bad_input_names_the_field() {
        let cases: [(HeaveParams, &str); 4] = [
            (
                HeaveParams {
                    radius: -1.0,
                    ..Default::default()
                },
                "radius",
            ),
            (
                HeaveParams {
                    density_ratio: 1.2,
                    ..Default::default()
                },
                "density_ratio",
            ),
            (
                HeaveParams {
                    offset: f64::NAN,
                    ..Default::default()
                },
                "offset",
            ),
            (
                HeaveParams {
                    tank: 1.0,
                    ..Default::default()
                },
                "tank",
            ),
        ];
        for (p, field) in cases {
            let e = p.validate().unwrap_err().to_string();
            assert!(e.contains(&format!("`{field}`")), "{field}: {e}");
        }
    }
}
