//! Validation cases of chrono-mpm.

pub mod column_collapse;
pub mod elastic_bar;
pub mod footing;
pub mod settle;
pub mod snow;
pub mod wheel;
