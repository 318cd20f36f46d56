//! The nodes of one design variable in a grid search: an interval ([`Bounds`]) and a count.

use crate::error::OptimizeError;
use pkm_traits::{Bounds, InvalidInput};
use serde::{Deserialize, Serialize};

/// Most nodes of one grid search: the values of every node are collected (in order, for
/// determinism) before the minimum is taken, so larger grids are refused before allocating.
pub const MAX_GRID_NODES: usize = 1 << 24;

/// Evenly spaced nodes `lower, lower + step, …, upper` of one design variable: an interval
/// ([`Bounds`]: finite ends, `lower <= upper`, a finite width) and at least one node (private
/// fields, so every axis went through [`GridAxis::new`] or [`GridAxis::with_step`]). Serialised
/// as `{ lower, upper, n }`, and checked by [`GridAxis::new`] when read.
///
/// # Example
/// ```
/// use pkm_optimizers::GridAxis;
/// let axis = GridAxis::new(0.0, 1.0, 5).unwrap();
/// assert_eq!(axis.nodes(), [0.0, 0.25, 0.5, 0.75, 1.0]);
/// assert_eq!(axis.bounds().width(), 1.0);
/// assert!(GridAxis::new(1.0, 0.0, 5).is_err() && GridAxis::new(0.0, 1.0, 0).is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "AxisFields", into = "AxisFields")]
pub struct GridAxis {
    bounds: Bounds,
    n: usize,
}

/// The serialised form of a [`GridAxis`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisFields {
    lower: f64,
    upper: f64,
    n: usize,
}

impl TryFrom<AxisFields> for GridAxis {
    type Error = OptimizeError;

    fn try_from(f: AxisFields) -> Result<Self, OptimizeError> {
        Self::new(f.lower, f.upper, f.n)
    }
}

impl From<GridAxis> for AxisFields {
    fn from(axis: GridAxis) -> Self {
        Self {
            lower: axis.lower(),
            upper: axis.upper(),
            n: axis.n,
        }
    }
}

impl GridAxis {
    /// `n` nodes from `lower` to `upper`.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] when `n = 0` or `n >` [`MAX_GRID_NODES`], or the interval
    /// fails [`Bounds::new`] (a bound is not finite, `lower > upper`, or the width overflows).
    pub fn new(lower: f64, upper: f64, n: usize) -> Result<Self, OptimizeError> {
        if n == 0 {
            return Err(InvalidInput::new("n", 0.0, "a grid axis needs at least one node").into());
        }
        let bounds = Bounds::new(lower, upper)?;
        InvalidInput::require_count_at_most(
            "n",
            n,
            MAX_GRID_NODES,
            "at most MAX_GRID_NODES nodes",
        )?;
        Ok(Self { bounds, n })
    }

    /// Nodes from `lower` to `upper` spaced by `step` (the count is rounded to the nearest whole
    /// number of steps, so `upper` is a node up to round-off).
    ///
    /// # Errors
    /// As [`GridAxis::new`], and when `step` is not finite and positive or gives more than
    /// [`MAX_GRID_NODES`] nodes.
    pub fn with_step(lower: f64, upper: f64, step: f64) -> Result<Self, OptimizeError> {
        InvalidInput::require_positive("step", step)?;
        let bounds = Bounds::new(lower, upper)?;
        let intervals = (bounds.width() / step).round();
        if !(intervals < MAX_GRID_NODES as f64) {
            return Err(InvalidInput::new(
                "step",
                step,
                "must give at most MAX_GRID_NODES nodes over [lower, upper]",
            )
            .into());
        }
        // `intervals` is a whole number in [0, MAX_GRID_NODES): the cast is exact.
        Self::new(lower, upper, intervals as usize + 1)
    }

    /// The interval spanned, `[lower, upper]`.
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// First node.
    pub fn lower(&self) -> f64 {
        self.bounds.lower()
    }

    /// Last node.
    pub fn upper(&self) -> f64 {
        self.bounds.upper()
    }

    /// Number of nodes (1 gives the single node `lower`).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Spacing of the nodes (0 for a single node).
    pub fn step(&self) -> f64 {
        if self.n > 1 {
            self.bounds.width() / (self.n - 1) as f64
        } else {
            0.0
        }
    }

    /// Node `i` (the last node is `upper` exactly; an `i` past it is extrapolated).
    pub fn node(&self, i: usize) -> f64 {
        if i == self.n - 1 {
            self.upper()
        } else {
            self.lower() + i as f64 * self.step()
        }
    }

    /// All nodes.
    pub fn nodes(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.node(i)).collect()
    }
}
