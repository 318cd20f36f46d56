//! The exhaustive design search of Miller 2004, §2.2.3: a coarse 4-D grid at step 0.1, then
//! exhaustive local grids at 0.05 and 0.01 (Table 2 prints two decimals).

use super::evaluation::Utility;
use crate::papers::{Context, ExperimentError, Mode};
use pkm_optimizers::{
    GridAxis, GridSearch, LatticeLevel, Sense, lattice_refined_search, lattice_window,
};
use pkm_traits::Bounds;
use pkm_workspace_indices::{Eta1Rule, SectionIndexCache};

/// Step of the coarse grid.
const COARSE_STEP: f64 = 0.1;
/// The intermediate level: ±2 steps of 0.05 around the coarse optimum.
const MIDDLE: LatticeLevel = LatticeLevel {
    step: 0.05,
    half_width: 2,
};
/// The final level: ±3 steps of 0.01 (the 0.05 optimum is within ±0.025 of the 0.01 one),
/// re-centred while the optimum sits on the window's edge.
const FINE: LatticeLevel = LatticeLevel {
    step: 0.01,
    half_width: 3,
};

/// The η1 rules of one study: a cheaper one for the coarse passes, an accurate one at 0.01.
#[derive(Debug, Clone, Copy)]
pub struct Rules {
    /// Coarse grid and the 0.05 level.
    pub coarse: Eta1Rule,
    /// The 0.01 level.
    pub fine: Eta1Rule,
}

impl Rules {
    /// Gauss–Legendre with 16 then 24 points (full), 8 then 16 (quick).
    pub fn for_mode(mode: Mode) -> Self {
        Self {
            coarse: Eta1Rule::Quadrature(mode.pick(8, 16)),
            fine: Eta1Rule::Quadrature(mode.pick(16, 24)),
        }
    }

    /// The same coarse rule, the paper's grid (eq. 4, $N_a > 5000$) at 0.01.
    pub fn with_paper_grid(self) -> Self {
        Self {
            fine: Eta1Rule::Grid,
            ..self
        }
    }
}

/// An optimum on the 0.01 lattice with its indices $(\eta_1, \eta_2, \eta)$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Optimum {
    /// `[L1/YR, YA/YR, ZR/YR, L2/L1]`.
    pub design: [f64; 4],
    /// $(\eta_1, \eta_2, \eta)$ by the fine rule ($\eta_1$ NaN when $w_1 = 0$).
    pub indices: [f64; 3],
}

/// The box `[L1/YR, YA/YR, ZR/YR, L2/L1]` of a search; equal bounds fix a variable.
///
/// # Errors
/// [`ExperimentError::Objective`] for a range that is empty or not finite.
pub fn search_box(ranges: [(f64, f64); 4]) -> Result<[Bounds; 4], ExperimentError> {
    let [a, b, c, d] = ranges;
    Ok([
        Bounds::new(a.0, a.1)?,
        Bounds::new(b.0, b.1)?,
        Bounds::new(c.0, c.1)?,
        Bounds::new(d.0, d.1)?,
    ])
}

/// Maximises $w_1\eta_1 + w_2\eta_2$ over `bounds` (coarse 0.1, then 0.05, then 0.01).
///
/// # Errors
/// [`ExperimentError::Optimize`] when no design is feasible or the run is cancelled.
pub fn optimise(
    (w1, w2): (f64, f64),
    bounds: [Bounds; 4],
    rules: Rules,
    cache: &SectionIndexCache,
    context: &Context<'_>,
) -> Result<Optimum, ExperimentError> {
    let utility = |rule| Utility {
        w1,
        w2,
        rule,
        bounds,
        cache,
    };
    let coarse = bounds
        .iter()
        .map(|b| GridAxis::with_step(b.lower(), b.upper(), COARSE_STEP))
        .collect::<Result<Vec<_>, _>>()?;
    let coarse_utility = utility(rules.coarse);
    let coarse = GridSearch::new(coarse)?;
    let middle = lattice_refined_search(
        &coarse_utility,
        Sense::Maximise,
        &coarse,
        &[MIDDLE],
        context.progress,
    )?;
    let fine_utility = utility(rules.fine);
    let window = GridSearch::new(lattice_window(&bounds, coarse.axes(), &middle.best, &FINE)?)?;
    let fine = lattice_refined_search(
        &fine_utility,
        Sense::Maximise,
        &window,
        &[FINE],
        context.progress,
    )?;
    let design: [f64; 4] = std::array::from_fn(|k| {
        if bounds[k].width() > 0.0 {
            on_lattice(fine.best[k])
        } else {
            fine.best[k]
        }
    });
    Ok(Optimum {
        design,
        indices: fine_utility.indices(&design)?,
    })
}

/// Rounds to the 0.01 lattice (removes the round-off of `lower + i·step`).
fn on_lattice(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}
