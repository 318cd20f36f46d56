//! The design problem of sec. 5: maximise the workspace volume (eq. 3) or the global condition
//! index (eq. 8) over $x = (a, b, d + e, c - r, \phi_2, \phi_3)$ (angles in degrees) subject to
//! $a + b + d + e \le 1$, leg separation $\ge 5°$ ($5 \le \phi_2$, $\phi_3 - \phi_2 \ge 5$,
//! $\phi_3 \le 355$) and non-negative lengths (bounds; $c - r \ge 0$, spec §4 A4).

use nalgebra::Vector3;
use pkm_mechanisms::{Elbow, Tsai3Dof, TsaiDesign};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};
use pkm_workspace_indices::{HemisphereEstimate, Workspace};

/// What is maximised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Criterion {
    /// Workspace volume, by the column quadrature (continuous in the design).
    Volume {
        /// Columns per axis.
        ngrid: usize,
    },
    /// Global condition index on the common random numbers.
    Gci,
}

/// Stamper's problem on a fixed set of unit-hemisphere points (common random numbers).
#[derive(Debug)]
pub(super) struct StamperProblem<'a> {
    pub(super) bounds: [Bounds; 6],
    pub(super) criterion: Criterion,
    pub(super) points: &'a [Vector3<f64>],
    /// Evaluate at the lengths divided by $R = a + b + d + e$ (see [`StamperProblem::screening`]).
    pub(super) scale_free: bool,
}

/// The design of a design vector.
pub(super) fn design(x: &[f64]) -> Result<Tsai3Dof, ObjectiveError> {
    Ok(Tsai3Dof::new(TsaiDesign::from_deg(
        x[0], x[1], x[2], x[3], x[4], x[5],
    ))?)
}

/// $W$ and $\eta$ of `design` (elbow out, no further constraint) on the unit-hemisphere
/// `points` scaled by its reach $R$ (one pass).
pub(super) fn estimate(
    design: &Tsai3Dof,
    points: &[Vector3<f64>],
) -> Result<HemisphereEstimate, pkm_workspace_indices::IndexError> {
    Workspace::new(design, &[[Elbow::Out; 3]], &[])?.hemisphere_estimate(
        points,
        design.reach(),
        &Silent,
    )
}

/// The screening objective uses this fraction of the points (GCI) or of the columns per axis
/// (volume).
const SCREENING_FRACTION: usize = 4;

impl StamperProblem<'_> {
    /// The problem for ranking multistart starts, at a quarter of the cost per evaluation
    /// (the first quarter of the common random numbers for the GCI, a quarter of the columns
    /// per axis for the volume) and scale-free: $W$ and $\eta$ scale with $R^3$ when
    /// $(a, b, d + e, c - r)$ scale together (spec §1), so evaluating at the lengths divided by
    /// $R$ is the value on the always-active length constraint, and a short run ranks a start
    /// without having to converge onto that constraint first.
    pub(super) fn screening(&self) -> Self {
        let n = self.points.len();
        Self {
            bounds: self.bounds,
            criterion: match self.criterion {
                Criterion::Volume { ngrid } => Criterion::Volume {
                    ngrid: (ngrid / SCREENING_FRACTION).max(1),
                },
                Criterion::Gci => Criterion::Gci,
            },
            points: match self.criterion {
                Criterion::Volume { .. } => self.points,
                Criterion::Gci => &self.points[..(n / SCREENING_FRACTION).max(1).min(n)],
            },
            scale_free: true,
        }
    }

    /// The design vector this problem evaluates at `x`.
    fn evaluated(&self, x: &[f64]) -> [f64; 6] {
        let mut v = [x[0], x[1], x[2], x[3], x[4], x[5]];
        let reach = v[0] + v[1] + v[2];
        if self.scale_free && reach > 0.0 {
            v[..4].iter_mut().for_each(|l| *l /= reach);
        }
        v
    }
}

impl Objective for StamperProblem<'_> {
    fn dimension(&self) -> usize {
        6
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        self.check_dimension(x)?;
        let d = design(&self.evaluated(x))?;
        match self.criterion {
            Criterion::Volume { ngrid } => Ok(d.column_volume(ngrid)?),
            Criterion::Gci => estimate(&d, self.points)
                .map(|e| e.eta)
                .map_err(|e| ObjectiveError::infeasible(e.to_string())),
        }
    }
}

impl Constraints for StamperProblem<'_> {
    fn n_constraints(&self) -> usize {
        2
    }
    fn inequalities(&self, x: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        self.check_dimension(x)?;
        g[0] = x[0] + x[1] + x[2] - 1.0;
        g[1] = x[4] - x[5] + 5.0;
        Ok(())
    }
}
