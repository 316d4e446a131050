//! The HMMWV (handling tires) on flat rigid ground, driven straight at 5 m/s by a speed
//! controller for 4 s: prints its speed and position every half second.
//!
//! `cargo run --release -p chrono-vehicle --example hmmwv_flat`

use chrono_ccp::{Schur, SolverSettings};
use chrono_vehicle::DriverInputs;
use chrono_vehicle::driver::{PidGains, SpeedController};
use chrono_vehicle::hmmwv::{TireKind, hmmwv_data_with};
use chrono_vehicle::scene::FlatScene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let settings = SolverSettings {
        tolerance: 1e-8,
        max_iterations: 500,
        record_history: false,
    };
    let data = hmmwv_data_with(TireKind::Handling)?;
    let mut scene = FlatScene::new(data, 0.9, Box::new(Schur::new(settings)))?;
    let mut speed = SpeedController::new(PidGains::hmmwv_speed(), 5.0)?;
    let h = 1e-3;
    for step in 1..=4000 {
        let s = scene.vehicle.state(&scene.sys)?;
        let (throttle, brake) = SpeedController::pedals(speed.advance(s.time, s.forward_speed()));
        let inputs = DriverInputs {
            throttle,
            brake,
            steering: 0.0,
        };
        scene.step(inputs, h)?;
        if step % 500 == 0 {
            let s = scene.vehicle.state(&scene.sys)?;
            let (x, y) = (s.position.x, s.position.y);
            let v = s.forward_speed();
            println!(
                "t = {:.1} s  speed = {v:.2} m/s  x = {x:.2} m  y = {y:.3} m",
                s.time
            );
        }
    }
    Ok(())
}
