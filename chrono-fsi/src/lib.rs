//! # chrono-fsi
//!
//! Fluid–solid interaction (to be built): boundary condition enforcing (BCE) markers rigidly
//! attached to bodies and interpolated on FE meshes, two-way forces between SPH and solids,
//! SPH sub-stepping inside a multibody step, and active domains around moving bodies.
