//! The integration tests of `chrono-core`, one module per topic, built as one test binary
//! (one link instead of one per file: the cold CI build links each test binary).
//! Run one topic with `cargo test -p chrono-core --test integration <module>::`.

mod axis_spring;
mod common;
mod contact_friction;
mod distributed_granular;
mod ellipsoid;
mod force_elements;
mod granular_column;
mod granular_rolling_bed;
mod granular_scenes;
mod granular_wheel;
mod handles;
mod joints;
mod nsc_rolling;
mod nsc_sliding_lift;
mod proxies;
mod shear_box;
mod smc;
mod system_api;
