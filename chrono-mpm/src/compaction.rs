//! Confined (uniaxial-strain) compaction of a column by a rigid plate: the oedometer of
//! MPM materials.
//!
//! A column of square section `width x width` and height `H` stands on a frictionless
//! floor between frictionless side walls (slip walls of the grid's box: the lateral strain
//! is zero, the deformation `F = diag(1, 1, s)` is uniaxial). A sticky rigid plate
//! ([`crate::rigid`], with the mirror image that puts the contact at the plate's surface;
//! nothing moves laterally, so sticky and frictionless are the same load) resting on its
//! top moves down at the speed
//!
//! ```text
//! V(t) = strain_rate H r(t),   r(t) = (1 - cos(pi t / t_ramp)) / 2 for t < t_ramp, then 1
//! ```
//!
//! (the smooth ramp keeps the start's stress wave, of amplitude `rho c V` for a sudden
//! start, small). The axial strain is the plate's displacement over `H`, the axial stress
//! the plate's reaction (the momentum it takes from the grid, [`RigidBody::force_on_body`])
//! over the section, averaged over each sampling interval (the impulse over the interval
//! over its length, so no step's impulse is lost). Slow compaction (`strain_rate H` far
//! below the wave speed) is quasi-static: the stress is uniform and follows the material's
//! uniaxial-strain curve, e.g. [`FixedCorotated::uniaxial_strain_stress`]. Gravity is off.
//!
//! [`FixedCorotated::uniaxial_strain_stress`]: crate::FixedCorotated::uniaxial_strain_stress

use nalgebra::Vector3;

use crate::body::{MpmBody, MpmSettings};
use crate::error::{Result, at_least, invalid, positive};
use crate::grid::{GridSpec, Wall};
use crate::material::Material;
use crate::rigid::{Contact, RigidBody, push_down, speed_ramp};

/// Parameters of the compaction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompactionSpec {
    /// Column height `H`, m.
    pub height: f64,
    /// Side of the square section, m (rounded to whole cells, at least one).
    pub width: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Grid cells along the height (`dx = H / cells`).
    pub cells: usize,
    /// Markers per cell per axis.
    pub markers_per_cell: usize,
    /// Nominal strain rate `V / H`, 1/s.
    pub strain_rate: f64,
    /// Duration of the velocity ramp, s.
    pub ramp_time: f64,
    /// Final axial strain, -.
    pub final_strain: f64,
    /// CFL number of the time step (recomputed each step: hardening stiffens).
    pub cfl: f64,
    /// F-bar volume averaging ([`crate::fbar`]).
    pub f_bar: crate::fbar::FBar,
    /// The plate's boundary from mirrored markers instead of the lumped fold of its ghosts
    /// ([`RigidBody::mirrored_markers`]).
    pub mirrored_markers: bool,
}

/// One sample of the compaction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompactionSample {
    /// Time at the middle of the sampling interval, s.
    pub t: f64,
    /// Axial strain at the middle of the interval (plate displacement / H), -.
    pub strain: f64,
    /// Axial compressive stress from the plate's mean reaction over the interval, Pa.
    pub stress: f64,
    /// Kinetic energy of the markers at the end of the interval, J.
    pub kinetic: f64,
    /// Elastic energy of the markers at the end of the interval, J.
    pub elastic: f64,
}

/// The column, its plate and its clock.
#[derive(Clone, Debug)]
pub struct Compaction {
    /// The MPM body (the plate is `body.rigid[0]`).
    pub body: MpmBody,
    spec: CompactionSpec,
    /// Section area, m^2.
    pub area: f64,
    /// The plate's initial centre height, m.
    plate_z0: f64,
}

impl Compaction {
    /// Builds the column of `material`; errors name the field (`compaction.*`).
    pub fn new(spec: CompactionSpec, material: Material) -> Result<Self> {
        positive("compaction.height", spec.height)?;
        positive("compaction.width", spec.width)?;
        positive("compaction.density", spec.density)?;
        positive("compaction.strain_rate", spec.strain_rate)?;
        positive("compaction.cfl", spec.cfl)?;
        at_least(
            "compaction.ramp_time",
            spec.ramp_time,
            0.0,
            "must be finite and >= 0",
        )?;
        if !(spec.final_strain > 0.0 && spec.final_strain < 0.9) {
            return Err(invalid(
                "compaction.final_strain",
                spec.final_strain,
                "must lie in (0, 0.9)",
            ));
        }
        if spec.cells < 2 {
            return Err(invalid("compaction.cells", spec.cells, "must be >= 2"));
        }
        if spec.markers_per_cell == 0 || spec.markers_per_cell > 8 {
            return Err(invalid(
                "compaction.markers_per_cell",
                spec.markers_per_cell,
                "must lie in [1, 8]",
            ));
        }
        let h = spec.height;
        let dx = h / spec.cells as f64;
        let lateral = ((spec.width / dx).round() as usize).max(1);
        let w = lateral as f64 * dx;
        let grid = GridSpec::new([0.0; 3], [lateral, lateral, spec.cells + 3], dx)?
            .with_walls(0, Wall::Slip, Wall::Slip)
            .with_walls(1, Wall::Slip, Wall::Slip)
            .with_walls(2, Wall::Slip, Wall::Open);
        let settings = MpmSettings {
            gravity: [0.0; 3],
            cfl: spec.cfl,
            f_bar: spec.f_bar,
        };
        let mut body = MpmBody::new(grid, material, settings)?;
        let d = dx / spec.markers_per_cell as f64;
        body.markers.fill_box(
            Vector3::zeros(),
            Vector3::new(w, w, h),
            d,
            spec.density,
            |_| Vector3::zeros(),
        )?;
        // A plate wider than the column by more than its own thickness `h`, its lower face
        // on the top of the column: the nodes inside it near the column are nearest to the
        // lower face (whose normal the image uses), not to a side face.
        let plate_z0 = 2.0 * h;
        let mut plate = RigidBody::new_box(
            Vector3::new(w / 2.0, w / 2.0, plate_z0),
            [w + 2.0 * h, w + 2.0 * h, h],
            Vector3::zeros(),
            Contact::Sticky,
        )?;
        plate.set_mirrored_markers(spec.mirrored_markers)?;
        body.rigid.push(plate);
        Ok(Self {
            body,
            spec,
            area: w * w,
            plate_z0,
        })
    }

    /// The parameters.
    pub fn spec(&self) -> &CompactionSpec {
        &self.spec
    }

    /// The axial strain, plate displacement over `H`, -.
    pub fn strain(&self) -> f64 {
        (self.plate_z0 - self.body.rigid[0].position.z) / self.spec.height
    }

    /// The plate's speed at time `t`, m/s (downwards positive).
    pub fn plate_speed(&self, t: f64) -> f64 {
        self.spec.strain_rate * self.spec.height * speed_ramp(t, self.spec.ramp_time)
    }

    /// Runs to the final strain, taking `samples` samples (at least 1); `progress` gets
    /// the fraction done. The plate's speed is set at each step's start time.
    pub fn run(
        &mut self,
        samples: usize,
        progress: impl FnMut(f64),
    ) -> Result<Vec<CompactionSample>> {
        let (spec, z0) = (self.spec, self.plate_z0);
        let strain = |b: &MpmBody| (z0 - b.rigid[0].position.z) / spec.height;
        let speed = |t: f64| spec.strain_rate * spec.height * speed_ramp(t, spec.ramp_time);
        let out = push_down(
            &mut self.body,
            self.area,
            spec.final_strain,
            samples,
            strain,
            speed,
            progress,
        )?;
        Ok(out
            .into_iter()
            .map(|s| CompactionSample {
                t: s.t,
                strain: s.measure,
                stress: s.pressure,
                kinetic: s.kinetic,
                elastic: s.elastic,
            })
            .collect())
    }
}
