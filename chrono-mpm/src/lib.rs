//! # chrono-mpm
//!
//! The material point method: markers (material points) carry mass, volume, velocity, the
//! APIC affine matrix and the elastic and plastic deformation gradients `F_E`, `F_P`; a
//! sparse background grid is the scratchpad of each step.
//!
//! - [`bspline`]: quadratic B-spline transfers (and why quadratic);
//! - [`grid`]: the grid's box, its walls and the sparse block storage;
//! - [`fbar`]: F-bar, the markers' volume change averaged over the grid stencil (against
//!   volumetric locking);
//! - [`fold`]: consistent boundary images (the ghosts' mass and force folded into the
//!   nodes they mirror);
//! - [`markers`]: the markers, structure of arrays;
//! - [`material`]: fixed-corotated elasticity with snow hardening (Stomakhin et al. 2013),
//!   Drucker–Prager sand (Klar et al. 2016), von Mises clay and a compressible `mu(I)`
//!   sand with critical-state dilatancy, each with its return mapping;
//! - [`rigid`]: kinematic rigid bodies (plates, footings: boxes; wheels: spinning
//!   cylinders) in the grid update, with their reaction force and torque;
//! - [`body`]: an MPM body advanced by explicit APIC steps (Jiang et al. 2015);
//! - [`compaction`]: confined compaction of a column by a plate (the oedometer);
//! - [`footing`]: a rigid strip footing pushed into cohesive soil (Prandtl's problem);
//! - [`column`](mod@column): a granular column collapsing on a rough floor (Lube et al. 2005,
//!   Lajeunesse et al. 2005);
//! - [`mud`]: the seed's mud bed in a box by the split (the mud bench, issue 25);
//! - [`soil_bin`]: a sand layer under gravity in its geostatic state (plane strain);
//! - [`plate`]: plate sinkage on it and Bekker's pressure–sinkage law fitted to two widths;
//! - [`wheel`]: a rigid wheel driven at fixed slip under a vertical load, two-way
//!   (sinkage, drawbar pull, torque);
//! - [`pressure`]: the split's pressure, density rows on the markers (chrono-core's
//!   `density_rows`) solved by APGD, with wall and rigid-body markers;
//! - [`bar`]: the axially vibrating elastic bar, a scene for validation;
//! - [`timings`]: wall time of the parts of a step (benches);
//! - [`vtk`]: VTP frames of the markers (stress, `J_E`, `J_P`, plastic strain).
//!
//! Two modes: plain MPM (the full stress by MPM, the default) and the seed's split
//! ([`MpmBody::set_pressure_rows`]; [`pressure`]): the deviatoric stress by MPM, the
//! pressure by constraint-fluid density rows on the markers (chrono-core's
//! `density_rows`, shared with chrono-cfluid), solved by chrono-ccp's APGD (Stomakhin et
//! al., "Augmented MPM for phase-change and varied materials", ACM TOG 2014).

pub mod bar;
pub mod body;
pub mod bspline;
pub mod column;
pub mod compaction;
pub mod error;
pub mod fbar;
pub mod fold;
pub mod footing;
pub mod grid;
pub mod markers;
pub mod material;
pub mod mud;
pub mod plate;
pub mod pressure;
pub mod rigid;
pub mod row_markers;
pub mod soil_bin;
pub mod timings;
pub mod vtk;
pub mod wheel;

#[cfg(test)]
mod mirror_tests;
#[cfg(test)]
mod mud_tests;
#[cfg(test)]
mod quadrature_tests;
#[cfg(test)]
mod split_tests;
#[cfg(test)]
mod tests;

pub use body::{MpmBody, MpmSettings};
pub use error::{MpmError, Result};
pub use fbar::FBar;
pub use grid::{GridSpec, SparseGrid, Wall};
pub use markers::Markers;
pub use material::{
    CriticalStateSand, DruckerPrager, Elasticity, FixedCorotated, Material, MuI, SnowHardening,
    VonMises,
};
pub use pressure::{PressureRows, PressureSettings, RowsNorm, StrainFrom};
pub use rigid::{Contact, RigidBody, Shape};
pub use timings::StepTimings;
