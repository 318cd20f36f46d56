//! The `pkm` executable: parses the command line, runs it, prints the summary or the error.
#![allow(clippy::print_stdout)]

use clap::Parser;
use pkm_cli::{Cli, CliError, run};
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(&cli) {
        Ok(report) => {
            for line in report.lines {
                println!("{line}");
            }
            ExitCode::SUCCESS
        }
        Err(CliError::Cancelled) => {
            eprintln!("pkm: cancelled; no results written");
            ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("pkm: {e}");
            ExitCode::FAILURE
        }
    }
}
