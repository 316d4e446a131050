//! Tests of the sticky bodies' boundary from mirrored markers
//! ([`RigidBody::mirrored_markers`]): the same sums as the sticky wall's fold on a node
//! plane, the impulse as the material's momentum change, the column on the plate.

use nalgebra::{Matrix3, Vector3};

use crate::tests::{plate_stress_error, pushed_block};
use crate::*;
use crate::{compaction, rigid};

fn rng(seed: &mut u64) -> f64 {
    *seed ^= *seed >> 12;
    *seed ^= *seed << 25;
    *seed ^= *seed >> 27;
    (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
}

/// A block of random markers (velocities, affine matrices, elastic strains) under
/// gravity, its top at `z = 0.8`, on a grid of 10 x 10 x `cells_z` cells of 0.1 m with the
/// walls `bottom`/`top` along z (open laterally, the block away from the sides).
fn random_block(cells_z: usize, top: Wall) -> MpmBody {
    let spec = GridSpec::new([0.0; 3], [10, 10, cells_z], 0.1)
        .unwrap()
        .with_walls(0, Wall::Open, Wall::Open)
        .with_walls(1, Wall::Open, Wall::Open)
        .with_walls(2, Wall::Slip, top);
    let mat = FixedCorotated::elastic(1e5, 0.3).unwrap();
    let mut body = MpmBody::new(
        spec,
        mat.into(),
        MpmSettings {
            gravity: [0.3, -0.2, -9.81],
            cfl: 0.5,
            f_bar: FBar::Off,
        },
    )
    .unwrap();
    let mut s = 17u64;
    for _ in 0..2000 {
        let x = Vector3::new(
            0.3 + 0.4 * rng(&mut s),
            0.3 + 0.4 * rng(&mut s),
            0.1 + 0.7 * rng(&mut s),
        );
        let v = Vector3::new(rng(&mut s) - 0.5, rng(&mut s) - 0.5, rng(&mut s) - 0.5) * 0.1;
        let p = body.markers.push(0.5 + rng(&mut s), 1e-3, x, v).unwrap();
        body.markers.c[p] = Matrix3::from_fn(|_, _| 0.2 * (rng(&mut s) - 0.5));
        body.markers.fe[p] =
            Matrix3::identity() + Matrix3::from_fn(|_, _| 0.01 * (rng(&mut s) - 0.5));
    }
    body
}

#[test]
fn mirrored_markers_on_a_node_plane_are_the_sticky_walls_fold() {
    // A plate at rest whose lower face is the node plane z = 0.8 with mirrored markers, and
    // a sticky wall on the same plane (the box ending there): the mirrored markers are the
    // images the wall's fold adds (`RigidBody::mirrored_markers`), so the two runs agree
    // to round-off (the sums in another order), markers' velocities, strains and positions.
    let mut wall = random_block(8, Wall::Sticky);
    let mut plate = random_block(12, Wall::Open);
    let mut r = RigidBody::new_box(
        Vector3::new(0.5, 0.5, 1.0),
        [2.0, 2.0, 0.2],
        Vector3::zeros(),
        rigid::Contact::Sticky,
    )
    .unwrap();
    r.set_mirrored_markers(true).unwrap();
    plate.rigid.push(r);
    let p0 = plate.momentum();
    let dt = 0.5 * wall.stable_dt();
    for _ in 0..5 {
        wall.step(dt).unwrap();
        plate.step(dt).unwrap();
    }
    let (a, b) = (&wall.markers, &plate.markers);
    let vscale = a.v.iter().map(|v| v.norm()).fold(0.0, f64::max);
    for p in 0..a.len() {
        assert!((a.v[p] - b.v[p]).norm() < 1e-12 * vscale, "v of {p}");
        assert!((a.fe[p] - b.fe[p]).norm() < 1e-13, "F_E of {p}");
        assert!((a.x[p] - b.x[p]).norm() < 1e-14, "x of {p}");
    }
    // The top layer did touch the plane (the test is not vacuous): some markers moved
    // differently than they would have without any condition there.
    let mut free = random_block(12, Wall::Open);
    for _ in 0..5 {
        free.step(dt).unwrap();
    }
    let diff = (0..a.len())
        .map(|p| (free.markers.v[p] - b.v[p]).norm())
        .fold(0.0, f64::max);
    assert!(diff > 1e-3 * vscale, "the plate changed nothing: {diff}");
    // The plate's impulse is the momentum the markers took from it (gravity's aside; the
    // floor is far below the top layer's reach only for the plate's nodes, so compare the
    // two runs' momenta instead: the wall's impulse is the same).
    let j = plate.rigid[0].total_impulse;
    assert!(j.norm() > 0.0);
    let p1 = plate.momentum();
    let m: f64 = plate.markers.mass.iter().sum();
    let g = Vector3::new(0.3, -0.2, -9.81) * (5.0 * dt * m);
    let floor = (p1 - p0) - g - j; // the floor's impulse, normal only (slip)
    assert!(
        floor.x.abs() + floor.y.abs() < 1e-10 * (p0.norm() + j.norm()),
        "tangential momentum change {} not the plate's {j}",
        p1 - p0 - g
    );
}

#[test]
fn mirrored_plate_impulse_is_the_material_momentum_change() {
    // As `rigid_impulse_equals_the_material_momentum_change`, the sticky plate with mirrored
    // markers (its impulse the real markers' share of the nodes' change).
    let (p0, p1, j) = pushed_block(rigid::Contact::Sticky, true);
    assert!(j.z < -1.0, "impulse {j}");
    assert!(j.x > 0.01 * j.norm(), "{j}");
    let err = (p1 - p0 - j).norm();
    assert!(
        err < 1e-12 * (j.norm() + p0.norm()),
        "momentum change {} vs plate impulse {j} (error {err:e})",
        p1 - p0
    );
}

#[test]
fn mirrored_plate_reaction_is_the_uniaxial_strain_modulus() {
    // As `plate_reaction_is_the_uniaxial_strain_modulus` (elastic column to 2 % strain),
    // with the plate's mirrored markers: its reaction is the modulus within the same bounds.
    let (e8, m8) = plate_stress_error(8, 2, true);
    let (e16, m16) = plate_stress_error(16, 2, true);
    let (e8_1, _) = plate_stress_error(8, 1, true);
    eprintln!("mirrored: 8 cells {e8}, 16 cells {e16}, one marker per cell {e8_1}");
    assert!(
        e16 < 0.005,
        "plate stress off the modulus by {e16} at 16 cells"
    );
    assert!(m8 < 2e-3 && m16 < 2e-3, "markers {m8}, {m16}");
    assert!(e8_1 < 0.005, "one marker per cell, 8 cells: {e8_1}");
}

/// The elastic column of `docs/mpm.md` "The lag and the layer alternation" (0.1 m, 8
/// cells, one marker per cell, E 1.4e5 Pa, nu 0.2, rho 400, strain rate 0.1/s)
/// compressed to `strain`: the lag of the markers' summed `J dx` behind the plate (dx),
/// the largest departure of a layer's `J` from the plate's uniform `1 - strain`, and the
/// plate's stress over the last sampling interval against the uniaxial curve.
fn elastic_column(strain: f64, mirrored: bool) -> (f64, f64, f64) {
    let mat = FixedCorotated::elastic(1.4e5, 0.2).unwrap();
    let cells = 8;
    let h = 0.1;
    let spec = compaction::CompactionSpec {
        height: h,
        width: h / cells as f64,
        density: 400.0,
        cells,
        markers_per_cell: 1,
        strain_rate: 0.1,
        ramp_time: 0.05,
        final_strain: strain,
        cfl: 0.4,
        f_bar: FBar::Off,
        mirrored_markers: mirrored,
    };
    let mut c = compaction::Compaction::new(spec, mat.into()).unwrap();
    let samples = c.run(16, |_| {}).unwrap();
    let s = c.strain();
    let mk = &c.body.markers;
    let js: Vec<f64> = mk.fe.iter().map(|f| f.determinant()).collect();
    let lag = js.iter().sum::<f64>() - cells as f64 * (1.0 - s);
    let spread = js
        .iter()
        .map(|j| (j / (1.0 - s) - 1.0).abs())
        .fold(0.0, f64::max);
    let last = samples.last().unwrap();
    let exact = -mat.uniaxial_strain_stress(1.0 - last.strain);
    (lag, spread, last.stress / exact - 1.0)
}

#[test]
fn mirrored_plate_keeps_an_elastic_column_on_the_plate() {
    // The lumped fold lets the top marker run up into the plate once the plate's face
    // passes the half-node above it (7.5 dx, 6.25 % strain): at 10 % the markers lag the
    // plate by 0.066 dx and their J alternate between layers (`docs/mpm.md`). With the
    // mirrored markers the column follows the plate: no lag, the layers uniform.
    let (lag, spread, err) = elastic_column(0.1, true);
    eprintln!("mirrored: lag {lag:+.4} dx, J spread {spread:.4}, plate stress {err:+.4}");
    assert!(lag.abs() < 0.005, "markers lag the plate by {lag} dx");
    assert!(spread < 0.01, "layers' J off the uniform one by {spread}");
    assert!(err.abs() < 0.01, "plate stress off the curve by {err}");
    // The lumped fold (the same run otherwise) fails these bounds: the test can fail.
    let (lag, spread, err) = elastic_column(0.1, false);
    eprintln!("folded: lag {lag:+.4} dx, J spread {spread:.4}, plate stress {err:+.4}");
    assert!(lag > 0.04, "{lag}");
    assert!(spread > 0.02, "{spread}");
}

#[test]
fn mirrored_markers_need_a_sticky_box_at_rest_in_rotation() {
    let mut slip = RigidBody::new_box(
        Vector3::zeros(),
        [1.0; 3],
        Vector3::zeros(),
        rigid::Contact::Slip { friction: 0.2 },
    )
    .unwrap();
    let e = slip.set_mirrored_markers(true).unwrap_err();
    assert!(e.to_string().contains("rigid.mirrored_markers"), "{e}");
    assert!(slip.set_mirrored_markers(false).is_ok());
    let mut wheel = RigidBody::new_cylinder(
        Vector3::new(0.5, 0.5, 0.5),
        0.2,
        0.2,
        Vector3::zeros(),
        Vector3::new(0.0, 1.0, 0.0),
        rigid::Contact::Sticky,
    )
    .unwrap();
    assert!(wheel.set_mirrored_markers(true).is_err());
    // Set directly: the step names the body and the field.
    wheel.mirrored_markers = true;
    let mut body = random_block(10, Wall::Open);
    body.rigid.push(wheel);
    let e = body.step(1e-5).unwrap_err();
    assert!(e.to_string().contains("rigid[0].mirrored_markers"), "{e}");
}

#[test]
fn mirrored_markers_are_the_same_bits_at_one_and_two_threads() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut body = random_block(12, Wall::Open);
            let mut r = RigidBody::new_box(
                Vector3::new(0.5, 0.5, 0.97),
                [2.0, 2.0, 0.2],
                Vector3::new(0.05, 0.0, -0.2),
                rigid::Contact::Sticky,
            )
            .unwrap();
            r.set_mirrored_markers(true).unwrap();
            body.rigid.push(r);
            for _ in 0..10 {
                let dt = 0.5 * body.stable_dt();
                body.step(dt).unwrap();
            }
            (
                body.markers.x.clone(),
                body.markers.v.clone(),
                body.rigid[0].total_impulse,
            )
        })
    };
    let a = run(1);
    assert!(a.2.norm() > 0.0);
    assert_eq!(a, run(2), "1 and 2 threads differ");
}
