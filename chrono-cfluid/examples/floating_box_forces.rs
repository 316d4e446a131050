//! Where the floating box's buoyancy comes from: the vertical force of the density rows
//! (fluid particles' rows by region, markers' own rows) and of the contact rows against
//! the box's weight, the markers' pressures against hydrostatics, and the fluid's
//! packing beside the box, averaged over the last quarter of the run (the case
//! `cfluid-floating-box` at its default set-up: dp = 0.02 m, tank 0.4 m, h = 2 ms, 2 s).
//!
//! `cargo run --profile test -p chrono-cfluid --example floating_box_forces -- RHO [DP] [T_END] [INITIAL_DRAFT]`

use chrono_ccp::Apgd;
use chrono_cfluid::floating_box::{FloatingBox, far_surface, volume_level};
use chrono_core::descriptor::SolverSettings;
use chrono_core::math::GRAVITY_MAGNITUDE;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>())
        .collect::<Result<_, _>>()?;
    let rho_box = args.first().copied().unwrap_or(800.0);
    let dp = args.get(1).copied().unwrap_or(0.02);
    let t_end = args.get(2).copied().unwrap_or(2.0);
    let initial_draft = args.get(3).copied().unwrap_or(0.0);
    let h = if dp < 0.015 { 1e-3 } else { 2e-3 };
    let setup = FloatingBox {
        box_density: rho_box,
        initial_draft,
        spacing: dp,
        tank_length: if dp < 0.015 { 0.48 } else { 0.4 },
        ..FloatingBox::default()
    };
    let solver = Box::new(Apgd::new(SolverSettings {
        tolerance: 1e-4,
        max_iterations: 300,
        record_history: false,
    }));
    let mut sc = setup.build(solver)?;
    let (wb, hb, len) = (setup.box_width, setup.box_height, setup.tank_length);
    let g = GRAVITY_MAGNITUDE;
    let mass = sc.sys.body(sc.body)?.mass();
    let n = (t_end / h).round() as usize;
    let from = 3 * n / 4;
    // vertical impulses over the window: fluid rows below the bottom, beside the box
    // (by height band relative to the far surface), marker rows, contacts
    let (mut j_below, mut j_side_deep, mut j_side_top, mut j_mark, mut j_total) =
        (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut j_mark_layer = [0.0f64; 8];
    let n_mk = sc.fluid()?.n_body_markers();
    let mut p_mark = vec![0.0; n_mk];
    let mut z_mark_rel = vec![0.0; n_mk];
    let mut x_mark_rel = vec![0.0; n_mk];
    let (mut surf_far, mut surf_near, mut bottom_avg, mut draft_avg) = (0.0, 0.0, 0.0, 0.0);
    let mut samples = 0usize;
    // fluid beside the box: columns [face, face + 2 dp) on both sides, bins of dp in z
    // relative to the far surface, from -6 dp to +2 dp
    let nb = 8usize;
    let (mut cnt, mut rho_sum, mut p_sum) = (vec![0.0; nb], vec![0.0; nb], vec![0.0; nb]);
    let (mut cnt_far, mut rho_far, mut p_far) = (vec![0.0; nb], vec![0.0; nb], vec![0.0; nb]);
    // pressure under the box (columns more than 1 dp inside its faces) and far, by
    // z - z_bottom in bins of dp from -4 dp to 0
    let (mut pu, mut nu, mut pf, mut nf) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
    for step in 1..=n {
        let vz0 = sc.sys.body(sc.body)?.linear_velocity().z;
        sc.sys.step(h)?;
        let b = sc.sys.body(sc.body)?;
        let (pos, vz1) = (b.position(), b.linear_velocity().z);
        if step % 50 == 0 {
            let f = sc.fluid()?;
            let bottom = pos.z - 0.5 * hb;
            let volume = f.n_fluid() as f64 * f.particle_mass() / f.settings().rest_density;
            let level = volume_level(volume, sc.ly, len, wb, bottom);
            // particles per dp^3 in the fluid under the box (between its faces, below
            // its bottom; the floor face at z = 0)
            let under = (0..f.n_fluid())
                .filter(|&i| {
                    let q = f.position(i);
                    (q[0] - pos.x).abs() < 0.5 * wb && q[2] < bottom
                })
                .count();
            let n_under = under as f64 * dp.powi(3) / (wb * sc.ly * bottom);
            println!(
                "t = {:.2} s  bottom {:.5} m  draft {:.5} m ({:+.2} %)  under the box {:.2} per column, {:.4} per dp^3",
                step as f64 * h,
                bottom,
                level - bottom,
                100.0 * ((level - bottom) / setup.archimedes_draft() - 1.0),
                under as f64 * dp * dp / (wb * sc.ly),
                n_under
            );
        }
        if step <= from {
            continue;
        }
        let f = sc.fluid()?;
        let bottom = pos.z - 0.5 * hb;
        let xs = [pos.x - 0.5 * wb, pos.x + 0.5 * wb];
        let zs = far_surface(f, dp, len, xs);
        let volume = f.n_fluid() as f64 * f.particle_mass() / f.settings().rest_density;
        draft_avg += volume_level(volume, sc.ly, len, wb, bottom) - bottom;
        j_total += mass * (vz1 - vz0) + mass * g * h;
        let (fl, mk) = f.row_impulses_on(sc.body);
        for (i, imp) in fl.iter().enumerate() {
            let q = f.position(i);
            if q[2] < bottom {
                j_below += imp[2];
            } else if q[2] > zs - 1.5 * dp {
                j_side_top += imp[2];
            } else {
                j_side_deep += imp[2];
            }
        }
        for (k, imp) in mk.iter().enumerate() {
            j_mark += imp[2];
            let zr = f.marker_position(k)[2] - bottom;
            let layer = ((zr / dp).floor() as usize).min(7);
            j_mark_layer[layer] += imp[2];
            p_mark[k] += f.marker_pressure(k);
            z_mark_rel[k] += f.marker_position(k)[2] - zs;
            x_mark_rel[k] += f.marker_position(k)[0] - pos.x;
        }
        for i in 0..f.n_fluid() {
            let q = f.position(i);
            let bin = ((bottom - q[2]) / dp).floor();
            if !(0.0..4.0).contains(&bin) {
                continue;
            }
            let dx = (q[0] - pos.x).abs() - 0.5 * wb;
            if dx < -dp {
                pu[bin as usize] += f.pressure(i);
                nu[bin as usize] += 1.0;
            } else if dx >= 2.0 * dp && q[0] > 2.0 * dp && q[0] < len - 2.0 * dp {
                pf[bin as usize] += f.pressure(i);
                nf[bin as usize] += 1.0;
            }
        }
        let mut near_top = f64::NEG_INFINITY;
        for i in 0..f.n_fluid() {
            let q = f.position(i);
            let dx = (q[0] - pos.x).abs() - 0.5 * wb;
            let far = (q[0] > 2.0 * dp && q[0] < len - 2.0 * dp) && dx >= 2.0 * dp;
            let bin = ((q[2] - zs) / dp + 6.0).floor();
            if (0.0..2.0 * dp).contains(&dx) {
                near_top = near_top.max(q[2]);
            }
            if !(0.0..nb as f64).contains(&bin) {
                continue;
            }
            let bin = bin as usize;
            if (0.0..2.0 * dp).contains(&dx) {
                cnt[bin] += 1.0;
                rho_sum[bin] += f.densities()[i];
                p_sum[bin] += f.pressure(i);
            } else if far {
                cnt_far[bin] += 1.0;
                rho_far[bin] += f.densities()[i];
                p_far[bin] += f.pressure(i);
            }
        }
        surf_far += zs;
        surf_near += near_top + 0.5 * dp;
        bottom_avg += bottom;
        samples += 1;
    }
    let s = samples as f64;
    let t = s * h;
    let w = mass * g;
    println!("\nbox {rho_box} kg/m^3, dp {dp} m, window {t:.2} s ({samples} steps)");
    println!(
        "draft (volume) {:.5} m, Archimedes {:.5} m: {:+.2} %",
        draft_avg / s,
        setup.archimedes_draft(),
        100.0 * (draft_avg / s / setup.archimedes_draft() - 1.0)
    );
    println!(
        "far surface {:.5} m, beside the box {:.5} m ({:+.3} dp); bottom {:.5} m; far-surface draft {:.5} m ({:+.2} %)",
        surf_far / s,
        surf_near / s,
        (surf_near - surf_far) / s / dp,
        bottom_avg / s,
        (surf_far - bottom_avg) / s,
        100.0 * ((surf_far - bottom_avg) / s / setup.archimedes_draft() - 1.0)
    );
    println!("vertical forces over the window, N (fraction of the weight {w:.4} N):");
    let contact = j_total - j_below - j_side_deep - j_side_top - j_mark;
    for (name, j) in [
        ("fluid rows below the bottom", j_below),
        ("fluid rows beside, deeper than 1.5 dp", j_side_deep),
        ("fluid rows beside, top 1.5 dp", j_side_top),
        ("marker rows", j_mark),
        ("contacts (rest)", contact),
        ("total (M dv + M g h)", j_total),
    ] {
        println!("  {name:40} {:+.5} ({:+.4})", j / t, j / t / w);
    }
    for (l, j) in j_mark_layer.iter().enumerate() {
        if *j != 0.0 {
            println!(
                "    marker rows, layer {l} from the bottom: {:+.5} N",
                j / t
            );
        }
    }
    // markers' pressure by position (averaged over y), against rho_0 g (z_s - z)
    println!("marker pressures (Pa) by (x - x_c, z - z_surface_far), hydrostatic in ()");
    let mut keys: Vec<(i64, i64)> = Vec::new();
    let mut acc: Vec<(f64, f64, usize)> = Vec::new();
    for k in 0..n_mk {
        let key = (
            (x_mark_rel[k] / s / dp).round() as i64,
            (z_mark_rel[k] / s / dp * 10.0).round() as i64,
        );
        let p = p_mark[k] / s;
        match keys.iter().position(|x| *x == key) {
            Some(i) => {
                acc[i].0 += p;
                acc[i].1 += z_mark_rel[k] / s;
                acc[i].2 += 1;
            }
            None => {
                keys.push(key);
                acc.push((p, z_mark_rel[k] / s, 1));
            }
        }
    }
    let mut order: Vec<usize> = (0..keys.len()).collect();
    order.sort_by_key(|&i| (-keys[i].1, keys[i].0));
    let mut last_z = i64::MIN;
    for i in order {
        if keys[i].1 != last_z {
            let z = acc[i].1 / acc[i].2 as f64;
            print!("\n  z {:+.2} dp (hydro {:7.1}):", z / dp, -1000.0 * g * z);
            last_z = keys[i].1;
        }
        print!(" {:7.1}", acc[i].0 / acc[i].2 as f64);
    }
    println!();
    println!("fluid pressure (Pa) under the box (1 dp inside its faces) and far, same z:");
    for b in 0..4 {
        println!(
            "  [{:+}, {:+}) dp below the bottom: under {:7.1} ({:5.0} samples)  far {:7.1} ({:5.0})  under - far {:+6.1}",
            b,
            b + 1,
            pu[b] / nu[b].max(1.0),
            nu[b],
            pf[b] / nf[b].max(1.0),
            nf[b],
            pu[b] / nu[b].max(1.0) - pf[b] / nf[b].max(1.0)
        );
    }
    println!("  weight / bottom area = {:.1} Pa", mass * g / (wb * sc.ly));
    let ly = sc.ly;
    println!("fluid beside the box (2 dp columns each side) and far, by z - z_surface_far (dp):");
    for b in (0..nb).rev() {
        let z0 = b as f64 - 6.0;
        let area = 2.0 * 2.0 * dp * ly * s; // two sides, 2 dp wide
        let (nf, lf) = (cnt_far[b], (len - wb - 8.0 * dp) * ly * s);
        println!(
            "  [{z0:+.0}, {:+.0}): beside n/dp^3 {:.3} rho {:7.2} p {:7.1} | far n/dp^3 {:.3} rho {:7.2} p {:7.1} | hydro {:7.1}",
            z0 + 1.0,
            cnt[b] * dp * dp / area,
            rho_sum[b] / cnt[b].max(1.0),
            p_sum[b] / cnt[b].max(1.0),
            nf * dp * dp / lf,
            rho_far[b] / nf.max(1.0),
            p_far[b] / nf.max(1.0),
            -1000.0 * g * (z0 + 0.5) * dp
        );
    }
    Ok(())
}
