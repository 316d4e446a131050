//! A rigid HMMWV tire loaded slowly onto the granular patch of `hmmwv-granular`, with no
//! vehicle: the sinkage against load of one bed recipe by NSC or SMC contact. It separates
//! the bed's quasi-static bearing from the vehicle's dynamics (suspension, landing,
//! vibration), the open question of docs/validation-vehicle.md, "The rolling spring".
//!
//! ```text
//! cargo run --release -p chrono-vehicle --example tire_footing -- --method smc --young 2e9 --h 4e-5
//! cargo run --release -p chrono-vehicle --example tire_footing -- --method nsc --h 1e-3
//! ```
//!
//! The patch (grains of `--diameter` d, 0.08 m, `--depth` 0.24 m, 1.6 m x `--width` 1.0 m,
//! friction 0.8, restitution 0.3, `--mu-r` 0.2, `--young` E 2e7 Pa, `--spring` for SMC's
//! rolling spring) settles for `--settle` s (0.4). The tire (the HMMWV data's rigid
//! cylinder and mass, its SMC tread modulus `--tire-young` Pa, default the grains', axis along y, its rotation held by a huge inertia as a suspension
//! would) is set `--gap` m (0.002) above the surface; a downward force on it ramps from 0 to
//! `--load` N (default: a quarter of the HMMWV's weight less the tire's own) over `--ramp`
//! s (2) and is then held for `--hold` s (1). NSC steps with `chrono_ccp::LocalDirect` (the
//! tire is a heavy body on light grains). Every 0.1 s it prints the time, the sinkage
//! (surface minus the tire's lowest point, m) and the total load (N); at the end the
//! sinkage under the full load.

use std::time::Instant;

use chrono_core::contact::smc::RollingModel;
use chrono_core::descriptor::SolverSettings;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMethod, RigidBodyBuilder, System, SystemSettings};
use chrono_vehicle::hmmwv::hmmwv_data;
use chrono_vehicle::terrain::{GranularPatch, GranularPatchParams};

struct Args {
    method: ContactMethod,
    diameter: f64,
    depth: f64,
    width: f64,
    young: f64,
    tire_young: Option<f64>,
    mu_r: f64,
    spring: bool,
    h: f64,
    settle: f64,
    gap: f64,
    ramp: f64,
    hold: f64,
    load: Option<f64>,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        method: ContactMethod::Smc,
        diameter: 0.08,
        depth: 0.24,
        width: 1.0,
        young: 2e7,
        tire_young: None,
        mu_r: 0.2,
        spring: false,
        h: 2.5e-4,
        settle: 0.4,
        gap: 0.002,
        ramp: 2.0,
        hold: 1.0,
        load: None,
    };
    let v: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < v.len() {
        let key = v[i].as_str();
        if key == "--spring" {
            a.spring = true;
            i += 1;
            continue;
        }
        let val = v
            .get(i + 1)
            .ok_or_else(|| format!("option {key} needs a value"))?;
        let num = || -> Result<f64, String> {
            val.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("option {key}: not a finite number: {val}"))
        };
        match key {
            "--method" => {
                a.method = match val.as_str() {
                    "nsc" => ContactMethod::Nsc,
                    "smc" => ContactMethod::Smc,
                    _ => return Err(format!("option --method: nsc or smc, got {val}")),
                }
            }
            "--diameter" => a.diameter = num()?,
            "--depth" => a.depth = num()?,
            "--width" => a.width = num()?,
            "--young" => a.young = num()?,
            "--tire-young" => a.tire_young = Some(num()?),
            "--mu-r" => a.mu_r = num()?,
            "--h" => a.h = num()?,
            "--settle" => a.settle = num()?,
            "--gap" => a.gap = num()?,
            "--ramp" => a.ramp = num()?,
            "--hold" => a.hold = num()?,
            "--load" => a.load = Some(num()?),
            _ => return Err(format!("unknown option {key}")),
        }
        i += 2;
    }
    for (name, x) in [
        ("--h", a.h),
        ("--ramp", a.ramp),
        ("--hold", a.hold),
        ("--settle", a.settle),
    ] {
        if x <= 0.0 {
            return Err(format!("option {name} must be > 0, got {x}"));
        }
    }
    Ok(a)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a = args()?;
    let data = hmmwv_data()?;
    let mut tire = match &data.wheel.tire {
        chrono_vehicle::tire::Tire::Rigid(t) => t.clone(),
        _ => return Err("the HMMWV data's tire is not rigid".into()),
    };
    tire.young_modulus = a.tire_young.unwrap_or(a.young);
    let g = chrono_core::math::GRAVITY.norm();
    let load = a.load.unwrap_or((0.25 * data.total_mass() - tire.mass) * g);
    let settings = SystemSettings {
        contact_method: a.method,
        rolling_model: if a.spring {
            RollingModel::Spring
        } else {
            RollingModel::Relative
        },
        ..SystemSettings::default()
    };
    let solver = chrono_ccp::LocalDirect::new(SolverSettings {
        tolerance: 1e-3,
        max_iterations: 60,
        ..SolverSettings::default()
    });
    let mut sys = System::new(settings, Box::new(solver))?;
    let length = 1.6;
    let params = GranularPatchParams {
        length,
        width: a.width,
        depth: a.depth,
        grain_radius: 0.5 * a.diameter,
        density: 2500.0,
        friction: 0.8,
        young_modulus: a.young,
        restitution: 0.3,
        rolling_friction: a.mu_r,
        compliance: 0.0,
        slab: (0.1 * length).max(2.0 * a.diameter),
        seed: 7,
        lanes: Vec::new(),
    };
    let mut patch = GranularPatch::build(&mut sys, &params, -0.5 * length)?;
    let wall = Instant::now();
    for _ in 0..(a.settle / a.h).round() as usize {
        sys.step(a.h)?;
    }
    patch.capture_settled(&sys)?;
    let surface = patch.surface();
    let radius = tire.radius;
    let body = sys.add_body(
        RigidBodyBuilder::dynamic()
            .name("tire")
            .mass(tire.mass)
            // the suspension holds the wheel level: no tipping or turning
            .inertia_diagonal(Vector3::repeat(1e6))
            .position(Vector3::new(0.0, 0.0, surface + radius + a.gap))
            .collider(tire.shape(), Isometry3::identity(), tire.material()),
    )?;
    println!(
        "# {:?}, {} grains, surface {surface:.4} m, load {load:.0} N + the tire's weight {:.0} N, settled in {:.1} s",
        a.method,
        patch.grains().len(),
        tire.mass * g,
        wall.elapsed().as_secs_f64()
    );
    println!("t_s,sinkage_m,load_n");
    let steps = ((a.ramp + a.hold) / a.h).round() as usize;
    let every = (0.1 / a.h).round().max(1.0) as usize;
    let mut sinkage = 0.0;
    for k in 1..=steps {
        let t = k as f64 * a.h;
        let f = load * (t / a.ramp).min(1.0);
        sys.body_mut(body)?
            .set_applied_force(Vector3::new(0.0, 0.0, -f))?;
        sys.step(a.h)?;
        sinkage = surface - (sys.body(body)?.position().z - radius);
        if k % every == 0 {
            println!("{t:.2},{sinkage:.5},{:.0}", f + tire.mass * g);
        }
    }
    println!(
        "# sinkage under the full load after {:.2} s held: {sinkage:.5} m",
        a.hold
    );
    println!("# wall {:.1} s", wall.elapsed().as_secs_f64());
    Ok(())
}
