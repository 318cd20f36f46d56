//! One study loader for every front end: the study text and a [`FileReader`] for the files it
//! names go in; the study, with the files it read (for the `results.json` echo), comes out.
//!
//! The study layer still reads no file itself: a front end says where names are read from
//! ([`Directory`]: relative to the study file, as `pkm` and `pkm.workspace(path)` both do, or
//! [`Echoed`]: the texts a `results.json` echoes) and this module does everything else, so the
//! command and Python read a study the same way, to the error message:
//! - `[mechanism.robot_file] file = "robot.toml"` is read (refused unread above the robot-file
//!   size bound), parsed, and put in place of `file`, the study's `modes` kept beside it;
//! - an error is placed at its line and column ([`Place`]): in the robot file for a key of
//!   the robot file, in the study text otherwise (TOML studies; JSON errors carry their own).
//!
//! The trajectory CSV of a dynamics study is read by the same reader when the study runs
//! ([`crate::dynamics::dynamics_reading`]).

pub use crate::files::{Directory, Echoed, FileReader, NamedFile, Place, locate};
use crate::schema::robot_file::{MODES, RobotFileFailure, read_robot_file};
use crate::{Key, KeyPath, StudyError, from_deserializer, from_json_str, from_toml_str};
use serde::de::DeserializeOwned;
use std::fmt;
use std::path::Path;
use toml::{Table, Value};

/// The text format of a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// TOML (study files).
    Toml,
    /// JSON (a study built by a program, or one echoed in `results.json`).
    Json,
}

impl Format {
    /// JSON for a `.json` file, TOML otherwise.
    pub fn of_path(path: &Path) -> Self {
        match path.extension() {
            Some(e) if e == "json" => Self::Json,
            _ => Self::Toml,
        }
    }
}

/// A study with the robot file it named.
#[derive(Debug, Clone)]
pub struct Loaded<S> {
    /// The study, any named file in place.
    pub study: S,
    /// The robot file named by `[mechanism.robot_file] file`, as read.
    pub robot_file: Option<NamedFile>,
}

/// A study that could not be loaded, or an error of a loaded study placed in its files.
#[derive(Debug)]
pub struct LoadError {
    /// What is wrong, at its key path.
    pub error: StudyError,
    /// Where, when the texts tell.
    pub place: Option<Box<Place>>,
}

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.place {
            Some(p) => write!(
                f,
                "{}:{}:{}: {}\n    | {}",
                p.file, p.line, p.column, self.error, p.source_line
            ),
            None => write!(f, "{}", self.error),
        }
    }
}

impl std::error::Error for LoadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.error)
    }
}

/// The texts a study was read from, to place its errors after it has loaded (a study's run
/// refuses a setting at its key path; this puts the key at its line).
#[derive(Debug, Clone)]
pub struct Sources {
    /// The study file's name for a person.
    pub file: String,
    /// The study text.
    pub text: String,
    /// The study's format.
    pub format: Format,
    /// The robot file it named.
    pub robot_file: Option<NamedFile>,
}

impl Sources {
    /// `error` placed in the file that holds its key: a key of a named robot file (under
    /// `mechanism.robot_file`, not the study's own `modes`) in the robot file, any other in the
    /// study; a TOML syntax error at its span.
    pub fn place(&self, error: StudyError) -> LoadError {
        let inner = error.path().and_then(inside_robot_file);
        let place = match (&self.robot_file, inner) {
            (Some(robot), Some(inner)) => Some(Place::at(
                &robot.file,
                &robot.text,
                locate(&robot.text, &inner).start,
            )),
            _ if self.format == Format::Json => None,
            _ => match &error {
                StudyError::Schema {
                    span: Some(span), ..
                } => Some(Place::at(&self.file, &self.text, span.start)),
                e => e
                    .path()
                    .map(|key| Place::at(&self.file, &self.text, locate(&self.text, key).start)),
            },
        };
        LoadError {
            error,
            place: place.map(Box::new),
        }
    }
}

/// Loads the study `text` (of `file`, its name for messages) in `format`, reading the robot
/// file it names through `reader`.
///
/// # Errors
/// [`LoadError`]: the study's schema error, or a named file that cannot be read, is too large
/// or is not TOML, placed at its line in the study or in the robot file.
pub fn load<S: DeserializeOwned>(
    file: &str,
    text: String,
    format: Format,
    reader: &dyn FileReader,
) -> Result<(Sources, Loaded<S>), LoadError> {
    let mut sources = Sources {
        file: file.to_owned(),
        text,
        format,
        robot_file: None,
    };
    let document = match format {
        Format::Toml => toml::from_str::<Table>(&sources.text).ok(),
        Format::Json => serde_json::from_str::<Table>(&sources.text).ok(),
    };
    let named = document.and_then(|d| named_robot_file(&d).map(|name| (d, name)));
    let Some((document, name)) = named else {
        let study = match format {
            Format::Toml => from_toml_str(&sources.text),
            Format::Json => from_json_str(&sources.text),
        };
        let study = study.map_err(|e| sources.place(e))?;
        return Ok((
            sources,
            Loaded {
                study,
                robot_file: None,
            },
        ));
    };
    let (robot_file, robot) = read_robot_file(&name, reader).map_err(|e| match e {
        RobotFileFailure::Study(e) => sources.place(e),
        RobotFileFailure::InFile(error, place) => LoadError {
            error,
            place: Some(place),
        },
    })?;
    sources.robot_file = Some(robot_file);
    let study = splice(document, robot).map_err(|e| sources.place(e))?;
    let robot_file = sources.robot_file.clone();
    Ok((sources, Loaded { study, robot_file }))
}

/// Loads a study given as a document (a Python dict or any serde source turned into a table),
/// reading the robot file it names through `reader`.
///
/// # Errors
/// As [`load`]: errors in a named robot file are placed in it; others carry their key path.
pub fn load_document<S: DeserializeOwned>(
    document: Table,
    reader: &dyn FileReader,
) -> Result<Loaded<S>, LoadError> {
    let unplaced = |error| LoadError { error, place: None };
    let Some(name) = named_robot_file(&document) else {
        let study = from_deserializer(Value::Table(document)).map_err(unplaced)?;
        return Ok(Loaded {
            study,
            robot_file: None,
        });
    };
    let (robot_file, robot) = read_robot_file(&name, reader).map_err(|e| match e {
        RobotFileFailure::Study(e) => unplaced(e),
        RobotFileFailure::InFile(error, place) => LoadError {
            error,
            place: Some(place),
        },
    })?;
    let sources = Sources {
        file: String::new(),
        text: String::new(),
        format: Format::Json,
        robot_file: Some(robot_file),
    };
    let study = splice(document, robot).map_err(|e| sources.place(e))?;
    Ok(Loaded {
        study,
        robot_file: sources.robot_file,
    })
}

/// The study of `document` with the robot file's table `robot` in place of `file = "..."`,
/// the study's `modes` kept beside its keys.
fn splice<S: DeserializeOwned>(mut document: Table, mut robot: Table) -> Result<S, StudyError> {
    if let Some(mechanism) = document.get_mut("mechanism").and_then(Value::as_table_mut) {
        let modes = mechanism
            .get("robot_file")
            .and_then(|t| t.get(MODES))
            .cloned();
        if let Some(modes) = modes {
            robot.insert(MODES.into(), modes);
        }
        mechanism.insert("robot_file".into(), Value::Table(robot));
    }
    from_deserializer(Value::Table(document))
}

/// The name of the document's `[mechanism.robot_file] file`, when the table holds `file`
/// alone or with the study's `modes` (with other keys the study layer reports the mix).
fn named_robot_file(document: &Table) -> Option<String> {
    let table = document.get("mechanism")?.get("robot_file")?.as_table()?;
    let file = table.get("file")?.as_str()?.to_owned();
    let only_file = table.keys().all(|k| k == "file" || k == MODES);
    only_file.then_some(file)
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
