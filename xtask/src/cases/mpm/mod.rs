//! Validation cases of chrono-mpm.

pub mod elastic_bar;
