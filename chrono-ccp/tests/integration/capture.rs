//! `Capture`: the saved solve replays bit for bit (the problem and its warm start), the
//! other solves are the inner solver's, and bad files are named.

use chrono_ccp::testing::random_problem;
use chrono_ccp::{Apgd, Capture, CcpSolver, SolverSettings, load_capture};

fn settings() -> SolverSettings {
    SolverSettings {
        tolerance: 1e-6,
        max_iterations: 50,
        record_history: false,
    }
}

#[test]
fn a_captured_solve_replays_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("chrono-capture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let prefix = dir.join("run.v1"); // a dot in the prefix must not cut it
    let mut cap = Capture::new(Box::new(Apgd::new(settings())), &[1], &prefix).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let (mut warm1, mut out1) = (Vec::new(), Vec::new());
    for (n, seed) in [3u64, 4, 5].into_iter().enumerate() {
        let p = random_problem(seed).unwrap();
        // A warm start that is not zero: half the plain solve's answer.
        let mut g = vec![0.0; p.n_rows()];
        Apgd::new(settings()).solve(&p, &mut g);
        g.iter_mut().for_each(|x| *x *= 0.5);
        if n == 1 {
            warm1 = g.clone();
        }
        let mut expect = g.clone();
        Apgd::new(settings()).solve(&p, &mut expect);
        cap.solve(&p, &mut g);
        assert_eq!(
            bits(&g),
            bits(&expect),
            "solve {n}: the wrapper changed the answer"
        );
        if n == 1 {
            out1 = g;
        }
    }
    assert_eq!(cap.solves(), 3);
    assert!(!dir.join("run.v1_0.ccpb").exists() && !dir.join("run.v1_2.ccpb").exists());
    let (p, warm) = load_capture(dir.join("run.v1_1")).unwrap();
    assert_eq!(bits(&warm), bits(&warm1));
    let mut g = warm;
    Apgd::new(settings()).solve(&p, &mut g);
    assert_eq!(
        bits(&g),
        bits(&out1),
        "the replay differs from the captured solve"
    );
    // A warm start of the wrong length is named.
    std::fs::write(dir.join("run.v1_1.warm"), [0u8; 16]).unwrap();
    let e = load_capture(dir.join("run.v1_1")).unwrap_err().to_string();
    assert!(e.contains("warm") && e.contains("rows"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
    // An unwritable place is refused at construction.
    assert!(
        Capture::new(
            Box::new(Apgd::new(settings())),
            &[0],
            std::path::Path::new("/nonexistent-dir-for-capture/x")
        )
        .is_err()
    );
}
