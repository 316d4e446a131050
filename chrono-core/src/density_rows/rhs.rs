//! The right-hand side of a density row: stabilization, compliance and the free-surface
//! treatment (bilateral or unilateral row).

use serde::{Deserialize, Serialize};

use crate::descriptor::{ConstraintRows, RowEntry, RowId};
use crate::error::{ChronoError, Result};

/// How the density row of a particle treats a density deficit (`rho_i < rho_0`, a
/// free-surface or splashing particle, whose kernel support is not full).
///
/// With the row written as `c_i = -grad C_i . v - C_i / h + eps g_i` (so that `g_i >= 0`
/// is a pressure impulse that pushes neighbours apart), the choices are:
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceMode {
    /// The default. A particle with `C_i >= 0` has a bilateral row (`c_i = 0`: the
    /// density returns to `rho_0` within the step, tension allowed while compressed);
    /// a particle with `C_i < 0` has a **unilateral** row, `0 <= g_i ⊥ c_i >= 0`: its
    /// density may grow back up to `rho_0` but not beyond, and it never pulls (a
    /// free-surface particle is free to leave, the fluid does not contract into a blob).
    #[default]
    OneSided,
    /// Every row unilateral (`g_i >= 0` everywhere): pressure is never negative, the fluid
    /// never holds tension, even while compressed (a purely repulsive constraint, the
    /// position-based-fluids view with clamped pressure).
    Unilateral,
    /// Every row bilateral with `C_i` clamped at 0 (`b_i = -max(C_i, 0) / h`). The deficit
    /// is not pulled back, but the row still holds the density *rate* at zero, so a
    /// free-surface particle cannot separate from its neighbours (it resists tearing
    /// apart, a spurious tension). Kept for comparison with Chrono's bilateral rows.
    Clamped,
}

impl SurfaceMode {
    /// Parses `one_sided`, `unilateral` or `clamped`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "one_sided" => Ok(Self::OneSided),
            "unilateral" => Ok(Self::Unilateral),
            "clamped" => Ok(Self::Clamped),
            other => Err(ChronoError::invalid(
                "surface",
                other,
                "must be `one_sided`, `unilateral` or `clamped`",
            )),
        }
    }
}

/// The compliance of a density row, `eps = kappa rho_0 / (h^2 m)`, for a compressibility
/// `kappa = 1 / K` (1/Pa), rest density `rho_0` (kg/m^3), step `h` (s) and the particles'
/// inertial mass `m` (kg): at rest the row then holds `C_i = kappa p_i m_k / m`, the
/// material behaves as one of bulk modulus `K` (Mazhar 2016, the compliant density row).
pub fn compliance(kappa: f64, rho_0: f64, h: f64, m: f64) -> f64 {
    kappa * rho_0 / (h * h * m)
}

/// Pushes one density row with entries `entries` into `rows`: constraint value `c`
/// (`rho / rho_0 - phi`), step `h` (s), compliance `eps`, the known part `known` of
/// `D' v` (markers of fixed or kinematic bodies, 1/s), the surface treatment `surface`
/// and the largest stabilization rate `max_rate` (1/s) of a compressed particle:
///
/// ```text
/// b = known - min(c / h, max_rate)      (OneSided with c < 0: b = known - c / h, unilateral)
/// ```
///
/// `Clamped` uses `max(c, 0)`. Returns the row's id.
#[allow(clippy::too_many_arguments)]
pub fn push_density_row(
    rows: &mut ConstraintRows,
    entries: &[RowEntry],
    c: f64,
    h: f64,
    eps: f64,
    known: f64,
    surface: SurfaceMode,
    max_rate: f64,
) -> RowId {
    match surface {
        SurfaceMode::OneSided if c < 0.0 => rows.push_unilateral(entries, known - c / h, eps),
        SurfaceMode::OneSided => rows.push_bilateral(entries, known - (c / h).min(max_rate), eps),
        SurfaceMode::Unilateral => {
            rows.push_unilateral(entries, known - (c / h).min(max_rate), eps)
        }
        SurfaceMode::Clamped => {
            rows.push_bilateral(entries, known - (c.max(0.0) / h).min(max_rate), eps)
        }
    }
}
