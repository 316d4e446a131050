//! The command line (clap derive) and the `list` command.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::case::{Case, Mode};
use crate::cases::{all_benches, all_cases};
use crate::params::Override;
use crate::runner::{self, RunOptions};

/// `cargo xtask`: validation runs, benches and reports for chrono-rs.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask", bin_name = "cargo xtask", version, about)]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// The `cargo xtask` commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the validation cases (area, description, parameters) and the benches.
    List,
    /// Run validation cases; write report.md, summary.json, CSV series and plots.
    Validate {
        /// Cases to run, by name or area (default: all).
        #[arg(value_name = "CASE")]
        cases: Vec<String>,
        /// Options shared with `bench`.
        #[command(flatten)]
        run: RunArgs,
        /// Write VTK frames into `DIR/<case>/vtk/`.
        #[arg(long)]
        vtk: bool,
        /// Cases run at once, each on `threads / JOBS` threads (at least one); the
        /// longest first. Figures then are those of that thread count.
        #[arg(long, value_name = "JOBS", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
        jobs: u32,
    },
    /// Run whole-scene throughput benches (steps/s, contacts/s ...).
    Bench {
        /// Benches to run, by name or area (default: all).
        #[arg(value_name = "NAME")]
        benches: Vec<String>,
        /// Options shared with `validate`.
        #[command(flatten)]
        run: RunArgs,
    },
}

/// Options shared by `validate` and `bench`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Short smoke runs (coarse resolution, short horizon).
    #[arg(long, conflicts_with = "full")]
    pub quick: bool,
    /// The complete published setups (may take long).
    #[arg(long)]
    pub full: bool,
    /// Override a parameter of every selected case that has it (repeatable); VALUE is
    /// parsed as JSON, else taken as a string.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<Override>,
    /// Output directory (default: `<workspace>/target/validation` or `target/bench`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Also write the summary JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

impl RunArgs {
    fn options(&self, default_out: &str, vtk: bool, jobs: usize) -> RunOptions {
        RunOptions {
            mode: Mode::from_flags(self.quick, self.full),
            overrides: self.set.clone(),
            out_dir: self
                .out
                .clone()
                .unwrap_or_else(|| runner::workspace_root().join("target").join(default_out)),
            vtk,
            progress: runner::interactive(),
            jobs,
        }
    }
}

/// Runs a parsed command line. Returns whether everything passed.
pub fn run(cli: Cli) -> anyhow::Result<bool> {
    match cli.command {
        Command::List => {
            print!("{}", list_text(&all_cases(), &all_benches()));
            Ok(true)
        }
        Command::Validate {
            cases,
            run,
            vtk,
            jobs,
        } => {
            let opts = run.options("validation", vtk, jobs as usize);
            runner::validate(all_cases(), &cases, &opts, run.json.as_deref())
        }
        Command::Bench { benches, run } => {
            let opts = run.options("bench", false, 1);
            crate::bench::bench(all_benches(), &benches, &opts, run.json.as_deref())
        }
    }
}

fn describe(out: &mut String, case: &dyn Case) {
    use std::fmt::Write as _;
    let _ = writeln!(
        out,
        "\n  {}  [{}]\n    {}",
        case.name(),
        case.area(),
        case.description()
    );
    let params = case.params_json();
    let Some(map) = params.as_object().filter(|m| !m.is_empty()) else {
        return;
    };
    let info = case.param_info();
    let mut names: Vec<&str> = info
        .iter()
        .map(|i| i.name)
        .filter(|n| map.contains_key(*n))
        .collect();
    names.extend(
        map.keys()
            .map(String::as_str)
            .filter(|k| !info.iter().any(|i| i.name == *k)),
    );
    let rows: Vec<[String; 4]> = names
        .iter()
        .map(|&n| {
            let i = info.iter().find(|i| i.name == n);
            [
                n.to_string(),
                format!("= {}", map[n]),
                i.map_or("", |i| i.unit).to_string(),
                i.map_or("(undocumented)", |i| i.meaning).to_string(),
            ]
        })
        .collect();
    let table = crate::report::text_table(["", "", "", ""], &rows);
    for line in table.lines().skip(1) {
        let _ = writeln!(out, "      {line}");
    }
}

/// The text of `cargo xtask list`.
pub fn list_text(cases: &[Box<dyn Case>], benches: &[Box<dyn Case>]) -> String {
    let mut out = format!("Validation cases ({}):\n", cases.len());
    if cases.is_empty() {
        out += "  (none registered; see xtask/src/cases/mod.rs)\n";
    }
    for c in cases {
        describe(&mut out, c.as_ref());
    }
    out += &format!("\nBenches ({}):\n", benches.len());
    if benches.is_empty() {
        out += "  (none registered)\n";
    }
    for b in benches {
        describe(&mut out, b.as_ref());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::testing;
    use clap::CommandFactory;

    #[test]
    fn cli_is_consistent_and_parses() {
        Cli::command().debug_assert();
        let cli = Cli::try_parse_from([
            "xtask", "validate", "a", "--quick", "--set", "h=0.1", "--vtk",
        ])
        .unwrap();
        let Command::Validate {
            cases,
            run,
            vtk,
            jobs,
        } = cli.command
        else {
            panic!()
        };
        assert_eq!(cases, ["a"]);
        assert!(run.quick && vtk);
        assert_eq!(jobs, 1);
        let two = Cli::try_parse_from(["xtask", "validate", "--jobs", "2"]).unwrap();
        assert!(matches!(two.command, Command::Validate { jobs: 2, .. }));
        assert!(Cli::try_parse_from(["xtask", "validate", "--jobs", "0"]).is_err());
        assert!(Cli::try_parse_from(["xtask", "bench", "--jobs", "2"]).is_err());
        assert_eq!(run.set[0].key, "h");
        assert!(Cli::try_parse_from(["xtask", "validate", "--quick", "--full"]).is_err());
        assert!(Cli::try_parse_from(["xtask", "bench", "--set", "novalue"]).is_err());
    }

    #[test]
    fn list_shows_parameters() {
        let text = list_text(&[testing::decay_case()], &[]);
        assert!(text.contains("test-decay  [test]"), "{text}");
        assert!(
            text.lines()
                .any(|l| l.contains("h") && l.contains("= 0.01") && l.contains("time step")),
            "{text}"
        );
        assert!(
            text.contains("label") && text.contains("= \"decay\""),
            "{text}"
        );
        assert!(text.contains("Benches (0)"));
    }
}
