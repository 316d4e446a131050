//! # chrono-cfluid
//!
//! Constraint fluids (H. Mazhar, "Parallel multi-body dynamics with frictional contact and
//! constraint fluids", PhD thesis, UW-Madison 2016; the seed's "Alternative Approach:
//! Constrained Fluids"): fluid particles are 3-dof variables of the system's CCP and
//! incompressibility is one compliant density constraint per particle,
//! `C_i = rho_i / rho_0 - 1`, enforced at the velocity level with the stabilization
//! `C_i / h`, in the same problem as the rigid bodies, joints and contacts.
//!
//! - [`ConstraintFluid`]: the [`PhysicsItem`](chrono_core::item::PhysicsItem) (density
//!   rows, compliance, free-surface treatment, XSPH viscosity, wall markers, warm start);
//! - [`CfluidSettings`], [`SurfaceMode`]: its settings;
//! - [`lattice_box`], [`tank_markers`], [`lattice_mass`], [`wall_layers`]: initial
//!   particle sets; [`box_markers`]: the markers of a rigid box, attached with
//!   [`ConstraintFluid::attach_body`] (fluid–solid coupling; particles are also contact
//!   spheres of the body colliders); the lattice and the tanks themselves are
//!   [`chrono_core::particles::lattice`];
//! - [`scene`]: ready-made scenes ([`scene::TankScene`]: the quasi-2D tank of a dam
//!   break, still water or sloshing);
//! - [`floating_box`]: a rigid box floating in a tank ([`floating_box::FloatingBox`]) and
//!   the probes of its draft against Archimedes.
//!
//! ```
//! use chrono_cfluid::{CfluidSettings, ConstraintFluid, lattice_box, tank_markers, wall_layers};
//! use chrono_core::{System, SystemSettings};
//!
//! let dp = 0.02;
//! let settings = CfluidSettings {
//!     spacing: dp,
//!     domain_lower: [-0.1, 0.0, -0.1],
//!     domain_upper: [0.2, 0.12, 0.3],
//!     periodic: [false, true, false],
//!     ..CfluidSettings::default()
//! };
//! let (lo, hi) = ([0.0, 0.0, 0.0], [0.1, 0.12, 0.1]);
//! let fluid = lattice_box(lo, hi, dp).unwrap();
//! let walls = tank_markers(lo, hi, dp, wall_layers(settings.h_over_dp),
//!     [true, true, false, false, true, false]).unwrap();
//! let item = ConstraintFluid::new("water", settings, &fluid, &walls).unwrap();
//! let solver = Box::new(chrono_ccp::Apgd::new(Default::default()));
//! let mut sys = System::new(SystemSettings::default(), solver).unwrap();
//! let id = sys.add_item(Box::new(item));
//! for _ in 0..5 {
//!     sys.step(2e-3).unwrap();
//! }
//! let water = sys.item::<ConstraintFluid>(id).unwrap();
//! assert!(water.max_compression() < 1e-3);
//! ```

#[cfg(test)]
mod body_tests;
mod density;
pub mod floating_box;
mod fluid;
mod geometry;
#[cfg(test)]
mod projection_tests;
pub mod scene;
mod settings;
#[cfg(test)]
mod tests;

pub use chrono_core::particles::lattice::wall_layers;
pub use fluid::{ConstraintFluid, KIND_BODY_MARKER, KIND_FLUID, KIND_WALL, ProjectionReport};
pub use geometry::{box_markers, lattice_box, lattice_mass, tank_markers};
pub use settings::{CfluidSettings, SurfaceMode};
