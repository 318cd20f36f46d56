//! The Linear Delta's performance indices for one design of the paper's search space
//! `[L1/YR, YA/YR, ZR/YR, L2/L1]` ($Y_R = 1$), and the weighted utility (Miller 2004,
//! eqs. 1–4) as an [`Objective`] for the exhaustive search. The indices are the library's
//! ([`SectionIndices`]); this module adds the paper's design vector and lattice.

use nalgebra::Vector3;
use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
use pkm_traits::{Bounds, Objective, ObjectiveError};
use pkm_workspace_indices::{
    Eta1Rule, GridMean, GridRule, IndexError, SectionIndex, SectionIndexCache, SectionIndices,
    inverse_condition_at,
};

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

/// An index failure as the objective's: an invalid design keeps its typed cause, an empty
/// workspace is infeasible.
fn objective_error(e: IndexError) -> ObjectiveError {
    match e {
        IndexError::Design(design) => design.into(),
        e => ObjectiveError::infeasible(e.to_string()),
    }
}

/// `index` at `design`, computed on the library's [`SectionIndices`].
fn section_index(design: &[f64; 4], index: SectionIndex) -> Result<f64, ObjectiveError> {
    let delta = linear_delta(design)?;
    let indices = SectionIndices::new(&delta, LinearDeltaMode::PAPER);
    indices.value(index).map_err(objective_error)
}

/// $\eta_1$ (eq. 1) by an `n`-point Gauss–Legendre product rule.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta1(design: &[f64; 4], n: usize) -> Result<f64, ObjectiveError> {
    section_index(design, SectionIndex::Eta1(Eta1Rule::Quadrature(n)))
}

/// $\eta_1$ by the paper's uniform grid, eq. 4 with $N_a > 5000$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta1_by_grid(design: &[f64; 4]) -> Result<GridMean, ObjectiveError> {
    let delta = linear_delta(design)?;
    SectionIndices::new(&delta, LinearDeltaMode::PAPER)
        .eta1_by_grid(&GridRule::default())
        .map_err(objective_error)
}

/// $\eta_2$ (eq. 2): cross-section area over the box containing it and the three rails.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
pub fn eta2(design: &[f64; 4]) -> Result<f64, ObjectiveError> {
    section_index(design, SectionIndex::Eta2)
}

/// The exact cross-section area $A_W / Y_R^2$.
///
/// # Errors
/// [`ObjectiveError::Infeasible`] for an invalid design.
pub fn area(design: &[f64; 4]) -> Result<f64, ObjectiveError> {
    section_index(design, SectionIndex::Area)
}

/// The lattice node a design of the searches stands for: each value rounded to millionths.
/// Every lattice of the searches has a step of at least 0.01 (and the fixed values, such as
/// `L2/L1 = 1e-3`, are millionths), so this removes only the round-off of `lower + i·step`:
/// the indices of a node are computed at its decimal value, whichever round-off variant of it
/// a search reaches.
pub fn lattice_node(design: &[f64; 4]) -> [f64; 4] {
    design.map(|v| (v * 1e6).round() / 1e6)
}

/// The utility $\eta = w_1\eta_1 + w_2\eta_2$ (eq. 3), to be maximised (`Sense::Maximise`),
/// evaluated at the [`lattice_node`] of each design.
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
    /// The study's cache of $\eta_1$ and $\eta_2$ (they do not depend on the weights).
    pub cache: &'a SectionIndexCache,
}

impl Utility<'_> {
    /// $(\eta_1, \eta_2, \eta)$ at the lattice node of `design`; $\eta_1$ is skipped (NaN)
    /// when $w_1 = 0$.
    ///
    /// # Errors
    /// [`ObjectiveError::Infeasible`] for an invalid design or an empty workspace.
    pub fn indices(&self, design: &[f64; 4]) -> Result<[f64; 3], ObjectiveError> {
        let node = lattice_node(design);
        let skip_eta1 = self.w1.abs() < f64::MIN_POSITIVE;
        let wanted = [SectionIndex::Eta2, SectionIndex::Eta1(self.rule)];
        let wanted = if skip_eta1 { &wanted[..1] } else { &wanted[..] };
        let build = || {
            LinearDelta::new(LinearDeltaDesign {
                ratios: LinearDeltaRatios::from_slice(&node),
                yr: 1.0,
            })
        };
        let values = self
            .cache
            .values(&node, wanted, LinearDeltaMode::PAPER, build);
        let values: Vec<_> = values
            .into_iter()
            .map(|v| v.map_err(objective_error))
            .collect();
        match values.as_slice() {
            [eta2] => {
                let eta2 = eta2.clone()?;
                Ok([f64::NAN, eta2, self.w2 * eta2])
            }
            [eta2, eta1] => {
                let (eta2, eta1) = (eta2.clone()?, eta1.clone()?);
                Ok([eta1, eta2, self.w1 * eta1 + self.w2 * eta2])
            }
            // `values` answers every index asked for.
            _ => Err(ObjectiveError::Dimension {
                expected: wanted.len(),
                got: values.len(),
            }),
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

    #[test]
    fn a_round_off_variant_of_a_lattice_node_is_evaluated_at_the_node() {
        let cache = SectionIndexCache::new();
        let utility = Utility {
            w1: 1.0,
            w2: 1.0,
            rule: Eta1Rule::Quadrature(8),
            bounds: [Bounds::new(0.0, 3.0).unwrap(); 4],
            cache: &cache,
        };
        let node: [f64; 4] = [1.6, 0.0, 0.0, 0.66];
        // lower + i·step as the searches form it: 1.5999999999999999 and 0.6599999999999999.
        let variant: [f64; 4] = [1.4 + 2.0 * 0.1, 0.0, 0.0, 0.6 + 6.0 * 0.01];
        assert_ne!(variant[0].to_bits(), node[0].to_bits(), "not a variant");
        let direct = [eta1(&node, 8).unwrap(), eta2(&node).unwrap()];
        for d in [node, variant, node] {
            let [e1, e2, eta] = utility.indices(&d).unwrap();
            assert_eq!([e1.to_bits(), e2.to_bits()], direct.map(f64::to_bits));
            assert_eq!(eta.to_bits(), (direct[0] + direct[1]).to_bits());
        }
        // One node, two indices; a non-finite design is its own typed error.
        assert_eq!(cache.len(), 2);
        let nan = utility.indices(&[2.0, f64::NAN, 0.0, 0.63]).unwrap_err();
        assert!(nan.cause().is_some(), "{nan}");
    }
}
