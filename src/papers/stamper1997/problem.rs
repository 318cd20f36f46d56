//! The design problem of sec. 5: maximise the workspace volume (eq. 3) or the global condition
//! index (eq. 8) over $x = (a, b, d + e, c - r, \phi_2, \phi_3)$ (angles in degrees) subject to
//! $a + b + d + e \le 1$, leg separation $\ge 5°$ ($5 \le \phi_2$, $\phi_3 - \phi_2 \ge 5$,
//! $\phi_3 \le 355$) and non-negative lengths (bounds; $c - r \ge 0$, spec §4 A4).
//!
//! The problem itself is the study layer's [`TsaiProblem`] (the one the `optimize` study
//! solves), with every variable free and the paper's two linear inequalities.

use nalgebra::Vector3;
use pkm_design_problems::tsai::{LinearInequality, TsaiCriterion, TsaiProblem, tsai_design};
use pkm_mechanisms::Tsai3Dof;
use pkm_traits::{Bounds, ObjectiveError};

pub(super) use pkm_design_problems::tsai::hemisphere_estimate as estimate;

/// What is maximised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Criterion {
    /// Workspace volume, by the column quadrature (continuous in the design).
    Volume {
        /// Columns per axis.
        ngrid: usize,
    },
    /// Global condition index on the common random numbers (Stamper's eq. 8: $\eta$).
    Gci,
}

/// The two inequalities of sec. 5: $a + b + (d + e) \le 1$ and $\phi_2 - \phi_3 \le -5$.
const INEQUALITIES: [LinearInequality; 2] = [
    LinearInequality {
        coefficients: [1.0, 1.0, 1.0, 0.0, 0.0, 0.0],
        at_most: 1.0,
    },
    LinearInequality {
        coefficients: [0.0, 0.0, 0.0, 0.0, 1.0, -1.0],
        at_most: -5.0,
    },
];

/// Stamper's problem in the box `bounds` on the common unit-hemisphere `points`.
pub(super) fn stamper_problem(
    bounds: [Bounds; 6],
    criterion: Criterion,
    points: &[Vector3<f64>],
) -> TsaiProblem<'_> {
    let criterion = match criterion {
        Criterion::Volume { ngrid } => TsaiCriterion::Volume { columns: ngrid },
        Criterion::Gci => TsaiCriterion::Eta,
    };
    let free = bounds.into_iter().enumerate().collect();
    TsaiProblem::new([0.0; 6], free, criterion, points, INEQUALITIES.to_vec())
}

/// The design of a design vector.
pub(super) fn design(x: &[f64]) -> Result<Tsai3Dof, ObjectiveError> {
    let v: [f64; 6] = x.try_into().map_err(|_| ObjectiveError::Dimension {
        expected: 6,
        got: x.len(),
    })?;
    tsai_design(&v)
}
