//! A granular column released against a wall collapses and spreads on a rough floor, in
//! a slab (plane strain): the experiments of Lube, Huppert, Sparks & Freundt (Phys. Rev.
//! E 72, 041301, 2005) and Lajeunesse, Monnier & Homsy (Phys. Fluids 17, 103302, 2005)
//! in a channel, whose deposit depends on the aspect ratio `a = H0 / L0` alone.
//!
//! The scene: a rectangle of cohesionless Drucker–Prager sand, `L0` long from the wall
//! `x = 0` and `H0 = a L0` high, at rest and stress-free at `t = 0` (the gate is removed
//! at once), under gravity `-g z`. The wall `x = 0` is a slip wall (the channel's smooth
//! back wall, or equally the symmetry plane of a column `2 L0` wide); the floor `z = 0`
//! is sticky (a rough bed: sliding over it shears the sand itself, so the basal friction
//! is the internal one, as on the beds of glued grains of the experiments); the slab is
//! one cell thick in `y` between slip walls, one layer of markers (plane strain); the
//! far end and the top are open, far enough away that no marker reaches them.
//!
//! The sand ([`DruckerPrager::plane_strain`] with zero cohesion): the cone matched to
//! Mohr–Coulomb of friction angle `phi` at this model's non-dilatant plane-strain flow,
//! Hencky elasticity, the apex return in tension (the grains separate). The same model as
//! the frictional footing (`crate::footing`).
//!
//! The run ends at rest: when the markers' kinetic energy stays below
//! `rest_kinetic M g H0` (a fraction of the column's initial potential energy scale) for
//! `rest_window sqrt(H0/g)`, after at least `sqrt(H0/g)` (the column starts at rest).
//! Measured: the runout `L_inf`, the farthest extent of a marker from the wall (its
//! position plus half the marker spacing), and the final height `H_inf`, the highest
//! extent of a marker.

use nalgebra::Vector3;

use crate::body::{MpmBody, MpmSettings};
use crate::error::{Result, invalid, positive};
use crate::fbar::FBar;
use crate::grid::{GridSpec, Wall};
use crate::material::{CriticalStateSand, DruckerPrager, Material, MuI};
use crate::pressure::{PressureSettings, slab_wall_markers};
use crate::rigid::{Contact, RigidBody};

/// Grid cells below the floor (the nodes a marker's stencil reaches there, and one more).
const FLOOR_CELLS: usize = 3;

/// Parameters of the column collapse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnSpec {
    /// Aspect ratio `a = H0 / L0`, -.
    pub aspect_ratio: f64,
    /// Column length `L0` from the wall, m.
    pub column_length: f64,
    /// Friction angle `phi` of the sand, degrees, in (0, 90).
    pub friction_angle_deg: f64,
    /// Cohesion of the sand, Pa (0: cohesionless).
    pub cohesion: f64,
    /// The associated (dilatant) flow rule ([`DruckerPrager::associated`]) instead of the
    /// non-dilatant one.
    pub associated_flow: bool,
    /// Young's modulus of the sand, Pa.
    pub young: f64,
    /// Poisson's ratio of the sand.
    pub poisson: f64,
    /// Bulk density of the sand, kg/m^3.
    pub density: f64,
    /// Gravity `g`, m/s^2 (acting along `-z`).
    pub gravity: f64,
    /// Grid cells across the column length `L0`.
    pub cells_length: usize,
    /// Markers per cell per axis in the plane (one layer across the slab).
    pub markers_per_cell: usize,
    /// The floor's Coulomb friction angle, degrees, in [0, 90); `None`: sticky (no slip
    /// at the floor's nodes).
    pub floor_friction_angle_deg: Option<f64>,
    /// CFL number of the time step.
    pub cfl: f64,
    /// The rest criterion: kinetic energy below this fraction of `M g H0`, -.
    pub rest_kinetic: f64,
    /// The rest criterion holds for this long, in `sqrt(H0/g)`.
    pub rest_window: f64,
    /// The longest run, in `sqrt(H0/g)` (the run that has not come to rest by then
    /// returns with [`ColumnResult::at_rest`] false).
    pub max_time: f64,
    /// F-bar volume averaging ([`crate::fbar`]).
    pub f_bar: FBar,
    /// The FLIP fraction of the velocity update ([`MpmBody::set_flip`]; 0: APIC).
    pub flip: f64,
    /// Start from the geostatic state (every marker at the stress of a laterally confined
    /// elastic column under its own weight, as [`crate::soil_bin`]) instead of stress-free.
    pub geostatic: bool,
    /// The rate-dependent friction of the sand ([`DruckerPrager::with_mu_i`]); `None`:
    /// rate-independent.
    pub mu_i: Option<MuI>,
    /// The sand is this compressible `mu(I)` sand with critical-state dilatancy (e.g.
    /// [`CriticalStateSand::glass_beads`]; its packing at the start `phi0` is replaced by
    /// `density` over its grain density) instead of the Drucker–Prager sand:
    /// `friction_angle_deg`, `cohesion`, `associated_flow` and `mu_i` are then not used.
    pub critical_state: Option<CriticalStateSand>,
}

impl Default for ColumnSpec {
    /// A laboratory column (`L0` = 0.1 m), sand of 30 degrees, 8 cells across `L0`.
    fn default() -> Self {
        Self {
            aspect_ratio: 2.0,
            column_length: 0.1,
            friction_angle_deg: 30.0,
            cohesion: 0.0,
            associated_flow: false,
            young: 2e6,
            poisson: 0.3,
            density: 1500.0,
            gravity: 9.81,
            cells_length: 8,
            markers_per_cell: 2,
            floor_friction_angle_deg: Some(30.0),
            cfl: 0.4,
            rest_kinetic: 1e-4,
            rest_window: 1.0,
            max_time: 30.0,
            f_bar: FBar::Off,
            flip: 0.0,
            geostatic: false,
            mu_i: None,
            critical_state: None,
        }
    }
}

/// One sample of the collapse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnSample {
    /// Time, s.
    pub t: f64,
    /// The front's distance from the wall, m.
    pub front: f64,
    /// The deposit's height, m.
    pub height: f64,
    /// Kinetic energy of the markers, J.
    pub kinetic: f64,
}

/// What a collapse run measured.
#[derive(Clone, Debug)]
pub struct ColumnResult {
    /// Final runout `L_inf` from the wall, m.
    pub runout: f64,
    /// Final height `H_inf`, m.
    pub height: f64,
    /// Normalized runout `(L_inf - L0) / L0`, -.
    pub runout_ratio: f64,
    /// Final height over the initial one, `H_inf / H0`, -.
    pub final_height_ratio: f64,
    /// Whether the rest criterion was met before [`ColumnSpec::max_time`].
    pub at_rest: bool,
    /// Time at the end of the run, s.
    pub time: f64,
    /// Total marker mass at the end over that at the start, -.
    pub mass_ratio: f64,
    /// The samples, every `0.01 sqrt(H0/g)` (the first step past each).
    pub samples: Vec<ColumnSample>,
    /// Steps taken.
    pub steps: u64,
}

/// The column and its sand.
#[derive(Clone, Debug)]
pub struct Column {
    /// The MPM body.
    pub body: MpmBody,
    spec: ColumnSpec,
    /// Marker spacing, m.
    spacing: f64,
    mass0: f64,
}

impl Column {
    /// Builds the column; errors name the field (`column.*`, `material.*`).
    pub fn new(spec: ColumnSpec) -> Result<Self> {
        let a = positive("column.aspect_ratio", spec.aspect_ratio)?;
        if a > 100.0 {
            return Err(invalid("column.aspect_ratio", a, "must be <= 100"));
        }
        let l0 = positive("column.column_length", spec.column_length)?;
        positive("column.density", spec.density)?;
        let g = positive("column.gravity", spec.gravity)?;
        positive("column.cfl", spec.cfl)?;
        positive("column.rest_kinetic", spec.rest_kinetic)?;
        positive("column.rest_window", spec.rest_window)?;
        positive("column.max_time", spec.max_time)?;
        if !(spec.friction_angle_deg.is_finite()
            && spec.friction_angle_deg > 0.0
            && spec.friction_angle_deg < 90.0)
        {
            return Err(invalid(
                "column.friction_angle_deg",
                spec.friction_angle_deg,
                "must lie in (0, 90) (cohesionless sand needs friction)",
            ));
        }
        if spec.cells_length < 2 {
            return Err(invalid(
                "column.cells_length",
                spec.cells_length,
                "must be >= 2",
            ));
        }
        if spec.markers_per_cell == 0 || spec.markers_per_cell > 8 {
            return Err(invalid(
                "column.markers_per_cell",
                spec.markers_per_cell,
                "must lie in [1, 8]",
            ));
        }
        let mut dp = DruckerPrager::plane_strain(
            spec.young,
            spec.poisson,
            spec.friction_angle_deg,
            spec.cohesion,
        )?;
        if spec.associated_flow {
            dp = dp.associated();
        }
        if let Some(mi) = spec.mu_i {
            dp = dp.with_mu_i(mi)?;
        }
        let sand = match spec.critical_state {
            Some(cs) => {
                let phi0 = spec.density / cs.grain_density;
                Material::CriticalState(CriticalStateSand { phi0, ..cs }.validated()?)
            }
            None => Material::DruckerPrager(dp),
        };
        let dx = l0 / spec.cells_length as f64;
        let h0 = a * l0;
        // The marker rows: whole marker spacings in H0 (at least one).
        let d = dx / spec.markers_per_cell as f64;
        let (mx, mz) = (
            spec.cells_length * spec.markers_per_cell,
            ((h0 / d).round() as usize).max(1),
        );
        // Room for the runout: beyond three times the larger of the published fits'
        // scales, `a` and `a^(2/3)` (the sparse grid costs nothing where no marker is).
        let reach = 1.0 + 3.0 * (2.0 * a).max(2.5 * a.powf(2.0 / 3.0));
        let nx = (reach * spec.cells_length as f64).ceil() as usize + 4;
        let nz = (h0 / dx).ceil() as usize + 4;
        // The floor: a rigid box whose top face is z = 0, with FLOOR_CELLS of the grid's
        // box below it, so that every node a marker's stencil reaches below the floor is
        // inside the box and takes the floor's contact condition.
        let below = FLOOR_CELLS as f64 * dx;
        let grid = GridSpec::new([0.0, 0.0, -below], [nx, 1, nz + FLOOR_CELLS], dx)?
            .with_walls(0, Wall::Slip, Wall::Open)
            .with_walls(1, Wall::Slip, Wall::Slip)
            .with_walls(2, Wall::Open, Wall::Open);
        let settings = MpmSettings {
            gravity: [0.0, 0.0, -g],
            cfl: spec.cfl,
            f_bar: spec.f_bar,
        };
        let mut body = MpmBody::new(grid, sand, settings)?;
        body.set_flip(spec.flip)?;
        let vol = d * d * dx;
        let top = mz as f64 * d;
        let stiffness = dp.elastic.lambda + 2.0 * dp.elastic.mu;
        for i in 0..mx {
            for k in 0..mz {
                let x = Vector3::new((i as f64 + 0.5) * d, 0.5 * dx, (k as f64 + 0.5) * d);
                let p = body
                    .markers
                    .push(spec.density * vol, vol, x, Vector3::zeros())?;
                if spec.geostatic {
                    let eps = -spec.density * g * (top - x.z) / stiffness;
                    body.markers.fe[p] =
                        nalgebra::Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, eps.exp()));
                }
            }
        }
        let contact = match spec.floor_friction_angle_deg {
            None => Contact::Sticky,
            Some(f) => {
                if !(f.is_finite() && (0.0..90.0).contains(&f)) {
                    return Err(invalid(
                        "column.floor_friction_angle_deg",
                        f,
                        "must lie in [0, 90)",
                    ));
                }
                Contact::Slip {
                    friction: f.to_radians().tan(),
                }
            }
        };
        // Far wider than the grid in x and y, deep enough that its top face is the
        // nearest one of every node below the floor.
        let half = [(nx + 20) as f64 * dx, 4.0 * dx, 4.0 * below];
        body.rigid.push(RigidBody::new_box(
            Vector3::new(0.5 * nx as f64 * dx, 0.5 * dx, -half[2]),
            half,
            Vector3::zeros(),
            contact,
        )?);
        let mass0 = body.markers.mass.iter().sum();
        Ok(Self {
            body,
            spec,
            spacing: d,
            mass0,
        })
    }

    /// Switches the sand to the split (`pressure = rows`, `docs/mpm.md` "The split"): MPM
    /// carries the deviatoric stress, density rows on the markers the pressure, with the
    /// sand's bulk modulus as their compliance (`kappa = 1 / K`, `K = E / (3 (1 - 2 nu))`,
    /// the same volumetric stiffness as plain MPM) and the Drucker–Prager cone evaluated
    /// at the rows' pressure. Fixed wall markers
    /// (`chrono_core::particles::lattice::wall_layers` layers on the markers' lattice)
    /// lie beyond the floor `z < 0` over the grid's length and beyond the back wall
    /// `x < 0` up to the grid's top; the far end and the top stay open. The floor's
    /// Coulomb contact stays on the grid, and its friction also acts on the rows' normal
    /// impulse of the floor's markers ([`crate::pressure::PressureRows::set_wall_friction`]).
    /// `tolerance` is APGD's on the rows' velocity
    /// residual, m/s ([`PressureSettings::tolerance`]). Call before [`Column::run`].
    /// Errors name the field (a dilatant flow: `material.dilatancy`).
    pub fn use_pressure_rows(&mut self, tolerance: f64) -> Result<()> {
        let spec = self.spec;
        let grid = *self.body.spec();
        let dx = grid.dx;
        let d = self.spacing;
        let settings = PressureSettings::plane_strain_soil(
            spec.density,
            spec.young,
            spec.poisson,
            d,
            tolerance,
        );
        let layers = chrono_core::particles::lattice::wall_layers(settings.h_over_dp);
        let length = grid.cells[0] as f64 * dx;
        let top = grid.origin[2] + grid.cells[2] as f64 * dx;
        // the floor and both sides of the box, then the far side dropped (open)
        let walls: Vec<[f64; 3]> =
            slab_wall_markers([0.0, length], [0.0, top], 0.5 * dx, d, layers, true, true)?
                .into_iter()
                .filter(|w| w[0] < length)
                .collect();
        self.body.set_pressure_rows(settings, &walls)?;
        // The floor's Coulomb friction takes the rows' normal impulse too (the grid's
        // contact sees only the gravity and the deviatoric stress of the nodes on it); a
        // sticky floor needs no normal force.
        if let Some(f) = spec.floor_friction_angle_deg
            && let Some(rows) = self.body.pressure_rows_mut()
        {
            rows.set_wall_friction(f.to_radians().tan(), [0.0, 0.0, 1.0], |w| w[2] < 0.0)?;
        }
        Ok(())
    }

    /// The parameters.
    pub fn spec(&self) -> &ColumnSpec {
        &self.spec
    }

    /// The initial height `H0` (whole marker rows), m.
    pub fn initial_height(&self) -> f64 {
        let rows = ((self.spec.aspect_ratio * self.spec.column_length / self.spacing).round()
            as usize)
            .max(1);
        rows as f64 * self.spacing
    }

    /// The time scale `sqrt(H0 / g)`, s.
    pub fn time_scale(&self) -> f64 {
        (self.initial_height() / self.spec.gravity).sqrt()
    }

    /// The front: the farthest extent of a marker from the wall, `max x_p + d/2`, m.
    pub fn front(&self) -> f64 {
        self.body
            .markers
            .x
            .iter()
            .map(|x| x.x)
            .fold(f64::NEG_INFINITY, f64::max)
            + 0.5 * self.spacing
    }

    /// The height: the highest extent of a marker, `max z_p + d/2`, m.
    pub fn height(&self) -> f64 {
        self.body
            .markers
            .x
            .iter()
            .map(|x| x.z)
            .fold(f64::NEG_INFINITY, f64::max)
            + 0.5 * self.spacing
    }

    fn sample(&self) -> ColumnSample {
        ColumnSample {
            t: self.body.time(),
            front: self.front(),
            height: self.height(),
            kinetic: self.body.kinetic_energy(),
        }
    }

    /// Runs the collapse until rest (or [`ColumnSpec::max_time`]); `progress` gets the
    /// fraction of `max_time` done. Errors: a diverging run or a marker leaving the grid
    /// (naming the marker and the step).
    pub fn run(&mut self, mut progress: impl FnMut(f64)) -> Result<ColumnResult> {
        let tau = self.time_scale();
        let h0 = self.initial_height();
        let l0 = self.spec.column_length;
        let scale = self.mass0 * self.spec.gravity * h0;
        let t_max = self.spec.max_time * tau;
        let window = self.spec.rest_window * tau;
        let every = 0.01 * tau;
        let mut samples = vec![self.sample()];
        let mut next = every;
        let mut quiet_since: Option<f64> = None;
        let mut at_rest = false;
        let mut k = 0u64;
        while self.body.time() < t_max {
            let dt = self.body.stable_dt();
            self.body.advance(dt)?;
            k += 1;
            let t = self.body.time();
            if t >= next {
                next += every;
                let s = self.sample();
                samples.push(s);
                if t >= tau && s.kinetic < self.spec.rest_kinetic * scale {
                    let since = *quiet_since.get_or_insert(t);
                    if t - since >= window {
                        at_rest = true;
                        break;
                    }
                } else {
                    quiet_since = None;
                }
            }
            if k.is_multiple_of(64) {
                progress(t / t_max);
            }
        }
        let last = self.sample();
        let mass: f64 = self.body.markers.mass.iter().sum();
        Ok(ColumnResult {
            runout: last.front,
            height: last.height,
            runout_ratio: (last.front - l0) / l0,
            final_height_ratio: last.height / h0,
            at_rest,
            time: last.t,
            mass_ratio: mass / self.mass0,
            samples,
            steps: self.body.steps(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coarse(a: f64) -> ColumnSpec {
        ColumnSpec {
            aspect_ratio: a,
            cells_length: 4,
            max_time: 20.0,
            ..ColumnSpec::default()
        }
    }

    #[test]
    fn bad_column_input_names_the_field() {
        let bad = |s: ColumnSpec, field: &str| {
            let e = Column::new(s).unwrap_err();
            assert!(e.to_string().contains(field), "{e} should name {field}");
        };
        let d = coarse(1.0);
        bad(
            ColumnSpec {
                aspect_ratio: -1.0,
                ..d
            },
            "column.aspect_ratio",
        );
        bad(
            ColumnSpec {
                friction_angle_deg: 0.0,
                ..d
            },
            "column.friction_angle_deg",
        );
        bad(
            ColumnSpec {
                floor_friction_angle_deg: Some(f64::NAN),
                ..d
            },
            "column.floor_friction_angle_deg",
        );
        bad(
            ColumnSpec {
                cells_length: 1,
                ..d
            },
            "column.cells_length",
        );
        bad(
            ColumnSpec {
                column_length: 0.0,
                ..d
            },
            "column.column_length",
        );
        bad(ColumnSpec { young: -1.0, ..d }, "material.young");
        bad(
            ColumnSpec {
                cohesion: -1.0,
                ..d
            },
            "material.cohesion",
        );
    }

    #[test]
    fn cohesive_column_stands_below_the_critical_height_and_fails_above() {
        // A vertical cut in a Mohr-Coulomb soil of unit weight gamma stands up to
        // H_c = 4 c / gamma tan(pi/4 + phi/2) (Culmann's wedge; Terzaghi, Theoretical
        // Soil Mechanics, 1943, art. 62). A column at half of it keeps its shape (the front
        // moves by elastic strain only; the sudden release can overshoot the static stress
        // up to twice, so half is the margin), one at twice it collapses.
        let run = |h_over_hc: f64| {
            let s = coarse(1.0);
            let gamma = s.density * s.gravity;
            let phi = s.friction_angle_deg.to_radians();
            let h0 = s.aspect_ratio * s.column_length;
            let hc_per_c = 4.0 / gamma * (std::f64::consts::FRAC_PI_4 + 0.5 * phi).tan();
            let c = h0 / (h_over_hc * hc_per_c);
            let mut col = Column::new(ColumnSpec { cohesion: c, ..s }).unwrap();
            let r = col.run(|_| {}).unwrap();
            assert!(
                r.at_rest,
                "H0/H_c {h_over_hc}: not at rest at t = {}",
                r.time
            );
            r
        };
        let stands = run(0.5);
        assert!(stands.runout_ratio.abs() < 0.02, "{}", stands.runout_ratio);
        assert!(
            stands.final_height_ratio > 0.99,
            "{}",
            stands.final_height_ratio
        );
        let fails = run(2.0);
        assert!(fails.runout_ratio > 0.1, "{}", fails.runout_ratio);
        assert!(
            fails.final_height_ratio < 0.97,
            "{}",
            fails.final_height_ratio
        );
    }

    #[test]
    fn critical_state_column_comes_to_rest_and_dilates_where_it_flowed() {
        // The glass beads start at phi0 = 1500 / 2450 = 0.612, denser than phi_c = 0.6:
        // the collapse shears them, they dilate toward phi_eq(I) <= phi_c, and the
        // deposit comes to rest with its mass; a bulk density above the grains' is an
        // error naming the field.
        let s = ColumnSpec {
            critical_state: Some(CriticalStateSand::glass_beads(2e6, 0.3, 0.6).unwrap()),
            floor_friction_angle_deg: Some(32.76),
            ..coarse(1.0)
        };
        let e = Column::new(ColumnSpec {
            density: 3000.0,
            ..s
        })
        .unwrap_err();
        assert!(
            e.to_string().contains("material.critical_state.phi0"),
            "{e}"
        );
        let mut col = Column::new(s).unwrap();
        let r = col.run(|_| {}).unwrap();
        assert!(r.at_rest, "not at rest at t = {}", r.time);
        assert_eq!(r.mass_ratio, 1.0);
        assert!(r.runout_ratio > 0.1 && r.final_height_ratio < 1.0, "{r:?}");
        let Material::CriticalState(m) = col.body.material() else {
            panic!("not the critical-state sand")
        };
        let mk = &col.body.markers;
        let phi: Vec<f64> = (0..mk.len())
            .map(|p| m.packing_of(&mk.fe[p], &mk.fp[p]))
            .collect();
        let min = phi.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(min < m.phi_c, "no marker dilated below phi_c: min {min}");
        assert!(phi.iter().all(|f| f.is_finite() && *f > 0.0 && *f < 1.0));
    }

    #[test]
    fn sand_spreads_farther_with_less_friction_and_comes_to_rest() {
        let run = |phi: f64| {
            let mut col = Column::new(ColumnSpec {
                friction_angle_deg: phi,
                floor_friction_angle_deg: Some(phi),
                ..coarse(1.0)
            })
            .unwrap();
            let r = col.run(|_| {}).unwrap();
            assert!(r.at_rest, "phi {phi}: not at rest at t = {}", r.time);
            // The markers keep their mass; the deposit is lower than the column and
            // spread beyond it.
            assert_eq!(r.mass_ratio, 1.0);
            assert!(r.final_height_ratio < 1.0 && r.runout_ratio > 0.0, "{r:?}");
            r.runout_ratio
        };
        let (low, high) = (run(20.0), run(40.0));
        assert!(low > 1.5 * high, "phi 20: {low}, phi 40: {high}");
    }
}
