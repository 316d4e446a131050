//! The seed's mud bed settling in a box by the split (`chrono_mpm::mud`): prints the
//! density error, the solver's iterations and the vertical stress against `rho g H / 2`.
//!
//! `cargo run --release -p chrono-mpm --example mud [markers [steps [dt]]]`

use chrono_mpm::mud::{MudBed, MudSpec};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, d: usize| std::env::args().nth(i).map_or(Ok(d), |s| s.parse());
    let mut bed = MudBed::new(MudSpec::seed(arg(1, 4000)?))?;
    let dt: f64 = std::env::args().nth(3).map_or(Ok(1e-3), |s| s.parse())?;
    let start = std::time::Instant::now();
    for k in 1..=arg(2, 200)? {
        bed.step(dt)?;
        let rows = bed.body.pressure_rows().ok_or("no rows")?;
        let (max, mean) = bed.compression_pct();
        if k % 50 == 0 {
            println!(
                "step {k}: compression max {max:.4} % mean {mean:.5} %, {} iterations, \
                 sigma_zz {:.1} Pa",
                rows.last_solve().0,
                bed.mean_vertical_stress()
            );
        }
    }
    let hydro = bed.spec().density * bed.spec().gravity * bed.depth() / 2.0;
    let n = bed.body.markers.len() as f64 * bed.body.steps() as f64;
    println!(
        "mean sigma_zz {:.1} Pa against -rho g H / 2 = {:.1} Pa; {:.3e} marker-steps/s",
        bed.mean_vertical_stress(),
        -hydro,
        n / start.elapsed().as_secs_f64()
    );
    Ok(())
}
