//! A heap of 1 cm spheres left on a plate in a slot after discharge over both edges (SMC,
//! Hertz–Mindlin with rolling friction): its angle of repose, as in Zhou et al. (2002).
//!
//! `cargo run --release -p chrono-core --example heap`

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::HeapSlot;
use chrono_core::system::{ContactMethod, RollingModel};
use chrono_core::{ContactFriction, ContactMaterial, System, SystemSettings};

fn main() -> chrono_core::Result<()> {
    let settings = SystemSettings {
        contact_method: ContactMethod::Smc,
        envelope: 5e-4,
        // Zhou et al.'s rolling resistance: against each grain's own rotation.
        rolling_model: RollingModel::PerBody,
        ..SystemSettings::default()
    };
    let mut sys = System::new(settings, Box::new(Apgd::new(SolverSettings::default())))?;
    // Zhou et al.'s base case on a small plate: grains mu 0.4, walls and plate mu 0.6,
    // rolling friction 0.02 for both; a 12 d plate, a 4 d slot, a 7 d bed.
    let grains = ContactMaterial::smc(1e7, 0.3, 0.5, 0.4).with_rolling_friction(0.02);
    let slot = HeapSlot {
        plate_width: 12.0,
        bed_height: 7.0,
        wall_friction: ContactFriction {
            friction: 0.6,
            rolling_friction: 0.02,
            spinning_friction: 0.0,
        },
        t_settle: 0.3,
        t_discharge: 2.0,
        ..HeapSlot::new(0.01, grains)
    };
    let mut scene = slot.build(&mut sys)?;
    let heap = scene.run(&mut sys, |_, _| Ok::<(), chrono_core::ChronoError>(()))?;
    println!(
        "{} of {} grains stay on the plate",
        heap.on_plate, heap.grains
    );
    println!(
        "angle of repose {:.1} deg (flanks {:.1} and {:.1}), crest {:.1} d",
        heap.angle,
        heap.flanks[0],
        heap.flanks[1],
        heap.crest / slot.grain_diameter
    );
    Ok(())
}
