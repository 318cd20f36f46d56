//! `pkm dynamics FILE`: the study layer's [`pkm_study::dynamics()`] on a study file: motor
//! torques by Hamilton and Lagrange along a trajectory, and the forward retrace.
//!
//! A `trajectory.csv` file is read relative to the study file by the study layer's reader
//! ([`pkm_study::dynamics::dynamics_reading`]); an error about a row is placed at the `csv` key
//! and names the CSV file and line.

use super::{Context, Report, Run};
use crate::CliError;
use pkm_study::dynamics::DynamicsStudy;
use pkm_study::load::Directory;
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
            |study: &DynamicsStudy, progress: &dyn Progress| {
                pkm_study::dynamics::dynamics_reading(study, &Directory(base.into()), progress)
            },
        )
    }
}
