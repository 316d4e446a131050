//! The driveline: shafts with inertia in the system's CCP ([`shafts`]: gears,
//! differentials with optional locking, clutches and brakes, couplings to the wheel
//! spindles, speed motors), the HMMWV's 4WD layout ([`four_wd`]) and the drivelines of a
//! tracked vehicle: the braked differential ([`track_bds`]) and the differential steering
//! unit ([`track_dsu`]), either built from the data by [`track_steer`].
//!
//! Wiring a powertrain and the 4WD driveline into a system (one [`ShaftSystem`] item
//! holds the shafts of both), and the per-step calls:
//!
//! ```
//! use chrono_ccp::{Apgd, SolverSettings};
//! use chrono_core::{RigidBodyBuilder, System, SystemSettings};
//! use chrono_vehicle::driveline::{FourWd, FourWdParams, ShaftSystem, Wheel};
//! use chrono_vehicle::powertrain::{Powertrain, PowertrainParams};
//!
//! let mut sys = System::new(SystemSettings::default(), Box::new(Apgd::new(SolverSettings::default())))?;
//! let chassis = sys.add_body(RigidBodyBuilder::dynamic().mass(2086.52))?;
//! let spindles = [0, 1, 2, 3].map(|_| {
//!     sys.add_body(RigidBodyBuilder::dynamic().mass(14.705)).unwrap()
//! });
//! let mut shafts = ShaftSystem::new("driveline");
//! let mut powertrain = Powertrain::new(&PowertrainParams::default(), &mut shafts)?;
//! let mut driveline = FourWd::new(
//!     &FourWdParams::default(), &mut shafts, powertrain.output_shaft(), spindles, chassis)?;
//! let item = sys.add_item(Box::new(shafts));
//! for _ in 0..10 {
//!     let time = sys.time();
//!     let s = sys.item_mut::<ShaftSystem>(item).unwrap();
//!     powertrain.synchronize(time, 0.5, s)?; // throttle
//!     driveline.synchronize(0.0, s)?;        // brake pedal
//!     sys.step(1e-3)?;
//! }
//! let s = sys.item::<ShaftSystem>(item).unwrap();
//! println!("{} rpm, FL wheel {} rad/s", powertrain.engine_speed_rpm(),
//!     driveline.wheel_speed(Wheel::FrontLeft, s));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod four_wd;
pub mod shafts;
pub mod track_bds;
pub mod track_dsu;
pub mod track_steer;

pub use four_wd::{FourWd, FourWdParams, Wheel};
pub use shafts::{LinkId, LinkKind, ShaftId, ShaftSystem};
pub use track_bds::{TrackDriveline, TrackDrivelineParams, TrackSteering};
pub use track_dsu::{DsuDriveline, DsuParams};
pub use track_steer::SteeredDriveline;
