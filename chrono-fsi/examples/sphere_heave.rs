//! A floating hemisphere (a sphere at half the water's density) released 0.2 radii above
//! its equilibrium, at 5 spacings per diameter: its free-heave period against Hulme's
//! (1982) estimate.
//!
//! `cargo run --release -p chrono-fsi --example sphere_heave`

use chrono_ccp::Psor;
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_fsi::heave::{HeaveParams, fit_damped_oscillation, hemisphere_heave, sphere_heave};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let p = HeaveParams::default();
    let mut scene = sphere_heave(&p, Box::new(Psor::new(Default::default())))?;
    let hulme = hemisphere_heave(p.radius, GRAVITY_MAGNITUDE)?;
    let h = 1e-3;
    for _ in 0..100 {
        scene.hold(h, 20.0)?; // the fluid settles around the held sphere
    }
    let (mut t, mut z) = (vec![0.0], vec![scene.heave()?]);
    for i in 1..=(1.5 * hulme.period / h) as usize {
        scene.step(h)?;
        t.push(i as f64 * h);
        z.push(scene.heave()?);
    }
    let fit = fit_damped_oscillation(&t, &z).ok_or("no oscillation")?;
    println!(
        "period {:.4} s (Hulme {:.4} s, {:+.1} %), damping ratio {:.3} (Hulme {:.3})",
        fit.period,
        hulme.period,
        100.0 * (fit.period / hulme.period - 1.0),
        fit.zeta,
        hulme.zeta
    );
    Ok(())
}
