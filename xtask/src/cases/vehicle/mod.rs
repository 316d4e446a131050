//! Vehicle cases: the HMMWV of `chrono-vehicle` on rigid terrain.

pub mod accel;
pub mod granular;
pub mod lane_change;
pub mod scene;
pub mod static_settle;
pub mod turn;
