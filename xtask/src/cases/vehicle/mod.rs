//! Vehicle cases: the HMMWV of `chrono-vehicle` on rigid terrain.

pub mod scene;
pub mod static_settle;
