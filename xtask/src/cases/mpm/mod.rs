//! Validation cases of chrono-mpm.

pub mod elastic_bar;
pub mod footing;
pub mod snow;
