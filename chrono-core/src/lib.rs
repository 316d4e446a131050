//! # chrono-core
//!
//! The foundation of chrono-rs: math, the *descriptor* (variables with mass operators and
//! constraint rows, assembled into one cone complementarity problem), rigid bodies, joints,
//! collision through parry, contact, the [`System`] with its NSC time
//! stepper, and io (CSV, VTK).
//!
//! The method is the one of Anitescu and Tasora (M. Anitescu, "Optimization-based simulation
//! of nonsmooth rigid multibody dynamics", Math. Program. 105(1), 2006): each step solves
//!
//! ```text
//! min 1/2 g'N g + r'g   s.t. g_i in Y_i,    N = D'M^-1 D + E,  r = b + D'M^-1 k
//! ```
//!
//! then `v+ = M^-1 (k + D g)` and `q+ = q + h L(q) v+`.

pub mod bodies;
pub mod body;
pub mod collision;
pub mod contact;
pub mod curve;
pub mod density_rows;
pub mod descriptor;
pub mod distributed;
pub mod error;
pub mod force;
pub mod granular;
pub mod io;
pub mod item;
pub mod joint;
pub mod material;
pub mod math;
pub mod parallel;
pub mod particles;
pub mod rng;
pub mod shape;
mod slots;
pub mod system;
#[cfg(any(test, feature = "testing"))]
pub mod testing;

pub use error::{ChronoError, Result};

pub use bodies::Bodies;
pub use body::{BodyHandle, BodyMotion, RigidBody, RigidBodyBuilder};
pub use curve::{Curve, Extrapolation};
pub use force::{ForceElement, ForceHandle, SpringDamper};
pub use joint::{AxisSpring, Drive, Joint, JointBuilder, JointHandle, JointKind};
pub use material::{ContactFriction, ContactMaterial};
pub use shape::Shape;
pub use system::{ContactMethod, FrictionLaw, StepReport, System, SystemSettings};
