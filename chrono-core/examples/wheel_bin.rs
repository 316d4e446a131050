//! A rigid wheel at 20 % slip on a granular slab (SMC): sinkage, drawbar pull, torque.
//!
//! `cargo run --release -p chrono-core --example wheel_bin [grain_diameter [slip]]`

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::WheelBin;
use chrono_core::{ContactMaterial, ContactMethod, System, SystemSettings};

fn main() -> chrono_core::Result<()> {
    let arg = |i, v: f64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(v)
    };
    // The glass beads of the shear box (mu 0.18); a 0.25 m wheel, 0.15 m wide, 400 N, on a
    // bed of 1500 kg/m^3, rim friction tan 30 deg, a slab 3 d thick.
    let beads = ContactMaterial::smc(4e7, 0.22, 0.87, 0.18);
    let d = arg(1, 0.04);
    let spec = WheelBin {
        rim_friction: 30f64.to_radians().tan(),
        slab_thickness: 3.0 * d,
        ..WheelBin::new(0.25, 0.15, 400.0, arg(2, 0.2), d, 1500.0, beads)
    };
    let system = |v: f64| {
        let mut s = SystemSettings {
            contact_method: ContactMethod::Smc,
            ..Default::default()
        };
        s.smc.characteristic_velocity = v; // the rim speed bounds the run's impacts
        System::new(s, Box::new(Apgd::new(SolverSettings::default())))
    };
    let bed = spec.prepare(&mut system(1.0)?)?;
    let run = spec.run(&mut system(spec.rim_speed)?, &bed, |_| {})?;
    let (w, r) = (spec.load, spec.wheel_radius);
    println!(
        "{} grains, solid fraction {:.3}, bulk density {:.0} kg/m^3",
        run.grains, bed.solid_fraction, run.bulk_density
    );
    println!(
        "static sinkage {:.4} m; at slip {}: sinkage {:.4} m, DP/W {:.3}, T/(W R) {:.3}, F_z/W {:.3}",
        run.static_sinkage,
        spec.slip,
        run.sinkage,
        run.drawbar_pull / w,
        run.torque / (w * r),
        run.vertical_force / w
    );
    Ok(())
}
