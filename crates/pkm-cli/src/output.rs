//! What a command leaves in `--out DIR`: `results.json` (a versioned schema with the study file
//! echoed in it), CSV tables and SVG figures, each written atomically by `pkm-term`'s
//! [`OutputDir`] (a temporary file renamed into place), so an interrupted run never leaves a
//! half-written file.
//!
//! Nothing that depends on the run (time, thread count, host) goes into `results.json`: two
//! runs of the same study, or a sharded run and its merge, write the same bytes.

use crate::CliError;
use pkm_draw::chart::render_svg as render_chart;
use pkm_draw::{DrawOptions, Scene, render_svg};
use pkm_study::Artifact;
use pkm_study::scene::{ROBOT_CSV, ROBOT_SVG};
use pkm_term::{OutputDir, OutputError};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What a command tells the user when it is done (printed by `main`, one line each).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Lines of the summary.
    pub lines: Vec<String>,
}

impl Report {
    /// Adds a line.
    pub fn line(&mut self, line: impl Into<String>) {
        self.lines.push(line.into());
    }
}

/// The schema of `results.json`; bumped on any incompatible change.
pub const SCHEMA: &str = "pkm-cli/results/v1";

/// The study as echoed in `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyEcho {
    /// The path the study was read from, as given.
    pub file: String,
    /// Its full text.
    pub text: String,
    /// The robot file named by the study's `[mechanism.robot_file] file`, so that
    /// `results.json` holds everything the study read (absent for any other study).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub robot_file: Option<RobotFileEcho>,
}

/// A robot file read by a study, as echoed in `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotFileEcho {
    /// The path it was read from (the study file's directory joined with `file`).
    pub file: String,
    /// Its full text.
    pub text: String,
}

/// The envelope of every `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Results<R> {
    /// [`SCHEMA`].
    pub schema: String,
    /// The command that wrote it.
    pub command: String,
    /// Version of pkm-cli.
    pub version: String,
    /// The study file.
    pub study: StudyEcho,
    /// The command's result.
    pub result: R,
    /// The other files written beside it, in the order written.
    pub files: Vec<String>,
}

/// The output directory of one command.
#[derive(Debug)]
pub struct Output {
    dir: OutputDir,
}

/// The command's error for a failed write of `name`.
fn error(name: &str, e: OutputError) -> CliError {
    match e {
        OutputError::Io { path, source } => CliError::io(path, source),
        OutputError::Writer { source, .. } => CliError::Invalid(format!("{name}: {source}")),
        e => CliError::Invalid(e.to_string()),
    }
}

impl Output {
    /// Creates `dir` (and its parents) if needed and checks that it can be written.
    ///
    /// # Errors
    /// [`CliError::Io`] when it cannot be created or written; [`CliError::Invalid`] when it is
    /// not a directory.
    pub fn create(dir: &Path) -> Result<Self, CliError> {
        Ok(Self {
            dir: OutputDir::create(dir).map_err(|e| error("--out", e))?,
        })
    }

    /// Writes `bytes` to `name` atomically and records it.
    ///
    /// # Errors
    /// [`CliError::Io`]; [`CliError::Invalid`] for a name that is not a plain file name.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, CliError> {
        self.dir.write(name, bytes).map_err(|e| error(name, e))
    }

    /// Writes a study's artifacts in order: tables as CSV, charts as SVG, the robot as
    /// [`ROBOT_SVG`] and [`ROBOT_CSV`] (a drawing that cannot be rendered becomes a warning
    /// line of `report`).
    ///
    /// # Errors
    /// [`CliError::Io`]; [`CliError::Invalid`] for a chart the renderer refuses.
    pub fn write_artifacts(
        &mut self,
        artifacts: &[Artifact],
        report: &mut Report,
    ) -> Result<(), CliError> {
        for artifact in artifacts {
            match artifact {
                Artifact::Table { name, table } => {
                    self.write(name, table.to_csv().as_bytes())?;
                }
                Artifact::Chart { name, chart } => {
                    let svg = render_chart(chart)
                        .map_err(|e| CliError::Invalid(format!("{name}: {e}")))?;
                    self.write(name, svg.as_bytes())?;
                }
                Artifact::Robot { caption, scene } => {
                    self.write_robot(report, caption, Ok(scene.as_ref().clone()))?;
                }
            }
        }
        Ok(())
    }

    /// Renders `scene` with the caption `title` and writes [`ROBOT_SVG`] and [`ROBOT_CSV`]; a
    /// scene that could not be built or drawn becomes a warning line of `report` instead.
    ///
    /// # Errors
    /// [`CliError::Io`] only: a failed drawing is a warning, not an error.
    pub fn write_robot(
        &mut self,
        report: &mut Report,
        title: &str,
        scene: Result<Scene, String>,
    ) -> Result<(), CliError> {
        let drawn = scene.and_then(|scene| {
            let svg = render_svg(&scene, &DrawOptions::titled(title)).map_err(|e| e.to_string())?;
            Ok((scene, svg))
        });
        match drawn {
            Ok((scene, svg)) => {
                self.write(ROBOT_SVG, svg.as_bytes())?;
                self.write(ROBOT_CSV, scene.to_csv().as_bytes())?;
            }
            Err(reason) => report.line(format!("warning: no drawing of the robot: {reason}")),
        }
        Ok(())
    }

    /// Writes `results.json` last, listing every file written before it.
    ///
    /// # Errors
    /// [`CliError::Io`]; [`CliError::Invalid`] when the result cannot be serialised.
    pub fn finish<R: Serialize>(
        mut self,
        command: &str,
        study: StudyEcho,
        result: R,
    ) -> Result<PathBuf, CliError> {
        let results = Results {
            schema: SCHEMA.to_owned(),
            command: command.to_owned(),
            version: env!("CARGO_PKG_VERSION").to_owned(),
            study,
            result,
            files: self.dir.files().to_vec(),
        };
        let mut json = serde_json::to_string_pretty(&results)
            .map_err(|e| CliError::Invalid(format!("results.json: {e}")))?;
        json.push('\n');
        self.write("results.json", json.as_bytes())
    }
}

pub use pkm_study::short;
