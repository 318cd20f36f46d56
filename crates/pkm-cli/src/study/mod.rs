//! Study files for the command: read from disk and handed to the study layer's loader
//! ([`pkm_study::load`]), which reads the files a study names relative to it and places every
//! error at its line in the study file or in the robot file. The command only reads bytes and
//! turns a placed error into [`CliError::Study`].

use crate::CliError;
use crate::output::{RobotFileEcho, StudyEcho};
use pkm_study::StudyError;
use pkm_study::load::{self, Directory, Echoed, Format, LoadError, NamedFile, Sources};
use serde::de::DeserializeOwned;
use std::path::Path;

/// The texts a study was read from: the study file and, when it names one, its robot file.
#[derive(Debug, Clone)]
pub struct StudySource {
    sources: Sources,
}

impl StudySource {
    /// The study file's text (echoed in `results.json`).
    pub fn text(&self) -> &str {
        &self.sources.text
    }

    /// The robot file the study read, for `results.json`.
    pub fn robot_echo(&self) -> Option<RobotFileEcho> {
        self.sources.robot_file.as_ref().map(|f| RobotFileEcho {
            file: f.file.clone(),
            text: f.text.clone(),
        })
    }

    /// The command's error for a study layer's error, at its line in the study file or in the
    /// robot file that holds its key.
    pub fn error(&self, error: StudyError) -> CliError {
        placed(self.sources.place(error))
    }
}

/// Reads the study at `path` with the study layer's schema and returns its text.
///
/// # Errors
/// As [`load_study_source`].
pub fn load_study<T: DeserializeOwned>(path: &Path) -> Result<(String, T), CliError> {
    load_study_source(path).map(|(source, study)| (source.sources.text, study))
}

/// Reads the study at `path` (TOML, or JSON for a `.json` file) with the study layer's schema,
/// with its named robot file (if any) read relative to it and put in place of `file`.
///
/// # Errors
/// [`CliError::Io`] when the study cannot be read; [`CliError::Study`] at the offending line
/// of the study or of the robot file.
pub fn load_study_source<T: DeserializeOwned>(path: &Path) -> Result<(StudySource, T), CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::io(path, e))?;
    let name = path.display().to_string();
    let reader = Directory::of_study(path);
    let (sources, loaded) =
        load::load(&name, text, Format::of_path(path), &reader).map_err(placed)?;
    Ok((StudySource { sources }, loaded.study))
}

/// The study of a `results.json` echo: its text, with the echoed robot file (if any) in place
/// of the one on disk, so a study's output is read back without the files it came from.
///
/// # Errors
/// As [`load_study_source`].
pub fn study_from_echo<T: DeserializeOwned>(
    echo: &StudyEcho,
) -> Result<(StudySource, T), CliError> {
    let robot = echo.robot_file.as_ref().map(|f| NamedFile {
        file: f.file.clone(),
        text: f.text.clone(),
    });
    let path = Path::new(&echo.file);
    let (sources, loaded) = load::load(
        &echo.file,
        echo.text.clone(),
        Format::of_path(path),
        &Echoed(robot),
    )
    .map_err(placed)?;
    Ok((StudySource { sources }, loaded.study))
}

/// [`CliError::Study`] at the place of a placed error; the study error as it is otherwise.
fn placed(error: LoadError) -> CliError {
    let Some(place) = error.place.map(|p| *p) else {
        return CliError::from(error.error);
    };
    let message = match error.error.path() {
        Some(key) if !key.is_root() => format!("{key}: {}", error.error.message()),
        _ => error.error.message(),
    };
    CliError::Study {
        file: place.file,
        line: place.line,
        column: place.column,
        message: format!("{message}\n    | {}", place.source_line),
    }
}
