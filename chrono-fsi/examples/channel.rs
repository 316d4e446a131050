//! The seed's channel, scaled: free ellipsoids and ANCF beams in a periodic duct flow
//! (`chrono_fsi::channel`). Prints the fluid's mean velocity, the beams' tip deflection
//! and the fluid particles found inside a solid.
//!
//! `cargo run --release -p chrono-fsi --example channel`

use chrono_fsi::channel::{ChannelParams, channel};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let p = ChannelParams::default();
    let mut s = channel(&p, Box::new(chrono_ccp::Psor::new(Default::default())))?;
    println!(
        "Re {:.1}, Re_p {:.2}, Ca {:.1}, body force {:.4} m/s^2, c_s {:.2} m/s, {} fluid particles",
        p.reynolds(),
        p.particle_reynolds(),
        p.cauchy(),
        s.body_force,
        s.sound_speed,
        s.fluid().sph().num_fluid()
    );
    for k in 1..=30 {
        s.step(p.coupling_step)?;
        if k % 10 == 0 {
            let tip = s.tip_displacement(0).unwrap_or_default();
            println!(
                "t {:.2} s: mean u {:.4} m/s, tip 0 dx {:.4} m, inside {:?}, sub-steps {}",
                s.system.time(),
                s.mean_fluid_velocity(),
                tip.x,
                s.fluid_inside(0.5 * p.spacing)?,
                s.fluid().substeps()
            );
        }
    }
    println!("{:.2} s wall for the steps", s.step_time);
    Ok(())
}
