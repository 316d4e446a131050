//! # chrono-fsi
//!
//! Fluid–solid interaction: an explicit WCSPH fluid (chrono-sph) as a physics item of the
//! one chrono-core [`System`](chrono_core::System), two-way coupled to rigid bodies through
//! boundary condition enforcing (BCE) markers.
//!
//! - [`markers`]: marker layers inside boxes, spheres and cylinders at the fluid spacing;
//! - [`cable`]: markers over the round section of ANCF cable/beam meshes, placed by the
//!   shape functions, their forces put back on the nodal coordinates with the same
//!   weights (consistent virtual work; [`FsiBuilder::add_cable`]);
//! - [`beam_flow`]: a flexible beam clamped in a periodic array flow (the scene of
//!   `fsi-flexible-beam`);
//! - [`sphere_settling`]: a free sphere settling in a triply periodic cell, the mean
//!   pressure gradient as compensating body forces (the scene of `fsi-sphere-settling`);
//! - [`heave`]: a floating hemisphere's free heave against Hulme's (1982) added mass
//!   and damping (the scene of `fsi-sphere-heave`);
//! - [`channel`]: free ellipsoids and ANCF beams anchored to the floor in a periodic duct
//!   flow (the seed's channel scene, `fsi-channel`), with the laminar duct solution
//!   ([`duct`]) for its driving body force;
//! - [`jeffery`]: a neutrally buoyant spheroid in simple shear between two moving-belt
//!   walls against Jeffery's (1922) orbit, with the orbit fit (the scene of
//!   `fsi-jeffery`);
//! - [`towed`]: a cylinder towed through a long tank, with or without the fluid's active
//!   domain ([`chrono_sph::ActiveDomain`]: only the fluid near the moving bodies is
//!   stepped; the scene of `fsi-active-domain`);
//! - [`FsiBuilder`]: tanks, fluid blocks carved around the bodies, the bodies' markers
//!   (bad input, e.g. a body thinner than the kernel support, is an error naming the body);
//! - [`SphFluid`]: the item. [`System::step(h)`](chrono_core::System::step) advances it to
//!   `t + h` exactly with its own sub-steps, the markers following the bodies, and puts the
//!   fluid's impulse on each body into the multibody step (the coupling and its stability
//!   limit: [`fluid`]).
//!
//! - [`cfluid`]: the same markers on rigid bodies in a constraint fluid (chrono-cfluid):
//!   the body's markers in the fluid's density rows, one CCP for fluid and bodies
//!   ([`cfluid::attach_body`]), and the floating scene by it ([`cfluid::floating_cfluid`]).
//!
//! Not yet: shell and tetrahedral mesh markers, cable markers in a constraint fluid,
//! convex-hull and triangle-mesh markers.
//!
//! ```
//! use chrono_ccp::Psor;
//! use chrono_core::math::{Isometry3, Vector3};
//! use chrono_core::{RigidBodyBuilder, Shape, System, SystemSettings};
//! use chrono_fsi::FsiBuilder;
//! use chrono_sph::SphSettings;
//!
//! let dp = 0.02;
//! let settings = SphSettings {
//!     spacing: dp,
//!     sound_speed: 10.0,
//!     domain_lower: [0.0; 3],
//!     domain_upper: [0.4; 3],
//!     periodic: [true; 3],
//!     gravity: [0.0; 3],
//!     ..SphSettings::default()
//! };
//! let sys_settings = SystemSettings { gravity: Vector3::zeros(), ..SystemSettings::default() };
//! let mut sys = System::new(sys_settings, Box::new(Psor::new(Default::default()))).unwrap();
//! let ball = Shape::Sphere { radius: 0.06 };
//! let b = sys
//!     .add_body(
//!         RigidBodyBuilder::dynamic()
//!             .mass_from_shape(&ball, 500.0).unwrap()
//!             .position(Vector3::new(0.2, 0.2, 0.2))
//!             .collider(ball, Isometry3::identity(), Default::default()),
//!     )
//!     .unwrap();
//! let mut fsi = FsiBuilder::new(settings).unwrap();
//! fsi.add_fluid_box([0.0; 3], [0.4; 3], None).unwrap();
//! fsi.add_body(&sys, b).unwrap();
//! let fluid = sys.add_item(Box::new(fsi.build("water", 1).unwrap()));
//! sys.step(2e-3).unwrap();
//! let f = sys.item::<chrono_fsi::SphFluid>(fluid).unwrap();
//! assert!(f.last_substeps() >= 1);
//! ```

pub mod beam_flow;
pub mod builder;
pub mod cable;
#[cfg(test)]
mod cable_tests;
pub mod cfluid;
#[cfg(test)]
mod cfluid_tests;
pub mod channel;
#[cfg(test)]
mod channel_tests;
pub mod cylinder_array;
pub mod cylinder_flow;
pub mod duct;
pub mod error;
pub mod fluid;
pub mod heave;
pub mod jeffery;
#[cfg(test)]
mod jeffery_tests;
pub mod markers;
mod periodic;
pub mod scene;
pub mod sphere_settling;
#[cfg(test)]
mod tests;
pub mod towed;

pub use builder::FsiBuilder;
pub use error::{FsiError, Result};
pub use fluid::SphFluid;
