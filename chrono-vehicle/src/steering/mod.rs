//! Steering templates: [`pitman_arm`].

pub mod pitman_arm;

pub use pitman_arm::{PitmanArm, PitmanArmData};
