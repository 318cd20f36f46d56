//! The Linear Delta's performance indices for one design, and the weighted utility (Miller 2004,
//! eqs. 1–4) as an [`Objective`] for the exhaustive search.

use pkm_mechanisms::{LinearDelta, LinearDeltaMode, LinearDeltaRatios};
use pkm_traits::{Bounds, Objective, ObjectiveError, SlicedRegion};
use pkm_workspace_indices::{
    GridMean, GridRule, IndexError, inverse_condition_number_3x3, mean_by_grid, mean_by_quadrature,
    space_utilization,
};
use std::collections::HashMap;
use std::sync::Mutex;

/// Builds the design `[L1/YR, YA/YR, ZR/YR, L2/L1]` with $Y_R = 1$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design.
pub fn linear_delta(design: &[f64; 4]) -> Result<LinearDelta, ObjectiveError> {
    Ok(LinearDelta::new(
        LinearDeltaRatios::from_slice(design),
        1.0,
    )?)
}

/// $1/\kappa(J)$ at $(y, z)$, 0 outside the discs and on their boundaries (serial singularities).
pub fn inverse_condition(delta: &LinearDelta, y: f64, z: f64) -> f64 {
    delta
        .velocity_jacobian(y, z, LinearDeltaMode::PAPER)
        .map_or(0.0, |j| inverse_condition_number_3x3(&j))
}

fn infeasible(e: IndexError) -> ObjectiveError {
    ObjectiveError::Infeasible {
        reason: e.to_string(),
    }
}

/// $\eta_1$ (eq. 1) by an `n`-point Gauss–Legendre product rule.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta1(design: &[f64; 4], n: usize) -> Result<f64, ObjectiveError> {
    let delta = linear_delta(design)?;
    let region = delta.cross_section();
    mean_by_quadrature(&region, |y, z| inverse_condition(&delta, y, z), n).map_err(infeasible)
}

/// $\eta_1$ by the paper's uniform grid, eq. 4 with $N_a > 5000$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta1_by_grid(design: &[f64; 4]) -> Result<GridMean, ObjectiveError> {
    let delta = linear_delta(design)?;
    let region = delta.cross_section();
    let rule = GridRule::default();
    mean_by_grid(&region, |y, z| inverse_condition(&delta, y, z), &rule).map_err(infeasible)
}

/// $\eta_2$ (eq. 2): cross-section area over the box containing it and the three rails.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta2(design: &[f64; 4]) -> Result<f64, ObjectiveError> {
    let delta = linear_delta(design)?;
    space_utilization(&delta.cross_section(), &delta.rails()).map_err(infeasible)
}

/// The exact cross-section area $A_W / Y_R^2$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design.
pub fn area(design: &[f64; 4]) -> Result<f64, ObjectiveError> {
    Ok(linear_delta(design)?.cross_section().area())
}

/// How $\eta_1$ is integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Eta1Rule {
    /// `n`-point Gauss–Legendre product rule per piece ([`eta1`]).
    Quadrature(usize),
    /// The paper's uniform grid with $N_a > 5000$ ([`eta1_by_grid`]).
    PaperGrid,
}

impl Eta1Rule {
    /// $\eta_1$ at `design` by this rule.
    ///
    /// # Errors
    /// As [`eta1`].
    pub fn eta1(self, design: &[f64; 4]) -> Result<f64, ObjectiveError> {
        match self {
            Self::Quadrature(n) => eta1(design, n),
            Self::PaperGrid => eta1_by_grid(design).map(|g| g.mean),
        }
    }
}

/// Memo key: the design in millionths and the rule.
type MemoKey = ([i64; 4], Eta1Rule);

/// Memo of $\eta_1$ values shared by every search of a study (it does not depend on the weights).
#[derive(Debug, Default)]
pub struct Eta1Memo {
    values: Mutex<HashMap<MemoKey, Result<f64, ObjectiveError>>>,
}

impl Eta1Memo {
    /// $\eta_1$ at `design` by `rule`, computed once per (design, rule).
    ///
    /// # Errors
    /// As [`eta1`].
    pub fn eta1(&self, design: &[f64; 4], rule: Eta1Rule) -> Result<f64, ObjectiveError> {
        let key = (design.map(|v| (v * 1e6).round() as i64), rule);
        if let Some(v) = self.values.lock().ok().and_then(|m| m.get(&key).cloned()) {
            return v;
        }
        let value = rule.eta1(design);
        if let Ok(mut map) = self.values.lock() {
            map.insert(key, value.clone());
        }
        value
    }
}

/// The utility $\eta = w_1\eta_1 + w_2\eta_2$ (eq. 3), negated for minimisation.
#[derive(Debug)]
pub struct Utility<'a> {
    /// Weight of manipulability.
    pub w1: f64,
    /// Weight of space utilisation.
    pub w2: f64,
    /// How $\eta_1$ is integrated.
    pub rule: Eta1Rule,
    /// The search box `[L1/YR, YA/YR, ZR/YR, L2/L1]`.
    pub bounds: [Bounds; 4],
    /// Shared memo of $\eta_1$.
    pub memo: &'a Eta1Memo,
}

impl Utility<'_> {
    /// $(\eta_1, \eta_2, \eta)$ at `design`; $\eta_1$ is skipped (NaN) when $w_1 = 0$.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
    pub fn indices(&self, design: &[f64; 4]) -> Result<[f64; 3], ObjectiveError> {
        let eta2 = eta2(design)?;
        if self.w1.abs() < f64::MIN_POSITIVE {
            return Ok([f64::NAN, eta2, self.w2 * eta2]);
        }
        let eta1 = self.memo.eta1(design, self.rule)?;
        Ok([eta1, eta2, self.w1 * eta1 + self.w2 * eta2])
    }
}

impl Objective for Utility<'_> {
    fn dimension(&self) -> usize {
        4
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn value(&self, design: &[f64]) -> Result<f64, ObjectiveError> {
        let design: [f64; 4] = design.try_into().map_err(|_| ObjectiveError::Dimension {
            expected: 4,
            got: design.len(),
        })?;
        Ok(-self.indices(&design)?[2])
    }
}
