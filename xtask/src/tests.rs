//! End-to-end tests of the runner: a full `validate` run of the test-only cases into a
//! temporary directory, and failure handling.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

use serde_json::Value;

use crate::case::Mode;
use crate::cases::testing;
use crate::runner::{RunOptions, run_case, validate};

/// A fresh directory under the system temp dir.
pub(crate) fn temp_dir(tag: &str) -> PathBuf {
    static N: AtomicU32 = AtomicU32::new(0);
    let n = N.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("xtask-{tag}-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn opts(dir: &Path, overrides: &[&str]) -> RunOptions {
    RunOptions {
        mode: Mode::Quick,
        overrides: overrides.iter().map(|s| s.parse().unwrap()).collect(),
        out_dir: dir.to_path_buf(),
        vtk: true,
        progress: false,
        jobs: 1,
    }
}

#[test]
fn full_run_writes_report_csv_summary_and_plots() {
    let dir = temp_dir("validate");
    let json = dir.join("extra/out.json");
    let all = vec![testing::decay_case(), testing::failing_case()];
    let o = opts(&dir, &["k=1.0", "panic=true"]);
    // The failing case panics; the run continues and reports it.
    let passed = validate(all, &[], &o, Some(&json)).unwrap();
    assert!(!passed);
    for f in [
        "report.md",
        "summary.json",
        "test-decay/series.csv",
        "test-decay/plot.png",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    assert!(dir.join("test-decay/speed_vs_error.png").is_file());
    assert!(dir.join("test-decay/vtk").is_dir());
    assert!(json.is_file());

    let csv = std::fs::read_to_string(dir.join("test-decay/series.csv")).unwrap();
    assert_eq!(csv.lines().next(), Some("t,x,x_exact"));
    assert_eq!(csv.lines().count(), 2 + 50); // header, t = 0, 50 steps of the quick mode

    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    // The one-screen summary opens the report: the test area, 2 cases, 1 passed, the
    // failing case named, and the timings file for the next run's estimate.
    let summary = md.find("## Summary").expect("summary");
    assert!(
        summary < md.find("## Checks").expect("checks table"),
        "{md}"
    );
    assert!(
        md.contains("| test | 2 | 1 |") && md.contains("| total | 2 | 1 |"),
        "{md}"
    );
    assert!(md.contains("(1 errored)"), "{md}");
    let timings = crate::eta::Timings::load(&dir);
    assert!(timings.get(Mode::Quick, "test-decay").is_some());
    assert!(timings.get(Mode::Quick, "test-fail").is_some());
    assert!(md.contains(
        "| case | metric | value | reference | error | tolerance | pass | wall s | steps/s |"
    ));
    assert!(md.contains("| test-decay | x_end |"), "{md}");
    assert!(md.contains("![test-decay](test-decay/plot.png)"), "{md}");
    assert!(md.contains("panicked: deliberate panic"), "{md}");
    assert!(md.contains("`not_finite` = NaN"), "{md}");
    // The sweep's runs, each with its error and wall time.
    assert!(md.contains("## Speed against error"), "{md}");
    assert!(
        md.contains("| test-decay | h/1 |") && md.contains("| test-decay | h/4 |"),
        "{md}"
    );

    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let cases = v["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 2);
    let c = &cases[0];
    for key in [
        "name", "params", "metrics", "checks", "wall_s", "steps", "series", "mode",
    ] {
        assert!(c.get(key).is_some(), "missing {key}");
    }
    assert_eq!(c["name"], "test-decay");
    assert_eq!(c["params"]["t_end"], 0.5); // the quick mode
    assert_eq!(c["steps"], 50);
    assert!(c["metrics"]["not_finite"].is_null());
    assert!(c["metrics"]["x_end"].is_f64());
    assert!(c.get("error").is_none());
    let check = &c["checks"][0];
    let mut keys: Vec<&str> = check
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    keys.sort();
    assert_eq!(keys, ["metric", "pass", "reference", "tolerance", "value"]);
    assert_eq!(check["pass"], true);
    assert!(c["series"].as_str().unwrap().ends_with("series.csv"));
    assert_eq!(cases[1]["error"], "panicked: deliberate panic");
    assert!(cases[1]["series"].is_null());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn errors_fail_the_case_and_bad_overrides_stop_the_run() {
    let dir = temp_dir("errors");
    let r = run_case(testing::failing_case().as_ref(), "t", &opts(&dir, &[])).unwrap();
    assert_eq!(r.error.as_deref(), Some("diverged at step 3"));
    assert!(!r.passed());
    assert!(r.output.is_none() && r.steps_per_s().is_none());
    let e = validate(
        vec![testing::decay_case()],
        &[],
        &opts(&dir, &["h=abc"]),
        None,
    );
    assert!(e.unwrap_err().to_string().contains("expects a number"));
    assert!(validate(Vec::new(), &[], &opts(&dir, &[]), None).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tolerance_ratio_ranks_the_worst_check() {
    use crate::case::Check;
    use crate::report::tolerance_ratio;
    assert!((tolerance_ratio(&Check::relative("a", 1.1, 1.0, 0.2)) - 0.5).abs() < 1e-12);
    assert!((tolerance_ratio(&Check::absolute("b", 3.0, 1.0, 4.0)) - 0.5).abs() < 1e-12);
    assert!((tolerance_ratio(&Check::below("c", 3.0, 2.0)) - 1.5).abs() < 1e-12);
    assert!(tolerance_ratio(&Check::below("d", f64::NAN, 2.0)).is_nan());
    assert_eq!(tolerance_ratio(&Check::absolute("e", 1.0, 1.0, 0.0)), 0.0);
    assert!(tolerance_ratio(&Check::absolute("f", 2.0, 1.0, 0.0)).is_infinite());
}

#[test]
fn jobs_run_every_case_once_and_keep_the_order_and_the_figures() {
    let cases = || {
        vec![
            testing::decay_case(),
            testing::failing_case(),
            testing::decay_case(),
        ]
    };
    let one = {
        let dir = temp_dir("jobs1");
        let o = opts(&dir, &["k=1.0", "panic=true"]);
        let mut c = cases();
        crate::runner::prepare(&mut c, o.mode, &o.overrides).unwrap();
        crate::runner::run_all(&mut c, &o).unwrap()
    };
    let two = {
        let dir = temp_dir("jobs2");
        let mut o = opts(&dir, &["k=1.0", "panic=true"]);
        o.jobs = 2;
        let mut c = cases();
        crate::runner::prepare(&mut c, o.mode, &o.overrides).unwrap();
        crate::runner::run_all(&mut c, &o).unwrap()
    };
    assert_eq!(one.len(), 3);
    assert_eq!(two.len(), 3);
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.passed(), b.passed());
        assert_eq!(a.error.is_some(), b.error.is_some());
        let metrics = |r: &crate::runner::CaseResult| {
            r.output.as_ref().map(|o| {
                o.metrics
                    .iter()
                    .map(|(k, v)| (k.clone(), v.to_bits()))
                    .collect::<Vec<_>>()
            })
        };
        assert_eq!(metrics(a), metrics(b), "{}", a.name);
    }
}
