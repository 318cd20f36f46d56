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

use super::{Experiment, Paper};

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
