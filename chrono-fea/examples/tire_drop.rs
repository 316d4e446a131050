//! A pressurized ANCF shell tire (16 x 4 elements) on a 100 kg rigid rim dropped 5 mm
//! onto rigid ground: prints the rim height and speed as it bounces and settles.
//!
//! `cargo run --release -p chrono-fea --example tire_drop`

use chrono_ccp::{Schur, SolverSettings};
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fea::{BeadMount, InflatedTire, ShellItem, ShellMaterial, TireGeometry, TireMesh};

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
    let inflated = InflatedTire::new(&tire, 1.5e5, BeadMount::Hinged, 4)?;
    let (r_contact, ground) = (0.002, ContactMaterial::with_friction(0.8));
    let lift = -inflated.lowest_z() + r_contact + 0.005;
    let settings = SolverSettings {
        tolerance: 1e-10,
        max_iterations: 2000,
        record_history: false,
    };
    let mut sys = System::new(SystemSettings::default(), Box::new(Schur::new(settings)))?;
    let half_space = Shape::HalfSpace {
        normal: Vector3::z(),
    };
    sys.add_body(RigidBodyBuilder::fixed().collider(half_space, Isometry3::identity(), ground))?;
    let (rim_at, r) = (Vector3::new(0.0, 0.0, lift), geometry.bead_radius());
    let rim = sys.add_body(
        RigidBodyBuilder::dynamic()
            .mass(100.0)
            .inertia_diagonal(Vector3::new(0.5, 1.0, 0.5) * (100.0 * r * r))
            .position(rim_at),
    )?;
    let mut item = ShellItem::new("tire", inflated.lifted(lift)?)?;
    item.set_damping(0.02)?;
    item.set_contact_spheres(r_contact, ground)?;
    chrono_fea::mount_on_rim(&mut item, &tire.beads, rim, rim_at, BeadMount::Hinged)?;
    sys.add_item(Box::new(item));
    for step in 1..=150 {
        sys.step(4e-3)?;
        if step % 25 == 0 {
            let b = sys.body(rim)?;
            let (z, vz) = (b.position().z, b.linear_velocity().z);
            println!(
                "t = {:.2} s  rim height = {z:.4} m  vz = {vz:+.4} m/s",
                sys.time()
            );
        }
    }
    println!(
        "static deflection = {:.4} m",
        lift - 0.005 - sys.body(rim)?.position().z
    );
    Ok(())
}
