//! The split's surface layers against plain MPM's (`docs/mpm.md`, "The split's surface
//! layers"): the pressure per marker layer of a resting, laterally confined sand column,
//! and the deposit's surface profile after a column collapse.
//!
//! `cargo run --release -p chrono-mpm --example surface_layers -- rest [split (0/1) [cells [time_s [surface_reference (0/1)]]]]`
//! prints, per marker layer of a Drucker–Prager sand column (`L0` = `H0` = 0.1 m, the
//! column case's sand: rho 1500, E 2 MPa, nu 0.3, phi 30) between slip walls on a slip
//! floor, the mean over the last 0.1 s of: the rows' own pressure, its kernel average (what
//! the cone takes), and in plain MPM `-tr(tau) / (3 J)`, against `rho g d` (`d` from the
//! top of the markers).
//!
//! `... -- collapse a [split [cells [surface_reference]]]` runs the column collapse as
//! `xtask validate mpm-column-collapse` does (flip 0.99, floor friction 30 degrees, cfl
//! 0.4; the environment's `SURF_FLIP` and `SURF_CFL` replace the FLIP fraction and the
//! CFL number, `SURF_HIST` prints the front and height every 0.1 `sqrt(H0/g)`) and prints
//! the deposit's profile: per marker-spacing bin of `x`, the highest marker's top
//! `z + d/2`, the markers in the bin and their packing `count d / top` (1 on the lattice).

use chrono_core::particles::lattice::wall_layers;
use chrono_mpm::column::{Column, ColumnSpec};
use chrono_mpm::pressure::slab_wall_markers;
use chrono_mpm::*;
use nalgebra::Vector3;

type Res<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn arg(i: usize, default: f64) -> Res<f64> {
    Ok(match std::env::args().nth(i) {
        Some(s) => s.parse()?,
        None => default,
    })
}

fn rest() -> Res<()> {
    let split = arg(2, 1.0)? > 0.0;
    let cells = arg(3, 4.0)? as usize;
    let t_end = arg(4, 0.5)?;
    let (l0, h0, rho, g) = (0.1, 0.1, 1500.0, 9.81);
    let dx = l0 / cells as f64;
    let d = dx / 2.0;
    let spec = GridSpec::new([0.0; 3], [cells, 1, 2 * cells + 4], dx)?
        .with_walls(0, Wall::Slip, Wall::Slip)
        .with_walls(1, Wall::Slip, Wall::Slip)
        .with_walls(2, Wall::Slip, Wall::Open);
    let dp = DruckerPrager::plane_strain(2e6, 0.3, 30.0, 0.0)?;
    let settings = MpmSettings {
        gravity: [0.0, 0.0, -g],
        cfl: 0.4,
        f_bar: FBar::Off,
    };
    let mut body = MpmBody::new(spec, dp.into(), settings)?;
    body.set_flip(0.99)?;
    let vol = d * d * dx;
    let (mx, mz) = (2 * cells, (h0 / d).round() as usize);
    for i in 0..mx {
        for k in 0..mz {
            let x = Vector3::new((i as f64 + 0.5) * d, 0.5 * dx, (k as f64 + 0.5) * d);
            body.markers.push(rho * vol, vol, x, Vector3::zeros())?;
        }
    }
    if split {
        let rows = PressureSettings::plane_strain_soil(rho, 2e6, 0.3, d, 1e-6);
        let layers = wall_layers(rows.h_over_dp);
        let walls = slab_wall_markers(
            [0.0, l0],
            [0.0, h0 + 4.0 * dx],
            0.5 * dx,
            d,
            layers,
            true,
            true,
        )?;
        body.set_pressure_rows(rows, &walls)?;
        if let Some(r) = body.pressure_rows_mut() {
            r.set_surface_reference(arg(5, 0.0)? > 0.0);
        }
    }
    let n = body.markers.len();
    let mut own = vec![0.0; n];
    let mut smooth = vec![0.0; n];
    let mut samples = 0usize;
    while body.time() < t_end {
        let dt = body.stable_dt().min(1e-3);
        body.step(dt)?;
        if body.time() > t_end - 0.1 {
            samples += 1;
            match body.pressure_rows() {
                Some(r) => {
                    for p in 0..n {
                        own[p] += r.pressure()[p];
                        smooth[p] += r.smoothed_pressure()[p];
                    }
                }
                None => {
                    let mat = *body.material();
                    for p in 0..n {
                        let (fe, fp) = (body.markers.fe[p], body.markers.fp[p]);
                        let tau = mat.kirchhoff(&fe, &fp);
                        let j = (fe * fp).determinant();
                        let pr = -tau.trace() / (3.0 * j);
                        own[p] += pr;
                        smooth[p] += pr;
                    }
                }
            }
        }
    }
    let top = body.markers.x.iter().map(|x| x[2]).fold(f64::MIN, f64::max) + d / 2.0;
    println!(
        "# {} column, {cells} cells, t {:.3} s, KE {:.3e} J, top {top:.5} m (H0 {h0})",
        if split { "split" } else { "plain" },
        body.time(),
        body.kinetic_energy()
    );
    println!("# layer z_m depth_m rho_g_d_Pa own_Pa own/rgd smoothed_Pa smoothed/rgd");
    for k in (0..mz).rev() {
        let z0 = (k as f64 + 0.5) * d;
        // markers that started in layer k (every marker stays in its layer at rest)
        let ids: Vec<usize> = (0..n).filter(|&p| p % mz == k).collect();
        let m = ids.len() as f64;
        let z = ids.iter().map(|&p| body.markers.x[p][2]).sum::<f64>() / m;
        let o = ids.iter().map(|&p| own[p]).sum::<f64>() / m / samples as f64;
        let s = ids.iter().map(|&p| smooth[p]).sum::<f64>() / m / samples as f64;
        let rgd = rho * g * (top - z);
        let _ = z0;
        println!(
            "{k} {z:.5} {:.5} {rgd:.1} {o:.1} {:.3} {s:.1} {:.3}",
            top - z,
            o / rgd,
            s / rgd
        );
    }
    Ok(())
}

fn collapse() -> Res<()> {
    let a = arg(2, 1.0)?;
    let split = arg(3, 1.0)? > 0.0;
    let cells = arg(4, 4.0)? as usize;
    let d = ColumnSpec::default();
    let spec = ColumnSpec {
        aspect_ratio: a,
        cells_length: if a >= 1.0 {
            cells
        } else {
            (cells as f64 / a).ceil() as usize
        },
        floor_friction_angle_deg: Some(30.0),
        // SURF_FLIP: another FLIP fraction than the case's 0.99
        flip: std::env::var("SURF_FLIP")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(0.99),
        cfl: std::env::var("SURF_CFL")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(d.cfl),
        ..d
    };
    let mut c = Column::new(spec)?;
    if split {
        c.use_pressure_rows(1e-6)?;
        if let Some(r) = c.body.pressure_rows_mut() {
            r.set_surface_reference(arg(5, 0.0)? > 0.0);
        }
    }
    let h0 = c.initial_height();
    let r = c.run(|_| {})?;
    println!(
        "# {} a {a} cells {cells}: runout/L0 {:.3}, H_inf/H0 {:.3}, at rest {}, t {:.3} s",
        if split { "split" } else { "plain" },
        r.runout_ratio,
        r.final_height_ratio,
        r.at_rest,
        r.time
    );
    if std::env::var("SURF_HIST").is_ok() {
        for s in r.samples.iter().step_by(10) {
            println!(
                "# t/tau {:.2} front/L0 {:.3} height/H0 {:.3} KE {:.3e}",
                s.t / c.time_scale(),
                s.front / spec.column_length,
                s.height / h0,
                s.kinetic
            );
        }
    }
    let dp = spec.column_length / spec.cells_length as f64 / spec.markers_per_cell as f64;
    let nb = (c.front() / dp).ceil() as usize + 1;
    let mut top = vec![f64::NAN; nb];
    let mut count = vec![0usize; nb];
    for x in &c.body.markers.x {
        let b = (x.x / dp).floor().max(0.0) as usize;
        if b < nb {
            let z = x.z + dp / 2.0;
            top[b] = if top[b].is_nan() { z } else { top[b].max(z) };
            count[b] += 1;
        }
    }
    // the packing of a bin: its markers' area `count dp^2` over the bin's `dp top`
    println!("# x/L0 top/H0 markers packing");
    for (b, t) in top.iter().enumerate() {
        if t.is_finite() {
            println!(
                "{:.4} {:.4} {} {:.3}",
                (b as f64 + 0.5) * dp / spec.column_length,
                t / h0,
                count[b],
                count[b] as f64 * dp / t
            );
        }
    }
    Ok(())
}

fn main() -> Res<()> {
    match std::env::args().nth(1).as_deref() {
        Some("collapse") => collapse(),
        _ => rest(),
    }
}
