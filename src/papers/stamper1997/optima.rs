//! The three optimisations of sec. 5: maximum volume (free legs, symmetric legs) and maximum
//! global condition index, each by the augmented Lagrangian from seeded multistarts on common
//! random numbers, then re-evaluated with the paper's design on one fresh point set.

use super::problem::{Criterion, StamperProblem, design, estimate};
use crate::papers::{Comparison, Context, ExperimentError, Mode, Outcome, Paper, Source};
use pkm_optimizers::{
    AugmentedLagrangianSettings, OptimizeError, augmented_lagrangian, run_multistart,
    uniform_start_points,
};
use pkm_traits::Bounds;
use pkm_workspace_indices::{HemisphereEstimate, Sampler};

/// One optimisation study and the design the paper reports.
pub(super) struct Study {
    pub(super) id: &'static str,
    pub(super) location: &'static str,
    pub(super) criterion: Criterion,
    /// `None`: legs free in $[5, 355]$; `Some((φ2, φ3))`: legs fixed.
    pub(super) legs: Option<(f64, f64)>,
    /// Paper's optimum $(a, b, d+e, c-r, φ_2, φ_3)$.
    pub(super) paper: [f64; 6],
    /// Tolerances on the six design variables (full mode).
    pub(super) tolerance: [f64; 6],
    /// Heading in `docs/conventions.md` with the evidence where the optimum differs.
    pub(super) anchor: &'static str,
}

const NAMES: [&str; 6] = ["a", "b", "d+e", "c-r", "phi_2", "phi_3"];
const UNITS: [&str; 6] = ["R", "R", "R", "R", "deg", "deg"];

fn bounds(legs: Option<(f64, f64)>) -> Result<[Bounds; 6], ExperimentError> {
    let (p2, p3) = match legs {
        Some((p2, p3)) => (Bounds::new(p2, p2)?, Bounds::new(p3, p3)?),
        None => (Bounds::new(5.0, 350.0)?, Bounds::new(10.0, 355.0)?),
    };
    Ok([
        Bounds::new(0.02, 1.0)?,
        Bounds::new(0.02, 1.0)?,
        Bounds::new(0.0, 0.5)?,
        Bounds::new(0.0, 0.3)?,
        p2,
        p3,
    ])
}

/// Runs `study`: the optimum, its objective values and the paper design's on the same points.
///
/// # Errors
/// A failed optimisation (no start reached a feasible design) or evaluation.
pub(super) fn run(study: &Study, ctx: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let quick = ctx.mode == Mode::Quick;
    let crn =
        Sampler::MonteCarlo { seed: 999 }.unit_hemisphere_points(ctx.mode.pick(3_000, 30_000))?;
    let problem = StamperProblem {
        bounds: bounds(study.legs)?,
        criterion: match study.criterion {
            Criterion::Volume { ngrid } => Criterion::Volume {
                ngrid: if quick { ngrid / 4 } else { ngrid },
            },
            Criterion::Gci => Criterion::Gci,
        },
        points: &crn,
    };
    let settings = AugmentedLagrangianSettings {
        fd_step: 1e-3,
        tolerance: 1e-6,
        max_outer: ctx.mode.pick(6, 15),
        max_inner: ctx.mode.pick(30, 150),
        ..Default::default()
    };
    let starts = uniform_start_points(&problem.bounds, ctx.mode.pick(2, 8), 2024);
    ctx.progress.check()?;
    let best = run_multistart(&starts, |s| augmented_lagrangian(&problem, s, &settings))
        .into_iter()
        .filter_map(Result::ok)
        .min_by(|a, b| a.value.total_cmp(&b.value))
        .ok_or_else(|| OptimizeError::NoFeasibleDesign {
            evaluations: starts.len(),
            last_reason: "no start converged to a feasible design".into(),
        })?;
    ctx.progress.check()?;
    let fresh =
        Sampler::MonteCarlo { seed: 101 }.unit_hemisphere_points(ctx.mode.pick(20_000, 200_000))?;
    let ours = estimate(&design(&best.design)?, &fresh)?;
    let paper = estimate(&design(&study.paper)?, &fresh)?;
    let source = Source::new(study.id, Paper::Stamper1997, study.location);
    let widen = if quick { 4.0 } else { 1.0 };
    let mut rows: Vec<Comparison> = (0..6)
        .map(|k| {
            source
                .check(
                    NAMES[k],
                    UNITS[k],
                    study.paper[k],
                    best.design[k],
                    widen * study.tolerance[k],
                )
                .erratum(study.anchor)
        })
        .collect();
    rows.extend(estimate_rows(&source, "", &ours));
    rows.extend(estimate_rows(&source, "paper_design_", &paper));
    if quick {
        for row in &mut rows {
            *row = row
                .clone()
                .with_note("quick mode: 3,000 CRN points, 2 starts, tolerances x4");
        }
    }
    Ok(Outcome {
        comparisons: rows,
        ..Outcome::default()
    })
}

fn estimate_rows(source: &Source, prefix: &str, e: &HemisphereEstimate) -> Vec<Comparison> {
    [
        ("volume", e.volume),
        ("volume_se", e.volume_se),
        ("gci", e.gci),
        ("gci_se", e.gci_se),
    ]
    .into_iter()
    .map(|(q, v)| source.info(&format!("{prefix}{q}"), "R^3", v))
    .collect()
}
