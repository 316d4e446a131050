//! `cargo xtask list | validate | bench` (see the `xtask` library for the runner).

use std::process::ExitCode;

use clap::Parser;
use xtask::cli::{self, Cli};

fn main() -> ExitCode {
    // under `mpirun -n N` every rank would run every case whole: say so instead
    if let Err(e) = chrono_sph::distributed::require_single_process("xtask") {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    match cli::run(Cli::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
