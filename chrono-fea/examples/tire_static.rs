//! An inflated ANCF shell tire (16 x 4 elements) on its rim pressed statically onto flat
//! frictionless ground: prints the load–deflection curve at 1.5 bar.
//!
//! `cargo run --release -p chrono-fea --example tire_static`

use chrono_fea::{BeadMount, InflatedTire, ShellMaterial, TireGeometry, TireMesh, TireOnGround};
use nalgebra::Vector3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let geometry = TireGeometry {
        centre: Vector3::zeros(),
        ring_radius: 0.28,
        section_radius: 0.08,
        bead_angle: 135f64.to_radians(),
        n_around: 16,
        n_across: 4,
        thickness: 0.004,
    };
    let tire = TireMesh::new(geometry, ShellMaterial::isotropic(1.0e8, 0.3, 1100.0)?)?;
    chrono_fea::check_fits_rim(&tire, geometry.bead_radius(), 1e-6)?;
    let inflated = InflatedTire::new(&tire, 1.5e5, BeadMount::Hinged, 4)?;
    let mut on_ground = TireOnGround::new(&tire, &inflated, BeadMount::Hinged)?;
    for load in [250.0, 500.0, 750.0, 1000.0] {
        let s = on_ground.press_to_load(load, 0.002, 1e-4)?;
        println!(
            "load = {:7.1} N  deflection = {:.4} m  nodes on the ground = {}",
            s.load, s.deflection, s.nodes_in_contact
        );
    }
    Ok(())
}
