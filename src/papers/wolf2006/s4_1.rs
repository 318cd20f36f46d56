//! §4.1: the pose $(n, \alpha, p)$ of a given platform ($x = (12, 8, 30°, 8°)$) that maximises
//! $F$ (eq. 14) for the twists with λ = 1 and λ = 0.

use super::pose_report::{
    PaperPose, maximise, objective_rows, optimal_pose_drawing, pose_problem, pose_rows,
    section_4_1_twist,
};
use crate::papers::{Context, ExperimentError, Figure, Outcome, Paper, Source, Verdict};
use pkm_mechanisms::{StewartGough, WrenchSystem, presets};

/// The paper's printed λ = 1 optimum: n = z, α = −13.5°, p = (−10, −10, 50) cm.
const PAPER_POSE_LAMBDA1: PaperPose = PaperPose {
    n: [0.0, 0.0, 1.0],
    alpha_deg: -13.5,
    p: [-10.0, -10.0, 50.0],
};

/// The paper's printed λ = 0 optimum (n not a unit vector).
const PAPER_POSE_LAMBDA0: PaperPose = PaperPose {
    n: [0.3e-3, 0.01, 0.74],
    alpha_deg: -6.2,
    p: [-10.0, -10.0, 50.0],
};

/// The paper's λ = 0 maximum.
const PAPER_F_LAMBDA0: f64 = 284.4;

/// Spec §3.2's model-free lower bound on F for the λ = 0 twist at the paper's λ = 1 pose
/// (triangle inequality with the largest leg component of χ1 − χ0).
const LAMBDA0_BOUND_AT_LAMBDA1_POSE: f64 = 358.3;

/// λ = 1: F(paper pose) reproduces to about 1 %.
pub(super) fn run_lambda1(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    run(
        context,
        "wolf2006.s4_1.lambda1",
        (1.0, "Fig. 4"),
        &PAPER_POSE_LAMBDA1,
        400.3,
    )
}

/// λ = 0: 284.4 is below F at the λ = 1 pose, an erratum.
pub(super) fn run_lambda0(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    run(
        context,
        "wolf2006.s4_1.lambda0",
        (0.0, "Fig. 5"),
        &PAPER_POSE_LAMBDA0,
        PAPER_F_LAMBDA0,
    )
}

fn run(
    context: &Context<'_>,
    id: &str,
    (lambda, figure): (f64, &str),
    paper: &PaperPose,
    paper_f: f64,
) -> Result<Outcome, ExperimentError> {
    let source = Source::new(id, Paper::WolfShoham, "§4.1");
    let twist = section_4_1_twist(lambda);
    let mechanism = StewartGough::new(presets::wolf_shoham_stewart_s4_1())?;
    let f_paper_pose = mechanism.task_objective(&paper.isometry()?, &twist)?;
    context.progress.check()?;
    let problem = pose_problem(presets::wolf_shoham_stewart_s4_1(), twist)?;
    let optimum = maximise(&problem, context.mode, context.progress)?;
    let (optimal, pose) = problem.evaluate(&optimum.design)?;
    let note = "F at the paper's printed pose (n normalised), same-pattern layout";
    let [mut f_row, mut optimum_row] =
        objective_rows(&source, paper_f, (f_paper_pose, note), optimum.value);
    let mut evidence = Vec::new();
    if lambda == 0.0 {
        // Evidence of the erratum (spec §3.2): the λ = 0 twist at the paper's own λ = 1 pose
        // already gives more than the printed λ = 0 maximum, so 284.4 cannot be the maximum
        // over the same box.
        let f0_at_p1 = mechanism.task_objective(&PAPER_POSE_LAMBDA1.isometry()?, &twist)?;
        let above_print = f0_at_p1 > PAPER_F_LAMBDA0;
        f_row = f_row.erratum_if(above_print, "wolf-s4-1-lambda0");
        optimum_row = optimum_row.erratum_if(above_print, "wolf-s4-1-lambda0");
        // A lower bound, not a printed value: the row fails when the bound is violated.
        let mut bound_row = source
            .info("F_lambda0_at_lambda1_pose", "cm^2/s^2", f0_at_p1)
            .with_note(format!(
                "λ = 0 twist at the paper's λ = 1 pose; must exceed spec §3.2's bound \
                 F0(P1) >= {LAMBDA0_BOUND_AT_LAMBDA1_POSE} and the printed λ = 0 maximum \
                 {PAPER_F_LAMBDA0} (the erratum's evidence)"
            ));
        if f0_at_p1.is_nan() || f0_at_p1 < LAMBDA0_BOUND_AT_LAMBDA1_POSE {
            bound_row.verdict = Verdict::Fail;
        }
        evidence.push(bound_row);
    }
    let mut comparisons = vec![f_row, optimum_row];
    comparisons.extend(evidence);
    comparisons.extend(pose_rows(&source, &pose, paper, &optimum));
    let drawing = optimal_pose_drawing(&optimal, &pose, &twist, lambda)?;
    let name = format!("{}_optimal_pose", figure.replace(". ", "").to_lowercase());
    let title = format!(
        "{figure}: pkm's optimal platform pose for the λ = {lambda} twist (F = {:.1}), task axis",
        optimum.value
    );
    Ok(Outcome {
        comparisons,
        figures: vec![Figure::robot(name, title, drawing, "cm")],
        ..Outcome::default()
    })
}
