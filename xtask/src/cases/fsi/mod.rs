//! Fluid–solid interaction cases (chrono-fsi).

pub mod active_domain;
pub mod channel;
pub mod cylinder_array;
pub mod cylinder_flow;
pub mod flexible_beam;
pub mod floating_body;
pub mod jeffery;
pub mod sphere_heave;
pub mod sphere_settling;
