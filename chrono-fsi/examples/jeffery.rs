//! A prolate spheroid (`r = 2`) in simple shear between two moving-belt walls at the
//! coarse default resolution (4 spacings on the major semi-axis): its axis angle over a
//! bit more than a quarter of Jeffery's period, and the period fitted to it.
//!
//! `cargo run --release -p chrono-fsi --example jeffery [spacings_per_semi_axis] [fraction_of_period] [aspect_ratio] [length] [width] [gap]`

use chrono_ccp::Psor;
use chrono_fsi::jeffery::{JefferyParams, fit_jeffery_orbit, jeffery_scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let n: f64 = args.next().map_or(Ok(4.0), |s| s.parse())?;
    let fraction: f64 = args.next().map_or(Ok(0.3), |s| s.parse())?;
    let mut p = JefferyParams::default();
    p.spacing = p.semi_axis / n;
    // further arguments: aspect ratio, length and width of the cell in major axes, gap
    for (k, v) in args.enumerate() {
        let v: f64 = v.parse()?;
        match k {
            0 => p.aspect_ratio = v,
            1 => p.length = v,
            2 => p.width = v,
            _ => p.gap = v,
        }
    }
    let mut scene = jeffery_scene(&p, Box::new(Psor::new(Default::default())))?;
    let t_j = p.period();
    let steps = (fraction * t_j / p.spin_time()).ceil() as usize;
    let h = fraction * t_j / steps as f64;
    let (mut t, mut theta) = (vec![0.0], vec![scene.angle()]);
    let start = std::time::Instant::now();
    for i in 1..=steps {
        scene.system.step(h)?;
        let a = scene.angle();
        let last = theta[theta.len() - 1];
        // unwrap
        theta.push(
            last + (a - last + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI)
                - std::f64::consts::PI,
        );
        t.push(i as f64 * h);
        if i % (steps / 10).max(1) == 0 {
            println!(
                "t {:.3} s: angle {:.4} rad, out of plane {:.1e}, centre moved {:.1e} m",
                t[i],
                theta[i],
                scene.out_of_plane(),
                (scene.centre() - scene.centre0).norm()
            );
        }
    }
    {
        // diagnostic: the fluid's shear rate (least squares of u_x on z) and the spin
        let d = scene.fluid().sph().data();
        let zc = scene.centre0.z;
        let (mut szz, mut szu) = (0.0, 0.0);
        for i in 0..d.len() {
            if d.kind[i] == chrono_sph::data::FLUID {
                let z = d.z[i] - zc;
                szz += z * z;
                szu += z * d.vx[i];
            }
        }
        println!(
            "fluid shear rate {:.5} 1/s, spin {:.5} rad/s, wall stress / mu gamma {:.4}",
            szu / szz,
            scene.angular_velocity().y,
            scene.wall_shear_stress() / (p.viscosity * p.shear_rate)
        );
    }
    let fit = fit_jeffery_orbit(&t, &theta, t_j, p.aspect_ratio, true)?;
    println!(
        "a / dp {n}: period {:.4} s (Jeffery {:.4} s, {:+.2} %), fitted r {:.4}, t0 {:.4} s, residual {:.2e} rad, {} fluid particles, {} fluid steps, {:.1} s",
        fit.period,
        t_j,
        100.0 * (fit.period / t_j - 1.0),
        fit.aspect_ratio,
        fit.t0,
        fit.residual,
        scene.fluid().sph().num_fluid(),
        scene.fluid().substeps(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
