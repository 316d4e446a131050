//! A rigid wheel at 20 % slip on a granular slab (SMC): sinkage, drawbar pull, torque.
//!
//! `cargo run --release -p chrono-core --example wheel_bin [grain_diameter [slip]]`

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::WheelBin;
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, System, SystemSettings};

fn main() -> chrono_core::Result<()> {
    let arg = |i: usize, default: f64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(default)
    };
    // Glass beads of the shear box (mu 0.18, E reduced to 4e7 Pa), a 0.25 m wheel of
    // 0.15 m under 400 N, a bed of 1500 kg/m^3.
    let beads = ContactMaterial::smc(4e7, 0.22, 0.87, 0.18);
    let spec = WheelBin {
        rim_friction: 30f64.to_radians().tan(),
        slab_thickness: arg(3, 4.0) * arg(1, 0.025),
        ..WheelBin::new(0.25, 0.15, 400.0, arg(2, 0.2), arg(1, 0.025), 1500.0, beads)
    };
    let system = |v: f64| {
        let mut settings = SystemSettings {
            contact_method: ContactMethod::Smc,
            ..SystemSettings::default()
        };
        settings.smc.characteristic_velocity = v;
        System::new(settings, Box::new(Apgd::new(SolverSettings::default())))
    };
    let t = std::time::Instant::now();
    let bed = spec.prepare(&mut system(1.0)?)?;
    println!(
        "{} grains settled in {:.2} s (wall {:.1} s), solid fraction {:.3}, grain density {:.0}",
        bed.grains.len(),
        bed.time,
        t.elapsed().as_secs_f64(),
        bed.solid_fraction,
        bed.grain_density
    );
    let t = std::time::Instant::now();
    let run = spec.run(&mut system(spec.rim_speed)?, &bed, |_| {})?;
    println!(
        "bed depth {:.3} m (roughness {:.4}), bulk density {:.0} kg/m^3, h {:.2e} s, {} steps, wall {:.1} s",
        run.surface,
        run.roughness,
        run.bulk_density,
        run.h,
        run.steps,
        t.elapsed().as_secs_f64()
    );
    println!(
        "static sinkage {:.4} m; sinkage {:.4} m, DP/W {:.3}, T/(W R) {:.3}, F_z/W {:.3}",
        run.static_sinkage,
        run.sinkage,
        run.drawbar_pull / spec.load,
        run.torque / (spec.load * spec.wheel_radius),
        run.vertical_force / spec.load
    );
    for s in run.samples.iter().step_by(10) {
        println!(
            "t {:.3} x {:.3} z {:.4} DP {:.1} T {:.1} Fz {:.1}",
            s.t, s.travel, s.sinkage, s.drawbar_pull, s.torque, s.vertical_force
        );
    }
    Ok(())
}
