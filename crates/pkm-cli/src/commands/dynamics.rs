//! `pkm dynamics FILE`: the study layer's [`pkm_study::dynamics()`] on a study file: motor
//! torques by Hamilton and Lagrange along a trajectory, and the forward retrace.
//!
//! A `trajectory.csv` file is read here, relative to the study file, and handed to the study
//! layer as `trajectory.positions` (the study layer reads no files); an error about a row is
//! placed at the `csv` key and names the CSV file and line.

use super::{Context, Report, Run};
use crate::CliError;
use pkm_study::StudyError;
use pkm_study::dynamics::{DynamicsStudy, TrajectoryCsv};
use pkm_traits::Progress;
use std::path::{Path, PathBuf};

/// Arguments of `pkm dynamics`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let base = self.file.parent().unwrap_or(Path::new(""));
        super::run_library_study(
            "dynamics",
            &self.file,
            context,
            |study: &DynamicsStudy, progress: &dyn Progress| run(base, study, progress),
        )
    }
}

/// Runs `study`, first reading its CSV trajectory (relative to `base`) into its positions.
fn run(
    base: &Path,
    study: &DynamicsStudy,
    progress: &dyn Progress,
) -> Result<pkm_study::Outcome<pkm_study::DynamicsResult>, StudyError> {
    let Some(name) = &study.trajectory.csv else {
        return pkm_study::dynamics(study, progress);
    };
    read_csv(&base.join(name))?.run(study, progress)
}

/// Reads the CSV file `path` (refused unread above [`TrajectoryCsv::MAX_BYTES`]).
///
/// # Errors
/// [`StudyError::Invalid`] at `trajectory.csv` naming the file (and the line) for a file that
/// cannot be read, is too large, or has a row that is not four finite numbers.
fn read_csv(path: &Path) -> Result<TrajectoryCsv, StudyError> {
    let unreadable = |e: std::io::Error| {
        StudyError::invalid("trajectory.csv", format!("{}: {e}", path.display()))
    };
    TrajectoryCsv::check_size(path, std::fs::metadata(path).map_err(unreadable)?.len())?;
    let text = std::fs::read_to_string(path).map_err(unreadable)?;
    TrajectoryCsv::parse(path, &text)
}
