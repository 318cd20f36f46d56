//! `cargo xtask reproduce`: recomputes every result of the papers; `cargo xtask perf`: the
//! benches and the peers side by side.
//!
//! The science lives in `pkm::papers`; this binary only runs the experiments, shows progress,
//! prints the comparison table and writes the report (`results.json`, `report.md`, CSV, SVG).
#![allow(clippy::print_stdout)]

mod figure;
mod perf;
mod report;
mod reproduce;
mod run;
mod table;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Project automation for pkm.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask", bin_name = "cargo xtask")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the registered experiments, compare with the papers and write the report.
    Reproduce(reproduce::ReproduceArgs),
    /// Run the benches and the peers side by side and write the performance tables.
    Perf(perf::PerfArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Reproduce(args) => reproduce::run(&args),
        Command::Perf(args) => perf::run(&args).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(status) => status,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
