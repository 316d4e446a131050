//! The explicit coupling's stability limit, measured: a light sphere (density ratio
//! `ratio` to the fluid, added mass `rho V / 2` in unbounded fluid, so `m_a / m = 0.5 /
//! ratio`) moving through a triply periodic box of fluid, stepped with multibody steps of
//! `k` fluid sub-steps. Prints, per `(ratio, k)`, the largest body speed over the run
//! relative to the start: bounded (the fluid slows the sphere) or growing (the staggered
//! coupling's added-mass instability).
//!
//! `cargo run --release -p chrono-fsi --example coupling_stability`

use chrono_ccp::Psor;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fsi::{FsiBuilder, SphFluid};
use chrono_sph::SphSettings;

fn run(ratio: f64, substeps: f64) -> Result<(f64, u64), String> {
    let (dp, l, rho) = (0.02, 0.36, 1000.0);
    let settings = SphSettings {
        spacing: dp,
        sound_speed: 10.0,
        viscosity: 1e-3,
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        gravity: [0.0; 3],
        ..SphSettings::default()
    };
    let s = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut sys =
        System::new(s, Box::new(Psor::new(Default::default()))).map_err(|e| e.to_string())?;
    let ball = Shape::Sphere { radius: 0.07 };
    let v0 = Vector3::new(0.5, 0.0, 0.0);
    let b = sys
        .add_body(
            RigidBodyBuilder::dynamic()
                .mass_from_shape(&ball, ratio * rho)
                .map_err(|e| e.to_string())?
                .position(Vector3::repeat(0.5 * l))
                .linear_velocity(v0)
                .collider(ball, Isometry3::identity(), Default::default()),
        )
        .map_err(|e| e.to_string())?;
    let mut fsi = FsiBuilder::new(settings).map_err(|e| e.to_string())?;
    fsi.add_fluid_box([0.0; 3], [l; 3], None)
        .map_err(|e| e.to_string())?;
    fsi.add_body(&sys, b).map_err(|e| e.to_string())?;
    let item = sys.add_item(Box::new(fsi.build("water", 1).map_err(|e| e.to_string())?));
    // the fluid's own step, from its first evaluation
    let dt = {
        let f = sys.item_mut::<SphFluid>(item).unwrap();
        f.sph_mut().initialize().map_err(|e| e.to_string())?;
        f.sph().dt()
    };
    let h = substeps * dt;
    let t_end = 0.2;
    let mut vmax: f64 = 0.0;
    while sys.time() < t_end {
        sys.step(h).map_err(|e| e.to_string())?;
        let v = sys.body(b).unwrap().linear_velocity().norm() / v0.norm();
        if !v.is_finite() || v > 100.0 {
            return Ok((f64::INFINITY, sys.step_count()));
        }
        vmax = vmax.max(v);
    }
    Ok((vmax, sys.step_count()))
}

fn main() {
    println!("ratio  m_a/m  substeps_per_step  max |v|/v0  steps");
    for ratio in [1.0, 0.5, 0.2, 0.1, 0.05] {
        for k in [1.0, 4.0, 16.0, 64.0] {
            match run(ratio, k) {
                Ok((v, n)) => println!("{ratio:5}  {:5.1}  {k:17}  {v:10.3}  {n}", 0.5 / ratio),
                Err(e) => println!("{ratio:5}  {:5.1}  {k:17}  error: {e}", 0.5 / ratio),
            }
        }
    }
}
