//! Diagnosis of the snow compaction's lag (`docs/mpm.md`, `mpm-snow`): per layer the
//! markers' `J` against the uniform `J` of the plate, the top marker's extent against the
//! plate, the markers' velocity and `C_zz` against the linear field.
//!
//! `cargo run --profile test -p chrono-mpm --example snow_diag -- [cells [final_strain [rate [elastic [mirrored [step]]]]]]`
//! (`elastic` 1: fixed-corotated without plasticity; `mirrored` 2: the plate's boundary
//! from mirrored markers, `RigidBody::mirrored_markers`, else the lumped fold (1 was an
//! unused argument before); `step`: the strain between prints; one marker per cell, the
//! layers' figures assume it).

use chrono_mpm::compaction::{Compaction, CompactionSpec};
use chrono_mpm::fbar::FBar;
use chrono_mpm::rigid::speed_ramp;
use chrono_mpm::{FixedCorotated, SnowHardening};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, d: f64| std::env::args().nth(i).map_or(d, |s| s.parse().unwrap());
    let cells = arg(1, 8.0) as usize;
    let h = 0.1;
    let dx = h / cells as f64;
    let elastic = arg(4, 0.0) > 0.0;
    let mat = if elastic {
        FixedCorotated::elastic(1.4e5, 0.2)?
    } else {
        FixedCorotated::snow(1.4e5, 0.2, SnowHardening::stomakhin_2013())?
    };
    let spec = CompactionSpec {
        height: h,
        width: dx,
        density: 400.0,
        cells,
        markers_per_cell: 1,
        strain_rate: arg(3, 0.1),
        ramp_time: 0.05,
        final_strain: arg(2, 0.3),
        cfl: 0.4,
        f_bar: FBar::Off,
        mirrored_markers: arg(5, 1.0) > 1.0,
    };
    let mut c = Compaction::new(spec, mat.into())?;
    let mut next = 0.0;
    let mut imp0 = 0.0;
    let mut t0 = 0.0;
    loop {
        let s = c.strain();
        if s >= next || s >= spec.final_strain {
            let b = &c.body;
            let mk = &b.markers;
            let zb = h * (1.0 - s); // plate's lower face
            let j_u = 1.0 - s;
            let mut idx: Vec<usize> = (0..mk.len()).collect();
            idx.sort_by(|&a, &q| mk.x[a].z.total_cmp(&mk.x[q].z));
            let js: Vec<f64> = idx
                .iter()
                .map(|&p| (mk.fe[p] * mk.fp[p]).determinant())
                .collect();
            let jps: Vec<f64> = idx.iter().map(|&p| mk.fp[p].determinant()).collect();
            let sum_j: f64 = js.iter().sum::<f64>() / cells as f64;
            let top = *idx.last().unwrap();
            let ztop = mk.x[top].z + 0.5 * dx * js[cells - 1];
            let vb = -spec.strain_rate * h * speed_ramp(b.time(), spec.ramp_time);
            let imp = b.rigid[0].total_impulse.z;
            let sig = -(imp - imp0) / (b.time() - t0).max(1e-30) / (dx * dx);
            imp0 = imp;
            t0 = b.time();
            let exact = -mat.uniaxial_strain_stress(1.0 - s);
            let vt = mk.v[top].z / vb;
            println!(
                "plate {:.3} dx  top marker {:.3} dx  (plate - top marker) {:+.3} dx  top marker's v / plate's {:.3}",
                zb / dx,
                mk.x[top].z / dx,
                (zb - mk.x[top].z) / dx,
                vt
            );
            println!(
                "strain {s:.4}  markers' J mean {sum_j:.5} (uniform {j_u:.5}, lag {:+.2e} = {:+.3} dx)  top extent - plate {:+.3} dx  stress/exact {:.4}",
                sum_j - j_u,
                (sum_j - j_u) * h / dx,
                (ztop - zb) / dx,
                sig / exact
            );
            println!(
                "  J/uniform - 1 (e-3): {}",
                js.iter()
                    .map(|j| format!("{:+.2}", 1e3 * (j / j_u - 1.0)))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            println!(
                "  J_P: {}",
                jps.iter()
                    .map(|j| format!("{:.4}", j))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            println!(
                "  z/dx: {}",
                idx.iter()
                    .map(|&p| format!("{:.3}", mk.x[p].z / dx))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            // linear field v(z) = vb z / zb, grad = vb / zb
            println!(
                "  v_p/lin - 1: {}",
                idx.iter()
                    .map(|&p| format!("{:+.3}", mk.v[p].z / (vb * mk.x[p].z / zb) - 1.0))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            println!(
                "  Czz/lin - 1: {}",
                idx.iter()
                    .map(|&p| format!("{:+.3}", mk.c[p][(2, 2)] / (vb / zb) - 1.0))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            // The nodal force of a uniform stress (the quadrature's residual), per node
            // below the plate, over sigma A: sum_p J_p dx dN_k(z_p)/dz.
            let zs: Vec<f64> = idx.iter().map(|&p| mk.x[p].z).collect();
            let kmax = (zb / dx).floor() as i64;
            let res: Vec<f64> = (1..=kmax)
                .map(|k| {
                    zs.iter()
                        .zip(&js)
                        .map(|(z, j)| {
                            let r = z / dx - k as f64;
                            let a = r.abs();
                            let dn = if a < 0.5 {
                                -2.0 * r
                            } else if a < 1.5 {
                                -r.signum() * (1.5 - a)
                            } else {
                                0.0
                            };
                            j * dn
                        })
                        .sum::<f64>()
                })
                .collect();
            println!(
                "  residual of a uniform stress per node (sigma A): {}",
                res.iter()
                    .map(|r| format!("{:+.3}", r))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            // The tiling: gaps between neighbours against their half sizes, in dx.
            let mut gaps = vec![zs[0] / dx - 0.5 * js[0]];
            for q in 1..cells {
                gaps.push((zs[q] - zs[q - 1]) / dx - 0.5 * (js[q] + js[q - 1]));
            }
            gaps.push(zb / dx - zs[cells - 1] / dx - 0.5 * js[cells - 1]);
            println!(
                "  tiling gaps (dx; floor, between, plate): {}",
                gaps.iter()
                    .map(|g| format!("{:+.3}", g))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            next += arg(6, 0.025);
            if s >= spec.final_strain {
                break;
            }
        }
        let v = spec.strain_rate * h * speed_ramp(c.body.time(), spec.ramp_time);
        c.body.rigid[0].velocity = nalgebra::Vector3::new(0.0, 0.0, -v);
        let dt = 0.999 * c.body.stable_dt();
        c.body.step(dt)?;
    }
    Ok(())
}
