//! Tests of the granular column ([`super`]).
use super::*;

#[test]
fn bad_column_input_names_the_field() {
    let mat = ContactMaterial::with_friction(0.5);
    let ok = GranularColumn::new(1.0, 0.1, 10.0, mat);
    assert!(ok.validate().is_ok());
    let bad = |c: GranularColumn, field: &str| {
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e} should name {field}");
    };
    bad(
        GranularColumn {
            aspect_ratio: -1.0,
            ..ok
        },
        "column.aspect_ratio",
    );
    bad(
        GranularColumn {
            aspect_ratio: 0.1,
            ..ok
        },
        "column.aspect_ratio",
    );
    bad(
        GranularColumn {
            column_length: 0.0,
            ..ok
        },
        "column.column_length",
    );
    bad(
        GranularColumn {
            grains_across: 1.0,
            ..ok
        },
        "column.grains_across",
    );
    bad(
        GranularColumn {
            size_ratio: 0.0,
            ..ok
        },
        "column.size_ratio",
    );
    bad(
        GranularColumn {
            slab_width: 1.0,
            ..ok
        },
        "column.slab_width",
    );
    bad(
        GranularColumn {
            floor_length: 0.5,
            ..ok
        },
        "column.floor_length",
    );
    bad(
        GranularColumn {
            material: ContactMaterial::with_friction(-0.1),
            ..ok
        },
        "material.friction",
    );
    bad(
        GranularColumn {
            max_time: 0.0,
            ..ok
        },
        "column.max_time",
    );
}

#[test]
fn deposit_front_ignores_a_grain_that_rolled_away() {
    // A row of touching grains of radius 1 from the wall to x = 10, one alone at 20.
    let mut q: Vec<(Vector3<f64>, f64, f64)> = (0..5)
        .map(|i| (Vector3::new(1.0 + 2.0 * i as f64, 0.0, 1.0), 1.0, 1.0))
        .collect();
    q.push((Vector3::new(20.0, 0.0, 1.0), 1.0, 1.0));
    let dep = Deposit::measure(&q, 0.0, 2.0).unwrap();
    assert_eq!(dep.front, 10.0);
    assert_eq!(dep.farthest, 21.0);
    assert_eq!(dep.detached, 1);
    assert_eq!(dep.height, 2.0);
    // 99 % of six equal masses: the sixth grain.
    assert_eq!(dep.front_99, 21.0);
    // A gap of 9 within a wider tolerance joins it.
    let dep = Deposit::measure(&q, 0.0, 10.0).unwrap();
    assert_eq!((dep.front, dep.detached), (21.0, 0));
    assert!(Deposit::measure(&[], 0.0, 1.0).is_none());
}
