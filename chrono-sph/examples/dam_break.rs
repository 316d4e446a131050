//! Dam break (Martin and Moyce 1952) with explicit WCSPH: a square water column
//! collapses in a quasi-2D tank; prints the surge front `x` along the floor against time,
//! in Martin and Moyce's scaling `Z = x / a`, `T = t sqrt(2 g / a)` (their measured front
//! reaches `Z ~ 2.4` at `T = 2` and `Z ~ 3.5` at `T = 3`; this coarse run, `dp = a / 12`,
//! lags a little behind).
//!
//! `cargo run --release -p chrono-sph --example dam_break`

use chrono_core::math::GRAVITY;
use chrono_core::particles::lattice::SlabTank;
use chrono_sph::{SphSettings, data::FLUID, scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (a, g) = (0.06, -GRAVITY.z); // column width and height (m), |g| (m/s^2)
    let dp = a / 12.0;
    let h_over_dp = SphSettings::default().h_over_dp;
    let tank = SlabTank::dam_break(dp, h_over_dp, [a, a], 5.0 * a, 1.25 * a);
    let settings = SphSettings {
        sound_speed: 10.0 * (2.0 * g * a).sqrt(),
        artificial_viscosity: 0.03,
        xsph: 0.5,
        ..SphSettings::default()
    };
    let mut sys = scene::slab_tank(settings, &tank)?;
    let t_scale = (2.0 * g / a).sqrt();
    for k in 1..=6 {
        let t_end = 0.5 * k as f64 / t_scale; // T = 0.5, 1, ..., 3
        while sys.time() < t_end {
            sys.step()?;
        }
        let d = sys.data();
        let front = (0..d.len())
            .filter(|&i| d.kind[i] == FLUID && d.z[i] < 2.0 * dp)
            .map(|i| d.x[i] + 0.5 * dp)
            .fold(0.0, f64::max);
        let t = sys.time();
        println!(
            "t = {t:.4} s  T = {:.2}  front x = {front:.4} m  Z = {:.2}",
            t * t_scale,
            front / a
        );
    }
    Ok(())
}
