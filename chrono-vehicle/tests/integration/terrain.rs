//! Tests of the rigid terrains: heights, normals, file input, colliders in a system.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_vehicle::VehicleError;
use chrono_vehicle::terrain::{FlatTerrain, HeightmapTerrain, Terrain};

/// A bilinear function is reproduced exactly by the bilinear interpolation.
fn bilinear(x: f64, y: f64) -> f64 {
    0.3 + 0.05 * x - 0.02 * y + 0.01 * x * y
}

#[test]
fn heightmap_interpolates_bilinearly_with_the_gradient_normal() {
    let t = HeightmapTerrain::from_fn(11, 7, [-5.0, -3.0], [1.0, 1.0], 0.8, bilinear).unwrap();
    for &(x, y) in &[(0.3, 0.7), (-4.9, 2.9), (2.25, -1.5), (4.0, 0.0)] {
        assert!(
            (t.height(x, y) - bilinear(x, y)).abs() < 1e-12,
            "at ({x}, {y})"
        );
        let (hx, hy) = (0.05 + 0.01 * y, -0.02 + 0.01 * x);
        let n = Vector3::new(-hx, -hy, 1.0).normalize();
        assert!((t.normal(x, y) - n).norm() < 1e-12, "normal at ({x}, {y})");
    }
    assert_eq!(t.friction(1.0, 1.0), 0.8);
    // outside: clamped to the edge, flat across it
    assert!((t.height(-8.0, 0.5) - bilinear(-5.0, 0.5)).abs() < 1e-12);
    let n = t.normal(-8.0, 0.5);
    assert_eq!(n.x, 0.0);
    assert!(n.y.abs() > 0.0);
}

#[test]
fn heightmap_reads_csv_and_plain_grids_and_names_bad_lines() {
    let csv = "# heights\n0, 1, 2\n1, 2, 3\n";
    let plain = "0 1 2\n\n1\t2 3\n";
    for (text, name) in [(csv, "a.csv"), (plain, "b.txt")] {
        let t = HeightmapTerrain::parse(text, name, [0.0, 0.0], [2.0, 1.0], 0.7).unwrap();
        assert_eq!(t.size(), (3, 2));
        // row j is at y = j: h = x/2 + y
        assert!((t.height(3.0, 0.5) - 2.0).abs() < 1e-12);
    }
    let e = HeightmapTerrain::parse("0, 1\n1, x\n", "g.csv", [0.0; 2], [1.0; 2], 0.7).unwrap_err();
    match &e {
        VehicleError::Data { path, message } => {
            assert_eq!(path, "g.csv");
            assert!(
                message.contains("line 2, column 2") && message.contains("\"x\""),
                "{e}"
            );
        }
        _ => panic!("{e}"),
    }
    let e = HeightmapTerrain::parse("0 1 2\n# c\n1 2\n", "g", [0.0; 2], [1.0; 2], 0.7).unwrap_err();
    assert!(
        e.to_string()
            .contains("line 3: 2 heights, but the first row has 3"),
        "{e}"
    );
    let e = HeightmapTerrain::parse("0 1 2\n", "g", [0.0; 2], [1.0; 2], 0.7).unwrap_err();
    assert!(e.to_string().contains("1 rows"), "{e}");
    let e = HeightmapTerrain::new(2, 2, [0.0; 2], [1.0, -1.0], vec![0.0; 4], 0.5).unwrap_err();
    assert!(e.to_string().contains("heightmap.spacing.y") && e.to_string().contains("-1"));
    let e = HeightmapTerrain::new(2, 2, [0.0; 2], [1.0; 2], vec![0.0; 3], 0.5).unwrap_err();
    assert!(e.to_string().contains("heightmap.heights.len()"), "{e}");
    let e = FlatTerrain::new(0.0, -0.1).unwrap_err();
    assert!(e.to_string().contains("flat_terrain.friction"));
}

#[test]
fn heightmap_file_round_trip() {
    let path = std::env::temp_dir().join(format!("chrono_vehicle_hm_{}.csv", std::process::id()));
    std::fs::write(&path, "1,1,1\n1,2,1\n1,1,1\n").unwrap();
    let t = HeightmapTerrain::from_file(&path, [0.0, 0.0], [1.0, 1.0], 0.9).unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!((t.height(1.0, 1.0) - 2.0).abs() < 1e-12);
    assert!((t.height(0.5, 1.0) - 1.5).abs() < 1e-12);
    let e = HeightmapTerrain::from_file("/nonexistent/hm.csv", [0.0; 2], [1.0; 2], 0.9);
    assert!(matches!(e, Err(VehicleError::Data { .. })));
}

#[test]
fn boxes_rest_on_the_terrain_colliders_at_the_terrain_height() {
    let settings = SolverSettings {
        tolerance: 1e-10,
        max_iterations: 500,
        record_history: false,
    };
    let half = 0.2;
    let terrains: Vec<Box<dyn Terrain>> = vec![
        Box::new(FlatTerrain::new(0.3, 0.9).unwrap()),
        Box::new(
            HeightmapTerrain::from_fn(9, 9, [-4.0, -4.0], [1.0, 1.0], 0.9, |x, y| {
                // a plateau at 0.3 around the box, rising towards the edges
                0.3 + 0.1 * (x.abs().max(y.abs()) - 1.0).max(0.0)
            })
            .unwrap(),
        ),
    ];
    for t in terrains {
        let mut sys = System::new(
            SystemSettings::default(),
            Box::new(Apgd::new(settings.clone())),
        )
        .unwrap();
        t.add_to_system(&mut sys, ContactMaterial::with_friction(0.9))
            .unwrap();
        let shape = Shape::Box {
            half_extents: Vector3::repeat(half),
        };
        let b = sys
            .add_body(
                RigidBodyBuilder::dynamic()
                    .mass_from_shape(&shape, 500.0)
                    .unwrap()
                    .position(Vector3::new(0.1, -0.2, 0.3 + half + 0.05))
                    .collider(
                        shape,
                        Isometry3::identity(),
                        ContactMaterial::with_friction(0.9),
                    ),
            )
            .unwrap();
        for _ in 0..500 {
            sys.step(1e-3).unwrap();
        }
        let body = sys.body(b).unwrap();
        let expect = t.height(0.1, -0.2) + half;
        assert!(
            (body.position().z - expect).abs() < 1e-3,
            "z {} vs {expect}",
            body.position().z
        );
        assert!(body.linear_velocity().norm() < 1e-2);
    }
}
