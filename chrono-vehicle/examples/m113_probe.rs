//! Step the shoe-by-shoe M113A1 on flat ground (sprockets held) and print each step's cost,
//! contact count, solver residual, chassis height and joint drift: the probe behind the
//! M113 section of `docs/validation-vehicle.md`.
//!
//! `cargo run --release -p chrono-vehicle --example m113_probe -- [h] [steps] [solver]
//! [max_iterations] [compliance] [torsion_preload]`
//!
//! With `CENSUS=1` the last step's contacts are counted by body pair (names without their
//! indices): how many rows each kind of contact puts into the problem.
//!
//! With `RAMP=a` (rad/s^2) in the environment the sprockets are held for 0.5 s, then driven
//! at the prescribed speed `a (t - 0.5)` (both sides): the chassis' forward speed is printed
//! against the sprocket's pitch-circle speed `w r_p`, which shows whether the chain follows
//! the sprocket at every speed.

use std::time::Instant;

use chrono_core::Drive;
use chrono_core::descriptor::SolverSettings;
use chrono_vehicle::m113::m113_data;
use chrono_vehicle::state::DriverInputs;
use chrono_vehicle::tracked::TrackedFlatScene;
use chrono_vehicle::tracked_drive::TrackedDrive;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or(default.to_string());
    let h: f64 = arg(1, "2e-3").parse()?;
    let n: usize = arg(2, "300").parse()?;
    let solver = arg(3, "apgd");
    let max_iterations: usize = arg(4, "200").parse()?;
    let compliance: f64 = arg(5, "0").parse()?;
    let mut d = m113_data()?;
    d.track.materials.shoe.compliance = compliance;
    d.track.materials.wheel.compliance = compliance;
    if let Some(t) = args.get(6) {
        d.track.road_wheels.torsion_bar.preload = t.parse()?;
    }
    // `MU_WHEEL=x`: the friction of the wheels' and sprocket's material (for a test).
    if let Ok(m) = std::env::var("MU_WHEEL") {
        d.track.materials.wheel.friction = m.parse()?;
    }
    let settings = SolverSettings {
        tolerance: 1e-8,
        max_iterations,
        record_history: false,
    };
    // `schur-mf`: the Schur solver with its contact complement always matrix-free.
    let solver: Box<dyn chrono_core::descriptor::CcpSolver> = if solver == "schur-mf" {
        Box::new(chrono_ccp::Schur::new(settings).with_max_dense_rows(0))
    } else {
        chrono_ccp::by_name(&solver, settings)?
    };
    let mut sc = TrackedFlatScene::new(d, 0.8, solver)?;
    for side in &sc.vehicle.sides {
        println!(
            "side {}: {} shoes, idler offset {:.4} m, loop {:.4} m, closure {:.1e} m",
            side.side,
            side.shoes.len(),
            side.layout.idler_offset,
            side.layout.loop_length,
            side.layout.closure_error
        );
    }
    sc.vehicle
        .set_sprocket_drives(&mut sc.sys, Drive::Speed(0.0))?;
    let ramp: Option<f64> = std::env::var("RAMP").ok().map(|s| s.parse()).transpose()?;
    let power: Option<f64> = std::env::var("POWER").ok().map(|s| s.parse()).transpose()?;
    let mut drive = match power {
        Some(_) => Some(TrackedDrive::build(&mut sc.sys, &sc.vehicle, &sc.data)?),
        None => None,
    };
    let r_p = sc.data.track.sprocket.pitch_radius;
    let every = (n / 40).max(1);
    for i in 0..n {
        let w = ramp.map_or(0.0, |a| (a * (sc.sys.time() - 0.5)).max(0.0));
        if ramp.is_some() {
            sc.vehicle
                .set_sprocket_drives(&mut sc.sys, Drive::Speed(w))?;
        }
        if let (Some(d), Some(th)) = (drive.as_mut(), power) {
            let on = sc.sys.time() >= 0.5;
            let inputs = DriverInputs {
                throttle: if on { th } else { 0.0 },
                brake: if on { 0.0 } else { 1.0 },
                steering: 0.0,
            };
            d.synchronize(&mut sc.sys, inputs)?;
        }
        let t = Instant::now();
        let r = sc.sys.step(h);
        let dt = t.elapsed().as_secs_f64();
        let c = sc.sys.body(sc.vehicle.chassis)?;
        match r {
            Ok(_) if drive.is_some() && i % every == 0 => {
                let (seated, offset, near) = engagement(&sc)?;
                let near: Vec<String> = near
                    .iter()
                    .map(|(a, l)| format!("{a:.0}:{:.0}", 1e3 * l))
                    .collect();
                let d = drive.as_ref().expect("checked");
                println!(
                    "t {:.3}: vx {:.3} m/s, sprocket {:.3} rad/s ({:.3} m/s at r_p), \
                     torque {:.0} N m, {seated} pins seated (offset up to {:.1} mm), near \
                     (world angle deg: lift mm) {}",
                    sc.sys.time(),
                    c.linear_velocity().x,
                    d.sprocket_speed(&sc.sys, 0),
                    d.sprocket_speed(&sc.sys, 0) * r_p,
                    d.sprocket_torque(&sc.sys, 0),
                    1e3 * offset,
                    near.join(" ")
                );
            }
            Ok(r) if std::env::var("CENSUS").is_ok() && i + 1 == n => {
                println!("step {i}: {} contacts, {} rows", r.contacts, r.rows);
                for ((a, b), k) in census(&sc) {
                    println!("  {a} - {b}: {k}");
                }
            }
            Ok(r) if i % every == 0 || i + 1 == n => println!(
                "step {i}: {dt:.3} s, {} contacts, {} rows, {} iterations, residual {:.1e}, \
                 chassis z {:.4} m, vz {:.4} m/s, vx {:.4} m/s against w r_p {:.4} m/s, \
                 joint drift {:.1e} m",
                r.contacts,
                r.rows,
                r.solve.iterations,
                r.solve.residual,
                c.position().z,
                c.linear_velocity().z,
                c.linear_velocity().x,
                w * r_p,
                sc.sys.max_joint_violation()
            ),
            Ok(_) => {}
            Err(e) => {
                println!("step {i}: {e}");
                break;
            }
        }
    }
    Ok(())
}

/// The last step's contacts counted by the pair of body names, each name without its
/// `[k]` index.
fn census(sc: &TrackedFlatScene) -> std::collections::BTreeMap<(String, String), usize> {
    let kind = |owner: u32| -> String {
        let name = sc
            .sys
            .bodies()
            .get(owner as usize)
            .map_or("?", |b| b.name());
        match name.find('[') {
            Some(k) => name[..k].to_string(),
            None => name.to_string(),
        }
    };
    let mut m = std::collections::BTreeMap::new();
    for c in sc.sys.contacts() {
        *m.entry((kind(c.point.owner_a), kind(c.point.owner_b)))
            .or_insert(0) += 1;
    }
    m
}

/// Seated pins, the largest offset of a seated pin in its gap (m), and `(angle deg, lift
/// m)` of every pin near the sprocket.
type Engagement = (usize, f64, Vec<(f64, f64)>);

/// The left sprocket's pins near it (centres within the tip radius plus a pin radius of the
/// sprocket centre, in the track plane): how many are seated (centre within 5 mm of the
/// pitch circle), the largest tangential offset of a seated one from the centre of its
/// tooth gap (m), and every near pin's lift above the pitch circle (m) by angle.
fn engagement(sc: &TrackedFlatScene) -> Result<Engagement, Box<dyn std::error::Error>> {
    let side = &sc.vehicle.sides[0];
    let t = &sc.data.track;
    let (r_p, tau) = (
        t.sprocket.pitch_radius,
        std::f64::consts::TAU / t.sprocket.num_teeth as f64,
    );
    let sp = sc.sys.body(side.sprocket)?;
    let (c, rot) = (sp.position(), sp.rotation());
    let (mut seated, mut offset, mut near) = (0, 0.0f64, Vec::new());
    for &b in &side.shoes {
        let shoe = sc.sys.body(b)?;
        let pin = shoe.position()
            + shoe.rotation() * chrono_core::math::Vector3::new(0.5 * t.shoe.pitch, 0.0, 0.0);
        let world = pin - c;
        let local = rot.inverse() * world;
        let r = local.x.hypot(local.z);
        if r > t.sprocket.tip_radius + t.shoe.pin_radius {
            continue;
        }
        near.push((world.z.atan2(world.x).to_degrees(), r - r_p));
        if (r - r_p).abs() < 5e-3 {
            let a = local.z.atan2(local.x) - side.layout.sprocket_start_angle;
            let k = (a / tau).round();
            seated += 1;
            offset = offset.max(((a - k * tau) * r_p).abs());
        }
    }
    near.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok((seated, offset, near))
}
