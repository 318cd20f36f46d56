//! §4.3: pose and the upper-platform joint angle (the paper's "x3 in Fig. 3"; base angle 30°)
//! maximising $F$ for the λ = 1 twist.

use super::pose_report::{
    PaperPose, maximise, objective_rows, optimal_pose_drawing, pose_problem, pose_rows,
    section_4_1_twist,
};
use crate::papers::{Context, ExperimentError, Figure, Outcome, Paper, Source};
use pkm_mechanisms::{StewartDesign, StewartDesignVariable, StewartGough, WrenchSystem, presets};
use pkm_traits::Bounds;

/// Runs §4.3.
pub(super) fn run(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
    let source = Source::new("wolf2006.s4_3", Paper::WolfShoham, "§4.3");
    let twist = section_4_1_twist(1.0);
    let paper = PaperPose {
        n: [1.0, 0.0, 0.0],
        alpha_deg: 4.3,
        p: [-10.0, -10.0, 50.0],
    };
    let paper_angle: f64 = 21.1;
    let at_paper = StewartGough::new(StewartDesign {
        platform_separation: paper_angle.to_radians(),
        ..presets::wolf_shoham_stewart_s4_1()
    })?;
    let f_paper_pose = at_paper.task_objective(&paper.isometry()?, &twist)?;
    context.progress.check()?;
    let problem = pose_problem(presets::wolf_shoham_stewart_s4_1(), twist)?.free_design(
        StewartDesignVariable::PlatformSeparationDeg,
        Bounds::new(0.0, 30.0)?,
    );
    let optimum = maximise(&problem, context.mode, context.progress)?;
    let (mechanism, pose) = problem.evaluate(&optimum.design)?;
    let paper_f = 524.7;
    let note = "F at the paper's printed pose and upper angle 21.1 deg";
    // Evidence: with the upper angle free, the model's maximum over the box (which contains the
    // paper's pose and angle) stays more than 2 % below 524.7, so the paper's value is out of
    // the model's reach.
    let out_of_reach = optimum.value < 0.98 * paper_f;
    let [f_row, optimum_row] =
        objective_rows(&source, paper_f, (f_paper_pose, note), optimum.value)
            .map(|row| row.erratum_if(out_of_reach, "wolf-s4-3"));
    let mut comparisons = vec![
        f_row,
        optimum_row,
        source
            .info(
                "x3",
                "deg",
                mechanism.design().platform_separation.to_degrees(),
            )
            .with_note("upper-platform joint separation at pkm's optimum; paper prints 21.1"),
    ];
    comparisons.extend(pose_rows(&source, &pose, &paper, &optimum));
    let title = format!(
        "Fig. 8: pkm's optimal pose and upper joint angle x3 = {:.1}° (F = {:.1}), task axis",
        mechanism.design().platform_separation.to_degrees(),
        optimum.value
    );
    let drawing = optimal_pose_drawing(&mechanism, &pose, &twist, 1.0)?;
    Ok(Outcome {
        comparisons,
        figures: vec![Figure::robot("fig8_optimal_pose", title, drawing, "cm")],
        ..Outcome::default()
    })
}
