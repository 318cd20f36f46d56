//! The cross-section indices of a mechanism whose workspace is a prism along $x$
//! ([`CrossSectionWorkspace`]; Miller 2004, §2.2): the manipulability index
//! $$ \eta_1 = \frac{1}{A_W} \int_W \frac{1}{\kappa(J(y, z))}\, dA \qquad \text{(eq. 1)}, $$
//! the space utilisation $\eta_2 = A_W / A_{bb}$ (eq. 2, [`space_utilization`]) and the exact
//! area $A_W$ of the cross-section $W$.
//!
//! $\eta_1$ is integrated by a Gauss–Legendre product rule on each smooth piece of $W$
//! ([`mean_by_quadrature_lanes`]) or by the paper's uniform grid with $N_a > 5000$ (eq. 4,
//! [`mean_by_grid_lanes`]); $1/\kappa$ is the trig-free batch routine
//! ([`inverse_condition_number_3x3_lanes`]) on the mechanism's batch Jacobians, 0 where $J$ is
//! not defined (a disc boundary of the Linear Delta: a serial singularity).

use crate::{
    GaussLegendre, GridMean, GridRule, IndexError, LANES, inverse_condition_number_3x3_lanes,
    mean_by_grid_lanes, mean_by_quadrature_lanes, space_utilization,
};
use pkm_traits::{BlockKernel, CrossSectionWorkspace, SlicedRegion, run_block};
use serde::{Deserialize, Serialize};

/// How $\eta_1$ is integrated over the cross-section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Eta1Rule {
    /// The `n`-point Gauss–Legendre product rule on every piece of $W$
    /// ([`mean_by_quadrature_lanes`]); $n = 24$ is converged to about 3e-6 for the Linear
    /// Delta.
    Quadrature(usize),
    /// The paper's cell-centred uniform grid, refined until more than 5000 nodes lie in $W$
    /// (Miller 2004, eq. 4; [`GridRule::default`]).
    Grid,
}

/// One cross-section index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SectionIndex {
    /// $\eta_1$ (eq. 1) by the given rule.
    Eta1(Eta1Rule),
    /// $\eta_2$ (eq. 2).
    Eta2,
    /// The exact area $A_W$ (0 for an empty cross-section).
    Area,
}

/// [`SectionIndices::inverse_condition_lanes`] as a kernel for the vector path.
struct SliceLanes<'a, 'm, M: CrossSectionWorkspace> {
    indices: &'a SectionIndices<'m, M>,
    y: f64,
    z: &'a [f64; LANES],
}

impl<M: CrossSectionWorkspace> BlockKernel for SliceLanes<'_, '_, M> {
    type Output = [f64; LANES];

    #[inline(always)]
    fn run(&self) -> [f64; LANES] {
        let (m, mode) = (self.indices.mechanism, self.indices.mode);
        let batch = m.cross_section_jacobian_lanes(self.y, self.z, mode);
        let inverse = inverse_condition_number_3x3_lanes(&batch.jacobian);
        std::array::from_fn(|lane| {
            if batch.reachable[lane] {
                inverse[lane]
            } else {
                0.0
            }
        })
    }
}

/// The cross-section indices of one mechanism in one working mode: its cross-section is built
/// once and serves every index.
///
/// # Example
/// ```
/// use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
/// use pkm_workspace_indices::{Eta1Rule, SectionIndices};
/// let ratios = LinearDeltaRatios { l1_over_yr: 2.0, ya_over_yr: 0.0, zr_over_yr: 0.0, l2_over_l1: 0.63 };
/// let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 })?;
/// let indices = SectionIndices::new(&delta, LinearDeltaMode::PAPER);
/// let eta1 = indices.eta1(Eta1Rule::Quadrature(16))?;
/// let eta2 = indices.eta2()?;
/// assert!(eta1 > 0.0 && eta1 < 1.0 && eta2 > 0.0 && eta2 < 1.0);
/// // The paper's grid rule (eq. 4) agrees with the quadrature to its noise, ±2e-3.
/// assert!((indices.eta1(Eta1Rule::Grid)? - eta1).abs() < 2e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct SectionIndices<'m, M: CrossSectionWorkspace> {
    mechanism: &'m M,
    mode: M::WorkingMode,
    section: M::CrossSection,
}

impl<'m, M: CrossSectionWorkspace> SectionIndices<'m, M> {
    /// The indices of `mechanism` assembled in `mode`.
    pub fn new(mechanism: &'m M, mode: M::WorkingMode) -> Self {
        Self {
            mechanism,
            mode,
            section: mechanism.cross_section(),
        }
    }

    /// The cross-section $W$.
    pub fn section(&self) -> &M::CrossSection {
        &self.section
    }

    /// $1/\kappa(J)$ at the [`LANES`] points $(y, z_l)$ of one slice, 0 in a lane where $J$ is
    /// not defined; on the vector path of [`pkm_traits::run_block`] (the same bits on every
    /// path).
    pub fn inverse_condition_lanes(&self, y: f64, z: &[f64; LANES]) -> [f64; LANES] {
        run_block(&SliceLanes {
            indices: self,
            y,
            z,
        })
    }

    /// $\eta_1$ (eq. 1) by `rule`.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for an empty cross-section, a quadrature of no point or of
    /// more than [`GaussLegendre::MAX_ORDER`] points.
    pub fn eta1(&self, rule: Eta1Rule) -> Result<f64, IndexError> {
        match rule {
            Eta1Rule::Quadrature(n) => self.eta1_by_quadrature(&GaussLegendre::new(n)?),
            Eta1Rule::Grid => Ok(self.eta1_by_grid(&GridRule::default())?.mean),
        }
    }

    /// $\eta_1$ by a prebuilt Gauss–Legendre `rule` on every piece of $W$.
    ///
    /// # Errors
    /// As [`mean_by_quadrature_lanes`].
    pub fn eta1_by_quadrature(&self, rule: &GaussLegendre) -> Result<f64, IndexError> {
        mean_by_quadrature_lanes(
            &self.section,
            |y, z| self.inverse_condition_lanes(y, z),
            rule,
        )
    }

    /// $\eta_1$ by the uniform grid `rule` (eq. 4), with its node count, step and area
    /// estimate (eq. 5).
    ///
    /// # Errors
    /// As [`mean_by_grid_lanes`].
    pub fn eta1_by_grid(&self, rule: &GridRule) -> Result<GridMean, IndexError> {
        mean_by_grid_lanes(
            &self.section,
            |y, z| self.inverse_condition_lanes(y, z),
            rule,
        )
    }

    /// $\eta_2$ (eq. 2): $A_W$ over the area of the smallest rectangle that contains $W$ and
    /// the actuator points.
    ///
    /// # Errors
    /// As [`space_utilization`].
    pub fn eta2(&self) -> Result<f64, IndexError> {
        space_utilization(&self.section, &self.mechanism.actuator_points())
    }

    /// The exact area $A_W$.
    pub fn area(&self) -> f64 {
        self.section.area()
    }

    /// The value of `index`.
    ///
    /// # Errors
    /// As [`SectionIndices::eta1`] and [`SectionIndices::eta2`]; the area has none.
    pub fn value(&self, index: SectionIndex) -> Result<f64, IndexError> {
        match index {
            SectionIndex::Eta1(rule) => self.eta1(rule),
            SectionIndex::Eta2 => self.eta2(),
            SectionIndex::Area => Ok(self.area()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pkm_mechanisms::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
    use pkm_traits::{VectorPath, run_block_on};

    #[test]
    fn slice_lanes_give_the_same_bits_on_every_vector_path() {
        let ratios = LinearDeltaRatios {
            l1_over_yr: 2.0,
            ya_over_yr: 0.0,
            zr_over_yr: 0.0,
            l2_over_l1: 0.63,
        };
        let delta = LinearDelta::new(LinearDeltaDesign { ratios, yr: 1.0 }).unwrap();
        let indices = SectionIndices::new(&delta, LinearDeltaMode::PAPER);
        let mut inside = 0;
        for k in 0..40 {
            let y = -2.0 + 0.1 * f64::from(k);
            let z: [f64; LANES] =
                std::array::from_fn(|l| -3.0 + 0.37 * l as f64 + 0.01 * f64::from(k));
            let kernel = SliceLanes {
                indices: &indices,
                y,
                z: &z,
            };
            let baseline = run_block_on(VectorPath::Baseline, &kernel).map(f64::to_bits);
            for path in VectorPath::available() {
                assert_eq!(
                    run_block_on(path, &kernel).map(f64::to_bits),
                    baseline,
                    "{path:?}"
                );
            }
            inside += baseline
                .iter()
                .filter(|&&b| f64::from_bits(b) > 0.0)
                .count();
        }
        assert!(
            inside > 20,
            "{inside} lanes inside: the test would test nothing"
        );
    }
}
