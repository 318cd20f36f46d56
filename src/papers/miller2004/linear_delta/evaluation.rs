//! The Linear Delta's performance indices for one design, and the weighted utility (Miller 2004,
//! eqs. 1–4) as an [`Objective`] for the exhaustive search.

use nalgebra::Vector3;
use pkm_mechanisms::{
    CrossSection, LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios,
};
use pkm_traits::{Bounds, Objective, ObjectiveError, SlicedRegion};
use pkm_workspace_indices::{
    GaussLegendre, GridMean, GridRule, IndexError, LANES, inverse_condition_at,
    inverse_condition_number_3x3_lanes, mean_by_grid_lanes, mean_by_quadrature_lanes,
    space_utilization,
};
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::Mutex;

/// Builds the design `[L1/YR, YA/YR, ZR/YR, L2/L1]` with $Y_R = 1$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design.
pub fn linear_delta(design: &[f64; 4]) -> Result<LinearDelta, ObjectiveError> {
    Ok(LinearDelta::new(LinearDeltaDesign {
        ratios: LinearDeltaRatios::from_slice(design),
        yr: 1.0,
    })?)
}

/// $1/\kappa(J)$ at $(y, z)$ ([`inverse_condition_at`], $J$ independent of $x$), 0 outside
/// the cross-section and on the discs' boundaries (serial singularities).
pub fn inverse_condition(delta: &LinearDelta, y: f64, z: f64) -> f64 {
    inverse_condition_at(delta, &Vector3::new(0.0, y, z), LinearDeltaMode::PAPER).unwrap_or(0.0)
}

/// [`inverse_condition`] at the [`LANES`] points $(y, z_l)$: the batch Jacobian
/// ([`LinearDelta::velocity_jacobian_lanes`], the scalar one bit for bit) and one trig-free
/// batch $1/\kappa$ ([`inverse_condition_number_3x3_lanes`], equal to the scalar routine to
/// $10^{-12}$ relative for $\kappa \le 100$). A lane without a Jacobian (outside a disc or on
/// its boundary) is 0, as in [`inverse_condition`].
pub fn inverse_condition_lanes(delta: &LinearDelta, y: f64, z: &[f64; LANES]) -> [f64; LANES] {
    let batch = delta.velocity_jacobian_lanes(y, z, LinearDeltaMode::PAPER);
    let inverse = inverse_condition_number_3x3_lanes(&batch.jacobian);
    std::array::from_fn(|lane| {
        if batch.reachable[lane] {
            inverse[lane]
        } else {
            0.0
        }
    })
}

thread_local! {
    /// The Gauss–Legendre rules this thread has built, one per order: a rule is a pure function
    /// of its order, so reusing it changes no value, and the searches build each order once
    /// instead of once per design.
    static RULES: RefCell<Vec<GaussLegendre>> = const { RefCell::new(Vec::new()) };
}

/// `integrate` with the `n`-point Gauss–Legendre rule, built on first use on this thread.
fn with_rule<T>(
    n: usize,
    integrate: impl FnOnce(&GaussLegendre) -> Result<T, IndexError>,
) -> Result<T, IndexError> {
    RULES.with_borrow_mut(|rules| {
        let index = match rules.iter().position(|rule| rule.len() == n) {
            Some(index) => index,
            None => {
                rules.push(GaussLegendre::new(n)?);
                rules.len() - 1
            }
        };
        integrate(&rules[index])
    })
}

fn infeasible(e: IndexError) -> ObjectiveError {
    ObjectiveError::infeasible(e.to_string())
}

/// One design's mechanism and workspace cross-section, built once for all of its indices
/// (`eta1`, `eta2`, the area and the paper's grid rule share them).
#[derive(Debug, Clone)]
pub struct DesignEvaluation {
    delta: LinearDelta,
    region: CrossSection,
}

impl DesignEvaluation {
    /// The mechanism and cross-section of `design` (`[L1/YR, YA/YR, ZR/YR, L2/L1]`, $Y_R = 1$).
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an invalid design.
    pub fn new(design: &[f64; 4]) -> Result<Self, ObjectiveError> {
        let delta = linear_delta(design)?;
        let region = delta.cross_section();
        Ok(Self { delta, region })
    }

    /// $\eta_1$ (eq. 1) by an `n`-point Gauss–Legendre product rule.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an empty workspace or `n = 0`.
    pub fn eta1(&self, n: usize) -> Result<f64, ObjectiveError> {
        with_rule(n, |rule| {
            mean_by_quadrature_lanes(&self.region, |y, z| self.inverse_condition(y, z), rule)
        })
        .map_err(infeasible)
    }

    /// $\eta_1$ by the paper's uniform grid, eq. 4 with $N_a > 5000$.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an empty workspace.
    pub fn eta1_by_grid(&self) -> Result<GridMean, ObjectiveError> {
        let rule = GridRule::default();
        mean_by_grid_lanes(&self.region, |y, z| self.inverse_condition(y, z), &rule)
            .map_err(infeasible)
    }

    /// $\eta_2$ (eq. 2): cross-section area over the box containing it and the three rails.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an empty workspace.
    pub fn eta2(&self) -> Result<f64, ObjectiveError> {
        space_utilization(&self.region, &self.delta.rails()).map_err(infeasible)
    }

    /// The exact cross-section area $A_W / Y_R^2$.
    pub fn area(&self) -> f64 {
        self.region.area()
    }

    fn inverse_condition(&self, y: f64, z: &[f64; LANES]) -> [f64; LANES] {
        inverse_condition_lanes(&self.delta, y, z)
    }
}

/// $\eta_1$ (eq. 1) by an `n`-point Gauss–Legendre product rule.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta1(design: &[f64; 4], n: usize) -> Result<f64, ObjectiveError> {
    DesignEvaluation::new(design)?.eta1(n)
}

/// $\eta_1$ by the paper's uniform grid, eq. 4 with $N_a > 5000$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta1_by_grid(design: &[f64; 4]) -> Result<GridMean, ObjectiveError> {
    DesignEvaluation::new(design)?.eta1_by_grid()
}

/// $\eta_2$ (eq. 2): cross-section area over the box containing it and the three rails.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta2(design: &[f64; 4]) -> Result<f64, ObjectiveError> {
    DesignEvaluation::new(design)?.eta2()
}

/// The exact cross-section area $A_W / Y_R^2$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design.
pub fn area(design: &[f64; 4]) -> Result<f64, ObjectiveError> {
    Ok(DesignEvaluation::new(design)?.area())
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
        self.eta1_of(&DesignEvaluation::new(design)?)
    }

    /// $\eta_1$ of an evaluated design by this rule.
    ///
    /// # Errors
    /// As [`DesignEvaluation::eta1`].
    pub fn eta1_of(self, evaluation: &DesignEvaluation) -> Result<f64, ObjectiveError> {
        match self {
            Self::Quadrature(n) => evaluation.eta1(n),
            Self::PaperGrid => evaluation.eta1_by_grid().map(|g| g.mean),
        }
    }
}

/// A design in millionths: the memo's key. Every search lattice is at least 0.01 apart, so
/// designs that agree in millionths are the same lattice node up to the round-off of
/// `lower + i·step`.
type DesignKey = [i64; 4];

fn design_key(design: &[f64; 4]) -> DesignKey {
    design.map(|v| (v * 1e6).round() as i64)
}

/// The design a key stands for. Indices are computed there, not at whichever round-off variant
/// of the node a search reached first, so a memoised value does not depend on the order in
/// which threads evaluate the nodes.
fn canonical_design(key: &DesignKey) -> [f64; 4] {
    key.map(|k| k as f64 / 1e6)
}

/// A memoised index: its value or why the design has none.
type Index = Result<f64, ObjectiveError>;

/// What the memo knows of the designs: $\eta_2$ per design, $\eta_1$ per design and rule.
#[derive(Debug, Default)]
struct MemoTables {
    eta2: HashMap<DesignKey, Index>,
    eta1: HashMap<(DesignKey, Eta1Rule), Index>,
}

/// Memo of the indices shared by every search of a study ($\eta_1$ and $\eta_2$ do not depend
/// on the weights): each design's mechanism and cross-section are built once for whatever is
/// missing, and nothing is computed twice.
#[derive(Debug, Default)]
pub struct Eta1Memo {
    tables: Mutex<MemoTables>,
}

impl Eta1Memo {
    /// $\eta_1$ at `design` (to the nearest millionth) by `rule`, computed once per
    /// (design, rule).
    ///
    /// # Errors
    /// As [`eta1`].
    pub fn eta1(&self, design: &[f64; 4], rule: Eta1Rule) -> Result<f64, ObjectiveError> {
        let (eta1, _) = self.indices(design, Some(rule));
        eta1.unwrap_or_else(|| rule.eta1(&canonical_design(&design_key(design))))
    }

    /// $\eta_2$ at `design` (to the nearest millionth), computed once per design.
    ///
    /// # Errors
    /// As [`eta2`].
    pub fn eta2(&self, design: &[f64; 4]) -> Result<f64, ObjectiveError> {
        self.indices(design, None).1
    }

    /// $\eta_1$ by `rule` (when asked for) and $\eta_2$ at `design`, from the tables or
    /// computed on one [`DesignEvaluation`].
    fn indices(&self, design: &[f64; 4], rule: Option<Eta1Rule>) -> (Option<Index>, Index) {
        if design.iter().any(|v| !v.is_finite()) {
            // No key stands for it: its own error, never memoised.
            let evaluation = DesignEvaluation::new(design);
            return evaluate_missing(&evaluation, rule, None, None);
        }
        let key = design_key(design);
        let (known_eta1, known_eta2) = self.lookup(&key, rule);
        if let (Some(eta2), true) = (&known_eta2, rule.is_none() || known_eta1.is_some()) {
            return (known_eta1, eta2.clone());
        }
        let evaluation = DesignEvaluation::new(&canonical_design(&key));
        let (eta1, eta2) = evaluate_missing(&evaluation, rule, known_eta1, known_eta2);
        if let Ok(mut tables) = self.tables.lock() {
            tables.eta2.insert(key, eta2.clone());
            if let (Some(rule), Some(eta1)) = (rule, &eta1) {
                tables.eta1.insert((key, rule), eta1.clone());
            }
        }
        (eta1, eta2)
    }

    fn lookup(&self, key: &DesignKey, rule: Option<Eta1Rule>) -> (Option<Index>, Option<Index>) {
        self.tables.lock().ok().map_or((None, None), |tables| {
            (
                rule.and_then(|rule| tables.eta1.get(&(*key, rule)).cloned()),
                tables.eta2.get(key).cloned(),
            )
        })
    }
}

/// $\eta_1$ by `rule` (when asked for) and $\eta_2$ of `evaluation`, where not `known`.
fn evaluate_missing(
    evaluation: &Result<DesignEvaluation, ObjectiveError>,
    rule: Option<Eta1Rule>,
    known_eta1: Option<Index>,
    known_eta2: Option<Index>,
) -> (Option<Index>, Index) {
    let evaluation = evaluation.as_ref().map_err(Clone::clone);
    let eta2 = known_eta2.unwrap_or_else(|| evaluation.clone().and_then(DesignEvaluation::eta2));
    let eta1 =
        rule.map(|rule| known_eta1.unwrap_or_else(|| evaluation.and_then(|e| rule.eta1_of(e))));
    (eta1, eta2)
}

/// The utility $\eta = w_1\eta_1 + w_2\eta_2$ (eq. 3), to be maximised (`Sense::Maximise`).
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
    /// Shared memo of $\eta_1$ and $\eta_2$.
    pub memo: &'a Eta1Memo,
}

impl Utility<'_> {
    /// $(\eta_1, \eta_2, \eta)$ at `design`; $\eta_1$ is skipped (NaN) when $w_1 = 0$.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
    pub fn indices(&self, design: &[f64; 4]) -> Result<[f64; 3], ObjectiveError> {
        let skip_eta1 = self.w1.abs() < f64::MIN_POSITIVE;
        let (eta1, eta2) = self.memo.indices(design, (!skip_eta1).then_some(self.rule));
        let eta2 = eta2?;
        match eta1 {
            Some(eta1) => {
                let eta1 = eta1?;
                Ok([eta1, eta2, self.w1 * eta1 + self.w2 * eta2])
            }
            None => Ok([f64::NAN, eta2, self.w2 * eta2]),
        }
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
        Ok(self.indices(&design)?[2])
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use pkm_workspace_indices::{mean_by_grid, mean_by_quadrature};
    use proptest::prelude::*;

    /// Batched and scalar $\eta_1$ feed the same Jacobians to the two $1/\kappa$ routines and
    /// sum in the same order, so they differ by the routines' disagreement only: $10^{-12}$
    /// relative for $\kappa \le 100$, about $\epsilon\kappa$ absolute beyond, averaged.
    const BATCHED_ETA1_TOLERANCE: f64 = 1e-11;

    /// $\eta_1$ by the scalar $1/\kappa$ at every node ([`inverse_condition`]).
    fn scalar_eta1(evaluation: &DesignEvaluation, n: usize) -> Result<f64, IndexError> {
        mean_by_quadrature(
            &evaluation.region,
            |y, z| inverse_condition(&evaluation.delta, y, z),
            n,
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]

        /// Over the full search box of Table 2 row 1 (and beyond in $L_2/L_1$).
        #[test]
        fn batched_eta1_equals_the_scalar_path(
            l1 in 1.0..2.8f64,
            ya in -0.9..0.9f64,
            zr in -1.2..0.6f64,
            l2 in 0.01..2.0f64,
            n in prop::sample::select(vec![5usize, 8, 13, 16, 24]),
        ) {
            let evaluation = DesignEvaluation::new(&[l1, ya, zr, l2]).unwrap();
            match (evaluation.eta1(n), scalar_eta1(&evaluation, n)) {
                (Ok(batched), Ok(scalar)) => {
                    prop_assert!(
                        (batched - scalar).abs() <= BATCHED_ETA1_TOLERANCE,
                        "batched {batched} vs scalar {scalar}"
                    );
                }
                (batched, scalar) => prop_assert_eq!(batched.is_err(), scalar.is_err()),
            }
        }
    }

    #[test]
    fn batched_paper_grid_equals_the_scalar_path() {
        for design in [
            [1.48, 0.0, 0.0, 0.57],
            [2.0, 0.3, -0.6, 0.63],
            [1.55, 0.0, -0.75, 0.01],
        ] {
            let evaluation = DesignEvaluation::new(&design).unwrap();
            let batched = evaluation.eta1_by_grid().unwrap();
            let scalar = mean_by_grid(
                &evaluation.region,
                |y, z| inverse_condition(&evaluation.delta, y, z),
                &GridRule::default(),
            )
            .unwrap();
            assert_eq!(batched.n_points, scalar.n_points);
            assert!(
                (batched.mean - scalar.mean).abs() <= BATCHED_ETA1_TOLERANCE,
                "{design:?}: batched {} vs scalar {}",
                batched.mean,
                scalar.mean
            );
        }
    }

    #[test]
    fn memo_agrees_with_direct_evaluation_and_rejects_non_finite_designs() {
        let memo = Eta1Memo::default();
        let design = [2.0, 0.0, 0.0, 0.63];
        let rule = Eta1Rule::Quadrature(8);
        let (Ok(direct1), Ok(direct2)) = (eta1(&design, 8), eta2(&design)) else {
            panic!("the row-4 optimum is a valid design");
        };
        // A round-off variant of the same lattice node shares the memo entry.
        let variant = [1.4 + 6.0 * 0.1, 0.0, 0.0, 0.6 + 3.0 * 0.01];
        for d in [design, variant, design] {
            let (Ok(m1), Ok(m2)) = (memo.eta1(&d, rule), memo.eta2(&d)) else {
                panic!("memoised indices of a valid design");
            };
            assert!((m1 - direct1).abs() < 1e-14 && (m2 - direct2).abs() < 1e-14);
        }
        let nan = [2.0, f64::NAN, 0.0, 0.63];
        assert!(memo.eta1(&nan, rule).is_err());
        assert!(memo.eta2(&nan).is_err());
        assert!(
            memo.eta1(&design, rule)
                .is_ok_and(|v| (v - direct1).abs() < 1e-14)
        );
    }
}
