//! `[mechanism.robot_file]`: any parallel robot from a robot file (`docs/robots.md`) as a study
//! mechanism, with no Rust at all.
//!
//! The table holds the robot file's keys inline (so a JSON string or a Python dict is a robot
//! too), or `file = "path"`, read before the study runs by the study loader ([`crate::load`])
//! through the front end's reader (relative to the study file for `pkm` and Python): the study
//! layer opens no file itself and never guesses a working directory.
//! [`RobotFileSpec::resolve_file`] puts the text a library caller read in its place.
//!
//! Its design variables are the names of the robot file's `[parameters]` table (metres, or
//! degrees for a name ending in `_deg`). Workspace membership is the inverse kinematics in one of
//! the study's working modes (`modes`, a key of the study beside the robot file's; by default
//! the reference working mode of the file, the mode of its home configuration), actuator
//! `limits` of the file and the study's `[constraints]` included; the local index is 1/κ of the
//! velocity Jacobian of the platform position `["x", "y", "z"]`. A robot with any other task is
//! measured in its own task coordinates by a workspace study with `[task_space]`
//! ([`crate::task_space`]).

use crate::KeyPath;
use crate::StudyError;
use crate::files::{FileReader, NamedFile, Place, locate};
use nalgebra::Vector3;
use pkm_mechanisms::{Link, LinkKind, PointKind, Skeleton, SkeletonPoint};
use pkm_robot_file::{
    Configuration, LegPointKind, Robot, RobotFile, RobotFileError, RobotModel, WorkingMode,
};
use serde::{Deserialize, Serialize};
use toml::{Table, Value};

/// The size check of a robot file's text, for front ends that read the file themselves.
pub use pkm_robot_file::check_size as check_robot_file_size;

/// The key path of the table in a study.
pub const KEY_PATH: &str = "mechanism.robot_file";

/// The study's own key of the table, beside the robot file's keys: the working modes.
pub const MODES: &str = "modes";

/// `[mechanism.robot_file]`: a robot file's keys (inline), or `file = "path"` before the caller
/// resolves it.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(transparent)]
pub struct RobotFileSpec {
    table: Table,
}

impl RobotFileSpec {
    /// The robot of a robot file's keys (a TOML table read from a robot file, or built by hand).
    pub fn inline(table: Table) -> Self {
        Self { table }
    }

    /// The path of `file = "..."`, when the table names a robot file instead of holding one.
    pub fn file(&self) -> Option<&str> {
        self.table.get("file").and_then(Value::as_str)
    }

    /// Replaces `file = "path"` by the robot file it names, read by `reader` from the name as
    /// written (e.g. [`crate::load::Directory`] of the study file, as `pkm` reads it), as the
    /// study loader does; does nothing for an inline robot. The study layer itself opens no
    /// file.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at `mechanism.robot_file.file` when the file cannot be read, is
    /// too large or is not TOML (with its line and column), or when `file` comes with other
    /// keys.
    pub fn resolve_file(&mut self, reader: &dyn FileReader) -> Result<(), StudyError> {
        let Some(file) = self.file().map(str::to_owned) else {
            return Ok(());
        };
        self.only_file()?;
        let mut table = read_robot_file_table(&file, reader)?;
        if let Some(modes) = self.table.get(MODES) {
            table.insert(MODES.into(), modes.clone());
        }
        self.table = table;
        Ok(())
    }

    /// `file` (and the study's `modes`) alone: the robot is either named or given, never both.
    fn only_file(&self) -> Result<(), StudyError> {
        match self.table.keys().find(|k| *k != "file" && *k != MODES) {
            Some(other) => Err(StudyError::invalid(
                format!("{KEY_PATH}.{other}").as_str(),
                "a robot_file table gives either `file` or the robot file's keys, not both \
                 (`modes` goes with either)",
            )),
            None => Ok(()),
        }
    }

    /// The robot file of the table, its numbers resolved against its `[parameters]`.
    fn robot_file(&self) -> Result<RobotFile, StudyError> {
        if self.file().is_some() {
            self.only_file()?;
            return Err(StudyError::invalid(
                format!("{KEY_PATH}.file").as_str(),
                "a robot file named by `file` is read before the study runs (by the study \
                 loader, pkm_study::load, relative to the study file; library callers with a \
                 table use RobotFileSpec::resolve_file)",
            ));
        }
        let mut keys = self.table.clone();
        keys.remove(MODES);
        RobotFile::from_deserializer(Value::Table(keys)).map_err(located)
    }

    /// The working modes of the study, `modes = [...]` in the table: `"home"` (the default,
    /// alone), `"all"` (every combination of the legs' branches) or one `+` (branch 1) or `-`
    /// (branch 0) per leg ([`RobotModel::working_mode`]), in order, each mode once.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at `mechanism.robot_file.modes[k]` for another label, at
    /// `mechanism.robot_file.modes` for an empty list or another value.
    pub fn working_modes(&self, model: &RobotModel) -> Result<Vec<WorkingMode>, StudyError> {
        let Some(value) = self.table.get(MODES) else {
            return Ok(vec![model.home_mode()]);
        };
        let list = value.as_array().filter(|l| !l.is_empty()).ok_or_else(|| {
            StudyError::invalid(
                format!("{KEY_PATH}.{MODES}").as_str(),
                "a non-empty list of working modes: \"home\", \"all\" or one `+` or `-` per leg",
            )
        })?;
        let mut modes = Vec::new();
        for (k, label) in list.iter().enumerate() {
            let key = format!("{MODES}[{k}]");
            let found = match label.as_str() {
                Some("all") => model.working_modes(),
                Some(label) => vec![model.working_mode(&key, label).map_err(located)?],
                None => {
                    return Err(StudyError::invalid(
                        format!("{KEY_PATH}.{key}").as_str(),
                        "a working mode is a string: \"home\", \"all\" or one `+` or `-` per leg",
                    ));
                }
            };
            for mode in found {
                if !modes.contains(&mode) {
                    modes.push(mode);
                }
            }
        }
        Ok(modes)
    }

    /// The validated robot model.
    ///
    /// # Errors
    /// [`StudyError::Invalid`] at the key path of the offending value
    /// (`mechanism.robot_file.legs[0].joints[1].axis`).
    pub fn model(&self) -> Result<RobotModel, StudyError> {
        RobotModel::from_file(&self.robot_file()?).map_err(located)
    }

    /// The robot as a translational 3-DOF model: the task of a workspace study is the platform
    /// position.
    ///
    /// # Errors
    /// As [`RobotFileSpec::model`]; at `mechanism.robot_file.task` unless the task is
    /// `["x", "y", "z"]`.
    pub fn translational_robot(&self) -> Result<Robot<3>, StudyError> {
        self.translational(self.model()?)
    }

    /// `model` as a translational 3-DOF robot.
    ///
    /// # Errors
    /// At `mechanism.robot_file.task` unless the task is `["x", "y", "z"]`.
    pub(crate) fn translational(&self, model: RobotModel) -> Result<Robot<3>, StudyError> {
        position_task(&model)?;
        Robot::<3>::new(model).map_err(located)
    }

    /// The `[parameters]` table, to change a design variable.
    pub(crate) fn parameters_mut(&mut self) -> Option<&mut Table> {
        self.table.get_mut("parameters")?.as_table_mut()
    }

    /// The `[parameters]` table.
    pub(crate) fn parameters(&self) -> Option<&Table> {
        self.table.get("parameters").and_then(Value::as_table)
    }

    /// The `type` of every actuated joint in the file's legs (the template legs under
    /// `[symmetry]`).
    pub(crate) fn actuated_types(&self) -> Vec<&str> {
        let legs = self.table.get("legs").and_then(Value::as_array);
        let joints = legs
            .into_iter()
            .flatten()
            .filter_map(|leg| leg.get("joints").and_then(Value::as_array))
            .flatten();
        joints
            .filter(|j| j.get("actuated").and_then(Value::as_bool) == Some(true))
            .filter_map(|j| j.get("type").and_then(Value::as_str))
            .collect()
    }
}

/// A robot file error at its key path in the study.
/// Checks that the task of `model` is the platform position.
///
/// # Errors
/// At `mechanism.robot_file.task` unless the task is `["x", "y", "z"]`.
pub(crate) fn position_task(model: &RobotModel) -> Result<(), StudyError> {
    let task = model.task_names();
    if task == ["x", "y", "z"] && model.actuator_count() == 3 {
        return Ok(());
    }
    if task == ["x", "y", "z"] {
        return Err(StudyError::invalid(
            format!("{KEY_PATH}.legs").as_str(),
            format!(
                "without [task_space] a study rates platform positions by 1/κ of a square J: \
                 this robot has {} actuators for its 3 task coordinates (redundant \
                 actuation); give [task_space] to measure it in its own task space (1/κ from the \
                 singular values of its {} × 3 J)",
                model.actuator_count(),
                model.actuator_count()
            ),
        ));
    }
    Err(StudyError::invalid(
        format!("{KEY_PATH}.task").as_str(),
        format!(
            "without [task_space] a study samples platform positions and rates them by 1/κ of \
             J: the task must be [\"x\", \"y\", \"z\"], this robot's is {task:?}; give \
             [task_space] (its kind and box) to measure it in its own task space"
        ),
    ))
}

fn located(e: RobotFileError) -> StudyError {
    located_under(KEY_PATH, e)
}

/// A robot file error at its key path under `prefix` (the robot file's own root for `""`):
/// the key of an invalid value, `name`, `legs` or `task` for the errors about them, the root
/// for a parse error (whose message has its line and column).
pub(crate) fn located_under(prefix: &str, e: RobotFileError) -> StudyError {
    let key = match &e {
        RobotFileError::Schema { key, .. } | RobotFileError::Invalid { key, .. } => key.as_str(),
        RobotFileError::NameMismatch { .. } => "name",
        RobotFileError::Mobility { .. } => "legs",
        RobotFileError::Dimension { .. } | RobotFileError::Redundant { .. } => "task",
        _ => "",
    };
    let path = match (prefix, key.trim_start_matches('.')) {
        (prefix, "") => prefix.to_owned(),
        ("", key) => key.to_owned(),
        (prefix, key) => format!("{prefix}.{key}"),
    };
    let message = match e {
        RobotFileError::Schema { message, .. } => message,
        RobotFileError::Invalid {
            value, requirement, ..
        } => format!("{value}: {requirement}"),
        e => e.to_string(),
    };
    StudyError::invalid(path.as_str(), message)
}

/// The skeleton of `model` at `config`, drawn from its joints: the platform origin `p`, for leg
/// $n$ its stations ([`RobotModel::leg_points`]: the rail origin `On` of leading prismatic
/// joints, then the joint points `An`, `Bn`, ... from the base, the last one the platform
/// anchor) and the segments between them (actuated when the actuator moves them, passive
/// otherwise), and the polygons of the legs' first stations (base) and platform anchors
/// (platform), coincident corners drawn once.
pub fn robot_skeleton(model: &RobotModel, config: &Configuration) -> Skeleton {
    let mut s = Skeleton::default();
    let centre = model.platform_pose_of(config).translation.vector;
    s.points.push(point("p".into(), PointKind::Centre, centre));
    let (mut base, mut plate) = (Vec::new(), Vec::new());
    for leg in 0..model.legs().len() {
        let Some(stations) = model.leg_points(leg, config) else {
            continue;
        };
        let n = leg + 1;
        let first = s.points.len();
        let mut letters = ('A'..='Z').cycle();
        for station in &stations.points {
            let (label, kind) = match station.kind {
                LegPointKind::RailOrigin => (format!("O{n}"), PointKind::Base),
                LegPointKind::BaseJoint => (letter(&mut letters, n), PointKind::BaseJoint),
                LegPointKind::Actuator => (letter(&mut letters, n), PointKind::Actuator),
                LegPointKind::Joint => (letter(&mut letters, n), PointKind::Passive),
                LegPointKind::Platform => (letter(&mut letters, n), PointKind::Platform),
            };
            s.points.push(point(label, kind, station.position));
        }
        s.links.extend(stations.segments.iter().map(|seg| Link {
            from: first + seg.from,
            to: first + seg.to,
            kind: if seg.actuated {
                LinkKind::Actuated
            } else {
                LinkKind::Passive
            },
        }));
        base.push(first);
        plate.push(s.points.len() - 1);
    }
    polygon(&mut s, &base, LinkKind::Base, model);
    polygon(&mut s, &plate, LinkKind::Platform, model);
    s
}

fn point(label: String, kind: PointKind, position: Vector3<f64>) -> SkeletonPoint {
    SkeletonPoint {
        label,
        kind,
        position,
    }
}

fn letter(letters: &mut impl Iterator<Item = char>, leg: usize) -> String {
    format!("{}{leg}", letters.next().unwrap_or('Z'))
}

/// The closed polygon through the points `corners` of `s`, each position once (a point
/// platform, where every leg ends at one point, has no polygon): a link for two corners.
fn polygon(s: &mut Skeleton, corners: &[usize], kind: LinkKind, model: &RobotModel) {
    let tolerance = 1e-9 * model.characteristic_length();
    let mut ring: Vec<usize> = Vec::new();
    for &k in corners {
        let at = s.points[k].position;
        if ring
            .iter()
            .all(|&r| (s.points[r].position - at).norm() > tolerance)
        {
            ring.push(k);
        }
    }
    let links = match ring.len() {
        0 | 1 => 0,
        2 => 1,
        n => n,
    };
    for k in 0..links {
        s.links.push(Link {
            from: ring[k],
            to: ring[(k + 1) % ring.len()],
            kind,
        });
    }
}

/// The table of the robot file `name` read through `reader` ([`RobotFileSpec::resolve_file`]):
/// an error in the file names its line and column in the message.
fn read_robot_file_table(name: &str, reader: &dyn FileReader) -> Result<Table, StudyError> {
    read_robot_file(name, reader)
        .map(|(_, table)| table)
        .map_err(|e| match e {
            RobotFileFailure::Study(e) => e,
            RobotFileFailure::InFile(error, p) => StudyError::invalid(
                format!("{KEY_PATH}.file").as_str(),
                format!("{}:{}:{}: {}", p.file, p.line, p.column, error.message()),
            ),
        })
}

/// Why a named robot file could not be read: an error at the study's `file` key, or one placed
/// in the robot file's text.
pub(crate) enum RobotFileFailure {
    /// At the study's `mechanism.robot_file.file` (unreadable, too large).
    Study(StudyError),
    /// At a place in the robot file (not TOML, a study key in it).
    InFile(StudyError, Box<Place>),
}

/// Reads, bounds and parses the robot file `name` through `reader` (refused unread above
/// [`pkm_robot_file::MAX_FILE_BYTES`]): the file as read and its table.
pub(crate) fn read_robot_file(
    name: &str,
    reader: &dyn FileReader,
) -> Result<(NamedFile, Table), RobotFileFailure> {
    let key = format!("{KEY_PATH}.file");
    let shown = reader.display(name);
    let at = |m: String| RobotFileFailure::Study(StudyError::invalid(key.as_str(), m));
    let unreadable = |e: std::io::Error| at(format!("cannot read {shown}: {e}"));
    let size = usize::try_from(reader.size(name).map_err(unreadable)?).unwrap_or(usize::MAX);
    check_robot_file_size(size).map_err(|e| at(format!("{shown}: {e}")))?;
    let text = reader.read(name).map_err(unreadable)?;
    check_robot_file_size(text.len()).map_err(|e| at(format!("{shown}: {e}")))?;
    let in_file = |offset: usize, message: String| {
        let error = StudyError::invalid(key.as_str(), format!("{shown}: {message}"));
        RobotFileFailure::InFile(error, Box::new(Place::at(&shown, &text, offset)))
    };
    let table = toml::from_str::<Table>(&text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        in_file(offset, e.message().trim_end().to_owned())
    })?;
    if table.contains_key(MODES) {
        let offset = locate(&text, &KeyPath::root().field(MODES)).start;
        return Err(in_file(
            offset,
            format!("`{MODES}` is a key of the study's robot_file table, not of a robot file"),
        ));
    }
    Ok((NamedFile { file: shown, text }, table))
}
