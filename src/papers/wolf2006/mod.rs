//! Wolf & Shoham (`003_788af3b033109bd5.txt`): screw theory and task-based design of the
//! Stewart–Gough platform and the 3-UPU.
//!
//! Conventions (joint layout, row convention, corrected twists) and the errata are in
//! `docs/conventions.md`, section "Wolf & Shoham"; they follow `shared/spec/wolf-shoham.md`.

mod pose_report;
mod s4_1;
mod s4_2;
mod s4_3;
mod s4_4;
pub mod screw_checks;

use super::{Experiment, ExperimentError, Mode, Paper};
use pkm_mechanisms::StewartTaskProblem;
use pkm_optimizers::LocalOptimum;

/// The §4.1 pose problem exactly as `wolf2006.s4_1.*` builds it: platform
/// $x = (12, 8, 30°, 8°)$, the task twist with pitch `lambda` (1 or 0), $p$ in the paper's box and
/// $|\alpha| \le 30°$. Free variables: $(p_x, p_y, p_z, u_x, u_y, u_z)$, with $u$ the cube
/// coordinates of the rotation vector $w = 30° \cdot \mathrm{ball}(u)$. Public for the benches.
///
/// # Errors
/// [`ExperimentError`] when the problem cannot be built (it always can).
pub fn section_4_1_problem(lambda: f64) -> Result<StewartTaskProblem, ExperimentError> {
    pose_report::pose_problem(
        pkm_mechanisms::presets::wolf_shoham_stewart_s4_1(),
        pose_report::section_4_1_twist(lambda),
    )
}

/// The seeded multistart maximisation the §4.1 and §4.3 experiments run (20 starts in quick
/// mode, 64 in full). Public for the benches.
///
/// # Errors
/// [`ExperimentError`] when every start fails.
pub fn maximise_pose(
    problem: &StewartTaskProblem,
    mode: Mode,
) -> Result<LocalOptimum, ExperimentError> {
    pose_report::maximise(problem, mode)
}

/// The experiments of this paper.
pub fn experiments() -> Vec<Experiment> {
    vec![
        screw_checks::experiment(),
        Experiment {
            id: "wolf2006.s4_1.lambda1",
            paper: Paper::WolfShoham,
            title: "§4.1: platform pose maximising F for the λ = 1 twist (400.3)",
            run: s4_1::run_lambda1,
        },
        Experiment {
            id: "wolf2006.s4_1.lambda0",
            paper: Paper::WolfShoham,
            title: "§4.1: platform pose maximising F for the λ = 0 twist (284.4)",
            run: s4_1::run_lambda0,
        },
        Experiment {
            id: "wolf2006.s4_2",
            paper: Paper::WolfShoham,
            title: "§4.2: geometry (x1..x4) for the translation/rotation task pair, eq. 15",
            run: s4_2::run,
        },
        Experiment {
            id: "wolf2006.s4_3",
            paper: Paper::WolfShoham,
            title: "§4.3: pose and upper joint angle maximising F (524.7)",
            run: s4_3::run,
        },
        Experiment {
            id: "wolf2006.s4_4.min",
            paper: Paper::WolfShoham,
            title: "§4.4: 3-UPU upper U-joint axes minimising F (Park's singular design, F = 0)",
            run: s4_4::run_min,
        },
        Experiment {
            id: "wolf2006.s4_4.max",
            paper: Paper::WolfShoham,
            title: "§4.4: 3-UPU upper U-joint axes maximising F (457.5)",
            run: s4_4::run_max,
        },
    ]
}
