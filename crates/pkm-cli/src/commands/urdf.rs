//! `pkm urdf ROBOT_FILE`: a robot file with its masses as URDF plus its loop closures
//! (`pkm_study::urdf`), for tools that take a tree and constraints (Pinocchio's
//! closed-loop models). Writes `robot.urdf` and `closures.yaml` to `--out`.

use super::{Context, Report, Run};
use crate::CliError;
use std::path::PathBuf;

/// Arguments of `pkm urdf`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The robot file (`docs/robots.md`).
    pub robot_file: PathBuf,
}

impl Run for Args {
    fn run(&self, context: &Context) -> Result<Report, CliError> {
        let export = super::export_robot_file(&self.robot_file, pkm_study::urdf)?;
        std::fs::create_dir_all(&context.out).map_err(|e| CliError::io(&context.out, e))?;
        let mut report = Report { lines: Vec::new() };
        for (name, text) in [
            ("robot.urdf", &export.urdf),
            ("closures.yaml", &export.closures),
        ] {
            let file = context.out.join(name);
            std::fs::write(&file, text).map_err(|e| CliError::io(&file, e))?;
            report.line(format!("wrote {}", file.display()));
        }
        Ok(report)
    }
}
