//! Confined compaction of Stomakhin 2013's snow by a plate (`chrono_mpm::compaction`):
//! prints the axial stress against the model's own uniaxial-strain curve.
//!
//! `cargo run --release -p chrono-mpm --example snow_compaction [cells [strain_rate [final_strain [markers_per_cell [f_bar (0 off, 1 increment, 2 total, 3 plastic) [mirrored (1: the plate's mirrored markers)]]]]]]`

use chrono_mpm::compaction::{Compaction, CompactionSpec};
use chrono_mpm::{FixedCorotated, SnowHardening};

use chrono_mpm::fbar::FBar;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, default: f64| -> Result<f64, Box<dyn std::error::Error>> {
        Ok(match std::env::args().nth(i) {
            Some(s) => s.parse()?,
            None => default,
        })
    };
    let mat = FixedCorotated::snow(1.4e5, 0.2, SnowHardening::stomakhin_2013())?;
    let spec = CompactionSpec {
        height: 0.1,
        width: 0.0125,
        density: 400.0,
        cells: arg(1, 8.0)? as usize,
        markers_per_cell: arg(4, 2.0)? as usize,
        strain_rate: arg(2, 0.1)?,
        ramp_time: 0.05,
        final_strain: arg(3, 0.3)?,
        cfl: 0.4,
        f_bar: [
            FBar::Off,
            FBar::Increment,
            FBar::Total,
            FBar::PlasticIncrement,
        ][arg(5, 0.0)? as usize],
        mirrored_markers: arg(6, 0.0)? > 0.0,
    };
    let mut c = Compaction::new(spec, mat.into())?;
    let start = std::time::Instant::now();
    let samples = c.run(30, |_| {})?;
    for s in &samples {
        let exact = -mat.uniaxial_strain_stress(1.0 - s.strain);
        println!(
            "strain {:.4}  stress {:.1} Pa  analytic {:.1} Pa  error {:+.3} %",
            s.strain,
            s.stress,
            exact,
            100.0 * (s.stress / exact - 1.0)
        );
    }
    // The compaction through the column: 1 - J per marker layer, bottom to top.
    let mk = &c.body.markers;
    let mut layers: Vec<(f64, f64)> = (0..mk.len())
        .map(|p| (mk.x[p].z, 1.0 - (mk.fe[p] * mk.fp[p]).determinant()))
        .collect();
    layers.sort_by(|a, b| a.0.total_cmp(&b.0));
    let per = layers.len() / (spec.cells * spec.markers_per_cell);
    let strains: Vec<String> = layers
        .chunks(per.max(1))
        .map(|l| format!("{:.3}", l.iter().map(|q| q.1).sum::<f64>() / l.len() as f64))
        .collect();
    println!("strain by layer, bottom to top: {}", strains.join(" "));
    let mut jp: Vec<(f64, f64)> = (0..mk.len())
        .map(|p| (mk.x[p].z, mk.fp[p].determinant()))
        .collect();
    jp.sort_by(|a, b| a.0.total_cmp(&b.0));
    let jps: Vec<String> = jp
        .chunks(per.max(1))
        .map(|l| format!("{:.3}", l.iter().map(|q| q.1).sum::<f64>() / l.len() as f64))
        .collect();
    println!("J_P by layer, bottom to top: {}", jps.join(" "));
    println!(
        "{} markers, {} steps in {:.2} s",
        c.body.markers.len(),
        c.body.steps(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
