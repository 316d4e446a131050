//! Fluid–solid interaction cases (chrono-fsi).

pub mod flexible_beam;
pub mod floating_body;
