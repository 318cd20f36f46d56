//! Miller 2004, §2.2: the Linear Delta's 4-D exhaustive design search (Table 2), the
//! sensitivity of its optimum to the weights (§2.2.4) and Fig. 6.
//!
//! Conventions (reconstructed geometry, Jacobian, η1 rules) are in `docs/conventions.md`,
//! section "Miller 2004 §2.2: Linear Delta".

pub mod evaluation;
pub mod figures;
pub mod search;
pub mod sensitivity;
pub mod table2;

use crate::papers::{Context, Experiment, ExperimentError, Outcome, Paper};
use pkm_workspace_indices::SectionIndexCache;

/// Table 2 (four rows, Fig. 6) on one cache: rows 3 and 4 and the figure search the same
/// lattices with the same rules, so each node's indices are computed once.
fn run_table2(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let cache = SectionIndexCache::new();
    let mut comparisons = table2::row1(context, &cache)?;
    comparisons.extend(table2::row2(context, &cache)?);
    comparisons.extend(table2::row3(context, &cache)?);
    let (row4, optimum) = table2::row4(context, &cache)?;
    comparisons.extend(row4);
    let mut figures = figures::figure6(&optimum, context.mode, &cache)?;
    figures.push(figures::cross_section_map(&optimum.design, context.mode)?);
    Ok(Outcome {
        comparisons,
        tables: Vec::new(),
        figures,
    })
}

/// The sensitivity sweeps on one cache: every weighting searches the same lattices.
fn run_sensitivity(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let cache = SectionIndexCache::new();
    let mut comparisons = sensitivity::w1_sweep(context, &cache)?;
    comparisons.extend(sensitivity::w2_sweep(context, &cache)?);
    Ok(Outcome {
        comparisons,
        ..Outcome::default()
    })
}

/// The experiments of §2.2.
pub fn experiments() -> Vec<Experiment> {
    vec![
        Experiment {
            id: "miller2004.linear_delta.table2",
            paper: Paper::Miller2004,
            title: "Linear Delta: Table 2 (four weightings), indices at the optima, Fig. 6",
            run: run_table2,
        },
        Experiment {
            id: "miller2004.linear_delta.sensitivity",
            paper: Paper::Miller2004,
            title: "Linear Delta: sensitivity of the optimum to w1 and w2 (§2.2.4)",
            run: run_sensitivity,
        },
    ]
}
