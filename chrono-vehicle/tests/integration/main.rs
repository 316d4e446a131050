//! The integration tests of `chrono-vehicle`, one module per topic, built as one test binary
//! (one link instead of one per file: the cold CI build links each test binary).
//! Run one topic with `cargo test -p chrono-vehicle --test integration <module>::`.

mod ancf_tire;
mod driveline_four_wd;
mod driveline_powertrain;
mod driveline_shafts;
mod driver;
mod granular_patch;
mod hmmwv_build;
mod json_fuzz;
mod terrain;
mod tire;
