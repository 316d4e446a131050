//! Problem files: a problem captured from a scene, saved (binary and JSON), reloaded and
//! solved gives the same answer bit for bit; corrupt files are clear errors.

use chrono_ccp::{SolverSettings, by_name};
use chrono_core::descriptor::{CcpProblem, ProblemFile, ProblemFormat};
use chrono_core::math::{Isometry3, Vector3};
use chrono_core::system::RollingModel;
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

/// A small scene: spheres dropped in a loose column on a ground box, a few steps, then the
/// problem of the last step: friction triplets on the ground, per-body rolling contacts
/// between the spheres (rolling friction on the spheres only; materials take the minimum).
fn captured() -> CcpProblem {
    let settings = SolverSettings {
        tolerance: 1e-6,
        max_iterations: 200,
        record_history: false,
    };
    let mut sys = System::new(
        SystemSettings {
            rolling_model: RollingModel::PerBody,
            ..SystemSettings::default()
        },
        by_name("apgd", settings).unwrap(),
    )
    .unwrap();
    let mat = ContactMaterial::with_friction(0.4);
    let ball_mat = mat.with_rolling_friction(0.05);
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::Box {
            half_extents: Vector3::new(2.0, 2.0, 0.5),
        },
        Isometry3::translation(0.0, 0.0, -0.5),
        mat,
    ))
    .unwrap();
    let ball = Shape::Sphere { radius: 0.1 };
    for i in 0..12 {
        let (x, y) = ((i % 2) as f64 * 0.19, ((i / 2) % 2) as f64 * 0.19);
        sys.add_body(
            RigidBodyBuilder::dynamic()
                .mass_from_shape(&ball, 1000.0)
                .unwrap()
                .position(Vector3::new(x, y, 0.1 + 0.2 * (i / 4) as f64))
                .collider(ball.clone(), Isometry3::identity(), ball_mat),
        )
        .unwrap();
    }
    for _ in 0..10 {
        sys.step(0.005).unwrap();
    }
    let p = sys.last_problem().clone();
    let s = p.sections();
    assert!(s.friction.len() >= 12, "{} friction rows", s.friction.len());
    assert!(
        s.rolling_per_body.len() >= 50,
        "{} per-body rolling rows",
        s.rolling_per_body.len()
    );
    p
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn solve(p: &CcpProblem) -> (Vec<f64>, f64) {
    let mut s = by_name(
        "apgd",
        SolverSettings {
            tolerance: 1e-10,
            max_iterations: 500,
            record_history: false,
        },
    )
    .unwrap();
    let mut g = vec![0.0; p.n_rows()];
    let st = s.solve(p, &mut g);
    (g, st.residual)
}

#[test]
fn saved_reloaded_and_solved_bit_for_bit() {
    let p = captured();
    let (g0, r0) = solve(&p);
    let dir = std::env::temp_dir().join(format!("chrono-ccp-file-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, format) in [
        ("p.bin", ProblemFormat::Binary),
        ("p.json", ProblemFormat::Json),
    ] {
        let path = dir.join(name);
        ProblemFile::from_problem(&p, "test scene")
            .save(&path, format)
            .unwrap();
        let q = ProblemFile::load_problem(&path).unwrap();
        assert_eq!(q.n_rows(), p.n_rows());
        assert_eq!(bits(q.r()), bits(p.r()), "{name}: r differs");
        assert_eq!(bits(q.diag()), bits(p.diag()), "{name}: diag differs");
        let (g1, r1) = solve(&q);
        assert_eq!(bits(&g1), bits(&g0), "{name}: gamma differs");
        assert_eq!(r1.to_bits(), r0.to_bits());
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn files_without_the_per_body_group_still_load() {
    // Files written before the per-body rolling group have five groups; with the sixth
    // (empty) dropped, a problem without per-body contacts loads unchanged.
    let mut p = captured();
    let mut f = ProblemFile::from_problem(&p, "x");
    f.groups[5] = Default::default();
    f.groups[5].group = "rolling_per_body".into();
    f.groups[5].row_ptr = vec![0];
    p = f.to_problem().unwrap();
    let mut old = ProblemFile::from_problem(&p, "x");
    assert_eq!(old.groups.pop().map(|g| g.row_ptr.len()), Some(1));
    let q = old.to_problem().unwrap();
    assert_eq!(q.n_rows(), p.n_rows());
    assert_eq!(bits(q.r()), bits(p.r()));
    // Four groups are an error naming the field.
    old.groups.pop();
    let e = old.to_problem().unwrap_err().to_string();
    assert!(e.contains("groups.len()"), "{e}");
}

#[test]
fn corrupt_files_are_errors_naming_the_problem() {
    let p = captured();
    let mut f = ProblemFile::from_problem(&p, "x");
    f.groups[3].mu.pop();
    let e = f.to_problem().unwrap_err().to_string();
    assert!(e.contains("friction") && e.contains("mu"), "{e}");
    // (the friction triplets are frame-only: their blocks are the frames')
    let mut f = ProblemFile::from_problem(&p, "x");
    assert!(f.groups[3].ent_block.is_empty() && f.frames.iter().all(|fr| fr.only));
    f.frames[0].blocks[1] = Some(100_000);
    let e = f.to_problem().unwrap_err().to_string();
    assert!(
        e.contains("frames[0].blocks") && e.contains("variable blocks"),
        "{e}"
    );
    let mut f = ProblemFile::from_problem(&p, "x");
    f.groups[5].ent_block[0] = 100_000;
    let e = f.to_problem().unwrap_err().to_string();
    assert!(
        e.contains("rolling_per_body") && e.contains("variable block"),
        "{e}"
    );
    let mut f = ProblemFile::from_problem(&p, "x");
    f.groups[5].mu.pop();
    let e = f.to_problem().unwrap_err().to_string();
    assert!(e.contains("rolling_per_body") && e.contains("mu"), "{e}");
    let dir = std::env::temp_dir().join(format!("chrono-ccp-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.bin");
    ProblemFile::from_problem(&p, "x")
        .save(&path, ProblemFormat::Binary)
        .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    let e = ProblemFile::load(&path).unwrap_err().to_string();
    assert!(e.contains("bad.bin"), "{e}");
    // a huge array length is refused before anything is allocated
    let mut huge = bytes.clone();
    let len_at = 8 + 8 + "chrono-rs ccp problem v1".len();
    huge[len_at..len_at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    std::fs::write(&path, &huge).unwrap();
    let e = ProblemFile::load(&path).unwrap_err().to_string();
    assert!(e.contains("exceeds"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
