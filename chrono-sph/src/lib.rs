//! # chrono-sph
//!
//! Explicit weakly compressible SPH (WCSPH) on chrono-core's particle grid and kernels.
//!
//! - [`eos`]: the Tait equation of state `p = c_s^2 rho_0 / gamma ((rho/rho_0)^gamma - 1)`
//!   and the choice of `c_s` (Monaghan 1994; Morris, Fox and Zhu 1997);
//! - [`interact`](crate::system) passes: continuity, momentum with the symmetric
//!   pressure term and the Morris viscous term, optional Monaghan artificial viscosity,
//!   XSPH, delta-SPH density diffusion with the hydrostatic correction of Fourtakas et
//!   al. (2019), optional Shepard re-initialization; wall markers with pressure
//!   extrapolated from the fluid (Adami, Hu and Adams 2012) and a no-slip velocity
//!   extrapolated linearly through the wall surface (after Morris, Fox and Zhu 1997);
//! - [`system`]: [`SphSystem`], a kick-drift-kick leapfrog with an adaptive time step
//!   (CFL, force and viscous criteria), Mach number check, divergence errors naming the
//!   particle and step;
//! - [`builder`]: [`SphBuilder`], fluid blocks (optionally hydrostatic), wall boxes and
//!   tanks with marker layers, periodic directions (quasi-2D slabs, channels) (the
//!   lattice itself is [`chrono_core::particles::lattice`]);
//! - [`motion`]: [`WallMotion`], prescribed tank motion (sloshing);
//! - [`carrier`]: wall markers carried by a [`RigidMotion`] set from outside (a body of a
//!   multibody system, chrono-fsi), the force, torque and impulse of the fluid on them,
//!   and [`SphSystem::advance_exactly`], which ends exactly at a given time;
//! - [`open`]: open boundaries ([`OpenChannel`], off by default): a through-flow channel
//!   with a velocity inlet and a zero-gradient outlet, buffer zones recycling particles
//!   through a periodic seam;
//! - [`system::active`]: the active domain ([`ActiveDomain`], off by default): only the
//!   fluid near moving carriers is stepped, the rest frozen but still seen as neighbours;
//! - [`distributed`]: domain decomposition over ranks (slabs, ghosts, migration), with
//!   in-process ranks ([`LocalTransport`]) or MPI (cargo feature `mpi`);
//! - [`scene`]: ready-made scenes on the quasi-2D slab tank: the dam break or still
//!   water ([`scene::slab_tank`]) and the sloshing tank ([`scene::sloshing`]);
//! - probes ([`SphSystem::pressure_at`], [`SphSystem::free_surface_height`],
//!   [`SphSystem::wall_force`], [`SphSystem::fluid_force`]) and VTK frames
//!   ([`SphSystem::write_vtk`]);
//! - [`analytic`]: the start-up Poiseuille series and the sloshing force formula.
//!
//! Storage is a structure of arrays ([`ParticleData`]) re-sorted by cell every few
//! steps; every pass runs over particles with rayon; the step loop does not allocate
//! after warm-up. Units SI, `f64`, Z up.
//!
//! ```
//! use chrono_sph::{SphBuilder, SphSettings};
//! let dp = 0.05;
//! let settings = SphSettings {
//!     spacing: dp,
//!     sound_speed: 20.0,
//!     domain_lower: [0.0, 0.0, 0.0],
//!     domain_upper: [0.5, 7.0 * dp, 0.6],
//!     periodic: [false, true, false],
//!     ..SphSettings::default()
//! };
//! let mut b = SphBuilder::new(settings).unwrap();
//! b.add_fluid_box([0.0, 0.0, 0.0], [0.5, 7.0 * dp, 0.3], Some(0.3)).unwrap();
//! b.add_tank([0.0, 0.0, 0.0], [0.5, 7.0 * dp, 0.6], 3, [true, true, false, false, true, false], 0)
//!     .unwrap();
//! let mut sys = b.build().unwrap();
//! for _ in 0..10 {
//!     sys.step().unwrap();
//! }
//! assert!(sys.stats().max_speed < 0.1);
//! ```

#[cfg(test)]
mod active_tests;
pub mod analytic;
#[cfg(test)]
mod belt_tests;
pub mod builder;
pub mod carrier;
pub mod data;
pub mod distributed;
pub mod eos;
pub mod error;
mod interact;
pub mod motion;
pub mod open;
#[cfg(test)]
mod open_tests;
mod output;
mod pairs;
mod probes;
#[cfg(test)]
mod rotation_tests;
pub mod scene;
pub mod settings;
pub mod shifting;
#[cfg(test)]
mod shifting_tests;
pub mod system;
#[cfg(test)]
mod tests;

pub use builder::{SphBuilder, TankSides};
pub use carrier::RigidMotion;
pub use data::{Deriv, Kind, ParticleData};
pub use distributed::{DistributedSettings, LocalTransport, Slabs, Transport};
pub use eos::{Tait, sound_speed_for};
pub use error::{Result, SphError};
pub use motion::{Kinematics, WallMotion};
pub use open::{Inflow, OpenChannel, Outflow};
pub use settings::{
    ActiveDomain, DensityDiffusion, MachPolicy, NoSlip, ShiftForm, Shifting, SphSettings, WallBelt,
};
pub use system::halo::{GlobalSummary, HaloStats};
pub use system::{SphStats, SphSystem, Timings};
