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
    pose_report::maximise(problem, mode, &pkm_traits::Silent)
}

/// Eq. 15 as printed, $Q = \sum_i w_i q_i / n$ for $n$ tasks: the weighted mean of
/// [`pkm_optimizers::weighted_combination`] times $\sum_i w_i / n$, so a mean only when the
/// weights sum to $n$ (as with the equal unit weights of §4.2, where both readings agree).
///
/// # Errors
/// As [`pkm_optimizers::weighted_combination`], and
/// [`OptimizeError::Invalid`](pkm_optimizers::OptimizeError::Invalid) when the printed sum
/// overflows.
///
/// # Example
/// ```
/// use pkm::papers::wolf2006::eq15_as_printed;
/// let q = [vec![0.0, 2.0], vec![4.0, 6.0]];
/// assert_eq!(eq15_as_printed(&q, &[1.0, 3.0]).unwrap(), vec![6.0, 10.0]);
/// assert_eq!(eq15_as_printed(&q, &[1.0, 1.0]).unwrap(), vec![2.0, 4.0]);
/// ```
pub fn eq15_as_printed(
    optima: &[Vec<f64>],
    weights: &[f64],
) -> Result<Vec<f64>, pkm_optimizers::OptimizeError> {
    let mean = pkm_optimizers::weighted_combination(optima, weights)?;
    // Σ w_i / n summed as Σ (w_i / n), which cannot overflow for finite weights.
    let n = optima.len() as f64;
    let scale: f64 = weights.iter().map(|w| w / n).sum();
    let printed: Vec<f64> = mean.iter().map(|m| m * scale).collect();
    match printed.iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(pkm_traits::InvalidInput::new(
            "weighted sum",
            value,
            "must be representable (it overflows)",
        )
        .into()),
        None => Ok(printed),
    }
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
