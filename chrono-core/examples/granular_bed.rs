//! A bed of glass beads poured into a box and settled (NSC): its height and solid fraction.
//!
//! `cargo run --release -p chrono-core --example granular_bed`

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::probe::{bulk_density, surface_height};
use chrono_core::granular::{GrainBed, Region, Settle, add_box_container};
use chrono_core::math::Vector3;
use chrono_core::{ContactMaterial, System, SystemSettings};

fn main() -> chrono_core::Result<()> {
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-5,
        max_iterations: 60,
        record_history: false,
    });
    let mut sys = System::new(SystemSettings::default(), Box::new(solver))?;
    // 4 x 4 cm box, beads of 3.6-4 mm diameter, glass.
    let (r, half, density) = (0.002, 0.02, 2500.0);
    let glass = ContactMaterial::smc(1e7, 0.3, 0.5, 0.5);
    let (lower, upper) = (
        Vector3::new(-half, -half, 0.0),
        Vector3::new(half, half, 0.1),
    );
    add_box_container(&mut sys, "box", lower, upper, glass)?;
    let fill = Region::Box {
        lower,
        upper: Vector3::new(half, half, 0.05),
    };
    let spec = GrainBed {
        settle: Settle::KineticEnergy {
            below: 1e-4,
            check_every: 0.01,
            not_before: 0.2,
            timeout: 3.0,
        },
        ..GrainBed::new(fill, 0.9 * r, r, density, glass)
    };
    let (bed, settled) = spec.build(&mut sys)?;

    // Measure: the surface (columns one grain wide, one grain from the walls) and the
    // solid fraction in a band below it.
    let grains: Vec<_> = bed
        .grains(&sys)?
        .iter()
        .map(|g| (g.center, g.radius))
        .collect();
    let (height, roughness) = surface_height(&grains, half, 2.0 * r, 2.0 * r);
    let band = Region::Box {
        lower: Vector3::new(-half + 2.0 * r, -half + 2.0 * r, 2.0 * r),
        upper: Vector3::new(half - 2.0 * r, half - 2.0 * r, height - 2.0 * r),
    };
    let mass = |r: f64| density * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let rho = bulk_density(grains.iter().map(|&(x, r)| (x, mass(r))), &band);
    println!("{} grains settled in {:.2} s", bed.len(), settled.time);
    println!(
        "bed height {:.1} mm (roughness {:.2} mm)",
        height * 1e3,
        roughness * 1e3
    );
    println!("solid fraction {:.3}", rho / density);
    Ok(())
}
