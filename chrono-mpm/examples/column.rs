//! A granular column collapsing on a rough floor in a slab (`chrono_mpm::column`): prints
//! the runout and final height against time and at rest.
//!
//! `cargo run --release -p chrono-mpm --example column [aspect_ratio [friction_angle_deg [cells_length [markers_per_cell [young [floor_friction_angle_deg (-1 sticky) [f_bar (0 off, 1 increment) [cfl [cohesion [associated (0 or 1) [flip [geostatic (0 or 1) [grain_diameter (mu(I), 0 off) [split (0 plain, 1 pressure rows) [rheology (0 Drucker-Prager, 1 critical-state glass beads; grain_diameter then the beads') [dilatancy K_d of the beads (< 0: Pailha & Pouliquen's)]]]]]]]]]]]]]]]]`

use chrono_mpm::column::{Column, ColumnSpec};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: f64| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let d = ColumnSpec::default();
    let spec = ColumnSpec {
        aspect_ratio: arg(1, d.aspect_ratio)?,
        friction_angle_deg: arg(2, d.friction_angle_deg)?,
        cells_length: arg(3, d.cells_length as f64)? as usize,
        markers_per_cell: arg(4, d.markers_per_cell as f64)? as usize,
        young: arg(5, d.young)?,
        cfl: arg(8, d.cfl)?,
        cohesion: arg(9, 0.0)?,
        associated_flow: arg(10, 0.0)? > 0.0,
        flip: arg(11, 0.0)?,
        geostatic: arg(12, 0.0)? > 0.0,
        // the critical-state glass beads (Jop et al.'s grain diameter unless arg 13 > 0)
        critical_state: match (arg(15, 0.0)? > 0.0, arg(13, 0.0)?) {
            (false, _) => None,
            (true, diameter) => {
                let beads =
                    chrono_mpm::CriticalStateSand::glass_beads(arg(5, d.young)?, d.poisson, 0.6)?;
                Some(chrono_mpm::CriticalStateSand {
                    grain_diameter: if diameter > 0.0 {
                        diameter
                    } else {
                        beads.grain_diameter
                    },
                    dilatancy: match arg(16, -1.0)? {
                        k if k >= 0.0 => k,
                        _ => beads.dilatancy,
                    },
                    ..beads
                })
            }
        },
        mu_i: match arg(13, 0.0)? {
            d if d > 0.0 && arg(15, 0.0)? <= 0.0 => Some(chrono_mpm::MuI {
                grain_diameter: d,
                ..chrono_mpm::MuI::jop_2006()
            }),
            _ => None,
        },
        floor_friction_angle_deg: match arg(6, arg(2, 30.0)?)? {
            f if f < 0.0 => None,
            f => Some(f),
        },
        f_bar: if arg(7, 0.0)? > 0.0 {
            chrono_mpm::FBar::Increment
        } else {
            chrono_mpm::FBar::Off
        },
        ..d
    };
    let mut c = Column::new(spec)?;
    if arg(14, 0.0)? > 0.0 {
        c.use_pressure_rows(1e-6)?;
    }
    let x0 = c.body.markers.x.clone();
    let start = std::time::Instant::now();
    // COLUMN_I_AT="1,2,3": the inertial number of the flowing markers at these times (in
    // sqrt(H0/g)), from the APIC velocity gradient C_p and the marker's pressure
    if let (Ok(times), chrono_mpm::Material::CriticalState(m)) =
        (std::env::var("COLUMN_I_AT"), *c.body.material())
    {
        for t in times.split(',') {
            let t: f64 = t.trim().parse::<f64>()? * c.time_scale();
            while c.body.time() < t {
                let dt = c.body.stable_dt();
                c.body.step(dt)?;
            }
            let mk = &c.body.markers;
            let mut is = Vec::new();
            for p in 0..mk.len() {
                let d = 0.5 * (mk.c[p] + mk.c[p].transpose());
                let dev = d - nalgebra::Matrix3::identity() * (d.trace() / 3.0);
                let rate = 2.0f64.sqrt() * dev.norm();
                let tau = c.body.material().kirchhoff(&mk.fe[p], &mk.fp[p]);
                let pressure = -tau.trace() / 3.0 / mk.fe[p].determinant();
                if rate > 1.0 && pressure > 0.0 {
                    is.push(rate * m.grain_diameter / (pressure / m.grain_density).sqrt());
                }
            }
            is.sort_by(f64::total_cmp);
            let q = |f: f64| is.get(((is.len() as f64 - 1.0) * f) as usize).copied();
            println!(
                "t/tau {:.2}: {} of {} markers shear faster than 1/s; their I: 10 % {:.2e}, median {:.2e}, 90 % {:.2e}",
                c.body.time() / c.time_scale(),
                is.len(),
                mk.len(),
                q(0.1).unwrap_or(f64::NAN),
                q(0.5).unwrap_or(f64::NAN),
                q(0.9).unwrap_or(f64::NAN)
            );
        }
    }
    let r = c.run(|_| {})?;
    let (l0, h0) = (spec.column_length, c.initial_height());
    for s in r.samples.iter().step_by(25) {
        println!(
            "t/tau {:6.2}  (L - L0)/L0 {:.4}  H/H0 {:.4}  KE/(M g H0) {:.3e}",
            s.t / c.time_scale(),
            (s.front - l0) / l0,
            s.height / h0,
            s.kinetic / (c.body.markers.mass.iter().sum::<f64>() * spec.gravity * h0)
        );
    }
    let pe: f64 = c
        .body
        .markers
        .x
        .iter()
        .zip(&c.body.markers.mass)
        .map(|(x, m)| m * spec.gravity * x.z)
        .sum();
    println!(
        "final energy: kinetic {:.4e} elastic {:.4e} potential {:.4e} J",
        c.body.kinetic_energy(),
        c.body.elastic_energy(),
        pe
    );
    println!(
        "a {}: runout ratio {:.4}, final height ratio {:.4}, at rest {} at t/tau {:.2}; {} markers, {} steps in {:.2} s",
        spec.aspect_ratio,
        r.runout_ratio,
        r.final_height_ratio,
        r.at_rest,
        r.time / c.time_scale(),
        c.body.markers.len(),
        r.steps,
        start.elapsed().as_secs_f64()
    );
    if let chrono_mpm::Material::CriticalState(m) = c.body.material() {
        let mk = &c.body.markers;
        let phi: Vec<f64> = (0..mk.len())
            .map(|p| m.packing_of(&mk.fe[p], &mk.fp[p]))
            .collect();
        let mean = phi.iter().sum::<f64>() / phi.len() as f64;
        let min = phi.iter().copied().fold(f64::INFINITY, f64::min);
        let max = phi.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        println!(
            "packing fraction: mean {mean:.4}, min {min:.4}, max {max:.4} (start {:.4}, phi_c {})",
            m.phi0, m.phi_c
        );
    }
    if let Ok(path) = std::env::var("COLUMN_DUMP") {
        let mut out = String::new();
        // x z x0 z0 [phi]: the final and initial positions (and the packing fraction)
        let mk = &c.body.markers;
        for (p, (x, y)) in mk.x.iter().zip(&x0).enumerate() {
            let phi = match c.body.material() {
                chrono_mpm::Material::CriticalState(m) => m.packing_of(&mk.fe[p], &mk.fp[p]),
                _ => f64::NAN,
            };
            out += &format!("{} {} {} {} {phi}\n", x.x, x.z, y.x, y.z);
        }
        std::fs::write(path, out)?;
    }
    Ok(())
}
