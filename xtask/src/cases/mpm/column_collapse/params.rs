//! The parameters of `mpm-column-collapse` and the recorded DEM material's shear-box angles
//! (the case itself: the parent module).

use serde::{Deserialize, Serialize};

use crate::case::Mode;
use crate::params::{CaseParams, ParamInfo};

/// Parameters of `mpm-column-collapse`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ColumnParams {
    /// Aspect ratio `H0/L0` of the main run (its metrics are `runout_ratio` and
    /// `final_height_ratio`).
    pub aspect_ratio: f64,
    /// The aspect ratios of the slope runs (the main one is added).
    pub sweep: Vec<f64>,
    /// Friction angle of the sand, degrees.
    pub friction_angle_deg: f64,
    /// The floor's Coulomb friction angle, degrees; < 0: the sand's (a rough bed).
    pub floor_friction_angle_deg: f64,
    /// The associated (dilatant) flow rule instead of the non-dilatant one.
    pub associated_flow: bool,
    /// `mpm`, or `nsc`: the column by granular DEM (NSC, `chrono_core::granular::column`)
    /// with the MPM column at the shear-box angle of the DEM material beside it.
    pub method: String,
    /// Column length `L0`, m.
    pub column_length: f64,
    /// Grid cells across the smaller of `L0` and `H0`.
    pub cells: usize,
    /// Markers per cell per axis.
    pub markers_per_cell: usize,
    /// Young's modulus of the sand, Pa.
    pub young: f64,
    /// Poisson's ratio of the sand.
    pub poisson: f64,
    /// Bulk density of the sand, kg/m^3.
    pub density: f64,
    /// Gravity, m/s^2.
    pub gravity: f64,
    /// CFL number.
    pub cfl: f64,
    /// Rest: kinetic energy below this fraction of `M g H0`.
    pub rest_kinetic: f64,
    /// Rest: for this long, in `sqrt(H0/g)`.
    pub rest_window: f64,
    /// Longest run, in `sqrt(H0/g)`.
    pub max_time: f64,
    /// Tolerance of the small-`a` slope (about 1).
    pub slope_small_tolerance: f64,
    /// Tolerance of the large-`a` slope (about 2/3).
    pub slope_large_tolerance: f64,
    /// Whether the slopes and the envelope are checked (else reported).
    pub check: bool,
    /// F-bar: off or increment (`chrono_mpm::fbar`).
    pub f_bar: String,
    /// The FLIP fraction of the marker velocity update (`MpmBody::set_flip`; 0: APIC).
    pub flip: f64,
    /// Grain diameter of the `mu(I)` friction, m (`chrono_mpm::MuI`, Jop et al. 2006's
    /// other constants); 0: rate-independent.
    pub grain_diameter: f64,
    /// Start from the geostatic state instead of stress-free.
    pub geostatic: bool,
    /// The pressure: `stress` (plain MPM) or `rows` (the split: deviatoric stress by MPM,
    /// pressure by density rows on the markers, `chrono_mpm::pressure`, the cone at the
    /// rows' pressure).
    pub pressure: String,
    /// APGD's tolerance on the rows' velocity residual with `pressure = rows`, m/s.
    pub rows_tolerance: f64,
    /// With `pressure = rows`: each marker's row held at its truncated support's
    /// reference (`chrono_mpm::PressureSettings::surface_reference`; `docs/mpm.md`,
    /// "The split's surface layers").
    pub rows_surface_reference: bool,
    /// The sand: `drucker_prager` (the cone of `friction_angle_deg`) or `critical_state`
    /// (`chrono_mpm::CriticalStateSand::glass_beads`: compressible `mu(I)` with
    /// critical-state dilatancy, its own published friction; `friction_angle_deg`,
    /// `associated_flow` and `grain_diameter` are then not used, and a floor of the
    /// sand's friction is its `mu_2`).
    pub rheology: String,
    /// DEM (`method = nsc`): largest grain diameters across `L0`.
    pub grains_across: f64,
    /// DEM: grain–grain (and glued-floor) sliding friction coefficient `mu_c`.
    pub contact_friction: f64,
    /// DEM: grain–grain rolling friction coefficient.
    pub rolling_friction: f64,
    /// DEM: slab width between the frictionless side walls, in grain diameters.
    pub slab_width: f64,
    /// DEM: smallest over largest grain radius.
    pub size_ratio: f64,
    /// DEM: grain density, kg/m^3.
    pub grain_density: f64,
    /// DEM: a glued layer of grains on the floor (else the flat floor of the grains'
    /// friction).
    pub rough_floor: bool,
    /// DEM: time step, s (0: 1 ms).
    pub dem_step: f64,
    /// DEM: APGD tolerance, m/s.
    pub dem_tolerance: f64,
    /// DEM: APGD iteration cap.
    pub dem_max_iterations: usize,
    /// DEM: the NSC contacts' largest penetration recovery speed, m/s.
    pub dem_recovery_speed: f64,
    /// DEM: APGD iteration cap while the column settles behind the gate (0:
    /// `dem_max_iterations`); 300: at 100 the 80-grain column of `a = 8` does not settle
    /// (docs/mpm.md, "The DEM side").
    pub dem_settle_iterations: usize,
    /// DEM: seed of the packing and the glued floor.
    pub dem_seed: u64,
    /// DEM: the aspect ratios (`null`: `sweep`; the main `aspect_ratio` is added).
    pub dem_sweep: Option<Vec<f64>>,
    /// The friction angle of the MPM sand beside the DEM column, degrees: the shear-box
    /// residual angle of the DEM material; < 0: the recorded one of the default material
    /// ([`SHEAR_BOX_RESIDUAL_DEG`], an error for another material).
    pub matched_friction_angle_deg: f64,
    /// With `method = nsc`: run the MPM column at the matched angle beside the DEM one.
    pub mpm_beside: bool,
}

/// The DEM material whose shear-box angles are recorded: contact friction 0.5, no rolling
/// friction.
pub const RECORDED_CONTACT_FRICTION: f64 = 0.5;

/// The residual (critical-state) angle of the recorded DEM material in the direct shear
/// box, degrees: mean of three packings (seeds 7, 8, 9) of `granular-shear` by NSC at
/// 3.1 kPa, 12 d box, `mu` 0.5 (docs/mpm.md, "The DEM side (`method = nsc`)").
pub const SHEAR_BOX_RESIDUAL_DEG: f64 = 25.94;

/// The peak angle of the same runs, degrees (reported).
pub const SHEAR_BOX_PEAK_DEG: f64 = 35.59;

impl Default for ColumnParams {
    fn default() -> Self {
        Self {
            aspect_ratio: 1.0,
            sweep: vec![0.5, 1.5, 4.0, 8.0],
            friction_angle_deg: 30.0,
            floor_friction_angle_deg: -1.0,
            associated_flow: false,
            method: "mpm".into(),
            column_length: 0.1,
            cells: 4,
            markers_per_cell: 2,
            young: 2e6,
            poisson: 0.3,
            density: 1500.0,
            gravity: 9.81,
            cfl: 0.4,
            rest_kinetic: 1e-4,
            rest_window: 1.0,
            max_time: 30.0,
            slope_small_tolerance: 0.15,
            slope_large_tolerance: 0.12,
            check: false,
            f_bar: "off".into(),
            flip: 0.99,
            grain_diameter: 0.0,
            geostatic: false,
            pressure: "stress".into(),
            rows_tolerance: 1e-6,
            rows_surface_reference: false,
            rheology: "drucker_prager".into(),
            grains_across: 10.0,
            contact_friction: RECORDED_CONTACT_FRICTION,
            rolling_friction: 0.0,
            slab_width: 3.0,
            size_ratio: 0.8,
            grain_density: 2500.0,
            rough_floor: true,
            dem_step: 1e-3,
            dem_tolerance: 1e-5,
            dem_max_iterations: 100,
            dem_recovery_speed: 0.05,
            dem_settle_iterations: 300,
            dem_seed: 1,
            dem_sweep: None,
            matched_friction_angle_deg: -1.0,
            mpm_beside: true,
        }
    }
}

impl CaseParams for ColumnParams {
    const INFO: &'static [ParamInfo] = &[
        ParamInfo::new(
            "aspect_ratio",
            "-",
            "H0/L0 of the main run (metrics runout_ratio, final_height_ratio)",
        ),
        ParamInfo::new(
            "sweep",
            "-",
            "aspect ratios of the slope runs, e.g. [0.5,1.5,4,8] (the main one is added)",
        ),
        ParamInfo::new("friction_angle_deg", "deg", "friction angle of the sand"),
        ParamInfo::new(
            "floor_friction_angle_deg",
            "deg",
            "Coulomb friction angle of the floor; < 0: the sand's (a rough bed)",
        ),
        ParamInfo::new(
            "associated_flow",
            "-",
            "the associated (dilatant) Drucker-Prager flow instead of the non-dilatant one",
        ),
        ParamInfo::new(
            "method",
            "-",
            "mpm, or nsc: the column by granular DEM (NSC) with the MPM column at the DEM material's shear-box angle beside it (metrics _dem, _mpm)",
        ),
        ParamInfo::new("column_length", "m", "column length L0 from the wall"),
        ParamInfo::new(
            "cells",
            "-",
            "grid cells across the smaller of L0 and H0 (the resolution)",
        ),
        ParamInfo::new("markers_per_cell", "-", "markers per cell per axis"),
        ParamInfo::new("young", "Pa", "Young's modulus of the sand"),
        ParamInfo::new("poisson", "-", "Poisson's ratio of the sand"),
        ParamInfo::new("density", "kg/m^3", "bulk density of the sand"),
        ParamInfo::new("gravity", "m/s^2", "gravity"),
        ParamInfo::new("cfl", "-", "CFL number of the time step"),
        ParamInfo::new(
            "rest_kinetic",
            "-",
            "at rest: kinetic energy below this fraction of M g H0",
        ),
        ParamInfo::new("rest_window", "sqrt(H0/g)", "at rest for this long"),
        ParamInfo::new("max_time", "sqrt(H0/g)", "the longest run"),
        ParamInfo::new(
            "slope_small_tolerance",
            "-",
            "tolerance of the log-log runout slope over a <= 1.5 (reference 1)",
        ),
        ParamInfo::new(
            "slope_large_tolerance",
            "-",
            "tolerance of the log-log runout slope over a >= 4 (reference 2/3)",
        ),
        ParamInfo::new(
            "check",
            "-",
            "check the slopes and the envelope (else report them)",
        ),
        ParamInfo::new("f_bar", "-", "F-bar: off or increment (chrono_mpm::fbar)"),
        ParamInfo::new(
            "flip",
            "-",
            "FLIP fraction of the marker velocity update (0: APIC, whose loss per step makes the runout depend on the step count)",
        ),
        ParamInfo::new(
            "grain_diameter",
            "m",
            "grain diameter of the mu(I) friction (Jop et al. 2006's delta_mu 0.26, I0 0.279, rho_s 2450); 0: rate-independent",
        ),
        ParamInfo::new(
            "geostatic",
            "-",
            "start from the geostatic (K0) state instead of stress-free",
        ),
        ParamInfo::new(
            "pressure",
            "-",
            "stress (plain MPM) or rows (the split: deviatoric stress by MPM, pressure by density rows on the markers, the Drucker-Prager cone at the rows' pressure; docs/mpm.md)",
        ),
        ParamInfo::new(
            "rows_tolerance",
            "1/s",
            "APGD's tolerance on the rows' velocity residual with pressure = rows",
        ),
        ParamInfo::new(
            "rows_surface_reference",
            "-",
            "with pressure = rows: hold each marker's row at its truncated kernel support's reference (the free surface; docs/mpm.md)",
        ),
        ParamInfo::new(
            "rheology",
            "-",
            "drucker_prager (the cone of friction_angle_deg) or critical_state (compressible mu(I) glass beads with critical-state dilatancy, published constants; docs/mpm.md)",
        ),
        ParamInfo::new(
            "grains_across",
            "-",
            "nsc: largest grain diameters across L0 (d = column_length / grains_across)",
        ),
        ParamInfo::new(
            "contact_friction",
            "-",
            "nsc: grain-grain and glued-floor sliding friction coefficient mu_c",
        ),
        ParamInfo::new(
            "rolling_friction",
            "-",
            "nsc: grain-grain rolling friction coefficient",
        ),
        ParamInfo::new(
            "slab_width",
            "d",
            "nsc: slab width between the frictionless side walls, in grain diameters",
        ),
        ParamInfo::new(
            "size_ratio",
            "-",
            "nsc: smallest over largest grain radius (radii uniform between)",
        ),
        ParamInfo::new("grain_density", "kg/m^3", "nsc: grain density"),
        ParamInfo::new(
            "rough_floor",
            "-",
            "nsc: a glued layer of grains on the floor (else the flat floor of the grains' friction)",
        ),
        ParamInfo::new("dem_step", "s", "nsc: time step (0: 1 ms)"),
        ParamInfo::new("dem_tolerance", "m/s", "nsc: APGD tolerance"),
        ParamInfo::new("dem_max_iterations", "-", "nsc: APGD iteration cap"),
        ParamInfo::new(
            "dem_settle_iterations",
            "-",
            "nsc: APGD iteration cap while the column settles behind the gate (0: dem_max_iterations)",
        ),
        ParamInfo::new(
            "dem_recovery_speed",
            "m/s",
            "nsc: largest penetration recovery speed of the contacts (SystemSettings::max_recovery_speed)",
        ),
        ParamInfo::new(
            "dem_seed",
            "-",
            "nsc: seed of the packing and the glued floor",
        ),
        ParamInfo::new(
            "dem_sweep",
            "-",
            "nsc: aspect ratios of the DEM runs (null: sweep; the main one is added)",
        ),
        ParamInfo::new(
            "matched_friction_angle_deg",
            "deg",
            "nsc: friction angle of the MPM sand beside the DEM column, the DEM material's shear-box residual angle; < 0: the recorded one of contact_friction 0.5, rolling 0 (an error for another material)",
        ),
        ParamInfo::new(
            "mpm_beside",
            "-",
            "nsc: run the MPM column at the matched angle beside the DEM one",
        ),
    ];

    fn apply_mode(&mut self, mode: Mode) {
        match mode {
            Mode::Quick => {
                self.sweep = vec![0.5, 1.5, 4.0, 6.0];
                self.dem_sweep = Some(vec![1.0, 2.0]);
                self.grains_across = 6.0;
            }
            Mode::Default => {}
            Mode::Full => {
                self.cells = 8;
                self.sweep = vec![0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0];
            }
        }
    }
}
