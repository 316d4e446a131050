//! The integration tests of `chrono-fea`, one module per topic, built as one test binary
//! (one link instead of one per file: the cold CI build links each test binary).
//! Run one topic with `cargo test -p chrono-fea --test integration <module>::`.

mod contact;
mod dynamics;
mod fea;
mod shell;
mod shell_contact;
mod shell_dynamics;
mod slope_attach;
mod tet;
mod tet_dynamics;
