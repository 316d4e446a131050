//! The torque balance behind a free body's spin in shear: the fluid's mean torque on a
//! sphere (`r` = 1, or a spheroid of aspect ratio `r`) held at the spins 0, 0.5 and 0.66
//! `gamma` in the shear cell of `chrono_fsi::jeffery`, over the second half of 200
//! coupling steps, in units of Stokes' `4 pi mu a^3 gamma`. A free sphere turns where it
//! vanishes (Stokes: at `gamma / 2`; the torque falls by `8 pi mu a^3` per rad/s).
//!
//! `cargo run --release -p chrono-fsi --example jeffery_torque [a/dp] [r]`
use chrono_ccp::Psor;
use chrono_core::math::Vector3;
use chrono_fsi::jeffery::{JefferyParams, jeffery_scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let n: f64 = args.next().map_or(Ok(4.0), |s| s.parse())?;
    let r: f64 = args.next().map_or(Ok(1.0), |s| s.parse())?;
    for w in [0.0, 0.5, 0.66] {
        let mut p = JefferyParams::default();
        p.spacing = p.semi_axis / n;
        p.aspect_ratio = r;
        let mut s = jeffery_scene(&p, Box::new(Psor::new(Default::default())))?;
        let h = p.spin_time();
        let mut tq = 0.0;
        let m = 200;
        for i in 0..m {
            s.system
                .body_mut(s.body)?
                .set_angular_velocity(Vector3::new(0.0, w, 0.0))?;
            s.system
                .body_mut(s.body)?
                .set_linear_velocity(Vector3::zeros())?;
            s.system.step(h)?;
            if i >= m / 2 {
                tq += s.fluid().body_load(s.body).unwrap()[1].y;
            }
        }
        tq /= (m / 2) as f64;
        let a = p.semi_axis;
        println!(
            "spin {w}: torque {tq:.4e} N m = {:.4} x 4 pi mu a^3 gamma (t = {:.3} s)",
            tq / (4.0 * std::f64::consts::PI * p.viscosity * a.powi(3) * p.shear_rate),
            s.system.time()
        );
    }
    Ok(())
}
