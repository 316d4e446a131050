//! # chrono-vehicle
//!
//! Wheeled and tracked vehicles built from templates, each a small struct made from a serde description
//! (JSON), so another vehicle is a new data file, not new code:
//!
//! - [`suspension`]: double wishbone (control arms, upright, spindle, tie rod, spring and
//!   damper with nonlinear tables, bump stops) as bodies and joints of the system;
//! - [`steering`]: Pitman-arm steering;
//! - [`driveline`]: shafts with inertia in the system's CCP (gears, differentials with
//!   optional locking, a transfer case, couplings to the wheel spindles), the 4WD layout;
//! - [`powertrain`]: engine torque map, torque converter, automatic transmission;
//! - [`tire`]: a rigid tire (contact through the ordinary contact rows) and a handling tire
//!   (TMeasy-like, forces from slip with relaxation);
//! - [`driver`]: open loop, speed controller (PID), path follower;
//! - [`terrain`]: rigid flat and heightmap terrains;
//! - [`vehicle`]: the wheeled vehicle assembled from a description; [`hmmwv`] is the HMMWV;
//! - [`track`]: track templates (sprocket, idler and tensioner, road wheels on torsion-bar
//!   arms, support rollers, single-pin shoes) and [`tracked`]: the tracked vehicle built from
//!   them; [`m113`] is the M113A1; [`hull`]: a tracked vehicle's hull collision shape;
//!   [`obstacle`]: the vertical-obstacle (step) scene; [`tracked_granular`]: a tracked
//!   vehicle on a moving granular patch;
//! - [`scene`]: a vehicle set down on flat ground, steer angles, wheel slip and sinkage,
//!   differential locks for loose ground;
//! - [`output`]: the vehicle's time series as CSV.
//!
//! The vehicle frame is X forward, Y left, Z up (ISO 8855); units are SI.

pub mod aero;
pub mod driveline;
pub mod driver;
pub mod error;
pub mod hmmwv;
pub mod hull;
mod json_path;
pub mod m113;
pub mod obstacle;
pub mod output;
pub mod powertrain;
pub mod scene;
pub mod state;
pub mod steering;
pub mod suspension;
pub mod terrain;
pub mod tire;
pub mod track;
pub mod tracked;
pub mod tracked_drive;
pub mod tracked_granular;
pub mod vehicle;

pub use error::{Result, VehicleError};
pub use state::{DriverInputs, VehicleState};
pub use vehicle::{VehicleData, WheeledVehicle};
