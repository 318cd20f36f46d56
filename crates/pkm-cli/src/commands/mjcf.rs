//! `pkm mjcf ROBOT_FILE`: a robot file with its masses as MuJoCo's MJCF (`pkm_study::mjcf`):
//! the legs as nested bodies, the loops closed by `connect` and `weld` equality constraints,
//! a motor per actuator. Writes `robot.xml` to `--out`.

use super::{Context, Report, Run};
use crate::CliError;
use std::path::PathBuf;

/// Arguments of `pkm mjcf`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The robot file (`docs/robots.md`).
    pub robot_file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let mjcf = super::export_robot_file(&self.robot_file, pkm_study::mjcf)?;
        std::fs::create_dir_all(&context.out).map_err(|e| CliError::io(&context.out, e))?;
        let file = context.out.join("robot.xml");
        std::fs::write(&file, mjcf).map_err(|e| CliError::io(&file, e))?;
        let mut report = Report { lines: Vec::new() };
        report.line(format!("wrote {}", file.display()));
        Ok(report)
    }
}
