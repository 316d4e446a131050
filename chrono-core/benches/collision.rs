//! Benchmark of `CollisionWorld::detect` on about 1000 spheres settled in a box.
#![allow(missing_docs)] // criterion's macros generate undocumented items

use std::hint::black_box;

use chrono_core::collision::CollisionWorld;
use chrono_core::material::ContactMaterial;
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::shape::Shape;
use criterion::{Criterion, criterion_group, criterion_main};

/// 1000 spheres of radius 0.05 m on a jittered lattice with spacing 0.098 m (so most
/// neighbors touch, as in a settled pile), in a box of 5 half-spaces (owner 0, fixed).
fn scene() -> (CollisionWorld, Vec<Isometry3<f64>>, Vec<bool>) {
    let mut w = CollisionWorld::new(0.005).unwrap();
    let mat = ContactMaterial::default();
    let side = 10;
    let h = 0.098;
    let extent = side as f64 * h;
    let walls = [
        (Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.0, 0.0)),
        (Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 0.0)),
        (Vector3::new(-1.0, 0.0, 0.0), Vector3::new(extent, 0.0, 0.0)),
        (Vector3::new(0.0, 1.0, 0.0), Vector3::new(0.0, 0.0, 0.0)),
        (Vector3::new(0.0, -1.0, 0.0), Vector3::new(0.0, extent, 0.0)),
    ];
    for (n, p) in walls {
        w.add_collider(
            0,
            &Shape::HalfSpace { normal: n },
            Isometry3::translation(p.x, p.y, p.z),
            mat,
        )
        .unwrap();
    }
    let mut poses = vec![Isometry3::identity()];
    let mut rng = chrono_core::rng::Rng::new(12345);
    let mut jitter = move || rng.range(-0.002, 0.002);
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                let owner = poses.len() as u32;
                w.add_collider(
                    owner,
                    &Shape::Sphere { radius: 0.05 },
                    Isometry3::identity(),
                    mat,
                )
                .unwrap();
                let c = Vector3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * h;
                poses.push(Isometry3::translation(
                    c.x + jitter(),
                    c.y + jitter(),
                    c.z + jitter(),
                ));
            }
        }
    }
    let active = (0..poses.len()).map(|i| i != 0).collect();
    (w, poses, active)
}

fn bench_detect(c: &mut Criterion) {
    let (mut world, poses, active) = scene();
    let mut out = Vec::new();
    world.detect(&poses, &active, &mut out).unwrap();
    println!("{} colliders, {} contacts", world.len(), out.len());
    c.bench_function("detect_1000_spheres_in_box", |b| {
        b.iter(|| {
            world.detect(black_box(&poses), &active, &mut out).unwrap();
            black_box(out.len())
        })
    });
}

criterion_group!(benches, bench_detect);
criterion_main!(benches);
