//! `pkm task FILE`: the study layer's [`pkm_study::task()`] on a study file: task-based synthesis
//! after Wolf & Shoham (pose and geometry of a Stewart–Gough platform or a 3-UPU for weighted
//! task twists) and the 3-UPU singularity search; the starts as CSV and SVG, the optimal pose
//! drawn with the task twists' axes.

use super::{Context, Report, Run};
use crate::CliError;
use std::path::PathBuf;

/// Arguments of `pkm task`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study file (TOML).
    pub file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        super::run_library_study(
            "task",
            &self.file,
            context,
            pkm_study::task::<pkm_study::MechanismSpec>,
        )
    }
}
