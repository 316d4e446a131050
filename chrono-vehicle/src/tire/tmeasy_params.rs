//! TMeasy parameters, the load-dependent slip characteristic and the combined-slip force.
//!
//! Reference: W. Hirschberg, G. Rill, H. Weinfurter, "Tire model TMeasy", Vehicle System
//! Dynamics 45 (S1), 2007, 101-119 (the characteristic, the normalized combined slip and
//! the load interpolation below are the published formulas of that paper and of G. Rill,
//! "Road Vehicle Dynamics", CRC Press 2011, ch. 3).

use chrono_core::math::GRAVITY_MAGNITUDE;
use serde::{Deserialize, Serialize};

use crate::error::{Result, VehicleError, check_non_negative, check_positive};

/// One direction's (longitudinal or lateral) steady-state characteristic `F(s)` at the
/// two reference loads `F_zN` (index 0) and `2 F_zN` (index 1).
///
/// `F(s)` rises from 0 with the initial slope `df0` (N per unit slip) to the maximum
/// `f_max` at the slip `s_max`, then falls to the sliding force `f_slide` reached at
/// `s_slide`, and stays there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SlipCurve {
    /// Initial slope `dF0`, N (per unit slip).
    pub df0: [f64; 2],
    /// Slip `s_M` of the maximum force (dimensionless).
    pub s_max: [f64; 2],
    /// Maximum force `F_M`, N.
    pub f_max: [f64; 2],
    /// Slip `s_S` where full sliding starts (> `s_max`).
    pub s_slide: [f64; 2],
    /// Sliding force `F_S` (<= `f_max`), N.
    pub f_slide: [f64; 2],
}

/// A characteristic evaluated at one load (see [`SlipCurve::at_load`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveAtLoad {
    /// Initial slope, N.
    pub df0: f64,
    /// Slip at the maximum.
    pub s_max: f64,
    /// Maximum force, N.
    pub f_max: f64,
    /// Slip where sliding starts.
    pub s_slide: f64,
    /// Sliding force, N.
    pub f_slide: f64,
}

/// Rill's load interpolation of a force-like parameter given at `F_zN` (`p1`) and
/// `2 F_zN` (`p2`): with `z = F_z / F_zN`,
/// `p(z) = z [2 p1 - p2/2 - (p1 - p2/2) z]` (through 0, `p1`, `p2` at `z = 0, 1, 2`),
/// continued linearly with the slope at `z = 2` beyond `z = 2`, and never below
/// `1e-3 p2` (a heavily overloaded tire keeps a valid curve).
#[inline]
fn force_at(z: f64, p: [f64; 2]) -> f64 {
    let (p1, p2) = (p[0], p[1]);
    let a = 2.0 * p1 - 0.5 * p2;
    let b = p1 - 0.5 * p2;
    let v = if z <= 2.0 {
        z * (a - b * z)
    } else {
        p2 + (a - 4.0 * b) * (z - 2.0)
    };
    v.max(1e-3 * p2)
}

/// Linear load interpolation of a slip-like parameter, `s(z) = s1 + (s2 - s1)(z - 1)`,
/// kept at or above a quarter of the smaller given value.
#[inline]
fn slip_at(z: f64, s: [f64; 2]) -> f64 {
    (s[0] + (s[1] - s[0]) * (z - 1.0)).max(0.25 * s[0].min(s[1]))
}

impl SlipCurve {
    /// The characteristic at vertical load `fz` (N) for the nominal load `fz_nom` (N), with
    /// the forces scaled by `mu_scale` (the terrain's friction over the reference friction).
    pub fn at_load(&self, fz: f64, fz_nom: f64, mu_scale: f64) -> CurveAtLoad {
        let z = (fz / fz_nom).max(0.0);
        let s_max = slip_at(z, self.s_max);
        let f_max = mu_scale * force_at(z, self.f_max);
        CurveAtLoad {
            df0: force_at(z, self.df0),
            s_max,
            f_max,
            s_slide: slip_at(z, self.s_slide).max(1.001 * s_max),
            f_slide: (mu_scale * force_at(z, self.f_slide)).min(f_max),
        }
    }

    fn validate(&self, field: &str) -> Result<()> {
        for k in 0..2 {
            let f = |n: &str| format!("{field}.{n}[{k}]");
            check_positive(&f("df0"), self.df0[k])?;
            check_positive(&f("s_max"), self.s_max[k])?;
            check_positive(&f("f_max"), self.f_max[k])?;
            check_positive(&f("s_slide"), self.s_slide[k])?;
            check_positive(&f("f_slide"), self.f_slide[k])?;
            if self.s_slide[k] <= self.s_max[k] {
                return Err(VehicleError::invalid(
                    f("s_slide"),
                    self.s_slide[k],
                    format!("must exceed s_max = {}", self.s_max[k]),
                ));
            }
            if self.f_slide[k] > self.f_max[k] {
                return Err(VehicleError::invalid(
                    f("f_slide"),
                    self.f_slide[k],
                    format!("must not exceed f_max = {}", self.f_max[k]),
                ));
            }
        }
        Ok(())
    }
}

/// The TMeasy characteristic of the generalized slip `s >= 0` (Hirschberg et al. 2007,
/// eqs. for `F(s)`):
///
/// ```text
/// 0 <= s <= sM:   F = sM dF0 q / (1 + q (q + dF0 sM / FM - 2)),       q = s / sM
/// sM < s < sS:    F = FM - (FM - FS) q^2 (3 - 2 q),                   q = (s - sM)/(sS - sM)
/// s >= sS:        F = FS
/// ```
///
/// The first branch has slope `dF0` at 0 and its maximum `FM` at `sM`; the second is a
/// cubic that leaves the maximum and reaches `FS` with zero slope.
pub fn characteristic(s: f64, df0: f64, s_max: f64, f_max: f64, s_slide: f64, f_slide: f64) -> f64 {
    if s <= s_max {
        let q = s / s_max;
        s_max * df0 * q / (1.0 + q * (q + df0 * s_max / f_max - 2.0))
    } else if s < s_slide {
        let q = (s - s_max) / (s_slide - s_max);
        f_max - (f_max - f_slide) * q * q * (3.0 - 2.0 * q)
    } else {
        f_slide
    }
}

/// The combined-slip forces `(Fx, Fy)` (N) for the longitudinal slip `sx` and lateral slip
/// `sy` with the characteristics `x`, `y` at the current load, by TMeasy's normalized
/// slip (Hirschberg et al. 2007):
///
/// ```text
/// s^_x = sMx/(sMx + sMy) + (FMx/dF0x)/(FMx/dF0x + FMy/dF0y)     (s^_y likewise)
/// sN = sqrt((sx/s^_x)^2 + (sy/s^_y)^2),   cos p = sx/(s^_x sN),  sin p = sy/(s^_y sN)
/// dF0 = sqrt((dF0x s^_x cos p)^2 + (dF0y s^_y sin p)^2)
/// sM  = sqrt((sMx/s^_x cos p)^2 + (sMy/s^_y sin p)^2),  sS likewise
/// FM  = sqrt((FMx cos p)^2 + (FMy sin p)^2),           FS likewise
/// F = characteristic(sN; dF0, sM, FM, sS, FS),  Fx = F cos p,  Fy = F sin p
/// ```
///
/// For pure slip this is the direction's own curve. Positive slip gives positive force.
pub fn combined_force(sx: f64, sy: f64, x: &CurveAtLoad, y: &CurveAtLoad) -> (f64, f64) {
    let (ax, ay) = (x.f_max / x.df0, y.f_max / y.df0);
    let hx = x.s_max / (x.s_max + y.s_max) + ax / (ax + ay);
    let hy = y.s_max / (x.s_max + y.s_max) + ay / (ax + ay);
    let (nx, ny) = (sx / hx, sy / hy);
    let s = nx.hypot(ny);
    if s <= 0.0 {
        return (0.0, 0.0);
    }
    let (c, d) = (nx / s, ny / s);
    let df0 = (x.df0 * hx * c).hypot(y.df0 * hy * d);
    let sm = (x.s_max / hx * c).hypot(y.s_max / hy * d);
    let ss = (x.s_slide / hx * c).hypot(y.s_slide / hy * d);
    let fm = (x.f_max * c).hypot(y.f_max * d);
    let fs = (x.f_slide * c).hypot(y.f_slide * d);
    let f = characteristic(s, df0, sm, fm, ss.max(1.001 * sm), fs.min(fm));
    (f * c, f * d)
}

/// Size of a tire in the usual designation `D x W R d` (e.g. 37x12.5R16.5), inches.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TireSize {
    /// Outer diameter, in.
    pub outer_diameter_in: f64,
    /// Section width, in.
    pub section_width_in: f64,
    /// Rim diameter, in.
    pub rim_diameter_in: f64,
}

/// Parameters of [`TMeasyTire`](super::TMeasyTire). SI units; forces at the nominal load
/// `nominal_load` (index 0) and twice it (index 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TMeasyParams {
    /// Unloaded radius `R`, m.
    pub radius: f64,
    /// Tread width, m.
    pub width: f64,
    /// Tire mass, kg.
    pub mass: f64,
    /// Principal moments of inertia (wheel frame, spin axis Y), kg m^2.
    pub inertia: [f64; 3],
    /// Nominal vertical load `F_zN`, N.
    pub nominal_load: f64,
    /// Radial stiffness `c_z`, N/m: `F_z = c_z dz + d_z dz_dot` (clamped at 0).
    pub vertical_stiffness: f64,
    /// Radial damping `d_z`, N s/m.
    pub vertical_damping: f64,
    /// Longitudinal characteristic.
    pub longitudinal: SlipCurve,
    /// Lateral characteristic.
    pub lateral: SlipCurve,
    /// Relaxation lengths `[sigma_x, sigma_y]`, m. The tread then acts at standstill like
    /// springs of stiffness `dF0 / sigma` (N/m).
    pub relaxation_length: [f64; 2],
    /// Low-speed tread damping `[d_x, d_y]`, N s/m, faded out linearly up to
    /// `low_speed`.
    pub low_speed_damping: [f64; 2],
    /// Speed below which the low-speed damping acts, m/s (> 0).
    pub low_speed: f64,
    /// Rolling resistance coefficient `f_r` (torque `f_r r_D F_z` against the spin).
    pub rolling_resistance: f64,
    /// Friction coefficient of the road the force curves were measured on: the maximum and
    /// sliding forces are scaled by `mu_terrain / reference_friction`.
    pub reference_friction: f64,
    /// Pneumatic trail at zero lateral slip as a fraction of the contact length.
    pub trail_ratio: f64,
}

impl TMeasyParams {
    /// Check every field; errors name it (`tmeasy.lateral.s_max[1]` ...).
    pub fn validate(&self) -> Result<()> {
        check_positive("tmeasy.radius", self.radius)?;
        check_positive("tmeasy.width", self.width)?;
        check_positive("tmeasy.mass", self.mass)?;
        for (k, n) in ["x", "y", "z"].iter().enumerate() {
            check_positive(&format!("tmeasy.inertia.{n}"), self.inertia[k])?;
        }
        check_positive("tmeasy.nominal_load", self.nominal_load)?;
        check_positive("tmeasy.vertical_stiffness", self.vertical_stiffness)?;
        check_non_negative("tmeasy.vertical_damping", self.vertical_damping)?;
        self.longitudinal.validate("tmeasy.longitudinal")?;
        self.lateral.validate("tmeasy.lateral")?;
        check_positive("tmeasy.relaxation_length[0]", self.relaxation_length[0])?;
        check_positive("tmeasy.relaxation_length[1]", self.relaxation_length[1])?;
        check_non_negative("tmeasy.low_speed_damping[0]", self.low_speed_damping[0])?;
        check_non_negative("tmeasy.low_speed_damping[1]", self.low_speed_damping[1])?;
        check_positive("tmeasy.low_speed", self.low_speed)?;
        check_non_negative("tmeasy.rolling_resistance", self.rolling_resistance)?;
        check_positive("tmeasy.reference_friction", self.reference_friction)?;
        check_non_negative("tmeasy.trail_ratio", self.trail_ratio)?;
        Ok(())
    }

    /// A parameter set guessed from the size and rated load of a truck tire (bias or
    /// radial, off-road tread), for when no measurements exist. Each number's origin:
    ///
    /// - `nominal_load = rated_load / 2`, so the two reference loads span a lightly
    ///   loaded tire and the rated load (TMeasy's convention: data at `F_zN` and `2 F_zN`).
    /// - Vertical stiffness from the rule of thumb that a truck tire at its rated load and
    ///   pressure deflects about 12 % of its section height `(D - d)/2` (design range
    ///   10-17 %, e.g. Wong, "Theory of Ground Vehicles", ch. 1): `c_z = rated_load /
    ///   (0.12 (D - d)/2)`. Damping: 10 % of critical for the rated load's mass
    ///   `rated_load / g` on that spring.
    /// - Force ratios per unit load (at `F_zN` / `2 F_zN`), chosen for a truck tire on dry
    ///   road, of the size Rill reports for truck tires (Road Vehicle Dynamics, ch. 3):
    ///   longitudinal slip stiffness 30 / 28 `F_z`, peak friction 0.90 / 0.83 at slip
    ///   0.15 / 0.14, sliding friction 0.80 / 0.72 from slip 0.6 / 0.7; cornering
    ///   stiffness 10 / 8.5 `F_z` per unit lateral slip (lower than a passenger car's
    ///   15-20, as for bias-ply off-road tires), peak 0.85 / 0.78 at 0.25 / 0.28, sliding
    ///   0.78 / 0.70 from 0.7 / 0.8. The falling ratios are the usual load sensitivity.
    /// - Relaxation lengths 0.3 m (longitudinal) and 0.5 m (lateral): of the order of the
    ///   wheel radius for the lateral one and shorter for the longitudinal one
    ///   (Pacejka, "Tire and Vehicle Dynamics", ch. 7).
    /// - Low-speed damping: half of critical for the tire mass on the tread spring
    ///   `dF0(F_zN) / sigma`, `d = 2 * 0.5 sqrt(m dF0 / sigma)`, acting below 1 m/s (so a
    ///   vehicle corner of ~20 times that mass still gets ~10 % of critical).
    /// - Rolling resistance 0.015 (off-road tread on hard ground; Wong lists 0.006-0.01
    ///   for truck tires on concrete and more for coarse treads).
    /// - Reference friction 0.9 (the peak longitudinal ratio at `F_zN`), pneumatic trail
    ///   1/6 of the contact length (brush model, Pacejka ch. 3).
    pub fn guess_truck(
        size: TireSize,
        rated_load: f64,
        mass: f64,
        inertia: [f64; 3],
        width: f64,
    ) -> Result<Self> {
        const IN: f64 = 0.0254;
        check_positive("tire_size.outer_diameter_in", size.outer_diameter_in)?;
        check_positive("tire_size.section_width_in", size.section_width_in)?;
        check_positive("tire_size.rim_diameter_in", size.rim_diameter_in)?;
        check_positive("rated_load", rated_load)?;
        if size.rim_diameter_in >= size.outer_diameter_in {
            return Err(VehicleError::invalid(
                "tire_size.rim_diameter_in",
                size.rim_diameter_in,
                format!(
                    "must be below the outer diameter {}",
                    size.outer_diameter_in
                ),
            ));
        }
        let radius = 0.5 * size.outer_diameter_in * IN;
        let section_height = 0.5 * (size.outer_diameter_in - size.rim_diameter_in) * IN;
        let fzn = 0.5 * rated_load;
        let cz = rated_load / (0.12 * section_height);
        let dz = 0.2 * (cz * rated_load / GRAVITY_MAGNITUDE).sqrt();
        let two = |a: f64, b: f64| [a * fzn, b * 2.0 * fzn];
        let longitudinal = SlipCurve {
            df0: two(30.0, 28.0),
            s_max: [0.15, 0.14],
            f_max: two(0.90, 0.83),
            s_slide: [0.6, 0.7],
            f_slide: two(0.80, 0.72),
        };
        let lateral = SlipCurve {
            df0: two(10.0, 8.5),
            s_max: [0.25, 0.28],
            f_max: two(0.85, 0.78),
            s_slide: [0.7, 0.8],
            f_slide: two(0.78, 0.70),
        };
        let sigma = [0.3, 0.5];
        let damp = |df0: f64, s: f64| (df0 / s * mass).sqrt();
        let p = Self {
            radius,
            width,
            mass,
            inertia,
            nominal_load: fzn,
            vertical_stiffness: cz,
            vertical_damping: dz,
            longitudinal,
            lateral,
            relaxation_length: sigma,
            low_speed_damping: [
                damp(longitudinal.df0[0], sigma[0]),
                damp(lateral.df0[0], sigma[1]),
            ],
            low_speed: 1.0,
            rolling_resistance: 0.015,
            reference_friction: 0.9,
            trail_ratio: 1.0 / 6.0,
        };
        p.validate()?;
        Ok(p)
    }

    /// The HMMWV tire: 37x12.5R16.5, rated 3850 lbf at 50 psi (reference notes sec. 7),
    /// mass 37.6 kg, inertia (3.84, 6.69, 3.84) kg m^2, tread width 0.254 m, by
    /// [`guess_truck`](Self::guess_truck). The guess's radius `37/2 in = 0.470 m` is
    /// replaced by the 0.467 m of Chrono's HMMWV tire data (the notes) so that the rigid and
    /// the TMeasy tire have the same size.
    pub fn hmmwv() -> Self {
        const LBF: f64 = 4.448_221_615_260_5;
        let size = TireSize {
            outer_diameter_in: 37.0,
            section_width_in: 12.5,
            rim_diameter_in: 16.5,
        };
        let mut p = Self::guess_truck(size, 3850.0 * LBF, 37.6, [3.84, 6.69, 3.84], 0.254)
            .expect("the HMMWV tire data are valid");
        p.radius = 0.467;
        p
    }

    /// The steady-state forces `(Fx, Fy)` (N) at load `fz` (N), longitudinal slip `sx`,
    /// lateral slip `sy`, and friction scale `mu_scale` (terrain over reference friction).
    pub fn steady_force(&self, fz: f64, sx: f64, sy: f64, mu_scale: f64) -> (f64, f64) {
        if fz <= 0.0 {
            return (0.0, 0.0);
        }
        let x = self.longitudinal.at_load(fz, self.nominal_load, mu_scale);
        let y = self.lateral.at_load(fz, self.nominal_load, mu_scale);
        combined_force(sx, sy, &x, &y)
    }
}
