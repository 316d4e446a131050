//! Vehicle cases: the HMMWV and the M113 of `chrono-vehicle`.

pub mod accel;
pub mod granular;
pub mod lane_change;
pub mod m113_accel;
pub mod m113_static;
pub mod m113_turn;
pub mod scene;
pub mod static_settle;
pub mod turn;
