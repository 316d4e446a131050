//! Writing results: `series.csv`, `report.md`, `summary.json`, and the tables printed to
//! stdout.

use std::fmt::Write as _;
use std::fs;
use std::io::{BufWriter, Write as _};
use std::path::{Path, PathBuf};

use anyhow::Context;
use serde_json::{Value, json};

use crate::case::{Check, CheckKind, Series};
use crate::runner::CaseResult;

/// A number for tables: about 6 significant digits, scientific when very large or small.
pub fn fmt_num(v: f64) -> String {
    fmt_sig(v, 6)
}

/// A number with at most `sig` significant digits (4 in scientific notation, used when
/// `|v|` is below 1e-3 or from 1e6 up), trailing zeros removed.
pub fn fmt_sig(v: f64, sig: usize) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf".into() } else { "-inf".into() };
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    let trim = |m: &str| -> String {
        if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m.to_string()
        }
    };
    let sig = sig.max(1);
    if !(1e-3..1e6).contains(&a) {
        let s = format!("{v:.*e}", (sig - 1).min(3));
        let (mantissa, exp) = s.split_once('e').expect("scientific format");
        return format!("{}e{exp}", trim(mantissa));
    }
    let decimals = (sig as i32 - 1 - a.log10().floor() as i32).clamp(0, 9) as usize;
    trim(&format!("{v:.decimals$}"))
}

/// A JSON number, or `null` when not finite.
pub fn json_num(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// Writes a series as CSV (header row = column names, full precision).
pub fn write_csv(path: &Path, series: &Series) -> anyhow::Result<()> {
    let file = fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = BufWriter::new(file);
    writeln!(w, "{}", series.columns.join(","))?;
    let mut line = String::new();
    for row in &series.rows {
        line.clear();
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            // Shortest round-trip text; exponent form for very large or small values.
            let a = v.abs();
            if a == 0.0 || (1e-4..1e15).contains(&a) || !a.is_finite() {
                write!(line, "{v}").expect("writing to a String");
            } else {
                write!(line, "{v:e}").expect("writing to a String");
            }
        }
        writeln!(w, "{line}")?;
    }
    w.flush()?;
    Ok(())
}

/// The summary of a run:
/// `{"cases": [{"name", "mode", "params", "metrics", "checks", "wall_s", "steps",
/// "series", "error"?}]}`. Non-finite numbers are `null`.
pub fn summary_json(results: &[CaseResult]) -> Value {
    let cases: Vec<Value> = results
        .iter()
        .map(|r| {
            let metrics: serde_json::Map<String, Value> = r
                .output
                .as_ref()
                .map(|o| {
                    o.metrics
                        .iter()
                        .map(|(k, v)| (k.clone(), json_num(*v)))
                        .collect()
                })
                .unwrap_or_default();
            let checks: Vec<Value> = r
                .checks()
                .iter()
                .map(|c| {
                    json!({
                        "metric": c.metric,
                        "value": json_num(c.value),
                        "reference": json_num(c.reference),
                        "tolerance": json_num(c.tolerance),
                        "pass": c.pass,
                    })
                })
                .collect();
            let mut case = json!({
                "name": r.name,
                "mode": r.mode.as_str(),
                "params": r.params,
                "metrics": metrics,
                "checks": checks,
                "wall_s": json_num(r.wall_s),
                "steps": r.steps(),
                "series": r.series_csv.as_ref().map(|p| p.display().to_string()),
            });
            if let Some(e) = &r.error {
                case["error"] = Value::String(e.clone());
            }
            case
        })
        .collect();
    json!({ "cases": cases })
}

/// Writes [`summary_json`] to `path` (pretty-printed), creating its directory.
pub fn write_summary(path: &Path, results: &[CaseResult]) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let text = serde_json::to_string_pretty(&summary_json(results))?;
    fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))
}

/// The error and tolerance of a check as shown in tables, e.g. `1.2e-3 rel`.
fn err_tol(c: &Check) -> (String, String) {
    let k = c.kind.short();
    let err = match c.kind {
        CheckKind::Below => fmt_num(c.error()),
        _ => format!("{} {k}", fmt_num(c.error())),
    };
    (err, format!("{} {k}", fmt_num(c.tolerance)))
}

fn pass_text(pass: bool) -> &'static str {
    if pass { "PASS" } else { "FAIL" }
}

/// The rows of the result table (one per check; one for a case without checks).
/// Columns: case, metric, value, reference, error, tolerance, pass, wall s, steps/s.
pub fn table_rows(results: &[CaseResult]) -> Vec<[String; 9]> {
    let mut rows = Vec::new();
    for r in results {
        let wall = fmt_sig(r.wall_s, 3);
        let rate = r.steps_per_s().map_or("-".into(), |v| fmt_sig(v, 3));
        for c in r.checks() {
            let (err, tol) = err_tol(c);
            let reference = match c.kind {
                CheckKind::Below => "-".to_string(),
                _ => fmt_num(c.reference),
            };
            let pass = pass_text(c.pass && r.error.is_none()).to_string();
            let row = [
                r.name.clone(),
                c.metric.clone(),
                fmt_num(c.value),
                reference,
                err,
                tol,
                pass,
            ];
            let [a, b, cc, d, e, f, g] = row;
            rows.push([a, b, cc, d, e, f, g, wall.clone(), rate.clone()]);
        }
        if r.checks().is_empty() {
            let (metric, pass) = match &r.error {
                Some(_) => ("(error, see below)", "FAIL"),
                None => ("(no checks)", "-"),
            };
            let dash = || "-".to_string();
            rows.push([
                r.name.clone(),
                metric.into(),
                dash(),
                dash(),
                dash(),
                dash(),
                pass.into(),
                wall,
                rate,
            ]);
        }
    }
    rows
}

fn md_escape(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// How far a check is from failing: its error over its tolerance (`value / limit` for
/// [`CheckKind::Below`]); 1 is the edge, above 1 fails. Infinite for a zero tolerance
/// with a nonzero error, NaN for a non-finite value.
pub fn tolerance_ratio(c: &Check) -> f64 {
    let e = c.error();
    if !e.is_finite() || !c.tolerance.is_finite() {
        return f64::NAN;
    }
    if c.tolerance == 0.0 {
        return if e == 0.0 { 0.0 } else { f64::INFINITY };
    }
    e / c.tolerance.abs()
}

/// The one-screen summary, one row per area (in the order of first appearance) and a
/// total: cases, passed, the worst check as `error / tolerance` with its case and
/// metric, and the wall time. Columns: area, cases, passed, worst, worst check, wall.
pub fn area_rows(results: &[CaseResult]) -> Vec<[String; 6]> {
    let mut areas: Vec<&str> = Vec::new();
    for r in results {
        if !areas.contains(&r.area.as_str()) {
            areas.push(&r.area);
        }
    }
    let row = |label: &str, rs: &[&CaseResult]| -> [String; 6] {
        let passed = rs.iter().filter(|r| r.passed()).count();
        let wall: f64 = rs.iter().map(|r| r.wall_s).sum();
        // NaN (a non-finite value) ranks worst of all.
        let worst = rs
            .iter()
            .flat_map(|r| r.checks().iter().map(move |c| (r, c, tolerance_ratio(c))))
            .max_by(|a, b| {
                let key = |x: f64| if x.is_nan() { f64::INFINITY } else { x };
                key(a.2).total_cmp(&key(b.2))
            });
        let (ratio, which) = match worst {
            Some((r, c, x)) => (fmt_sig(x, 2), format!("{} `{}`", r.name, c.metric)),
            None => ("-".into(), "-".into()),
        };
        let errors = rs.iter().filter(|r| r.error.is_some()).count();
        let which = if errors > 0 {
            format!("{which} ({errors} errored)")
        } else {
            which
        };
        [
            label.to_string(),
            rs.len().to_string(),
            passed.to_string(),
            ratio,
            which,
            fmt_sig(wall, 3),
        ]
    };
    let mut rows: Vec<[String; 6]> = areas
        .iter()
        .map(|a| {
            let rs: Vec<&CaseResult> = results.iter().filter(|r| r.area == *a).collect();
            row(a, &rs)
        })
        .collect();
    let all: Vec<&CaseResult> = results.iter().collect();
    rows.push(row("total", &all));
    rows
}

/// The header of [`area_rows`].
pub const AREA_HEADER: [&str; 6] = [
    "area",
    "cases",
    "passed",
    "worst error / tolerance",
    "worst check",
    "wall s",
];

/// Writes `DIR/report.md`: the table, metrics without checks, plots, errors, parameters.
pub fn write_report_md(dir: &Path, title: &str, results: &[CaseResult]) -> anyhow::Result<PathBuf> {
    let mut md = String::new();
    let failed = results.iter().filter(|r| !r.passed()).count();
    let checks: usize = results.iter().map(|r| r.checks().len()).sum();
    let wall: f64 = results.iter().map(|r| r.wall_s).sum();
    let mode = results.first().map_or("default", |r| r.mode.as_str());
    writeln!(md, "# {title}\n")?;
    writeln!(
        md,
        "Mode `{mode}` · cases: {} · checks: {checks} · failed cases: {failed} · run time: {} s\n",
        results.len(),
        fmt_sig(wall, 3)
    )?;
    writeln!(md, "## Summary\n")?;
    writeln!(md, "| {} |", AREA_HEADER.join(" | "))?;
    writeln!(md, "|---|--:|--:|--:|---|--:|")?;
    for row in area_rows(results) {
        let cells: Vec<String> = row.iter().map(|c| md_escape(c)).collect();
        writeln!(md, "| {} |", cells.join(" | "))?;
    }
    writeln!(md, "\n## Checks\n")?;
    writeln!(
        md,
        "| case | metric | value | reference | error | tolerance | pass | wall s | steps/s |"
    )?;
    writeln!(md, "|---|---|--:|--:|--:|--:|---|--:|--:|")?;
    for row in table_rows(results) {
        let cells: Vec<String> = row.iter().map(|c| md_escape(c)).collect();
        let mut line = format!("| {} |", cells.join(" | "));
        if row[6] == "FAIL" {
            line = line.replace("| FAIL |", "| **FAIL** |");
        }
        writeln!(md, "{line}")?;
    }
    let unchecked = |r: &CaseResult| -> Vec<(String, f64)> {
        let Some(o) = &r.output else {
            return Vec::new();
        };
        let checked = |k: &String| o.checks.iter().any(|c| &c.metric == k);
        o.metrics
            .iter()
            .filter(|(k, _)| !checked(k))
            .map(|(k, v)| (k.clone(), *v))
            .collect()
    };
    if results.iter().any(|r| !unchecked(r).is_empty()) {
        writeln!(md, "\n## Metrics without checks\n")?;
        for r in results.iter().filter(|r| !unchecked(r).is_empty()) {
            let list: Vec<String> = unchecked(r)
                .iter()
                .map(|(k, v)| format!("`{k}` = {}", fmt_num(*v)))
                .collect();
            writeln!(md, "- **{}**: {}", r.name, list.join(", "))?;
        }
    }
    let sweeps = sweep_rows(results);
    if !sweeps.is_empty() {
        writeln!(
            md,
            "\n## Speed against error\n\nEach run of a case (e.g. one per contact method): its error against the case's reference and its wall time.\n"
        )?;
        writeln!(md, "| {} |", SWEEP_HEADER.join(" | "))?;
        writeln!(md, "|---|---|--:|--:|")?;
        for row in &sweeps {
            let cells: Vec<String> = row.iter().map(|c| md_escape(c)).collect();
            writeln!(md, "| {} |", cells.join(" | "))?;
        }
    }
    if results.iter().any(|r| !r.plots.is_empty()) {
        writeln!(md, "\n## Plots")?;
        for r in results.iter().filter(|r| !r.plots.is_empty()) {
            writeln!(md, "\n### {}\n\n{}\n", r.name, r.description)?;
            for p in &r.plots {
                let rel = p.strip_prefix(dir).unwrap_or(p);
                let rel = rel.to_string_lossy().replace('\\', "/");
                writeln!(md, "![{}]({rel})", r.name)?;
            }
        }
    }
    if results.iter().any(|r| r.error.is_some()) {
        writeln!(md, "\n## Errors\n")?;
        for r in results {
            if let Some(e) = &r.error {
                writeln!(md, "**{}** failed:\n\n```text\n{e}\n```\n", r.name)?;
            }
        }
    }
    if results.iter().any(|r| !r.warnings.is_empty()) {
        writeln!(md, "\n## Warnings\n")?;
        for r in results {
            for w in &r.warnings {
                writeln!(md, "- **{}**: {}", r.name, md_escape(w))?;
            }
        }
    }
    writeln!(md, "\n## Parameters\n")?;
    for r in results {
        writeln!(md, "- **{}** ({}): `{}`", r.name, r.area, r.params)?;
    }
    let path = dir.join("report.md");
    fs::write(&path, md).with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

/// Formats rows as a plain-text table with aligned columns.
pub fn text_table<const N: usize>(header: [&str; N], rows: &[[String; N]]) -> String {
    let mut width = header.map(|h| h.chars().count());
    for row in rows {
        for (w, cell) in width.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let mut out = String::new();
    let mut line = |cells: Vec<&str>| {
        let padded: Vec<String> = cells
            .iter()
            .zip(width)
            .map(|(c, w)| format!("{c:<w$}"))
            .collect();
        out.push_str(padded.join("  ").trim_end());
        out.push('\n');
    };
    line(header.to_vec());
    for row in rows {
        line(row.iter().map(String::as_str).collect());
    }
    out
}

/// Rows of the speed-against-error comparison: every run a case recorded in its sweep
/// (`CaseOutput::sweep`: e.g. one per contact method and parameter value), with its error
/// against the case's reference and its wall time. Empty when no case has a sweep.
pub fn sweep_rows(results: &[CaseResult]) -> Vec<[String; 4]> {
    let mut rows = Vec::new();
    for r in results {
        let Some(o) = &r.output else { continue };
        for s in &o.sweep {
            rows.push([
                r.name.clone(),
                s.label.clone(),
                fmt_sig(s.error, 3),
                fmt_sig(s.wall_s, 3),
            ]);
        }
    }
    rows
}

const SWEEP_HEADER: [&str; 4] = ["case", "run", "error", "wall s"];

/// The speed-against-error comparison for stdout (nothing when no case has a sweep).
pub fn print_sweeps(results: &[CaseResult]) {
    let rows = sweep_rows(results);
    if !rows.is_empty() {
        println!(
            "\nspeed against error (each run of a case: error against its reference, wall time)"
        );
        print!("{}", text_table(SWEEP_HEADER, &rows));
    }
}

/// The result table for stdout.
pub fn print_table(results: &[CaseResult]) {
    const HEADER: [&str; 9] = [
        "case",
        "metric",
        "value",
        "reference",
        "error",
        "tolerance",
        "pass",
        "wall s",
        "steps/s",
    ];
    print!("{}", text_table(HEADER, &table_rows(results)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_formatting() {
        assert_eq!(fmt_num(0.0), "0");
        assert_eq!(fmt_num(1.0), "1");
        assert_eq!(fmt_num(0.25), "0.25");
        assert_eq!(fmt_num(123456.7), "123457");
        assert_eq!(fmt_num(1.0 / 3.0), "0.333333");
        assert_eq!(fmt_num(2.5e-7), "2.5e-7");
        assert_eq!(fmt_num(1.23456e9), "1.235e9");
        assert_eq!(fmt_sig(0.00644603, 3), "0.00645");
        assert_eq!(fmt_sig(213519.0, 3), "213519");
        assert_eq!(fmt_sig(1.334e6, 3), "1.33e6");
        assert_eq!(fmt_num(f64::NAN), "NaN");
        assert_eq!(fmt_num(f64::NEG_INFINITY), "-inf");
        assert_eq!(json_num(f64::NAN), Value::Null);
        assert_eq!(json_num(1.5), json!(1.5));
    }

    #[test]
    fn csv_round_trips() {
        let path = std::env::temp_dir().join(format!("xtask-csv-{}.csv", std::process::id()));
        let mut s = Series::new(["t", "x"]);
        s.push(&[0.0, 1e-20]);
        s.push(&[0.1, f64::NAN]);
        s.push(&[1e20, -2.5]);
        write_csv(&path, &s).unwrap();
        let text = fs::read_to_string(&path).unwrap();
        assert_eq!(text, "t,x\n0,1e-20\n0.1,NaN\n1e20,-2.5\n");
        let back: Vec<f64> = text
            .lines()
            .skip(1)
            .flat_map(|l| l.split(','))
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(back[1], 1e-20);
        assert_eq!(back[4], 1e20);
        fs::remove_file(&path).unwrap();
    }

    #[test]
    fn text_table_aligns_columns() {
        let rows = [
            ["a".to_string(), "1".to_string()],
            ["long".to_string(), "22".to_string()],
        ];
        assert_eq!(
            text_table(["x", "y"], &rows),
            "x     y\na     1\nlong  22\n"
        );
    }
}
