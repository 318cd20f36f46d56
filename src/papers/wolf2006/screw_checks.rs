//! `wolf2006.s2`: the screw theory of Wolf & Shoham §2 on the paper's own data.
//!
//! - The §4.1 twists χ (eq. 3, 12) from the printed axis $\hat k = [2, 2, 1]$, point
//!   $k_0 = [2, 3, 6]$ cm and pitch λ = 1 and λ = 0, entry by entry against the printed χ. The
//!   printed 4th entry for λ = 1 is an erratum (`docs/conventions.md#wolf-shoham-twist-lambda-1`).
//! - On the six leg lines of the §4.1 Stewart–Gough platform at the paper's pose (layout of
//!   `docs/conventions.md`, Wolf & Shoham): Klein's identity (eq. 2), eq. 5 against eq. 6, and
//!   $L_i \wedge \chi$ against the leg rate $s_i \cdot (\bar x + x \times a_i)$.

use nalgebra::{Vector3, Vector6};
use pkm_screw_theory::{
    PluckerLine, ScrewAxis, Twist, Wrench, line_set_rank, reciprocal_product,
    reciprocal_product_geometric, rotation_from_axis_angle,
};

use crate::papers::{Comparison, Context, Experiment, ExperimentError, Outcome, Paper, Source};

/// Experiment id.
pub const ID: &str = "wolf2006.s2";

/// Absolute tolerance on a χ entry: the paper prints fractions; 1e-3 admits any 3-decimal
/// rounding of them.
const CHI_TOLERANCE: f64 = 1e-3;

/// Absolute tolerance on the identities (eq. 2, eq. 5 = eq. 6, leg rate) on the six legs:
/// round-off on lengths of about 50 cm is near 1e-13.
const IDENTITY_TOLERANCE: f64 = 1e-9;

/// The experiment.
pub fn experiment() -> Experiment {
    Experiment {
        id: ID,
        paper: Paper::WolfShoham,
        title: "§2 screw theory on the §4.1 data: twists χ (eq. 3/12), Klein (eq. 2), eq. 5 = eq. 6",
        run,
    }
}

/// The §4.1 screw axis of the task: $\hat k = [2, 2, 1]$ through $k_0 = [2, 3, 6]$ cm.
fn task_axis(pitch: f64) -> Result<ScrewAxis, ExperimentError> {
    Ok(ScrewAxis::new(
        &Vector3::new(2.0, 2.0, 1.0),
        &Vector3::new(2.0, 3.0, 6.0),
        pitch,
    )?)
}

fn run(_context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let mut comparisons = twist_rows(
        1.0,
        &[2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0, -1.0 / 3.0, 4.0, -1.0 / 3.0],
    )?;
    comparisons.extend(twist_rows(
        0.0,
        &[
            2.0 / 3.0,
            2.0 / 3.0,
            1.0 / 3.0,
            -3.0,
            10.0 / 3.0,
            -2.0 / 3.0,
        ],
    )?);
    comparisons.extend(leg_rows()?);
    Ok(Outcome {
        comparisons,
        ..Outcome::default()
    })
}

/// χ for pitch `lambda` (unit intensity), entry by entry against the printed χ.
fn twist_rows(lambda: f64, printed: &[f64; 6]) -> Result<Vec<Comparison>, ExperimentError> {
    let name = if lambda > 0.0 { "lambda1" } else { "lambda0" };
    let source = Source::new(&format!("{ID}.chi_{name}"), Paper::WolfShoham, "§4.1");
    let chi = Twist::on_axis(&task_axis(lambda)?, 1.0);
    let mut rows: Vec<Comparison> = chi
        .as_vector()
        .iter()
        .zip(printed)
        .enumerate()
        .map(|(k, (&value, &paper))| {
            let row = source.check(&format!("chi_{}", k + 1), "", paper, value, CHI_TOLERANCE);
            if lambda > 0.0 && k == 3 {
                row.erratum("wolf-shoham-twist-lambda-1").with_note(
                    "s0 × s + λ s gives −3 + 2/3 = −7/3; the print repeats the 6th entry −1/3",
                )
            } else {
                row.with_note("χ = [s; s0 × s + λ s], s = k/|k| (eq. 3, 12)")
            }
        })
        .collect();
    rows.push(source.check("pitch", "cm", lambda, chi.pitch()?, 1e-12));
    Ok(rows)
}

/// The six leg lines of the §4.1 platform (x1 = 12 cm, x2 = 8 cm, x3 = 30°, x4 = 8°) at the
/// paper's pose n = z, α = −13.5°, p = (−10, −10, 50) cm, same-pattern layout.
fn leg_lines() -> Result<Vec<(PluckerLine, Vector3<f64>)>, ExperimentError> {
    let rotation = rotation_from_axis_angle(&Vector3::z(), (-13.5_f64).to_radians())?;
    let p = Vector3::new(-10.0, -10.0, 50.0);
    let joint = |radius: f64, separation_deg: f64, k: usize| {
        let side = if k.is_multiple_of(2) { -1.0 } else { 1.0 };
        let t = (120.0 * (k / 2) as f64 + side * separation_deg / 2.0).to_radians();
        Vector3::new(radius * t.cos(), radius * t.sin(), 0.0)
    };
    (0..6)
        .map(|k| {
            let b = joint(12.0, 30.0, k);
            let a = p + rotation * joint(8.0, 8.0, k);
            Ok((PluckerLine::from_points(&b, &a)?.normalized(), a))
        })
        .collect()
}

/// Klein's identity, eq. 5 vs eq. 6 and the leg-rate identity on the six legs (λ = 1 task).
fn leg_rows() -> Result<Vec<Comparison>, ExperimentError> {
    let source = Source::new(
        &format!("{ID}.legs"),
        Paper::WolfShoham,
        "§2, eq. 2, 5, 6 on §4.1",
    );
    let axis = task_axis(1.0)?;
    let chi = Twist::on_axis(&axis, 1.0);
    let legs = leg_lines()?;
    let (mut klein, mut eq5_eq6, mut leg_rate) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (line, a) in &legs {
        klein = klein.max(line.klein_form().abs());
        let product = reciprocal_product(&Wrench::along_line(line, 1.0), &chi);
        let leg_axis = ScrewAxis::new(&line.direction(), a, 0.0)?;
        eq5_eq6 =
            eq5_eq6.max((product - reciprocal_product_geometric(&axis, 1.0, &leg_axis, 1.0)).abs());
        leg_rate = leg_rate.max((product - line.direction().dot(&chi.velocity_at(a))).abs());
    }
    let rows: Vec<Vector6<f64>> = legs.iter().map(|(line, _)| line.to_vector()).collect();
    Ok(vec![
        source
            .check("max_abs_klein_form", "cm", 0.0, klein, IDENTITY_TOLERANCE)
            .with_note("eq. 2: K(L) = 0 for every line"),
        source
            .check(
                "max_abs_eq5_minus_eq6",
                "cm/s",
                0.0,
                eq5_eq6,
                IDENTITY_TOLERANCE,
            )
            .with_note("eq. 5 (algebraic) and eq. 6 (geometric) reciprocal products agree"),
        source
            .check(
                "max_abs_product_minus_leg_rate",
                "cm/s",
                0.0,
                leg_rate,
                IDENTITY_TOLERANCE,
            )
            .with_note("L ∧ χ is the leg rate s · (x̄ + x × a)"),
        source
            .check(
                "line_set_rank",
                "",
                6.0,
                line_set_rank(&rows, 1e-9)? as f64,
                0.0,
            )
            .with_note("six legs in general position at the §4.1 pose span all wrenches"),
    ])
}
