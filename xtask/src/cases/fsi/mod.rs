//! Fluid–solid interaction cases (chrono-fsi).

pub mod floating_body;
