//! The Tsai platform's design problem (Stamper, Tsai & Walsh 1997, §5): maximise the workspace
//! volume $W$ (eq. 3) or the condition integral $\eta = \int_W 1/\kappa \, dW$ (eq. 8; Stamper's
//! "global condition index") or the Gosselin–Angeles GCI $\eta / W$ over any of the design
//! variables $x = (a, b, d + e, c - r, \phi_2, \phi_3)$ (lengths in m, angles in degrees),
//! subject to linear inequalities $g_i = c_i \cdot x - u_i \le 0$ and box bounds.
//!
//! One problem serves the `optimize` study and the reproduction of the paper's §5 in
//! `pkm::papers`; the indices of a design are evaluated on a fixed set of unit-hemisphere
//! points (common random numbers) scaled by the design's reach $R = a + b + d + e$.

use nalgebra::Vector3;
use pkm_mechanisms::{Elbow, Tsai3Dof, TsaiDesign};
use pkm_traits::{Bounds, Constraints, Objective, ObjectiveError, Silent};
use pkm_workspace_indices::{HemisphereEstimate, IndexError, Workspace};

/// The Tsai design variables in design-vector order, as named in `[mechanism.tsai]`.
pub const TSAI_VARIABLES: [&str; 6] = ["a", "b", "d_plus_e", "c_minus_r", "phi2_deg", "phi3_deg"];

/// What is maximised, with its quadrature setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TsaiCriterion {
    /// $W$ by the column quadrature ([`Tsai3Dof::column_volume`], continuous in the design), m³.
    Volume {
        /// Columns per axis.
        columns: usize,
    },
    /// $\eta = \int_W 1/\kappa \, dW$ on the common points (Stamper's eq. 8), m³.
    Eta,
    /// $\eta / W$ on the common points (Gosselin & Angeles), dimensionless.
    Gci,
}

/// A linear inequality $c \cdot x \le u$ over the six design variables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearInequality {
    /// $c$, in [`TSAI_VARIABLES`] order.
    pub coefficients: [f64; 6],
    /// $u$.
    pub at_most: f64,
}

/// The Tsai platform of the design vector `v` ([`TSAI_VARIABLES`] order, angles in degrees).
///
/// # Errors
/// [`ObjectiveError`] for an invalid design.
pub fn tsai_design(v: &[f64; 6]) -> Result<Tsai3Dof, ObjectiveError> {
    let [a, b, s, h, p2, p3] = *v;
    Ok(Tsai3Dof::new(TsaiDesign::from_deg(a, b, s, h, p2, p3))?)
}

/// $W$ and $\eta$ of `design` (elbows out, no further constraint) on the unit-hemisphere
/// `points` scaled by its reach $R$, in one pass.
///
/// # Errors
/// [`IndexError`] when the workspace or the estimate refuses its input.
pub fn hemisphere_estimate(
    design: &Tsai3Dof,
    points: &[Vector3<f64>],
) -> Result<HemisphereEstimate, IndexError> {
    Workspace::new(design, &[[Elbow::Out; 3]], &[])?.hemisphere_estimate(
        points,
        design.reach(),
        &Silent,
    )
}

/// The criterion's value for `design`, on the unit-hemisphere `points` for $\eta$ and the GCI.
///
/// # Errors
/// [`ObjectiveError`] for an invalid quadrature setting, an estimate that fails or an empty
/// workspace (GCI).
pub fn tsai_value(
    design: &Tsai3Dof,
    criterion: TsaiCriterion,
    points: &[Vector3<f64>],
) -> Result<f64, ObjectiveError> {
    let infeasible = |reason: String| ObjectiveError::infeasible(reason);
    match criterion {
        TsaiCriterion::Volume { columns } => Ok(design.column_volume(columns)?),
        TsaiCriterion::Eta | TsaiCriterion::Gci => {
            let e = hemisphere_estimate(design, points).map_err(|e| infeasible(e.to_string()))?;
            match criterion {
                TsaiCriterion::Gci => e
                    .gci()
                    .ok_or_else(|| infeasible("empty workspace: GCI = η/W undefined".into())),
                _ => Ok(e.eta),
            }
        }
    }
}

/// The problem: $f(x)$ = the criterion (to maximise) over the free variables, the others held
/// at their nominal values, and $g_i = c_i \cdot x - u_i \le 0$.
#[derive(Debug, Clone)]
pub struct TsaiProblem<'a> {
    nominal: [f64; 6],
    free: Vec<usize>,
    bounds: Vec<Bounds>,
    criterion: TsaiCriterion,
    points: &'a [Vector3<f64>],
    inequalities: Vec<LinearInequality>,
    scale_free: bool,
}

/// The screening problem uses this fraction of the points ($\eta$, GCI) or of the columns per
/// axis (volume).
const SCREENING_FRACTION: usize = 4;

impl<'a> TsaiProblem<'a> {
    /// The problem over the free variables `free` (indices into [`TSAI_VARIABLES`], in
    /// increasing order, each with its bounds), the others at `nominal`; `points` are the
    /// common unit-hemisphere points ($\eta$ and GCI only).
    pub fn new(
        nominal: [f64; 6],
        free: Vec<(usize, Bounds)>,
        criterion: TsaiCriterion,
        points: &'a [Vector3<f64>],
        inequalities: Vec<LinearInequality>,
    ) -> Self {
        Self {
            nominal,
            bounds: free.iter().map(|(_, b)| *b).collect(),
            free: free.into_iter().map(|(k, _)| k).collect(),
            criterion,
            points,
            inequalities,
            scale_free: false,
        }
    }

    /// The six design values at the free-variable vector `x`.
    pub fn design_values(&self, x: &[f64]) -> [f64; 6] {
        let mut all = self.nominal;
        for (k, v) in self.free.iter().zip(x) {
            all[*k] = *v;
        }
        all
    }

    /// Names of the free variables, in design-vector order.
    pub fn names(&self) -> Vec<&'static str> {
        self.free.iter().map(|&k| TSAI_VARIABLES[k]).collect()
    }

    /// The criterion.
    pub fn criterion(&self) -> TsaiCriterion {
        self.criterion
    }

    /// The problem for ranking multistart starts at a quarter of the cost per evaluation (the
    /// first quarter of the common points for $\eta$ and the GCI, a quarter of the columns per
    /// axis for the volume) and scale-free: $W$ and $\eta$ scale with $R^3$ when
    /// $(a, b, d + e, c - r)$ scale together, so evaluating at the lengths divided by $R$ is the
    /// value on an active reach constraint $R \le 1$, and a short run ranks a start without
    /// having to converge onto that constraint first.
    #[must_use]
    pub fn screening(&self) -> Self {
        let n = self.points.len();
        let (criterion, points) = match self.criterion {
            TsaiCriterion::Volume { columns } => (
                TsaiCriterion::Volume {
                    columns: (columns / SCREENING_FRACTION).max(1),
                },
                self.points,
            ),
            c => (c, &self.points[..(n / SCREENING_FRACTION).max(1).min(n)]),
        };
        Self {
            criterion,
            points,
            scale_free: true,
            ..self.clone()
        }
    }

    /// The design vector evaluated at `x` (lengths divided by $R$ when scale-free).
    fn evaluated(&self, x: &[f64]) -> [f64; 6] {
        let mut v = self.design_values(x);
        let reach = v[0] + v[1] + v[2];
        if self.scale_free && reach > 0.0 {
            v[..4].iter_mut().for_each(|l| *l /= reach);
        }
        v
    }
}

impl Objective for TsaiProblem<'_> {
    fn dimension(&self) -> usize {
        self.free.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn value(&self, x: &[f64]) -> Result<f64, ObjectiveError> {
        self.check_dimension(x)?;
        let design = tsai_design(&self.evaluated(x))?;
        tsai_value(&design, self.criterion, self.points)
    }
}

impl Constraints for TsaiProblem<'_> {
    fn n_constraints(&self) -> usize {
        self.inequalities.len()
    }
    fn inequalities(&self, x: &[f64], g: &mut [f64]) -> Result<(), ObjectiveError> {
        self.check_dimension(x)?;
        let all = self.design_values(x);
        for (gi, row) in g.iter_mut().zip(&self.inequalities) {
            *gi = row
                .coefficients
                .iter()
                .zip(&all)
                .map(|(c, v)| c * v)
                .sum::<f64>()
                - row.at_most;
        }
        Ok(())
    }
}
