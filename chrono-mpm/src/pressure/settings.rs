//! The settings of the split's pressure rows ([`super::PressureRows`]) and the norm of
//! their solver tolerance.

use crate::error::{Result, invalid, positive};

/// The norm over the rows in which [`PressureSettings::tolerance`] is read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RowsNorm {
    /// The root mean square of the rows' projected residual (chrono-ccp's common residual).
    #[default]
    Rms,
    /// The Euclidean norm over all rows (Chrono::Multicore's APGD, `ChSolverMulticoreAPGD`:
    /// the seed's tolerances), `sqrt(n)` times the RMS for `n` rows.
    L2,
}

/// Which velocity field updates the markers' `F_E` in the split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StrainFrom {
    /// The markers' final velocities (after the rows) rasterized to the grid by mass
    /// (PIC), under the wall conditions, and their B-spline gradient: `F_E` moves only if
    /// the markers do, so a bed at rest keeps its stress (Chrono::Multicore's MPM also
    /// updates `F_E` from the rasterized marker velocities, our reference notes sec. 5).
    #[default]
    FinalGrid,
    /// The grid's velocity before the rows plus the SPH gradient of the rows' velocity
    /// change ([`PressureRows::add_velocity_gradient`](super::PressureRows::add_velocity_gradient)):
    /// the two gradients are different discretizations and do not cancel next to a wall,
    /// so a bed at rest strains by `~ g dt^2 / dx` per step without moving (the growing
    /// mode of `docs/mpm.md`, "The mud bench"). Kept for comparison.
    GridPlusRows,
}

/// Settings of the split's pressure rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PressureSettings {
    /// Rest density `rho_0` of the markers, kg/m^3 (every marker's `mass / volume0`).
    pub rest_density: f64,
    /// Spacing `dp` of the markers' initial lattice, m (`dx / 2` for 2 markers per cell).
    pub spacing: f64,
    /// Smoothing length over spacing, `h_k / dp` (kernel support `2 h_k`; Wendland C2).
    pub h_over_dp: f64,
    /// Kernel dimension: 3, or 2 for a plane-strain slab one marker layer thick (the sums
    /// in the slab's plane).
    pub dim: u32,
    /// Compressibility `kappa = 1 / K`, 1/Pa (`>= 0`): the rows' compliance, the bulk
    /// modulus of the material (`K = lambda + 2 mu / 3` reproduces plain MPM's volumetric
    /// elasticity to first order); 0 is incompressible.
    pub compressibility: f64,
    /// Largest stabilization rate `C / dt` of a compressed marker, 1/s (`> 0`).
    pub max_recovery_rate: f64,
    /// APGD's tolerance on the rows' velocity residual, 1/s (`> 0`; the rows' constraint
    /// velocity `D' v` is a rate of relative density), read by `tolerance_norm`.
    pub tolerance: f64,
    /// How `tolerance` is read: chrono-ccp's RMS over the rows (the default) or
    /// Chrono::Multicore's Euclidean norm over all rows (the seed's tolerances,
    /// `docs/validation-cfluid.md`), for which the solver is given `tolerance / sqrt(n)`
    /// with `n` the step's rows.
    pub tolerance_norm: RowsNorm,
    /// APGD's iteration limit per step (`>= 1`).
    pub max_iterations: usize,
    /// The last step's impulses times this factor start the solver, in `[0, 1]`.
    pub warm_start_factor: f64,
    /// Set each marker's total volume ratio `J = det(F_E F_P)` to the rows' `rho_0 / rho_p`
    /// every step ([`PressureRows::match_volume`](super::PressureRows::match_volume)): the volume is the rows', and the
    /// trace of `dF` (the grid's velocity gradient plus the rows' SPH share) does not
    /// follow it next to walls in 3-D (a bed at rest: `J` 0.89 after 0.32 s in a corner
    /// while the rows hold the density to 1e-5, and a hardening material stiffens from
    /// it). Off by default (the existing cases' behaviour).
    pub volume_from_rows: bool,
    /// The velocity field whose gradient updates `F_E` ([`StrainFrom`]).
    pub strain_from: StrainFrom,
    /// Hold each marker's row at the reference of its truncated kernel support,
    /// `C_p = rho_p / rho_0 - phi_p`, with `phi_p` the support fraction of
    /// [`chrono_core::density_rows::SupportModel`] (the planar-surface model of the
    /// marker lattice, read from the first moment of the neighbourhood; chrono-cfluid's
    /// `surface_reference`), instead of `phi_p = 1`: a surface marker at the lattice
    /// spacing is then at `C = 0` and its row carries the pressure of its own
    /// compression, where with `phi_p = 1` it is slack (`p = 0`) until its truncated sum
    /// reaches `rho_0`. A row with `phi_p < 1` is unilateral (pushes, never pulls).
    /// Off by default (`docs/mpm.md`, "The split's surface layers").
    pub surface_reference: bool,
}

impl Default for PressureSettings {
    fn default() -> Self {
        Self {
            rest_density: 1000.0,
            spacing: 0.05,
            h_over_dp: 1.2,
            dim: 3,
            compressibility: 0.0,
            max_recovery_rate: 1e3,
            tolerance: 1e-6,
            tolerance_norm: RowsNorm::Rms,
            max_iterations: 500,
            warm_start_factor: 1.0,
            volume_from_rows: false,
            strain_from: StrainFrom::FinalGrid,
            surface_reference: false,
        }
    }
}

impl PressureSettings {
    /// Plane-strain rows (`dim` 2) for a soil of density `density` (kg/m^3) whose bulk
    /// modulus `K = E / (3 (1 - 2 nu))` (Pa; `young`, `poisson`) is the rows' compliance
    /// `kappa = 1 / K`, so the rows carry the volumetric elasticity plain MPM would; the
    /// marker spacing `spacing` (m) and APGD's `tolerance` (m/s), the rest the defaults.
    pub fn plane_strain_soil(
        density: f64,
        young: f64,
        poisson: f64,
        spacing: f64,
        tolerance: f64,
    ) -> Self {
        let bulk = young / (3.0 * (1.0 - 2.0 * poisson));
        Self {
            rest_density: density,
            spacing,
            dim: 2,
            compressibility: 1.0 / bulk,
            tolerance,
            ..Self::default()
        }
    }

    /// Checks every field; the error names it.
    pub fn validate(&self) -> Result<()> {
        positive("pressure.rest_density", self.rest_density)?;
        positive("pressure.spacing", self.spacing)?;
        positive("pressure.h_over_dp", self.h_over_dp)?;
        if !(0.8..=3.0).contains(&self.h_over_dp) {
            return Err(invalid(
                "pressure.h_over_dp",
                self.h_over_dp,
                "must be in [0.8, 3]",
            ));
        }
        if !(self.dim == 2 || self.dim == 3) {
            return Err(invalid("pressure.dim", self.dim, "must be 2 or 3"));
        }
        if !(self.compressibility.is_finite() && self.compressibility >= 0.0) {
            return Err(invalid(
                "pressure.compressibility",
                self.compressibility,
                "must be finite and >= 0",
            ));
        }
        positive("pressure.max_recovery_rate", self.max_recovery_rate)?;
        positive("pressure.tolerance", self.tolerance)?;
        if self.max_iterations == 0 {
            return Err(invalid("pressure.max_iterations", 0, "must be >= 1"));
        }
        if !(0.0..=1.0).contains(&self.warm_start_factor) {
            return Err(invalid(
                "pressure.warm_start_factor",
                self.warm_start_factor,
                "must be in [0, 1]",
            ));
        }
        Ok(())
    }
}
