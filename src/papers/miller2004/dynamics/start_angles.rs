//! `miller2004.nuwar.start_angles`: NUWAR's joint angles at the start point $(0, -0.2, -0.9)$.
//!
//! The reported $\theta_{1..3}$ are the canonical convention's (spec `miller-kinematics.md` §2:
//! $\varphi_1 = 300°$, $z_0 = -0.2928$ m, elbow out). The erratum evidence is the spec's wider
//! search, computed in the run ([`start_angle_search`](super::start_angle_search)): the best
//! least-squares fit of $z_0$ over every discrete convention of the leg model.

use super::start_angle_search::{AlphaValue, Convention, Search, Unknowns, fit_convention, search};
use super::{Robot, model};
use crate::papers::{Comparison, Context, Experiment, ExperimentError, Outcome, Paper, Source};
use nalgebra::Vector3;
use pkm_dynamics_hamilton::ExtendedModel;
use pkm_mechanisms::{ElbowMode, Placement};
use pkm_traits::InverseKinematics;

pub(super) const EXPERIMENT: Experiment = Experiment {
    id: "miller2004.nuwar.start_angles",
    paper: Paper::Miller2004,
    title: "NUWAR joint angles at the start of the pick-and-place cycle (§3.5)",
    run,
};

const PAPER_DEG: [f64; 3] = [70.95, 87.13, 51.65];
/// The printed angles carry two decimals.
const PRINT_PRECISION_DEG: f64 = 0.01;
/// The erratum needs the best one-unknown fit to miss by more than this many print precisions.
const EVIDENCE_MULTIPLE: f64 = 10.0;
/// Thresholds (deg, rms) at which the fits are counted.
const COUNT_THRESHOLDS_DEG: [f64; 4] = [0.05, 0.1, 0.3, 0.5];

fn start() -> Vector3<f64> {
    Vector3::new(0.0, -0.2, -0.9)
}

fn canonical_angles() -> Result<Vector3<f64>, ExperimentError> {
    let m: ExtendedModel = model(Robot::Nuwar, Placement::canonical())?;
    let th = m.mechanism().inverse_kinematics(&start(), ElbowMode::Out)?;
    Ok(th.map(f64::to_degrees))
}

/// The rows that report the search: its size, its best fit and how many fits come close.
fn search_rows(source: &Source, found: &Search, evidence: bool) -> Vec<Comparison> {
    let mut rows = vec![source.info("search_conventions", "", found.fits.len() as f64)];
    let Some(best) = found.best() else {
        return rows;
    };
    rows.push(
        source
            .check(
                "best_fit_rms_error",
                "deg",
                0.0,
                best.rms_deg,
                PRINT_PRECISION_DEG,
            )
            .erratum_if(evidence, "miller2004-start-angles")
            .with_note(format!(
                "least squares over z0 for each of {} conventions; best: {}",
                found.fits.len(),
                best.convention
            )),
    );
    rows.push(source.info("best_fit_max_error", "deg", best.max_deg));
    rows.push(source.info("best_fit_motor_plane_z", "m", best.motor_plane_z));
    rows.push(source.info(
        "best_fit_azimuth_motor_1",
        "deg",
        30.0 * best.convention.motor_1_step as f64,
    ));
    let canonical = fit_convention(
        &Convention::canonical(AlphaValue::Printed),
        PAPER_DEG,
        &start(),
    );
    rows.push(
        source
            .info("canonical_fit_rms_error", "deg", canonical.rms_deg)
            .with_note(format!(
                "the canonical convention with z0 fitted: z0 = {:.5} m",
                canonical.motor_plane_z
            )),
    );
    for threshold in COUNT_THRESHOLDS_DEG {
        let count = |quantity: &str, value: usize, note: &str| {
            source
                .info(&format!("{quantity}_{threshold}_deg"), "", value as f64)
                .with_note(note)
        };
        rows.push(count(
            "conventions_rms_within",
            found.count_within(threshold),
            "rms error of the z0 fit",
        ));
        rows.push(count(
            "conventions_max_within",
            found.count_all_within(threshold),
            "largest of the three errors at the z0 fit",
        ));
    }
    rows
}

/// Thresholds (deg, rms) at which the fits with a free zero are counted.
const FREE_ZERO_THRESHOLDS_DEG: [f64; 5] = [0.003, 0.01, 0.03, 0.05, 0.1];

/// The spec's two-unknown statistic: with $z_0$ and a common zero of the angles free, how many
/// conventions fit within each threshold (a count that grows linearly with the threshold is
/// what chance gives with one residual degree of freedom).
fn free_zero_rows(source: &Source, found: &Search) -> Vec<Comparison> {
    let note = "z0 and a common zero of the three angles fitted";
    let mut rows = vec![
        source
            .info("free_zero_search_conventions", "", found.fits.len() as f64)
            .with_note(note),
    ];
    if let Some(best) = found.best() {
        // The fitted zero: the mean error of the convention's angles at the fitted height.
        let zero = best
            .convention
            .printed_angles(&start(), best.motor_plane_z)
            .map_or(f64::NAN, |read| (read - Vector3::from(PAPER_DEG)).mean());
        rows.push(
            source
                .info("free_zero_best_fit_rms_error", "deg", best.rms_deg)
                .with_note(format!(
                    "{note}; best: {}, z0 = {:.5} m, zero {:.3} deg",
                    best.convention, best.motor_plane_z, zero
                )),
        );
    }
    for threshold in FREE_ZERO_THRESHOLDS_DEG {
        rows.push(
            source
                .info(
                    &format!("free_zero_conventions_rms_within_{threshold}_deg"),
                    "",
                    found.count_within(threshold) as f64,
                )
                .with_note(note),
        );
    }
    rows
}

fn run(_: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let source = Source::new(EXPERIMENT.id, Paper::Miller2004, "§3.5, start point");
    let canonical = canonical_angles()?;
    let found = search(PAPER_DEG, &start(), Unknowns::Height);
    let best_rms = found.best().map_or(f64::NAN, |b| b.rms_deg);
    // Evidence: no convention of the search fits the printed angles, with z0 free, to within
    // ten times their print precision. No reachable convention at all is no evidence.
    let evidence = best_rms.is_finite() && best_rms > EVIDENCE_MULTIPLE * PRINT_PRECISION_DEG;
    let mut comparisons: Vec<_> = (0..3)
        .map(|i| {
            source
                .check(
                    &format!("theta_{}", i + 1),
                    "deg",
                    PAPER_DEG[i],
                    canonical[i],
                    PRINT_PRECISION_DEG,
                )
                .erratum_if(evidence, "miller2004-start-angles")
                .with_note("canonical convention: z0 = -0.2928 m, motor 1 at 300°, elbow out")
        })
        .collect();
    comparisons.extend(search_rows(&source, &found, evidence));
    comparisons.extend(free_zero_rows(
        &source,
        &search(PAPER_DEG, &start(), Unknowns::HeightAndZero),
    ));
    Ok(Outcome {
        comparisons,
        ..Outcome::default()
    })
}
