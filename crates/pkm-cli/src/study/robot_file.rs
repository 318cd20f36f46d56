//! `[mechanism.robot_file] file = "..."`: the robot file is read relative to the study file
//! before the study runs (the study layer never guesses a working directory), and every error
//! about it is placed at its line and column in the robot file.

use super::{error_at, locate, study_error};
use crate::CliError;
use crate::output::{RobotFileEcho, StudyEcho};
use pkm_study::schema::robot_file::MODES;
use pkm_study::{Key, KeyPath, StudyError};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// The texts a study was read from: the study file and, when it names one, its robot file.
#[derive(Debug, Clone)]
pub struct StudySource {
    /// The study file.
    pub path: PathBuf,
    /// Its text (echoed in `results.json`).
    pub text: String,
    /// The robot file named by `[mechanism.robot_file] file`, and its text.
    robot: Option<(PathBuf, String)>,
}

impl StudySource {
    /// The robot file the study read, for `results.json`.
    pub fn robot_echo(&self) -> Option<RobotFileEcho> {
        self.robot.as_ref().map(|(path, text)| RobotFileEcho {
            file: path.display().to_string(),
            text: text.clone(),
        })
    }

    /// The command's error for a study layer's error: a key under `mechanism.robot_file` of a
    /// named robot file at its line and column in that file, any other at its place in the
    /// study file.
    pub fn error(&self, error: StudyError) -> CliError {
        let inner = error.path().and_then(inside_robot_file);
        match (&self.robot, inner) {
            (Some((path, text)), Some(inner)) => {
                let key = error.path().map(ToString::to_string).unwrap_or_default();
                error_at(
                    path,
                    text,
                    locate(text, &inner),
                    &format!("{key}: {}", error.message()),
                )
            }
            _ => study_error(&self.path, &self.text, error),
        }
    }
}

/// The path inside the robot file of a key under `mechanism.robot_file` (not the study's own
/// `modes`, which is in the study file).
fn inside_robot_file(key: &KeyPath) -> Option<KeyPath> {
    match key.keys() {
        [Key::Field(m), Key::Field(r), Key::Field(k), ..]
            if m == "mechanism" && r == "robot_file" && k == MODES =>
        {
            None
        }
        [Key::Field(m), Key::Field(r), rest @ ..] if m == "mechanism" && r == "robot_file" => {
            Some(rest.iter().fold(KeyPath::root(), |path, k| match k {
                Key::Field(name) => path.field(name.clone()),
                Key::Index(i) => path.index(*i),
            }))
        }
        _ => None,
    }
}

/// Reads the study at `path` with the study layer's schema and returns its text.
///
/// # Errors
/// As [`load_study_source`].
pub fn load_study<T: DeserializeOwned>(path: &Path) -> Result<(String, T), CliError> {
    load_study_source(path).map(|(source, study)| (source.text, study))
}

/// Reads the study at `path` with the study layer's schema, with its named robot file (if
/// any) read relative to it and put in place of `file`.
///
/// # Errors
/// [`CliError::Io`] when the study cannot be read; [`CliError::Study`] at the offending line
/// of the study or of the robot file.
pub fn load_study_source<T: DeserializeOwned>(path: &Path) -> Result<(StudySource, T), CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::io(path, e))?;
    parse_study_source(path, text, |robot_path| std::fs::read_to_string(robot_path))
}

/// The study of a `results.json` echo: its text, with the echoed robot file (if any) in place
/// of the one on disk, so a study's output is read back without the files it came from.
///
/// # Errors
/// As [`load_study_source`].
pub fn study_from_echo<T: DeserializeOwned>(echo: &StudyEcho) -> Result<T, CliError> {
    let robot = echo.robot_file.clone();
    let read = |_: &Path| match robot {
        Some(robot) => Ok(robot.text),
        None => Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "results.json echoes no robot file",
        )),
    };
    parse_study_source(Path::new(&echo.file), echo.text.clone(), read).map(|(_, study)| study)
}

/// The study in `text` (read from `path`), its named robot file (if any) read by `read` from
/// its path relative to `path` and put in place of `file`.
fn parse_study_source<T: DeserializeOwned>(
    path: &Path,
    text: String,
    read: impl FnOnce(&Path) -> std::io::Result<String>,
) -> Result<(StudySource, T), CliError> {
    let mut source = StudySource {
        path: path.to_path_buf(),
        text,
        robot: None,
    };
    let Some((mut document, file)) = named_robot_file(&source.text) else {
        let study = pkm_study::from_toml_str(&source.text)
            .map_err(|e| study_error(path, &source.text, e))?;
        return Ok((source, study));
    };
    let robot_path = path.parent().unwrap_or(Path::new("")).join(&file);
    let robot_text = read(&robot_path).map_err(|e| {
        let key = KeyPath::parse("mechanism.robot_file.file");
        let message = format!("{key}: cannot read {}: {e}", robot_path.display());
        error_at(path, &source.text, locate(&source.text, &key), &message)
    })?;
    if let Err(e) = pkm_study::schema::robot_file::check_robot_file_size(robot_text.len()) {
        let key = KeyPath::parse("mechanism.robot_file.file");
        let message = format!("{key}: {}: {e}", robot_path.display());
        return Err(error_at(
            path,
            &source.text,
            locate(&source.text, &key),
            &message,
        ));
    }
    let robot = toml::from_str::<Table>(&robot_text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        error_at(&robot_path, &robot_text, span, e.message().trim_end())
    })?;
    if robot.contains_key(MODES) {
        let key = KeyPath::root().field(MODES.to_owned());
        let message =
            format!("`{MODES}` is a key of the study's robot_file table, not of a robot file");
        return Err(error_at(
            &robot_path,
            &robot_text,
            locate(&robot_text, &key),
            &message,
        ));
    }
    if let Some(mechanism) = document.get_mut("mechanism").and_then(Value::as_table_mut) {
        let mut robot = robot;
        let modes = mechanism
            .get("robot_file")
            .and_then(|t| t.get(MODES))
            .cloned();
        if let Some(modes) = modes {
            robot.insert(MODES.into(), modes);
        }
        mechanism.insert("robot_file".into(), Value::Table(robot));
    }
    source.robot = Some((robot_path, robot_text));
    let study =
        pkm_study::from_deserializer(Value::Table(document)).map_err(|e| source.error(e))?;
    Ok((source, study))
}

/// The study document and the path of its `[mechanism.robot_file] file`, when the table holds
/// `file` alone or with the study's `modes` (with other keys the study layer reports the mix).
fn named_robot_file(text: &str) -> Option<(Table, String)> {
    let document = toml::from_str::<Table>(text).ok()?;
    let table = document.get("mechanism")?.get("robot_file")?.as_table()?;
    let file = table.get("file")?.as_str()?.to_owned();
    let only_file = table.keys().all(|k| k == "file" || k == MODES);
    only_file.then_some((document, file))
}
