//! Solver settings: resolution, fluid properties, boundary handling, time step criteria.

use chrono_core::particles::KernelKind;
use serde::{Deserialize, Serialize};

use crate::error::{Result, SphError, finite3, non_negative, positive};

/// What to do when the Mach number `|v|_max / c_s` exceeds [`SphSettings::mach_limit`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MachPolicy {
    /// Log a warning (once) and count the steps in
    /// [`SphStats::mach_warnings`](crate::SphStats::mach_warnings).
    #[default]
    Warn,
    /// Stop with [`SphError::MachExceeded`].
    Error,
}

/// Settings of an [`SphSystem`](crate::SphSystem). SI units throughout.
///
/// Defaults: water (`rho_0 = 1000`, `mu = 1e-3`), Wendland C2 with `h = 1.3 dp`, Tait
/// `gamma = 7`, XSPH `zeta = 0.5`, Shepard re-initialization every 30 steps, re-sort by
/// cell every 10 steps, Verlet skin 10 % of the support, CFL 0.2, force criterion 0.25, viscous criterion 0.125, gravity
/// `(0, 0, -9.81)`. `spacing`, `sound_speed` and the domain must be set by the caller.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SphSettings {
    /// Initial particle spacing `dp`, m.
    pub spacing: f64,
    /// Smoothing length over spacing, `h / dp` (support `2 h`).
    pub h_over_dp: f64,
    /// Smoothing kernel.
    pub kernel: KernelKind,
    /// Reference density `rho_0`, kg/m^3.
    pub rho0: f64,
    /// Tait exponent `gamma`.
    pub gamma: f64,
    /// Artificial sound speed `c_s`, m/s (see [`sound_speed_for`](crate::sound_speed_for)).
    pub sound_speed: f64,
    /// Dynamic viscosity `mu`, Pa s (Morris term).
    pub viscosity: f64,
    /// Monaghan artificial viscosity `alpha` (0 = off; 0.01 to 0.05 damps the acoustic
    /// noise of violent flows).
    pub artificial_viscosity: f64,
    /// XSPH coefficient `zeta` (0 = off).
    pub xsph: f64,
    /// Shepard density re-initialization every this many steps (0 = never).
    pub shepard_every: u32,
    /// Re-sort particle arrays by cell at a neighbour-list rebuild when at least this
    /// many steps passed since the last re-sort (0 = never).
    pub reorder_every: u32,
    /// Verlet skin as a fraction of the kernel support: lists hold the pairs within
    /// `2 h (1 + skin)` and are rebuilt only when some particle moved more than half the
    /// skin since the last build (0 = rebuild every step).
    pub skin: f64,
    /// Courant number of `dt <= C h / (c_s + |v|_max)`.
    pub cfl: f64,
    /// Coefficient of the force criterion `dt <= C sqrt(h / |a|_max)`.
    pub force_coef: f64,
    /// Coefficient of the viscous criterion `dt <= C h^2 rho_0 / mu`.
    pub visc_coef: f64,
    /// Upper bound of the time step, s.
    pub max_dt: f64,
    /// Gravity, m/s^2.
    pub gravity: [f64; 3],
    /// Extra body force per unit mass on the fluid, m/s^2 (e.g. a driving pressure
    /// gradient in a periodic channel).
    pub body_force: [f64; 3],
    /// Lower corner of the domain, m (the grid box; periodic axes use it as the period).
    pub domain_lower: [f64; 3],
    /// Upper corner of the domain, m.
    pub domain_upper: [f64; 3],
    /// Periodic axes.
    pub periodic: [bool; 3],
    /// Clamp the extrapolated wall pressure at 0 so walls never pull the fluid (no
    /// sticking to walls under tension).
    pub clamp_wall_pressure: bool,
    /// Velocity damping rate `k` (1/s) of the fluid, `dv/dt += -k v`: 0 for physics;
    /// positive only for an initial relaxation phase that settles a lattice start
    /// (see [`SphSystem::set_damping`](crate::SphSystem::set_damping)).
    pub damping: f64,
    /// The Mach number limit (0.1).
    pub mach_limit: f64,
    /// What to do above it.
    pub mach_policy: MachPolicy,
}

impl Default for SphSettings {
    fn default() -> Self {
        Self {
            spacing: 0.01,
            h_over_dp: 1.3,
            kernel: KernelKind::WendlandC2,
            rho0: 1000.0,
            gamma: 7.0,
            sound_speed: 20.0,
            viscosity: 1e-3,
            artificial_viscosity: 0.0,
            xsph: 0.5,
            shepard_every: 30,
            reorder_every: 10,
            skin: 0.1,
            cfl: 0.2,
            force_coef: 0.25,
            visc_coef: 0.125,
            max_dt: 1e-2,
            gravity: [0.0, 0.0, -9.81],
            body_force: [0.0; 3],
            domain_lower: [0.0; 3],
            domain_upper: [1.0; 3],
            periodic: [false; 3],
            clamp_wall_pressure: true,
            damping: 0.0,
            mach_limit: 0.1,
            mach_policy: MachPolicy::Warn,
        }
    }
}

impl SphSettings {
    /// The smoothing length `h = h_over_dp * spacing`, m.
    pub fn h(&self) -> f64 {
        self.h_over_dp * self.spacing
    }

    /// Checks every field; the error names the first bad one.
    pub fn validate(&self) -> Result<()> {
        positive("settings.spacing", self.spacing)?;
        positive("settings.h_over_dp", self.h_over_dp)?;
        if !(0.5..=3.0).contains(&self.h_over_dp) {
            return Err(SphError::invalid(
                "settings.h_over_dp",
                self.h_over_dp,
                "must be in [0.5, 3]",
            ));
        }
        positive("settings.rho0", self.rho0)?;
        positive("settings.gamma", self.gamma)?;
        positive("settings.sound_speed", self.sound_speed)?;
        non_negative("settings.viscosity", self.viscosity)?;
        non_negative("settings.artificial_viscosity", self.artificial_viscosity)?;
        non_negative("settings.xsph", self.xsph)?;
        if self.xsph > 1.0 {
            return Err(SphError::invalid(
                "settings.xsph",
                self.xsph,
                "must be in [0, 1]",
            ));
        }
        non_negative("settings.skin", self.skin)?;
        if self.skin > 1.0 {
            return Err(SphError::invalid(
                "settings.skin",
                self.skin,
                "must be in [0, 1]",
            ));
        }
        positive("settings.cfl", self.cfl)?;
        positive("settings.force_coef", self.force_coef)?;
        positive("settings.visc_coef", self.visc_coef)?;
        positive("settings.max_dt", self.max_dt)?;
        positive("settings.mach_limit", self.mach_limit)?;
        non_negative("settings.damping", self.damping)?;
        finite3("settings.gravity", self.gravity)?;
        finite3("settings.body_force", self.body_force)?;
        finite3("settings.domain_lower", self.domain_lower)?;
        finite3("settings.domain_upper", self.domain_upper)?;
        for a in 0..3 {
            if self.domain_upper[a] <= self.domain_lower[a] {
                return Err(SphError::invalid(
                    format!("settings.domain_upper[{a}]"),
                    self.domain_upper[a],
                    format!("must exceed domain_lower[{a}] = {}", self.domain_lower[a]),
                ));
            }
            let len = self.domain_upper[a] - self.domain_lower[a];
            if self.periodic[a] && len < 4.0 * self.h() * (1.0 + self.skin) - 1e-12 * len {
                return Err(SphError::invalid(
                    format!("settings.periodic[{a}] (period)"),
                    len,
                    format!(
                        "the period must be at least twice the list radius, 4 h (1 + skin) = {}",
                        4.0 * self.h() * (1.0 + self.skin)
                    ),
                ));
            }
        }
        Ok(())
    }
}
