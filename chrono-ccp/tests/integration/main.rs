//! The integration tests of `chrono-ccp`, one module per topic, built as one test binary
//! (one link instead of one per file: the cold CI build links each test binary).
//! Run one topic with `cargo test -p chrono-ccp --test integration <module>::`.

mod analytic;
mod apgd_fused;
mod apsor;
mod bilateral;
mod capture;
mod cone;
mod coulomb;
mod determinism;
mod local_direct;
mod parallel_psor;
mod pendulum;
mod problem_file;
mod random;
mod rolling;
mod stack;
