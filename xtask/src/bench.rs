//! `cargo xtask bench`: whole-scene throughput runs. A bench is a [`Case`] whose metrics
//! are throughput numbers (steps/s, contacts/s ...) and that usually has no checks.

use std::path::Path;

use anyhow::Context;

use crate::case::Case;
use crate::report::{self, fmt_num};
use crate::runner::{self, CaseResult, RunOptions};

/// The metric rows printed for benches: bench, metric, value.
fn metric_rows(results: &[CaseResult]) -> Vec<[String; 3]> {
    let mut rows = Vec::new();
    for r in results {
        if let Some(e) = &r.error {
            rows.push([
                r.name.clone(),
                "error".into(),
                e.lines().next().unwrap_or("").into(),
            ]);
            continue;
        }
        rows.push([r.name.clone(), "wall_s".into(), fmt_num(r.wall_s)]);
        if let Some(rate) = r.steps_per_s() {
            rows.push([r.name.clone(), "steps/s".into(), fmt_num(rate)]);
        }
        if let Some(out) = &r.output {
            for (k, v) in &out.metrics {
                rows.push([r.name.clone(), k.clone(), fmt_num(*v)]);
            }
        }
    }
    rows
}

/// Runs the selected benches of `all`, writes `summary.json` into `opts.out_dir` (and
/// `json` if given), prints the metrics. Returns whether every bench ran (and passed
/// its checks, if it has any).
pub fn bench(
    all: Vec<Box<dyn Case>>,
    names: &[String],
    opts: &RunOptions,
    json: Option<&Path>,
) -> anyhow::Result<bool> {
    let mut benches = runner::select(all, names, "bench")?;
    if benches.is_empty() {
        println!("no benches are registered (see xtask/src/cases/mod.rs); nothing to do");
        return Ok(true);
    }
    runner::prepare(&mut benches, opts.mode, &opts.overrides)?;
    std::fs::create_dir_all(&opts.out_dir)
        .with_context(|| format!("creating {}", opts.out_dir.display()))?;
    let results = runner::run_all(&mut benches, opts)?;
    let summary = opts.out_dir.join("summary.json");
    report::write_summary(&summary, &results)?;
    if let Some(json) = json {
        report::write_summary(json, &results)?;
    }
    println!();
    print!(
        "{}",
        report::text_table(["bench", "metric", "value"], &metric_rows(&results))
    );
    println!("\nsummary: {}", summary.display());
    Ok(results.iter().all(CaseResult::passed))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::Mode;
    use crate::cases::testing;

    #[test]
    fn bench_prints_metrics_and_writes_json() {
        let dir = crate::tests::temp_dir("bench");
        let opts = RunOptions {
            mode: Mode::Quick,
            overrides: Vec::new(),
            out_dir: dir.clone(),
            vtk: false,
            progress: false,
            jobs: 1,
        };
        let ok = bench(vec![testing::decay_case()], &[], &opts, None).unwrap();
        assert!(ok);
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["cases"][0]["name"], "test-decay");
        let results = [CaseResult {
            name: "b".into(),
            area: "a".into(),
            description: String::new(),
            mode: Mode::Default,
            params: serde_json::json!({}),
            output: None,
            error: Some("boom\nmore".into()),
            wall_s: 0.0,
            series_csv: None,
            plots: Vec::new(),
            warnings: Vec::new(),
        }];
        assert_eq!(
            metric_rows(&results),
            [["b".to_string(), "error".into(), "boom".into()]]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
