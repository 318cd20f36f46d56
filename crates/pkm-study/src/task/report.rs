//! What a task study reports: the result types of `results.json`, the wrench rows at the
//! optimum, the summary lines, and the starts as a table and a chart.

use super::schema::Goal;
use crate::StudyError;
use crate::outcome::{Artifact, Outcome, short};
use crate::starts::{self, Reached, ranked_chart};
use nalgebra::{DMatrix, Isometry3, Matrix6, Vector3, Vector6};
use pkm_optimizers::{ActiveBound, LocalOptimum, MultistartRun};
use pkm_screw_theory::{ScrewError, Twist, line_set_rank};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The Levenberg–Marquardt report at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Optimality {
    /// Why the iteration stopped.
    pub termination: String,
    /// Iterations spent.
    pub iterations: usize,
    /// Largest |∂f/∂x_j| over the variables off their bounds (0 at a KKT point).
    pub free_gradient_max: f64,
    /// Variables held on a bound.
    pub active_bounds: usize,
    /// Eigenvalues (ascending) of the Hessian on the free variables: ≤ 0 at a maximum, ≥ 0 at
    /// a minimum.
    pub reduced_hessian_eigenvalues: Vec<f64>,
}

impl From<&LocalOptimum> for Optimality {
    fn from(o: &LocalOptimum) -> Self {
        Self {
            termination: o.termination.to_string(),
            iterations: o.iterations,
            free_gradient_max: o.free_gradient_norm(),
            active_bounds: o.active.iter().filter(|a| **a != ActiveBound::Free).count(),
            reduced_hessian_eigenvalues: o.reduced_hessian_eigenvalues.clone(),
        }
    }
}

/// A pose in the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoseReport {
    /// Position (m).
    pub position: [f64; 3],
    /// Rotation vector $\alpha n$ (degrees).
    pub rotation_deg: [f64; 3],
    /// Unit rotation axis $n$ (z when there is no rotation).
    pub axis: [f64; 3],
    /// Rotation angle $\alpha \ge 0$ (degrees).
    pub angle_deg: f64,
}

impl From<&Isometry3<f64>> for PoseReport {
    fn from(pose: &Isometry3<f64>) -> Self {
        let w = pose.rotation.scaled_axis();
        let angle = w.norm();
        let axis = if angle > 0.0 { w / angle } else { Vector3::z() };
        let array = |v: Vector3<f64>| [v.x, v.y, v.z];
        Self {
            position: array(pose.translation.vector),
            rotation_deg: array(w.map(f64::to_degrees)),
            axis: array(axis),
            angle_deg: angle.to_degrees(),
        }
    }
}

/// The matrix of wrench rows at the optimum (6 × 6 for the papers' robots; a robot file has one
/// row per actuation wrench and per constraint wrench of every leg).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WrenchMatrix {
    /// Rank of the rows (relative tolerance 1e-9).
    pub rank: usize,
    /// Smallest singular value.
    pub sigma_min: f64,
    /// Determinant (six rows only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub det: Option<f64>,
    /// The unit twist most nearly reciprocal to every row ($[\omega; v]$, rad/s and m/s):
    /// the swapped right singular vector of $\sigma_{min}$.
    pub most_reciprocal_twist: [f64; 6],
    /// Its $F = \sigma_{min}^2$ by the library's task objective.
    pub most_reciprocal_f: f64,
}

/// One twist's $F$ at the optimum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TwistValue {
    /// $w_k$.
    pub weight: f64,
    /// $F_k = \sum_i (L_i \wedge \chi_k)^2$ (m²/s²).
    pub f: f64,
}

/// The result of a task study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskResult {
    /// The study's title.
    pub title: Option<String>,
    /// `stewart_gough` or `three_upu`.
    pub mechanism: String,
    /// The goal.
    pub goal: Goal,
    /// The optimised objective at the optimum: $F = \sum_k w_k F_k$ (m²/s²), $\sigma_{min}^2$
    /// or $\det^2$.
    pub objective: f64,
    /// The start it came from (from 0).
    pub best_start: usize,
    /// The optimised variables at the optimum (units of their keys; `u_x`, `u_y`, `u_z`: the
    /// cube coordinates of a free Stewart–Gough orientation).
    pub optimum: BTreeMap<String, f64>,
    /// The design at the optimum (units of its keys).
    pub design: BTreeMap<String, f64>,
    /// The platform pose at the optimum.
    pub pose: PoseReport,
    /// Each twist's $F$ there.
    pub twists: Vec<TwistValue>,
    /// Stewart–Gough: leg lengths (m).
    pub leg_lengths: Option<[f64; 6]>,
    /// The wrench rows there.
    pub wrench_matrix: WrenchMatrix,
    /// The first- and second-order report.
    pub optimality: Optimality,
    /// Starts run.
    pub starts: usize,
}

/// The wrench matrix report of `rows` (six or more rows of six), with $F$ of the most
/// reciprocal twist by `objective`.
///
/// # Errors
/// [`StudyError::Screw`] when there are fewer than six rows, the rank cannot be computed or the
/// SVD does not converge; `objective`'s error.
pub(super) fn wrench_matrix(
    rows: &DMatrix<f64>,
    objective: impl Fn(&Twist) -> Result<f64, StudyError>,
) -> Result<WrenchMatrix, StudyError> {
    let not_converged = || StudyError::Screw(ScrewError::SvdNotConverged { rows: rows.nrows() });
    let lines: Vec<Vector6<f64>> = rows
        .row_iter()
        .map(|r| Vector6::from_iterator(r.iter().copied()))
        .collect();
    let rank = line_set_rank(&lines, 1e-9).map_err(StudyError::Screw)?;
    let (sigma_min, twist) =
        pkm_screw_theory::most_reciprocal_twist(rows).ok_or_else(not_converged)?;
    let v = twist.as_vector();
    Ok(WrenchMatrix {
        rank,
        sigma_min,
        det: (rows.nrows() == 6).then(|| rows.determinant()),
        most_reciprocal_twist: [v[0], v[1], v[2], v[3], v[4], v[5]],
        most_reciprocal_f: objective(&twist)?,
    })
}

/// The unit twist most nearly reciprocal to every row of a 6 × 6 wrench matrix
/// ([`pkm_screw_theory::most_reciprocal_twist`]).
pub fn most_reciprocal_twist(rows: &Matrix6<f64>) -> Option<Twist> {
    let rows = DMatrix::from_fn(6, 6, |i, j| rows[(i, j)]);
    pkm_screw_theory::most_reciprocal_twist(&rows).map(|(_, t)| t)
}

/// The four summary lines: the optimum, the variables, the pose with the rows' rank, and the
/// first- and second-order report (numbers in [`short`] form).
pub(super) fn summarise(outcome: &mut Outcome<TaskResult>) {
    let r = &outcome.result;
    let list = |values: &[f64]| {
        values
            .iter()
            .map(|v| short(*v))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let lines = [
        format!(
            "{} {}: objective {} from start {} of {} ({})",
            r.mechanism,
            r.goal.name(),
            short(r.objective),
            r.best_start,
            r.starts,
            r.optimality.termination
        ),
        format!(
            "optimum: {}",
            r.optimum
                .iter()
                .map(|(n, v)| format!("{n} = {}", short(*v)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!(
            "pose: p = [{}] m, rotation {}° about [{}]; wrench rows rank {}, sigma_min {}",
            list(&r.pose.position),
            short(r.pose.angle_deg),
            list(&r.pose.axis),
            r.wrench_matrix.rank,
            short(r.wrench_matrix.sigma_min)
        ),
        format!(
            "free gradient {}, {} active bounds, reduced Hessian eigenvalues [{}]",
            short(r.optimality.free_gradient_max),
            r.optimality.active_bounds,
            list(&r.optimality.reduced_hessian_eigenvalues)
        ),
    ];
    outcome.summary.extend(lines);
}

/// `starts.csv` and `starts.svg` (the objective reached from each start, best first).
pub(super) fn starts_artifacts(
    names: &[String],
    result: &TaskResult,
    run: &MultistartRun<LocalOptimum>,
) -> [Artifact; 2] {
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let rows = starts::start_rows(run, names.len() + 1, |r| Reached {
        design: &r.design,
        numbers: vec![r.value],
        termination: &r.termination,
    });
    let values = run
        .outcomes
        .iter()
        .filter_map(|o| o.as_ref().ok().map(|r| r.value));
    let chart = ranked_chart(
        "objective reached from each start".into(),
        "objective",
        values.collect(),
        result.goal == Goal::Maximise,
        result.best_start,
    );
    starts::starts_artifacts(&names, &["objective"], rows, chart)
}
