//! The `pkm` command: design studies of parallel kinematic machines described in TOML study
//! files (see `docs/studies.md`). The binary (`src/main.rs`) only parses the arguments, calls
//! [`run`] and prints; everything else is here, so tests call the same functions.

pub mod commands;
pub use pkm_study::scene as drawing;
mod error;
pub mod output;
pub mod progress;
pub mod study;

pub use commands::{Command, Context, Report, Run};
pub use error::CliError;

use clap::Parser;
use progress::{CancelFlag, Spinner};
use std::path::PathBuf;

/// `pkm`: design studies of parallel kinematic machines from TOML study files.
#[derive(Debug, Parser)]
#[command(name = "pkm", version, about, long_about = None)]
pub struct Cli {
    /// What to run.
    #[command(subcommand)]
    pub command: Command,
    /// Directory for results.json, CSV tables and SVG figures (created if needed).
    #[arg(long, global = true, default_value = "pkm-out")]
    pub out: PathBuf,
    /// Worker threads (default: one per core). Results do not depend on it.
    #[arg(long, global = true)]
    pub threads: Option<usize>,
    /// No progress bar.
    #[arg(long, short, global = true)]
    pub quiet: bool,
}

/// Runs the command of `cli` with Ctrl-C cancellation and its thread count.
///
/// # Errors
/// Whatever stops the command; [`CliError::Cancelled`] on Ctrl-C.
pub fn run(cli: &Cli) -> Result<Report, CliError> {
    let cancel = CancelFlag::on_ctrl_c().map_err(CliError::Invalid)?;
    let context = Context {
        out: cli.out.clone(),
        progress: Spinner::new(cli.command.name(), cancel, cli.quiet),
    };
    let result = with_threads(cli.threads, || cli.command.run(&context));
    context.progress.close();
    result?
}

/// Runs `work` on a rayon pool of `threads` workers (the global pool when `None`).
///
/// # Errors
/// [`CliError::Invalid`] for zero threads or a pool that cannot be built.
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> T + Send,
) -> Result<T, CliError> {
    match threads {
        None => Ok(work()),
        Some(0) => Err(CliError::Invalid("--threads: expected at least 1".into())),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(|pool| pool.install(work))
            .map_err(|e| CliError::Invalid(format!("--threads {n}: {e}"))),
    }
}
