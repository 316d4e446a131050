//! `cargo xtask`: the validation and bench runner of chrono-rs.
//!
//! A validation case ([`case::Case`], usually built with [`params::ParamCase`]) has
//! serde parameters whose defaults are the published or analytic setup, and a run that
//! returns metrics, checks against references, a time series and a step count
//! ([`output::CaseOutput`]). The runner ([`runner`]) times the runs, and [`report`] and
//! [`plot`] write `report.md`, `summary.json`, `series.csv` and PNG plots. Cases are
//! registered in [`cases`]; the command line is in [`cli`].

pub mod bench;
pub mod budget;
pub mod case;
pub mod cases;
pub mod cli;
pub mod eta;
pub mod fit;
pub mod output;
pub mod params;
pub mod plot;
pub mod reference;
pub mod report;
pub mod runner;

#[cfg(test)]
mod tests;
