//! Validation cases are bit-for-bit reproducible: two runs of the same case (same thread
//! count) give identical series.

use xtask::case::{Mode, RunContext};

/// Two runs of the same case with the same thread count give bit-identical series.
#[test]
fn runs_are_bit_for_bit_reproducible() {
    let dir = std::env::temp_dir().join(format!("chrono-rs-determinism-{}", std::process::id()));
    let run = |name: &str| {
        let mut case = xtask::cases::all_cases()
            .into_iter()
            .find(|c| c.name() == name)
            .unwrap();
        case.apply_mode(Mode::Quick);
        let mut p = case.params_json();
        p["t_end"] = serde_json::json!(0.3);
        case.set_params_json(p).unwrap();
        case.run(&RunContext::new(Mode::Quick, &dir, false))
            .unwrap()
            .series
    };
    for name in ["rigid-stack-heavy", "rigid-incline"] {
        let (a, b) = (run(name), run(name));
        assert_eq!(a.rows.len(), b.rows.len());
        for (ra, rb) in a.rows.iter().zip(&b.rows) {
            for (x, y) in ra.iter().zip(rb) {
                assert_eq!(x.to_bits(), y.to_bits(), "{name}: runs differ");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
