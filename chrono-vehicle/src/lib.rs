//! # chrono-vehicle
//!
//! Vehicles (to be built; see the chrono-vehicle issue): templates built from serde
//! descriptions (double wishbone suspension, Pitman-arm steering, 4WD driveline, engine map,
//! torque converter and transmission, brakes, tires, tracks), drivers (open loop, speed PID,
//! path follower), terrains (rigid, heightmap, granular, fluid, mud), and the HMMWV and an
//! M113-like tracked vehicle built from them.
