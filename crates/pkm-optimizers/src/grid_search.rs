//! Exhaustive grid search over a box, with optional coarse-to-fine refinement.
//!
//! Every node is evaluated in parallel (rayon) and the values are collected in node order, so the
//! optimum, ties included (the first node in row-major order wins), does not depend on the thread
//! count.

use crate::error::OptimizeError;
use crate::sense::Sense;
use crate::termination::Termination;
use pkm_traits::{Objective, ObjectiveError, Progress};
use rayon::prelude::*;
use serde::Serialize;

/// Most nodes of one grid search: the values of every node are collected (in order, for
/// determinism) before the minimum is taken, so larger grids are refused before allocating.
pub const MAX_GRID_NODES: usize = 1 << 24;

/// Evenly spaced nodes `lower, lower + step, …, upper` of one design variable: finite bounds,
/// `lower <= upper`, a finite spacing and at least one node (private fields, so every axis went
/// through [`GridAxis::new`] or [`GridAxis::with_step`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GridAxis {
    lower: f64,
    upper: f64,
    n: usize,
}

impl GridAxis {
    /// `n` nodes from `lower` to `upper`.
    ///
    /// # Errors
    /// [`OptimizeError::InvalidSetting`] when `n = 0` or `n >` [`MAX_GRID_NODES`], a bound is not
    /// finite, `lower > upper` or the width `upper − lower` overflows.
    pub fn new(lower: f64, upper: f64, n: usize) -> Result<Self, OptimizeError> {
        if n == 0 {
            return Err(invalid("n", 0.0, "a grid axis needs at least one node"));
        }
        if !(lower.is_finite() && upper.is_finite() && lower <= upper) {
            return Err(invalid(
                "lower",
                lower,
                "bounds must be finite with lower <= upper",
            ));
        }
        if !(upper - lower).is_finite() {
            return Err(invalid(
                "upper",
                upper,
                "the width upper - lower must be finite",
            ));
        }
        if n > MAX_GRID_NODES {
            return Err(invalid("n", n as f64, "at most MAX_GRID_NODES nodes"));
        }
        Ok(Self { lower, upper, n })
    }

    /// First node.
    pub fn lower(&self) -> f64 {
        self.lower
    }

    /// Last node.
    pub fn upper(&self) -> f64 {
        self.upper
    }

    /// Number of nodes (1 gives the single node `lower`).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Nodes from `lower` to `upper` spaced by `step` (the count is rounded to the nearest whole
    /// number of steps, so `upper` is a node up to round-off).
    ///
    /// # Errors
    /// As [`GridAxis::new`], and when `step` is not finite and positive.
    pub fn with_step(lower: f64, upper: f64, step: f64) -> Result<Self, OptimizeError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(invalid("step", step, "must be finite and > 0"));
        }
        let intervals = ((upper - lower) / step).round();
        if !(intervals >= 0.0) {
            return Err(invalid(
                "lower",
                lower,
                "bounds must be finite with lower <= upper",
            ));
        }
        if !(intervals < MAX_GRID_NODES as f64) {
            return Err(invalid(
                "step",
                step,
                "must give at most MAX_GRID_NODES nodes over [lower, upper]",
            ));
        }
        // `intervals` is a whole number in [0, MAX_GRID_NODES): the cast is exact.
        Self::new(lower, upper, intervals as usize + 1)
    }

    /// Spacing of the nodes (0 for a single node).
    pub fn step(&self) -> f64 {
        if self.n > 1 {
            (self.upper - self.lower) / (self.n - 1) as f64
        } else {
            0.0
        }
    }

    /// Node `i`.
    pub fn node(&self, i: usize) -> f64 {
        if i + 1 == self.n {
            self.upper
        } else {
            self.lower + i as f64 * self.step()
        }
    }

    /// All nodes.
    pub fn nodes(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.node(i)).collect()
    }
}

fn invalid(setting: &'static str, value: f64, requirement: &'static str) -> OptimizeError {
    OptimizeError::InvalidSetting {
        setting,
        value,
        requirement,
    }
}

/// Objective values on every node of a grid (`None` where the design is infeasible), row-major:
/// the last axis varies fastest.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Landscape {
    /// The axes of the grid.
    pub axes: Vec<GridAxis>,
    /// One value per node, row-major.
    pub values: Vec<Option<f64>>,
}

impl Landscape {
    /// The design at flat node index `flat`.
    pub fn design(&self, flat: usize) -> Vec<f64> {
        node_design(&self.axes, flat)
    }
}

/// Outcome of a grid search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridResult {
    /// The best design found.
    pub best: Vec<f64>,
    /// Its objective value (the smallest or largest, in the sense of the search).
    pub best_value: f64,
    /// Designs evaluated, over all refinement levels.
    pub evaluations: usize,
    /// Designs found infeasible, over all refinement levels.
    pub infeasible: usize,
    /// The landscape of the first (coarse) grid, when it was asked for.
    pub landscape: Option<Landscape>,
    /// Why the search stopped: [`grid_search`] always after every node
    /// ([`Termination::Converged`], criterion `"every node evaluated"`); [`refined_grid_search`]
    /// with criterion `"resolution reached"`, or [`Termination::MaxIterations`] after
    /// [`RefinementSettings::max_levels`] levels with a spacing still above the resolution;
    /// [`crate::lattice_refined_search`] with criterion `"optimum inside every window"`, or
    /// [`Termination::MaxIterations`] when a level's window still moved after its last repeat.
    pub termination: Termination,
}

fn node_design(axes: &[GridAxis], mut flat: usize) -> Vec<f64> {
    let mut design = vec![0.0; axes.len()];
    for (k, axis) in axes.iter().enumerate().rev() {
        design[k] = axis.node(flat % axis.n);
        flat /= axis.n;
    }
    design
}

/// The grid of a [`grid_search`] (and the coarse grid of [`refined_grid_search`] and
/// [`crate::lattice_refined_search`]): the axes, with at most [`MAX_GRID_NODES`] nodes in all,
/// and whether the result keeps the value of every node.
///
/// # Example
/// ```
/// use pkm_optimizers::{GridAxis, GridSearch};
/// let axis = GridAxis::new(0.0, 1.0, 1 << 12).unwrap();
/// let grid = GridSearch::new(vec![axis; 2]).unwrap().keeping_landscape();
/// assert!(grid.keeps_landscape() && grid.nodes() == 1 << 24);
/// // Each axis is admissible, their product is not.
/// let wide = GridAxis::new(0.0, 1.0, 1 << 13).unwrap();
/// assert!(GridSearch::new(vec![wide; 2]).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridSearch {
    axes: Vec<GridAxis>,
    nodes: usize,
    keep_landscape: bool,
}

impl GridSearch {
    /// The grid spanned by `axes`, without its landscape.
    ///
    /// # Errors
    /// [`OptimizeError::InvalidSetting`] for no axis or more than [`MAX_GRID_NODES`] nodes in all
    /// (refused before anything is allocated).
    pub fn new(axes: Vec<GridAxis>) -> Result<Self, OptimizeError> {
        if axes.is_empty() {
            return Err(invalid("axes", 0.0, "at least one axis"));
        }
        let nodes = axes
            .iter()
            .try_fold(1usize, |acc, a| acc.checked_mul(a.n))
            .filter(|&n| n <= MAX_GRID_NODES)
            .ok_or_else(|| {
                let nodes = axes.iter().map(|a| a.n as f64).product();
                invalid("nodes", nodes, "a grid has at most MAX_GRID_NODES nodes")
            })?;
        Ok(Self {
            axes,
            nodes,
            keep_landscape: false,
        })
    }

    /// The same grid, whose result keeps every node's value ([`GridResult::landscape`], for
    /// plots).
    #[must_use]
    pub fn keeping_landscape(mut self) -> Self {
        self.keep_landscape = true;
        self
    }

    /// The axes.
    pub fn axes(&self) -> &[GridAxis] {
        &self.axes
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// Whether the result keeps the landscape.
    pub fn keeps_landscape(&self) -> bool {
        self.keep_landscape
    }
}

/// Evaluates `objective` on every node of `grid` and returns the best node in the sense of
/// `sense` (the first in row-major order on a tie).
///
/// `progress` hears one task of one unit per node and is asked for cancellation before every
/// evaluation.
///
/// # Errors
/// [`OptimizeError::InvalidSetting`] when the grid does not match the objective's dimension;
/// [`OptimizeError::NoFeasibleDesign`] when every node is infeasible;
/// [`OptimizeError::Objective`] for an objective failure other than infeasibility;
/// [`OptimizeError::Cancelled`] once `progress` is cancelled (a cancelled search returns no
/// design, as every solver of this crate).
///
/// # Example
/// ```
/// use pkm_optimizers::{GridAxis, GridSearch, Sense, grid_search};
/// use pkm_traits::{Bounds, Objective, ObjectiveError, Silent};
/// struct Bowl([Bounds; 2]);
/// impl Objective for Bowl {
///     fn dimension(&self) -> usize { 2 }
///     fn bounds(&self) -> &[Bounds] { &self.0 }
///     fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
///         Ok((p[0] - 0.3).powi(2) + (p[1] + 0.2).powi(2))
///     }
/// }
/// let b = Bounds::new(-1.0, 1.0).unwrap();
/// let grid = GridSearch::new(vec![GridAxis::new(-1.0, 1.0, 21).unwrap(); 2]).unwrap();
/// let result = grid_search(&Bowl([b, b]), Sense::Minimise, &grid, &Silent).unwrap();
/// assert!((result.best[0] - 0.3).abs() < 1e-12 && (result.best[1] + 0.2).abs() < 1e-12);
/// let worst = grid_search(&Bowl([b, b]), Sense::Maximise, &grid, &Silent).unwrap();
/// assert_eq!(worst.best, vec![-1.0, 1.0]);
/// ```
pub fn grid_search<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    grid: &GridSearch,
    progress: &dyn Progress,
) -> Result<GridResult, OptimizeError> {
    let (axes, keep_landscape, n_nodes) = (&grid.axes[..], grid.keep_landscape, grid.nodes);
    if axes.len() != objective.dimension() {
        return Err(invalid(
            "axes",
            axes.len() as f64,
            "one axis per design variable",
        ));
    }
    progress.start("grid search", n_nodes as u64);
    let values = (0..n_nodes)
        .into_par_iter()
        .with_min_len(64)
        .map(|flat| {
            progress.check()?;
            let value = objective.value(&node_design(axes, flat));
            progress.advance(1);
            Ok(value)
        })
        .collect::<Result<Vec<_>, OptimizeError>>();
    progress.finish();
    let values = values?;
    let mut best: Option<(usize, f64)> = None;
    let mut infeasible = 0;
    let mut last_reason = String::new();
    let mut landscape_values = Vec::with_capacity(if keep_landscape { n_nodes } else { 0 });
    for (flat, value) in values.into_iter().enumerate() {
        let value = match value {
            Ok(v) if v.is_finite() => Some(v),
            Ok(v) => return Err(ObjectiveError::NonFinite { value: v }.into()),
            Err(ObjectiveError::Infeasible { reason, .. }) => {
                infeasible += 1;
                last_reason = reason;
                None
            }
            Err(e) => return Err(e.into()),
        };
        if let Some(v) = value
            && best.is_none_or(|(_, b)| sense.improves(v, b))
        {
            best = Some((flat, v));
        }
        if keep_landscape {
            landscape_values.push(value);
        }
    }
    let (flat, best_value) = best.ok_or(OptimizeError::NoFeasibleDesign {
        evaluations: n_nodes,
        last_reason,
    })?;
    Ok(GridResult {
        best: node_design(axes, flat),
        best_value,
        evaluations: n_nodes,
        infeasible,
        landscape: keep_landscape.then(|| Landscape {
            axes: axes.to_vec(),
            values: landscape_values,
        }),
        termination: Termination::Converged {
            criterion: "every node evaluated",
        },
    })
}

/// Settings of [`refined_grid_search`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefinementSettings {
    /// Nodes per axis of every refined grid. Default 5: a ±2-step window around the incumbent.
    pub nodes_per_axis: usize,
    /// At most this many refinement levels. Default 20: with the default 5 nodes the spacing
    /// halves per level, so 20 levels refine any coarse grid by a factor of about 10⁶.
    pub max_levels: usize,
}

impl RefinementSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`OptimizeError::InvalidSetting`] for fewer than 3 nodes per axis or more than
    /// [`MAX_GRID_NODES`] (no level at all is a plain grid search).
    pub fn validate(&self) -> Result<(), OptimizeError> {
        if !(3..=MAX_GRID_NODES).contains(&self.nodes_per_axis) {
            let n = self.nodes_per_axis as f64;
            return Err(invalid(
                "nodes_per_axis",
                n,
                "at least 3, at most MAX_GRID_NODES",
            ));
        }
        Ok(())
    }
}

impl Default for RefinementSettings {
    fn default() -> Self {
        Self {
            nodes_per_axis: 5,
            max_levels: 20,
        }
    }
}

/// Grid search on `coarse`, then repeated searches on finer grids centred on the incumbent until
/// every axis's spacing is at most `resolution[k]`.
///
/// Each refined grid spans one coarse spacing either side of the incumbent (clipped to the
/// objective's bounds) with [`RefinementSettings::nodes_per_axis`] nodes, so the spacing halves
/// at each level with the default of 5 nodes. The landscape, if `coarse` keeps it, is the
/// coarse one.
///
/// # Errors
/// As [`grid_search`], and [`OptimizeError::InvalidSetting`] for a resolution that is not
/// positive or settings that fail [`RefinementSettings::validate`].
pub fn refined_grid_search<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    coarse: &GridSearch,
    resolution: &[f64],
    settings: &RefinementSettings,
    progress: &dyn Progress,
) -> Result<GridResult, OptimizeError> {
    if resolution.len() != coarse.axes.len() || resolution.iter().any(|r| !(*r > 0.0)) {
        return Err(invalid(
            "resolution",
            f64::NAN,
            "one positive resolution per axis",
        ));
    }
    settings.validate()?;
    let mut result = grid_search(objective, sense, coarse, progress)?;
    let mut axes = coarse.axes.clone();
    let resolved = |axes: &[GridAxis]| axes.iter().zip(resolution).all(|(a, r)| a.step() <= *r);
    for _ in 0..settings.max_levels {
        if resolved(&axes) {
            break;
        }
        axes = refined_axes(
            objective,
            &axes,
            &result.best,
            resolution,
            settings.nodes_per_axis,
        )?;
        let level = grid_search(objective, sense, &GridSearch::new(axes.clone())?, progress)?;
        result.evaluations += level.evaluations;
        result.infeasible += level.infeasible;
        if sense.at_least_as_good(level.best_value, result.best_value) {
            result.best = level.best;
            result.best_value = level.best_value;
        }
    }
    result.termination = if resolved(&axes) {
        Termination::Converged {
            criterion: "resolution reached",
        }
    } else {
        Termination::MaxIterations
    };
    Ok(result)
}

fn refined_axes<O: Objective + ?Sized>(
    objective: &O,
    axes: &[GridAxis],
    centre: &[f64],
    resolution: &[f64],
    nodes: usize,
) -> Result<Vec<GridAxis>, OptimizeError> {
    axes.iter()
        .zip(centre)
        .zip(resolution)
        .zip(objective.bounds())
        .map(|(((axis, &c), &r), bounds)| {
            let step = axis.step();
            if step <= r {
                return GridAxis::new(c, c, 1);
            }
            GridAxis::new(bounds.clamp(c - step), bounds.clamp(c + step), nodes)
        })
        .collect()
}
