//! The driveline: shafts with inertia in the system's CCP ([`shafts`]: gears,
//! differentials with optional locking, clutches and brakes, couplings to the wheel
//! spindles) and the HMMWV's 4WD layout ([`four_wd`]).

pub mod four_wd;
pub mod shafts;

pub use four_wd::{FourWd, FourWdParams, Wheel};
pub use shafts::{LinkId, LinkKind, ShaftId, ShaftSystem};
