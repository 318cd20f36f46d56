//! The assembly-mode study of a robot file (issue 32): every forward-kinematics solution at
//! given actuator coordinates, by [`RobotModel::assembly_search`] (parameter homotopy where the
//! robot has a polynomial form, with the multistart added when the homotopy's report is not
//! complete; the multistart alone otherwise), with the statement of what was searched: the
//! paths tracked and how each ended, so that "40 real of 40" is a statement, not a hope.
//!
//! The queries are actuator coordinates (`actuators`, in the actuators' order, rad or m) or
//! task poses (`poses`, in the robot's task coordinates, turned into actuator coordinates by
//! the inverse kinematics in the home working mode); without either, the home actuators.

use crate::StudyError;
use crate::outcome::{Artifact, Cell, Outcome, Table};
use crate::schema::mechanism::MechanismSpec;
use crate::schema::robot_file::robot_skeleton;
use crate::schema::units::Real;
use pkm_draw::chart::{Chart, Marker, Quantity, Series};
use pkm_robot_file::{
    AssemblyMode, AssemblySearch, EnumerationSettings, HomotopyReport, ModeSearch, RobotModel,
};
use pkm_traits::Progress;
use serde::{Deserialize, Serialize};

/// Most queries of one study.
const MAX_QUERIES: usize = 1000;

/// An assembly-mode study.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyStudy {
    /// Free text.
    pub title: Option<String>,
    /// The robot: a `[mechanism.robot_file]` table.
    pub mechanism: MechanismSpec,
    /// What to solve and how.
    #[serde(default)]
    pub assembly: AssemblySection,
}

/// `[assembly]`.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblySection {
    /// Actuator coordinates, one list per query, in the robot's actuator order (rad or m).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub actuators: Vec<Vec<Real>>,
    /// Task poses, one list per query, in the robot's task coordinates (m, rad): each query's
    /// actuator coordinates are the inverse kinematics there in the home working mode.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub poses: Vec<Vec<Real>>,
    /// `"auto"` (the default: homotopy where the robot has a polynomial form, the multistart
    /// added when its report is not complete) or `"multistart"` alone.
    #[serde(default)]
    pub search: SearchSpec,
    /// Random starts of the multistart (at most 100 000). Default 200.
    #[serde(default = "default_starts")]
    pub starts: usize,
    /// Seed of the multistart's starts. Default 0.
    #[serde(default)]
    pub seed: u64,
    /// Label every mode by continuation back to the home actuators (a second search there).
    /// Default true.
    #[serde(default = "yes")]
    pub label: bool,
}

impl Default for AssemblySection {
    fn default() -> Self {
        Self {
            actuators: Vec::new(),
            poses: Vec::new(),
            search: SearchSpec::default(),
            starts: default_starts(),
            seed: 0,
            label: true,
        }
    }
}

fn default_starts() -> usize {
    EnumerationSettings::default().starts
}

fn yes() -> bool {
    true
}

/// [`ModeSearch`] in a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SearchSpec {
    /// [`ModeSearch::Auto`].
    #[default]
    Auto,
    /// [`ModeSearch::Multistart`].
    Multistart,
}

/// The result of an assembly-mode study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AssemblyResult {
    /// The study's title.
    pub title: Option<String>,
    /// The robot's name.
    pub robot: String,
    /// The task coordinates' names, the order of every mode's `task`.
    pub task: Vec<String>,
    /// The polynomial form the homotopy writes the robot in, or `None` with
    /// `unsupported` saying why there is none.
    pub form: Option<String>,
    /// Why the robot has no polynomial form (the multistart alone runs).
    pub unsupported: Option<String>,
    /// One per query, in order.
    pub queries: Vec<AssemblyQuery>,
}

/// The modes at one set of actuator coordinates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AssemblyQuery {
    /// The actuator coordinates (rad or m).
    pub actuators: Vec<f64>,
    /// The modes, nearest the home pose first.
    pub modes: Vec<ModeRecord>,
    /// How the homotopy's paths ended, when it ran.
    pub homotopy: Option<HomotopyReport>,
    /// Whether the multistart ran.
    pub multistart: bool,
    /// Whether `modes` are every real assembly mode: the homotopy ran and its report is
    /// complete (every path ended at a finite, nonsingular solution).
    pub complete: bool,
}

/// One assembly mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModeRecord {
    /// The task coordinates (m, rad).
    pub task: Vec<f64>,
    /// The six pose coordinates, position then orientation (m, rad).
    pub pose: [f64; 6],
    /// The home assembly mode this one continues to (0: home itself), or `None` when the
    /// continuation meets a singularity or labels were not asked for.
    pub home_label: Option<usize>,
    /// Inverse (type I) singularity margin.
    pub inverse_margin: f64,
    /// Direct (type II) singularity margin.
    pub direct_margin: f64,
    /// Samples and extent (m or rad) of the self-motion this mode is one point of.
    pub self_motion: Option<(usize, f64)>,
}

/// Runs the assembly-mode study.
///
/// # Errors
/// [`StudyError::Invalid`] at `mechanism` for another mechanism than a robot file, at the
/// robot file's offending key, at `assembly.actuators[k]` or `assembly.poses[k]` for a query
/// of the wrong length, out of reach or refused, at `assembly.starts` for too many starts;
/// [`StudyError::Cancelled`] between queries.
pub fn assembly(
    study: &AssemblyStudy,
    progress: &dyn Progress,
) -> Result<Outcome<AssemblyResult>, StudyError> {
    let MechanismSpec::RobotFile(robot) = &study.mechanism else {
        return Err(StudyError::invalid(
            "mechanism",
            "an assembly-mode study needs a [mechanism.robot_file]",
        ));
    };
    let model = robot.model()?;
    let section = &study.assembly;
    let settings = settings_of(section)?;
    let queries = queries_of(section, &model)?;
    progress.start("assembly modes", queries.len() as u64);
    let mut searched = Vec::with_capacity(queries.len());
    for (q, key) in &queries {
        progress.check()?;
        let search = model
            .assembly_search(q, &settings)
            .map_err(|e| StudyError::invalid(key.as_str(), e.to_string()))?;
        searched.push((q.clone(), search));
        progress.advance(1);
    }
    progress.finish();
    let result = AssemblyResult {
        title: study.title.clone(),
        robot: model.name().to_owned(),
        task: model.task_names().iter().map(|s| (*s).to_owned()).collect(),
        form: model.homotopy_form().map(str::to_owned),
        unsupported: model.homotopy_unsupported().map(str::to_owned),
        queries: searched
            .iter()
            .map(|(q, s)| query_record(q, s, section.label))
            .collect(),
    };
    Ok(outcome_of(result, &model, &searched))
}

/// The library's settings of the section.
fn settings_of(section: &AssemblySection) -> Result<EnumerationSettings, StudyError> {
    let most = pkm_robot_file::MAX_STARTS;
    if section.starts > most {
        return Err(StudyError::invalid(
            "assembly.starts",
            format!("at most {most} starts"),
        ));
    }
    Ok(EnumerationSettings {
        method: match section.search {
            SearchSpec::Auto => ModeSearch::Auto,
            SearchSpec::Multistart => ModeSearch::Multistart,
        },
        starts: section.starts,
        seed: section.seed,
        label: section.label,
        ..EnumerationSettings::default()
    })
}

/// The queries' actuator coordinates with the key each came from.
fn queries_of(
    section: &AssemblySection,
    model: &RobotModel,
) -> Result<Vec<(Vec<f64>, String)>, StudyError> {
    let count = section.actuators.len() + section.poses.len();
    if count > MAX_QUERIES {
        return Err(StudyError::invalid(
            "assembly",
            format!("{count} queries: at most {MAX_QUERIES}"),
        ));
    }
    if count == 0 {
        return Ok(vec![(model.home_actuators(), "assembly".to_owned())]);
    }
    let mut queries = Vec::with_capacity(count);
    for (k, q) in section.actuators.iter().enumerate() {
        let key = format!("assembly.actuators[{k}]");
        let q: Vec<f64> = q.iter().map(|v| v.0).collect();
        if q.len() != model.actuator_count() {
            return Err(StudyError::invalid(
                key.as_str(),
                format!(
                    "{} values for {} actuators",
                    q.len(),
                    model.actuator_count()
                ),
            ));
        }
        queries.push((q, key));
    }
    for (k, x) in section.poses.iter().enumerate() {
        let key = format!("assembly.poses[{k}]");
        let x: Vec<f64> = x.iter().map(|v| v.0).collect();
        if x.len() != model.task_names().len() {
            return Err(StudyError::invalid(
                key.as_str(),
                format!(
                    "{} values for {} task coordinates",
                    x.len(),
                    model.task_names().len()
                ),
            ));
        }
        let q = model
            .inverse_kinematics(&x, model.home_mode())
            .map_err(|e| StudyError::invalid(key.as_str(), e.to_string()))?;
        queries.push((q.as_slice().to_vec(), key));
    }
    Ok(queries)
}

fn query_record(q: &[f64], search: &AssemblySearch, label: bool) -> AssemblyQuery {
    AssemblyQuery {
        actuators: q.to_vec(),
        modes: search.modes.iter().map(|m| mode_record(m, label)).collect(),
        homotopy: search.homotopy.clone(),
        multistart: search.multistart,
        complete: search
            .homotopy
            .as_ref()
            .is_some_and(HomotopyReport::complete),
    }
}

fn mode_record(mode: &AssemblyMode, label: bool) -> ModeRecord {
    ModeRecord {
        task: mode.task.clone(),
        pose: mode.configuration.pose(),
        home_label: mode.home_label.filter(|_| label),
        inverse_margin: mode.margins.inverse,
        direct_margin: mode.margins.direct,
        self_motion: mode.self_motion.as_ref().map(|s| (s.samples, s.extent)),
    }
}

/// The result with its table, chart, drawing and summary.
fn outcome_of(
    result: AssemblyResult,
    model: &RobotModel,
    searched: &[(Vec<f64>, AssemblySearch)],
) -> Outcome<AssemblyResult> {
    let mut outcome = Outcome::new(result);
    outcome.artifacts.push(Artifact::Table {
        name: "modes.csv".into(),
        table: modes_table(&outcome.result),
    });
    if let Some(chart) = modes_chart(&outcome.result) {
        outcome.artifacts.push(Artifact::Chart {
            name: "modes.svg".into(),
            chart: Box::new(chart),
        });
    }
    if let Some(first) = searched.first().and_then(|(_, s)| s.modes.first()) {
        outcome.robot(
            "the first query's mode nearest home",
            Ok(pkm_draw::Scene::new(robot_skeleton(
                model,
                &first.configuration,
            ))),
        );
    }
    let lines: Vec<String> = outcome
        .result
        .queries
        .iter()
        .enumerate()
        .map(|(k, q)| summary_line(k, q))
        .collect();
    outcome.summary.extend(lines);
    outcome
}

/// One line per query: the modes, and what the search guarantees.
fn summary_line(k: usize, q: &AssemblyQuery) -> String {
    let statement = match &q.homotopy {
        Some(h) if q.complete => format!(
            "complete: {} paths, {} real, {} complex",
            h.generic_solutions, h.real, h.complex
        ),
        Some(h) => format!(
            "not complete: {} paths, {} real, {} complex, {} singular, {} at infinity, {} \
             exceptional, {} repeated, {} failed{}",
            h.generic_solutions,
            h.real,
            h.complex,
            h.singular,
            h.at_infinity,
            h.exceptional,
            h.repeated,
            h.failed.len(),
            if q.multistart {
                "; multistart added"
            } else {
                ""
            }
        ),
        None => "multistart (no statement of completeness)".to_owned(),
    };
    let singular = q
        .modes
        .iter()
        .filter(|m| !(m.direct_margin >= 1e-9 && m.inverse_margin >= 1e-9))
        .count();
    format!(
        "query {}: {} assembly modes ({} singular); {}",
        k + 1,
        q.modes.len(),
        singular,
        statement
    )
}

/// `modes.csv`: one row per mode of every query.
fn modes_table(result: &AssemblyResult) -> Table {
    let mut header = vec!["query".to_owned(), "mode".to_owned()];
    header.extend(result.task.iter().cloned());
    header.extend(
        ["x", "y", "z", "o1", "o2", "o3"]
            .iter()
            .map(|c| format!("pose_{c}")),
    );
    header.extend(
        [
            "home_label",
            "inverse_margin",
            "direct_margin",
            "self_motion",
        ]
        .iter()
        .map(|s| (*s).to_owned()),
    );
    let mut table = Table::new(header);
    for (k, q) in result.queries.iter().enumerate() {
        for (j, m) in q.modes.iter().enumerate() {
            let mut row: Vec<Cell> = vec![(k + 1).into(), (j + 1).into()];
            row.extend(m.task.iter().map(|&v| Cell::from(v)));
            row.extend(m.pose.iter().map(|&v| Cell::from(v)));
            row.push(m.home_label.map_or(Cell::Missing, Cell::from));
            row.push(m.inverse_margin.into());
            row.push(m.direct_margin.into());
            row.push(m.self_motion.is_some().into());
            table.rows.push(row);
        }
    }
    table
}

/// `modes.svg`: the first query's modes over the two pose coordinates that differ most among
/// them, regular and singular apart, each marked with its number; `None` with fewer than two
/// modes.
fn modes_chart(result: &AssemblyResult) -> Option<Chart> {
    let q = result.queries.first()?;
    if q.modes.len() < 2 {
        return None;
    }
    let spread = |c: usize| {
        let values = q.modes.iter().map(|m| m.pose[c]);
        values.clone().fold(f64::NEG_INFINITY, f64::max) - values.fold(f64::INFINITY, f64::min)
    };
    let mut axes: Vec<usize> = (0..6).collect();
    axes.sort_by(|&a, &b| spread(b).total_cmp(&spread(a)).then(a.cmp(&b)));
    let (a, b) = (axes[0].min(axes[1]), axes[0].max(axes[1]));
    let names = ["x", "y", "z", "o1", "o2", "o3"];
    let unit = |c: usize| if c < 3 { "m" } else { "rad" };
    let singular = |m: &ModeRecord| !(m.direct_margin >= 1e-9 && m.inverse_margin >= 1e-9);
    let points = |want: bool| -> Vec<(f64, f64)> {
        q.modes
            .iter()
            .filter(|m| singular(m) == want)
            .map(|m| (m.pose[a], m.pose[b]))
            .collect()
    };
    let series: Vec<Series> = [("regular", false), ("singular", true)]
        .into_iter()
        .map(|(label, want)| Series::points(label, points(want)))
        .filter(|s| !s.points.is_empty())
        .collect();
    let markers = q
        .modes
        .iter()
        .enumerate()
        .map(|(j, m)| Marker::new(format!("{}", j + 1), m.pose[a], m.pose[b]));
    Some(
        Chart::series(
            format!(
                "{}: {} assembly modes at the first query{}",
                result.robot,
                q.modes.len(),
                if q.complete { " (complete)" } else { "" }
            ),
            Quantity::new(names[a], unit(a)),
            Quantity::new(names[b], unit(b)),
            series,
        )
        .with_markers(markers),
    )
}
