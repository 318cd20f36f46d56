//! Exhaustive grid search over a box, with optional coarse-to-fine refinement.
//!
//! Every node is evaluated in parallel (rayon) and the values are collected in node order, so the
//! optimum, ties included (the first node in row-major order wins), does not depend on the thread
//! count.

use crate::error::OptimizeError;
use crate::grid_axis::GridAxis;
pub use crate::grid_axis::MAX_GRID_NODES;
use crate::sense::Sense;
use crate::termination::Termination;
use pkm_traits::{Bounds, InvalidInput, Objective, ObjectiveError, Progress};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::ops::Range;

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
        design[k] = axis.node(flat % axis.n());
        flat /= axis.n();
    }
    design
}

/// The grid of a [`grid_search`] (and the coarse grid of [`refined_grid_search`] and
/// [`crate::lattice_refined_search`]): the axes, with at most [`MAX_GRID_NODES`] nodes in all,
/// and whether the result keeps the value of every node. Node `flat` is numbered row-major, the
/// last axis fastest. Serialised as `{ axes, keep_landscape }` (`keep_landscape` optional,
/// default `false`) and checked by [`GridSearch::new`] when read.
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "GridFields", into = "GridFields")]
pub struct GridSearch {
    axes: Vec<GridAxis>,
    nodes: usize,
    keep_landscape: bool,
}

/// The serialised form of a [`GridSearch`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GridFields {
    axes: Vec<GridAxis>,
    #[serde(default)]
    keep_landscape: bool,
}

impl TryFrom<GridFields> for GridSearch {
    type Error = OptimizeError;

    fn try_from(f: GridFields) -> Result<Self, OptimizeError> {
        let grid = Self::new(f.axes)?;
        Ok(if f.keep_landscape {
            grid.keeping_landscape()
        } else {
            grid
        })
    }
}

impl From<GridSearch> for GridFields {
    fn from(grid: GridSearch) -> Self {
        Self {
            axes: grid.axes,
            keep_landscape: grid.keep_landscape,
        }
    }
}

impl GridSearch {
    /// The grid spanned by `axes`, without its landscape.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for no axis or more than [`MAX_GRID_NODES`] nodes in all
    /// (refused before anything is allocated).
    pub fn new(axes: Vec<GridAxis>) -> Result<Self, OptimizeError> {
        if axes.is_empty() {
            return Err(InvalidInput::new("axes", 0.0, "at least one axis").into());
        }
        let nodes = axes
            .iter()
            .try_fold(1usize, |acc, a| acc.checked_mul(a.n()))
            .filter(|&n| n <= MAX_GRID_NODES)
            .ok_or_else(|| {
                let nodes = axes.iter().map(|a| a.n() as f64).product();
                InvalidInput::new("nodes", nodes, "a grid has at most MAX_GRID_NODES nodes")
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

    /// The box spanned, one [`Bounds`] per axis.
    pub fn bounds(&self) -> Vec<Bounds> {
        self.axes.iter().map(GridAxis::bounds).collect()
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// Whether the result keeps the landscape.
    pub fn keeps_landscape(&self) -> bool {
        self.keep_landscape
    }

    /// The node index on each axis of node `flat` (the last axis fastest); `None` past the last
    /// node.
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::{GridAxis, GridSearch};
    /// let axes = vec![GridAxis::new(0.0, 1.0, 3)?, GridAxis::new(0.0, 3.0, 4)?];
    /// let grid = GridSearch::new(axes)?;
    /// assert_eq!(grid.node_index(5), Some(vec![1, 1]));
    /// assert_eq!(grid.flat_index(&[1, 1]), Some(5));
    /// assert_eq!(grid.node_design(5), Some(vec![0.5, 1.0]));
    /// assert_eq!((grid.node_index(12), grid.flat_index(&[3, 0])), (None, None));
    /// # Ok::<(), pkm_optimizers::OptimizeError>(())
    /// ```
    pub fn node_index(&self, flat: usize) -> Option<Vec<usize>> {
        (flat < self.nodes).then(|| {
            let mut rest = flat;
            let mut index = vec![0; self.axes.len()];
            for (k, axis) in self.axes.iter().enumerate().rev() {
                index[k] = rest % axis.n();
                rest /= axis.n();
            }
            index
        })
    }

    /// The flat number of the node with index `index[k]` on axis `k`; `None` for an index
    /// outside its axis or of the wrong length.
    pub fn flat_index(&self, index: &[usize]) -> Option<usize> {
        if index.len() != self.axes.len() {
            return None;
        }
        index
            .iter()
            .zip(&self.axes)
            .try_fold(0, |flat, (&i, axis)| {
                (i < axis.n()).then(|| flat * axis.n() + i)
            })
    }

    /// The design at node `flat`; `None` past the last node.
    pub fn node_design(&self, flat: usize) -> Option<Vec<f64>> {
        (flat < self.nodes).then(|| node_design(&self.axes, flat))
    }

    /// `evaluate` at the nodes `range` (of `0..nodes()`), in parallel, returned in node order
    /// (so the result, and any best chosen from it with [`Sense::best`], does not depend on the
    /// thread count). This is the evaluation of [`grid_search`]; on a range it evaluates one
    /// shard of a grid split over several runs.
    ///
    /// `progress` hears one task (`"grid nodes"`) of one unit per node and is asked for
    /// cancellation before every evaluation.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] (converted into `E`) for a range that does not lie in
    /// `0..nodes()`; [`OptimizeError::Cancelled`] (converted into `E`) once `progress` is
    /// cancelled (the nodes not begun by then are skipped); else the error of the first node, in
    /// node order, whose evaluation failed (every node is evaluated, so the error does not
    /// depend on scheduling).
    ///
    /// # Example
    /// Two shards evaluate what the whole grid does:
    /// ```
    /// use pkm_optimizers::{GridAxis, GridSearch, OptimizeError, Sense};
    /// use pkm_traits::Silent;
    /// let grid = GridSearch::new(vec![GridAxis::new(-1.0, 1.0, 5)?; 2])?;
    /// let f = |p: &[f64]| Ok::<_, OptimizeError>((p[0] - 0.5).powi(2) + p[1] * p[1]);
    /// let whole = grid.evaluate_range(0..25, &Silent, f)?;
    /// let mut shards = grid.evaluate_range(0..12, &Silent, f)?;
    /// shards.extend(grid.evaluate_range(12..25, &Silent, f)?);
    /// assert_eq!(whole, shards);
    /// let (best, _) = Sense::Minimise.best(whole.iter().map(|v| Some(*v))).unwrap();
    /// assert_eq!(grid.node_design(best), Some(vec![0.5, 0.0]));
    /// assert!(grid.evaluate_range(20..26, &Silent, f).is_err());
    /// # Ok::<(), OptimizeError>(())
    /// ```
    pub fn evaluate_range<T, E, F>(
        &self,
        range: Range<usize>,
        progress: &dyn Progress,
        evaluate: F,
    ) -> Result<Vec<T>, E>
    where
        T: Send,
        E: Send + From<OptimizeError>,
        F: Fn(&[f64]) -> Result<T, E> + Sync,
    {
        if range.end > self.nodes {
            let end = range.end as f64;
            return Err(OptimizeError::from(InvalidInput::new(
                "range.end",
                end,
                "the nodes evaluated lie in 0..nodes()",
            ))
            .into());
        }
        progress.start("grid nodes", range.len() as u64);
        let values: Vec<Result<T, E>> = range
            .into_par_iter()
            .map(|flat| {
                progress.check().map_err(OptimizeError::from)?;
                let value = evaluate(&node_design(&self.axes, flat))?;
                progress.advance(1);
                Ok(value)
            })
            .collect();
        progress.finish();
        if progress.is_cancelled() {
            return Err(OptimizeError::Cancelled.into());
        }
        values.into_iter().collect()
    }
}

/// Evaluates `objective` on every node of `grid` and returns the best node in the sense of
/// `sense` (the first in row-major order on a tie).
///
/// `progress` hears one task of one unit per node and is asked for cancellation before every
/// evaluation.
///
/// # Errors
/// [`OptimizeError::Invalid`] when the grid does not match the objective's dimension;
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
        return Err(
            InvalidInput::new("axes", axes.len() as f64, "one axis per design variable").into(),
        );
    }
    let evaluated = grid.evaluate_range(0..n_nodes, progress, |design| {
        Ok::<_, OptimizeError>(objective.value(design))
    })?;
    let mut values = Vec::with_capacity(n_nodes);
    let mut last_reason = String::new();
    for value in evaluated {
        values.push(match value {
            Ok(v) if v.is_finite() => Some(v),
            Ok(v) => return Err(ObjectiveError::NonFinite { value: v }.into()),
            Err(ObjectiveError::Infeasible { reason, .. }) => {
                last_reason = reason;
                None
            }
            Err(e) => return Err(e.into()),
        });
    }
    let infeasible = values.iter().filter(|v| v.is_none()).count();
    let (flat, best_value) =
        sense
            .best(values.iter().copied())
            .ok_or(OptimizeError::NoFeasibleDesign {
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
            values,
        }),
        termination: Termination::Converged {
            criterion: "every node evaluated",
        },
    })
}

/// Settings of [`refined_grid_search`]. In a study file every key is optional, with the
/// defaults below.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, default)]
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
    /// [`OptimizeError::Invalid`] for fewer than 3 nodes per axis or more than
    /// [`MAX_GRID_NODES`] (no level at all is a plain grid search).
    pub fn validate(&self) -> Result<(), OptimizeError> {
        if !(3..=MAX_GRID_NODES).contains(&self.nodes_per_axis) {
            let n = self.nodes_per_axis as f64;
            return Err(InvalidInput::new(
                "nodes_per_axis",
                n,
                "at least 3, at most MAX_GRID_NODES",
            )
            .into());
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
/// coarse one. The result ends [`Termination::Converged`] at the resolution,
/// [`Termination::Stalled`] when a level neither shrinks a spacing nor improves the incumbent
/// (a resolution below the spacing of floats near the optimum), or
/// [`Termination::MaxIterations`].
///
/// # Errors
/// As [`grid_search`], and [`OptimizeError::Invalid`] for a resolution that is not
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
        return Err(
            InvalidInput::new("resolution", f64::NAN, "one positive resolution per axis").into(),
        );
    }
    settings.validate()?;
    let mut result = grid_search(objective, sense, coarse, progress)?;
    let mut axes = coarse.axes.clone();
    let resolved = |axes: &[GridAxis]| axes.iter().zip(resolution).all(|(a, r)| a.step() <= *r);
    let mut stalled = false;
    for _ in 0..settings.max_levels {
        if resolved(&axes) {
            break;
        }
        let finer = refined_axes(
            objective,
            &axes,
            &result.best,
            resolution,
            settings.nodes_per_axis,
        )?;
        let shrunk = finer.iter().zip(&axes).any(|(f, a)| f.step() < a.step());
        axes = finer;
        let level = grid_search(objective, sense, &GridSearch::new(axes.clone())?, progress)?;
        result.evaluations += level.evaluations;
        result.infeasible += level.infeasible;
        let improved = sense.improves(level.best_value, result.best_value);
        if sense.at_least_as_good(level.best_value, result.best_value) {
            result.best = level.best;
            result.best_value = level.best_value;
        }
        // A level whose spacing did not shrink (one float wide: c ± step rounds to the same
        // nodes; or 3 nodes per axis) and that found nothing better repeats itself for ever.
        if !shrunk && !improved {
            stalled = true;
            break;
        }
    }
    result.termination = if resolved(&axes) {
        Termination::Converged {
            criterion: "resolution reached",
        }
    } else if stalled {
        Termination::Stalled
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
