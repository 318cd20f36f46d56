//! Maps of a task-space workspace (`[[task_space.maps]]`): a local index on the plane of two
//! sampled coordinates through given values of the others, as a table and a heat map. The
//! index is 1/κ of the homogenised Jacobian (the one the study integrates; for a dexterous
//! workspace its least value over the first orientation grid) or one of the three singularity
//! margins (`RobotModel::singularity_margins`; for a dexterous workspace at the held
//! orientation); cells outside the workspace are blank.

use super::{Setup, coordinate, invalid};
use crate::outcome::{Artifact, Table};
use pkm_draw::chart::{self, Chart};
use pkm_robot_file::{RobotModel, TaskWorkspace};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Largest number of cells per side of a map.
pub const MAX_MAP_CELLS: usize = 512;

/// `[[task_space.maps]]`: one map.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TaskMapSpec {
    /// The two sampled coordinates of the plane, by key (`z`, `tilt_x_deg`).
    pub axes: [String; 2],
    /// Values of the other sampled coordinates, by key (default: the middle of their side).
    #[serde(default)]
    pub at: BTreeMap<String, f64>,
    /// Cells per side (default 60, 2 to [`MAX_MAP_CELLS`]).
    #[serde(default = "default_cells")]
    pub cells: usize,
    /// The index mapped (default `inverse_condition`).
    #[serde(default)]
    pub index: MapIndex,
}

fn default_cells() -> usize {
    60
}

/// What a map shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MapIndex {
    /// 1/κ of the homogenised Jacobian.
    #[default]
    InverseCondition,
    /// The inverse-kinematic (type I) margin.
    InverseMargin,
    /// The direct (type II) margin.
    DirectMargin,
    /// The constraint margin (blank for a robot without constraint wrenches).
    ConstraintMargin,
}

impl MapIndex {
    /// The name in study files and CSV headers.
    pub fn key(self) -> &'static str {
        match self {
            Self::InverseCondition => "inverse_condition",
            Self::InverseMargin => "inverse_margin",
            Self::DirectMargin => "direct_margin",
            Self::ConstraintMargin => "constraint_margin",
        }
    }
}

/// A map in the result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskMapResult {
    /// The plane's coordinates with their units (`"z (m)"`).
    pub axes: [String; 2],
    /// The index.
    pub index: MapIndex,
    /// The other sampled coordinates' values (m, rad).
    pub at: BTreeMap<String, f64>,
    /// Cells per side.
    pub cells: usize,
    /// Fraction of the cells inside the workspace.
    pub inside_fraction: f64,
    /// Largest value on the map.
    pub max_value: Option<f64>,
    /// The table's artifact name.
    pub csv: String,
    /// The heat map's artifact name.
    pub svg: String,
}

impl TaskMapResult {
    /// The index's name.
    pub fn index_key(&self) -> &'static str {
        self.index.key()
    }
}

/// A checked map: the positions (in the sampled coordinates) of its axes and the point the
/// plane passes through.
pub(super) struct MapPlan {
    axes: [usize; 2],
    through: Vec<f64>,
    cells: usize,
    index: MapIndex,
}

/// Checks every map of the section against `setup`, each at `task_space.maps[k]`.
///
/// # Errors
/// [`crate::StudyError::Invalid`] for an axis or a value that is not a sampled coordinate,
/// the same axis twice, a value outside its side, or a cell count out of range.
pub(super) fn plans(
    model: &RobotModel,
    setup: &Setup,
    maps: &[TaskMapSpec],
) -> Result<Vec<MapPlan>, crate::StudyError> {
    maps.iter()
        .enumerate()
        .map(|(k, map)| plan(model, setup, map, &format!("maps[{k}]")))
        .collect()
}

fn plan(
    model: &RobotModel,
    setup: &Setup,
    map: &TaskMapSpec,
    at: &str,
) -> Result<MapPlan, crate::StudyError> {
    let sampled = |key: &str, path: &str| -> Result<(usize, f64), crate::StudyError> {
        let (k, scale) = coordinate(model, path, key)?;
        let i = setup.sampled.iter().position(|&s| s == k).ok_or_else(|| {
            invalid(
                format!("{path}.{key}"),
                "not a sampled coordinate of the box",
            )
        })?;
        Ok((i, scale))
    };
    let (a, _) = sampled(&map.axes[0], &format!("{at}.axes"))?;
    let (b, _) = sampled(&map.axes[1], &format!("{at}.axes"))?;
    if a == b {
        return Err(invalid(format!("{at}.axes"), "two different coordinates"));
    }
    if !(2..=MAX_MAP_CELLS).contains(&map.cells) {
        let m = format!("{}: 2 to {MAX_MAP_CELLS} cells per side", map.cells);
        return Err(invalid(format!("{at}.cells"), m));
    }
    let (lower, upper) = (setup.region.lower(), setup.region.upper());
    let mut through: Vec<f64> = (0..lower.len())
        .map(|i| 0.5 * (lower[i] + upper[i]))
        .collect();
    for (key, &value) in &map.at {
        let (i, scale) = sampled(key, &format!("{at}.at"))?;
        let v = value * scale;
        if i == a || i == b || !(lower[i] <= v && v <= upper[i]) {
            let m = format!("{value}: a coordinate off the plane, within its side of the box");
            return Err(invalid(format!("{at}.at.{key}"), m));
        }
        through[i] = v;
    }
    Ok(MapPlan {
        axes: [a, b],
        through,
        cells: map.cells,
        index: map.index,
    })
}

/// The index of `plan` at the sampled values `u`, `None` outside the workspace.
fn value(ws: &TaskWorkspace<'_>, setup: &Setup, index: MapIndex, u: &[f64]) -> Option<f64> {
    let x = setup.pose(u);
    if let Some(levels) = &setup.levels {
        if ws.dexterous_levels(&x, levels) != levels.grid_levels.len() {
            return None;
        }
        if index == MapIndex::InverseCondition {
            return ws.dexterous_inverse_condition(&x, levels);
        }
    }
    match index {
        MapIndex::InverseCondition => ws.inverse_condition(&x),
        MapIndex::InverseMargin => ws.margins(&x).map(|m| m.inverse),
        MapIndex::DirectMargin => ws.margins(&x).map(|m| m.direct),
        MapIndex::ConstraintMargin => ws.margins(&x).and_then(|m| m.constraint),
    }
}

/// Computes map `number` (from 1) of `plan`: its table and heat map into `artifacts`, and its
/// summary. The rows of cells are computed in parallel and kept in order (the same bits for
/// any thread count).
pub(super) fn map(
    model: &RobotModel,
    ws: &TaskWorkspace<'_>,
    setup: &Setup,
    plan: &MapPlan,
    number: usize,
    artifacts: &mut Vec<Artifact>,
) -> TaskMapResult {
    let n = plan.cells;
    let [a, b] = plan.axes;
    let axis = |i: usize| -> Vec<f64> {
        let (lo, hi) = (setup.region.lower()[i], setup.region.upper()[i]);
        (0..n)
            .map(|c| lo + (hi - lo) * (c as f64 + 0.5) / n as f64)
            .collect()
    };
    let (u, v) = (axis(a), axis(b));
    let values: Vec<Option<f64>> = v
        .par_iter()
        .flat_map_iter(|&y| {
            let mut point = plan.through.clone();
            point[b] = y;
            u.iter()
                .map(|&x| {
                    point[a] = x;
                    value(ws, setup, plan.index, &point)
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let names = model.task_names();
    let label = |i: usize| {
        let k = setup.sampled[i];
        let unit = if model.task_is_angle(k) { "rad" } else { "m" };
        format!("{} ({unit})", names[k])
    };
    let stem = format!("task-map-{number}-{}", plan.index.key());
    let (csv, svg) = (format!("{stem}.csv"), format!("{stem}.svg"));
    let table = grid_table(
        [
            names[setup.sampled[a]],
            names[setup.sampled[b]],
            "inside",
            plan.index.key(),
        ],
        &u,
        &v,
        &values,
    );
    let others: BTreeMap<String, f64> = (0..setup.sampled.len())
        .filter(|&i| i != a && i != b)
        .map(|i| (names[setup.sampled[i]].to_owned(), plan.through[i]))
        .collect();
    let field = chart::Heatmap {
        colour_axis: plan.index.key().into(),
        x: u,
        y: v,
        values: values.clone(),
    };
    let title = if others.is_empty() {
        format!("{} on the box", plan.index.key())
    } else {
        let at: Vec<String> = others
            .iter()
            .map(|(k, v)| format!("{k} = {v:.4}"))
            .collect();
        format!("{} at {}", plan.index.key(), at.join(", "))
    };
    artifacts.push(Artifact::Table {
        name: csv.clone(),
        table,
    });
    artifacts.push(Artifact::Chart {
        name: svg.clone(),
        chart: Box::new(Chart::heatmap(title, label(a), label(b), field)),
    });
    TaskMapResult {
        axes: [label(a), label(b)],
        index: plan.index,
        at: others,
        cells: n,
        inside_fraction: values.iter().flatten().count() as f64 / values.len() as f64,
        max_value: values.iter().flatten().copied().reduce(f64::max),
        csv,
        svg,
    }
}

/// The table of a map on the grid `u` × `v` (`values[iy * u.len() + ix]`): the two
/// coordinates, whether the cell has a value, and the value (blank where none).
pub(crate) fn grid_table(header: [&str; 4], u: &[f64], v: &[f64], values: &[Option<f64>]) -> Table {
    let n = u.len();
    let mut table = Table::new(header);
    table.rows = values
        .iter()
        .enumerate()
        .map(|(k, value)| {
            vec![
                u[k % n].into(),
                v[k / n].into(),
                value.is_some().into(),
                (*value).into(),
            ]
        })
        .collect();
    table
}
