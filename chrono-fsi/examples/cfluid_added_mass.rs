//! The impulsive start of a sphere in a constraint fluid (chrono-fsi's `cfluid` coupling):
//! a free sphere at `v0` in a triply periodic box of fluid at rest without gravity. In an
//! incompressible inviscid fluid the first step's pressure impulse gives the sphere its
//! share of the momentum at once, `v / v0 = m / (m + C_a rho V)` with the potential-flow
//! added-mass coefficient `C_a = 1/2` of an isolated sphere (slightly more in the periodic
//! box: 4.4 % solid fraction). Prints `v / v0` after each of the first steps.
//!
//! ```text
//! cargo run --release -p chrono-fsi --example cfluid_added_mass -- [dp] [xsph] [contact_radius] [surface] [tolerance] [steps] [max_iterations] [surface_deficit]
//! ```
//! (`surface`: `one_sided`, the fluid's default, or `clamped`, every row bilateral.)

use chrono_ccp::Apgd;
use chrono_cfluid::{CfluidSettings, ConstraintFluid};
use chrono_core::density_rows::SurfaceMode;
use chrono_core::descriptor::SolverSettings;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::particles::lattice::{Fit, Lattice};
use chrono_core::{RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fsi::builder::signed_distance;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, d: &str| a.get(i).cloned().unwrap_or_else(|| d.to_string());
    let dp: f64 = arg(1, "0.02").parse()?;
    let xsph: f64 = arg(2, "0.1").parse()?;
    let contact: f64 = arg(3, "0.5").parse()?;
    let surface = SurfaceMode::parse(&arg(4, "one_sided"))?;
    let tolerance: f64 = arg(5, "1e-7").parse()?;
    let steps: usize = arg(6, "6").parse()?;
    let (side, r, rho_s) = (0.32, 0.07, 700.0);
    let settings = CfluidSettings {
        spacing: dp,
        xsph,
        contact_radius_over_dp: contact,
        body_contacts: contact > 0.0,
        surface,
        surface_deficit: arg(8, "0").parse()?,
        domain_lower: [0.0; 3],
        domain_upper: [side; 3],
        periodic: [true; 3],
        ..CfluidSettings::default()
    };
    let solver = Apgd::new(SolverSettings {
        tolerance,
        max_iterations: arg(7, "1000").parse()?,
        record_history: false,
    });
    let mut sys = System::new(
        SystemSettings {
            gravity: Vector3::zeros(),
            envelope: 0.25 * dp,
            ..SystemSettings::default()
        },
        Box::new(solver),
    )?;
    let shape = Shape::Sphere { radius: r };
    let c = 0.5 * side;
    let v0 = Vector3::new(0.1, 0.0, 0.0);
    let b = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("sphere")
            .mass_from_shape(&shape, rho_s)?
            .position(Vector3::new(c, c, c))
            .linear_velocity(v0)
            .collider(shape.clone(), Isometry3::identity(), Default::default()),
    )?;
    // carved as the floating scene is: no contact sphere overlaps the body
    let carve = (1e-6f64).max(contact - 1e-6) * dp;
    let fluid: Vec<[f64; 3]> = Lattice::new([0.0; 3], dp)?
        .fill([0.0; 3], [side; 3], Fit::Floor)?
        .into_iter()
        .filter(|q| signed_distance(&shape, [q[0] - c, q[1] - c, q[2] - c], [false; 3]) > carve)
        .collect();
    let mut item = ConstraintFluid::new("water", settings, &fluid, &[])?;
    chrono_fsi::cfluid::attach_body(&mut item, &sys, b)?;
    // the deficit `1 - rho / rho_0` of the fluid next to the body at the start, by
    // distance from its surface
    let rho = item.compute_densities()?.to_vec();
    let mut bands = [(0.0f64, 0usize, 0.0f64); 3];
    for (i, q) in fluid.iter().enumerate() {
        let d = signed_distance(&shape, [q[0] - c, q[1] - c, q[2] - c], [false; 3]) / dp;
        if d < 1.5 {
            let k = ((d - 0.5).max(0.0) / 0.5) as usize;
            let def = 1.0 - rho[i] / 1000.0;
            let band = &mut bands[k.min(2)];
            band.0 += def;
            band.1 += 1;
            band.2 = band.2.max(def);
        }
    }
    for (k, (sum, n, max)) in bands.iter().enumerate() {
        if *n > 0 {
            println!(
                "start: {n} particles {:.1}-{:.1} dp from the surface, deficit mean {:.3}, max {:.3}",
                0.5 + 0.5 * k as f64,
                1.0 + 0.5 * k as f64,
                sum / *n as f64,
                max
            );
        }
    }
    sys.add_item(Box::new(item));
    let m = sys.body(b)?.mass();
    let added = 0.5 * 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    println!(
        "{} particles; potential flow (C_a = 1/2): v / v0 = {:.4}",
        fluid.len(),
        m / (m + added)
    );
    for i in 1..=steps {
        sys.step(1e-3)?;
        let v = sys.body(b)?.linear_velocity().x / v0.x;
        println!(
            "step {i}: v / v0 = {v:.4}, effective C_a = {:.3}",
            (1.0 / v - 1.0) * m / (2.0 * added)
        );
    }
    Ok(())
}
