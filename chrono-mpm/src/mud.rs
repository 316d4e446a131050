//! The mud bench's scene (issue 25): a bed of the seed's mud at rest in a box under
//! gravity, by the split (the pressure as density rows on the markers, the shear by MPM
//! with snow-like plasticity), in 3-D.
//!
//! The seed's parameters ("Vehicle on Mud: Constraint Fluids", Chrono multi-physics
//! slides; [`MudSpec::seed`]): marker mass `m = 0.023 kg`, density `rho = 1200 kg/m^3`,
//! kernel radius `h = 0.032 m`, `E = 7e5 Pa`, `nu = 0.2`, `theta_c = theta_s = 2.5e-2`,
//! `dt = 1e-3 s`; 1 426 663 markers. The marker spacing follows from the mass,
//! `dp = (m / rho)^(1/3) = 0.0268 m`, so `h / dp = 1.19`, taken here as the rows' smoothing
//! length over spacing (`h_over_dp = 1.2`, the rows' default: support `2.4 dp`). The seed
//! names no hardening coefficient: `xi = 10`, Stomakhin et al. 2013's
//! ([`SnowHardening::seed_mud`]). The mud is incompressible in the rows (compliance 0:
//! the seed's constraint fluid; its density error is the solver's, not an elastic one).
//!
//! The box: `2 ppc` markers per grid cell and axis (`dx = ppc dp`), the bed `cz` cells
//! deep and `aspect cz` cells wide in `x` and `y`, filling the box's floor; the grid's
//! walls are frictionless separating walls (slip in contact) on the floor and the four
//! sides, open above; the rows have fixed wall markers (the lattice's layers beyond the
//! floor and the sides up to the grid's top, [`wall_layers`]). The number of markers
//! `n = (ppc cx)(ppc cy)(ppc cz)` is the requested one rounded to whole cells. With
//! `block_fraction < 1` the mud fills only `x < block_fraction L` and slumps.
//!
//! At rest the bed's vertical stress balances its weight: with frictionless side walls
//! and a free top, `int sigma_zz dV = -rho g int z dV = -M g H / 2` for a bed of depth
//! `H` and mass `M` (the `z`-moment of `div sigma = rho g e_z`;
//! [`MudBed::mean_vertical_stress`]).

use chrono_core::particles::lattice::{Fit, Lattice, Tank, wall_layers};
use nalgebra::{Matrix3, Vector3};

use crate::body::{MpmBody, MpmSettings};
use crate::error::{Result, invalid, positive};
use crate::grid::{GridSpec, Wall};
use crate::material::{FixedCorotated, Material, SnowHardening};
use crate::pressure::{PressureSettings, RowsNorm, StrainFrom};

/// Empty grid cells above the bed (room for the surface's motion).
const ROOM_CELLS: usize = 2;

/// Parameters of the mud bed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MudSpec {
    /// Requested number of markers `n` (rounded to whole cells; at least a bed 2 cells
    /// deep).
    pub markers: usize,
    /// Marker mass `m`, kg (the seed's 0.023).
    pub marker_mass: f64,
    /// Density `rho`, kg/m^3 (the seed's 1200); the spacing is `(m / rho)^(1/3)`.
    pub density: f64,
    /// Young's modulus `E`, Pa (the seed's 7e5).
    pub young: f64,
    /// Poisson's ratio `nu` (the seed's 0.2).
    pub poisson: f64,
    /// Snow plasticity (the seed's `theta_c = theta_s = 2.5e-2`, `xi = 10`).
    pub snow: SnowHardening,
    /// The rows' smoothing length over the marker spacing (the seed's `h / dp = 1.19`).
    pub h_over_dp: f64,
    /// Markers per grid cell and axis (`dx = ppc dp`), >= 1.
    pub markers_per_cell: usize,
    /// The bed's width over its depth, in `x` and `y` (> 0).
    pub aspect: f64,
    /// The mud's extent in `x` over the box's, in (0, 1] (1: a bed filling the floor; less:
    /// a block against the wall `x = 0` that slumps).
    pub block_fraction: f64,
    /// Gravity `g`, m/s^2 (along `-z`).
    pub gravity: f64,
    /// The rows' compressibility `kappa`, 1/Pa (0: incompressible, the seed's).
    pub compressibility: f64,
    /// The rows' solver tolerance, 1/s, read by `tolerance_norm`.
    pub tolerance: f64,
    /// The norm of the tolerance (the seed's: [`RowsNorm::L2`], Chrono's).
    pub tolerance_norm: RowsNorm,
    /// APGD's iteration limit per step.
    pub max_iterations: usize,
    /// The markers' volume ratio `J` from the rows' density
    /// ([`PressureSettings::volume_from_rows`]; off in [`MudSpec::seed`]: without it `J`
    /// drifts next to the walls, with it the rows' pressure grows faster, `docs/mpm.md`).
    pub volume_from_rows: bool,
    /// The velocity field whose gradient updates `F_E` ([`StrainFrom`]; the seed's
    /// [`StrainFrom::FinalGrid`], as Chrono::Multicore's MPM).
    pub strain_from: StrainFrom,
}

impl MudSpec {
    /// The seed's mud with `markers` markers; tolerance 1e-1 in Chrono's norm, up to
    /// 1000 iterations (the seed's bilateral count).
    pub fn seed(markers: usize) -> Self {
        Self {
            markers,
            marker_mass: 0.023,
            density: 1200.0,
            young: 7e5,
            poisson: 0.2,
            snow: SnowHardening::seed_mud(),
            h_over_dp: 1.2,
            markers_per_cell: 2,
            aspect: 2.0,
            block_fraction: 1.0,
            gravity: 9.81,
            compressibility: 0.0,
            tolerance: 0.1,
            tolerance_norm: RowsNorm::L2,
            max_iterations: 1000,
            volume_from_rows: false,
            strain_from: StrainFrom::FinalGrid,
        }
    }

    /// The marker spacing `dp = (m / rho)^(1/3)`, m.
    pub fn spacing(&self) -> f64 {
        (self.marker_mass / self.density).cbrt()
    }

    /// The bed's cells `[cx, cy, cz]` for the requested marker count, or an error naming
    /// the field.
    pub fn cells(&self) -> Result<[usize; 3]> {
        positive("mud.marker_mass", self.marker_mass)?;
        positive("mud.density", self.density)?;
        positive("mud.aspect", self.aspect)?;
        if self.markers_per_cell == 0 || self.markers_per_cell > 8 {
            return Err(invalid(
                "mud.markers_per_cell",
                self.markers_per_cell,
                "must lie in [1, 8]",
            ));
        }
        let ppc3 = (self.markers_per_cell as f64).powi(3);
        let depth = (self.markers as f64 / (ppc3 * self.aspect * self.aspect)).cbrt();
        let cz = depth.round() as usize;
        let cx = (self.aspect * cz as f64).round() as usize;
        if cz < 2 || cx < 2 {
            let least = 8.0 * ppc3 * (self.aspect * self.aspect).max(1.0 / self.aspect);
            return Err(invalid(
                "mud.markers",
                self.markers,
                &format!(
                    "too few for a bed at least 2 cells deep and wide at markers_per_cell = {} \
                     and aspect = {} (about {least:.0} or more)",
                    self.markers_per_cell, self.aspect
                ),
            ));
        }
        Ok([cx, cx, cz])
    }

    /// Checks every field; the error names it.
    pub fn validate(&self) -> Result<()> {
        self.cells()?;
        if !(self.block_fraction.is_finite()
            && self.block_fraction > 0.0
            && self.block_fraction <= 1.0)
        {
            return Err(invalid(
                "mud.block_fraction",
                self.block_fraction,
                "must lie in (0, 1]",
            ));
        }
        positive("mud.gravity", self.gravity)?;
        SnowHardening::new(self.snow.theta_c, self.snow.theta_s, self.snow.xi)?;
        Ok(())
    }
}

/// The mud bed: the MPM body in the split mode and its geometry.
#[derive(Clone, Debug)]
pub struct MudBed {
    spec: MudSpec,
    /// The MPM body (markers, grid, the split's rows).
    pub body: MpmBody,
    spacing: f64,
    depth: f64,
}

impl MudBed {
    /// The bed of `spec` at rest on its lattice (see the module documentation). Errors name
    /// the field.
    pub fn new(spec: MudSpec) -> Result<Self> {
        spec.validate()?;
        let [cx, cy, cz] = spec.cells()?;
        let dp = spec.spacing();
        let dx = spec.markers_per_cell as f64 * dp;
        let material =
            Material::Corotated(FixedCorotated::snow(spec.young, spec.poisson, spec.snow)?);
        let grid = GridSpec::new([0.0; 3], [cx, cy, cz + ROOM_CELLS], dx)?
            .with_walls(0, Wall::Separating, Wall::Separating)
            .with_walls(1, Wall::Separating, Wall::Separating)
            .with_walls(2, Wall::Separating, Wall::Open);
        let settings = MpmSettings {
            gravity: [0.0, 0.0, -spec.gravity],
            ..MpmSettings::default()
        };
        let mut body = MpmBody::new(grid, material, settings)?;
        let (lx, ly) = (cx as f64 * dx, cy as f64 * dx);
        let depth = cz as f64 * dx;
        // whole marker columns in x for the block
        let nx_block =
            ((spec.block_fraction * (cx * spec.markers_per_cell) as f64).round() as usize).max(1);
        body.markers.fill_box(
            Vector3::zeros(),
            Vector3::new(nx_block as f64 * dp, ly, depth),
            dp,
            spec.density,
            |_| Vector3::zeros(),
        )?;
        let rows = PressureSettings {
            rest_density: spec.density,
            spacing: dp,
            h_over_dp: spec.h_over_dp,
            dim: 3,
            compressibility: spec.compressibility,
            tolerance: spec.tolerance,
            tolerance_norm: spec.tolerance_norm,
            max_iterations: spec.max_iterations,
            volume_from_rows: spec.volume_from_rows,
            strain_from: spec.strain_from,
            ..PressureSettings::default()
        };
        rows.validate()?;
        let top = (cz + ROOM_CELLS) as f64 * dx;
        let tank = Tank::new(
            [0.0; 3],
            [lx, ly, top],
            wall_layers(rows.h_over_dp),
            [true, true, true, true, true, false],
        );
        let walls: Vec<[f64; 3]> = Lattice::new([0.0; 3], dp)?
            .tank(&tank, Fit::Nearest)?
            .into_iter()
            .map(|w| w.position)
            .collect();
        body.set_pressure_rows(rows, &walls)?;
        Ok(Self {
            spec,
            body,
            spacing: dp,
            depth,
        })
    }

    /// The parameters.
    pub fn spec(&self) -> &MudSpec {
        &self.spec
    }

    /// The marker spacing `dp`, m.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The initial depth of the mud `H`, m.
    pub fn depth(&self) -> f64 {
        self.depth
    }

    /// The wall markers of the rows.
    pub fn wall_markers(&self) -> usize {
        self.body
            .pressure_rows()
            .map_or(0, |r| r.wall_marker_count())
    }

    /// One step of `dt` seconds (the seed's 1e-3).
    pub fn step(&mut self, dt: f64) -> Result<()> {
        self.body.step(dt)
    }

    /// The rows' density error at the last step's start (the end of the step before):
    /// the worst marker's compression `100 max_p (rho_p / rho_0 - 1)` and the markers' mean
    /// compression `100 mean_p max(rho_p / rho_0 - 1, 0)`, %, from the SPH sums (the
    /// free surface's deficit is no error); the seed's "density error" is the first
    /// (`docs/validation-cfluid.md`).
    pub fn compression_pct(&self) -> (f64, f64) {
        let Some(rows) = self.body.pressure_rows() else {
            return (0.0, 0.0);
        };
        let r0 = self.spec.density;
        let rho = rows.density();
        if rho.is_empty() {
            return (0.0, 0.0);
        }
        let (mut max, mut sum) = (0.0f64, 0.0);
        for r in rho {
            let c = (r / r0 - 1.0).max(0.0);
            max = max.max(c);
            sum += c;
        }
        (100.0 * max, 100.0 * sum / rho.len() as f64)
    }

    /// The markers' volume-weighted mean vertical Cauchy stress `sigma_zz`, Pa (negative in
    /// compression): the rows' pressure (the last step's) plus MPM's deviatoric stress,
    /// `sigma = (dev tau) / J - p 1`. At rest it is `-rho g H / 2` (module documentation).
    pub fn mean_vertical_stress(&self) -> f64 {
        let mk = &self.body.markers;
        let mat = self.body.material();
        let p = self.body.pressure_rows().map(|r| r.pressure());
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..mk.len() {
            let j = mk.fe[k].determinant() * mk.fp[k].determinant();
            let tau = mat.kirchhoff(&mk.fe[k], &mk.fp[k]);
            let dev = tau - Matrix3::identity() * (tau.trace() / 3.0);
            let pk = p.and_then(|p| p.get(k)).copied().unwrap_or(0.0);
            let v = mk.volume0[k] * j;
            num += v * (dev[(2, 2)] / j - pk);
            den += v;
        }
        num / den
    }
}
