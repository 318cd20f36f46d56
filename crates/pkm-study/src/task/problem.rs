//! The optimisation problems of a task study, from its tables: the Stewart–Gough platform
//! through the library's [`StewartTaskProblem`] (one per twist, combined by
//! [`pkm_optimizers::WeightedSum`]), and the 3-UPU through the library's [`UpuProblem`] over any
//! subset of its 14 variables (radii, U-joint tilts, pose).

use super::schema::{Goal, PoseSpec};
use crate::schema::mechanism::{StewartSpec, ThreeUpuSpec, stewart_layout};
use crate::schema::units::Degrees;
use crate::{KeyPath, StudyError};
use nalgebra::Vector3;
use pkm_design_problems::upu::{UpuGoal, UpuProblem};
use pkm_mechanisms::{StewartDesign, StewartDesignVariable, StewartTaskProblem};
use pkm_screw_theory::Twist;
use pkm_traits::{Bounds, DesignError};

/// The library's design variables behind the first four names of [`STEWART_VARIABLES`], in
/// the study's units (lengths, and separations in degrees).
const STEWART_DESIGN_VARIABLES: [StewartDesignVariable; 4] = [
    StewartDesignVariable::BaseRadius,
    StewartDesignVariable::PlatformRadius,
    StewartDesignVariable::BaseSeparationDeg,
    StewartDesignVariable::PlatformSeparationDeg,
];

/// The Stewart–Gough variables a task may optimise, in [`StewartTaskProblem`] slot order.
pub const STEWART_VARIABLES: [&str; 7] = [
    "base_radius",
    "platform_radius",
    "base_separation_deg",
    "platform_separation_deg",
    "x",
    "y",
    "z",
];

/// The library problem of one twist: the nominal design and pose of the study with the
/// variables `free` (indices into [`STEWART_VARIABLES`]) and, with `max_angle` (radians), the
/// orientation freed.
///
/// # Errors
/// The library's reason for an invalid design or pose (at `mechanism`), position range (at
/// `task.variables.<name>`) or angle (at `task.max_angle_deg`).
pub fn stewart_problem(
    spec: &StewartSpec,
    pose: &PoseSpec,
    free: &[(usize, Bounds)],
    max_angle: Option<f64>,
    twist: Twist,
) -> Result<StewartTaskProblem, StudyError> {
    let design = StewartDesign {
        layout: stewart_layout(spec),
        ..StewartDesign::from_deg(
            spec.base_radius.0,
            spec.platform_radius.0,
            spec.base_separation_deg.0,
            spec.platform_separation_deg.0,
        )
    };
    let position = Vector3::from(pose.position.map(|x| x.0));
    let rotation = Vector3::from(pose.rotation_deg.map(Degrees::radians));
    let refused = |path: KeyPath| move |e: DesignError| StudyError::invalid(path, e.to_string());
    let mut problem = StewartTaskProblem::new(design, position, rotation, twist)
        .map_err(refused(KeyPath::parse("mechanism")))?;
    for &(k, bounds) in free {
        problem = match STEWART_DESIGN_VARIABLES.get(k) {
            Some(&variable) => problem.free_design(variable, bounds),
            None => {
                let path = KeyPath::parse("task.variables").field(STEWART_VARIABLES[k]);
                problem
                    .free_position(k - 4, bounds)
                    .map_err(refused(path))?
            }
        };
    }
    if let Some(angle) = max_angle {
        problem = problem
            .free_rotation(angle)
            .map_err(refused(KeyPath::parse("task.max_angle_deg")))?;
    }
    Ok(problem)
}

/// The library's 3-UPU problem ([`UpuProblem`]) of the study for `goal` and the weighted
/// twists, with the variables `free` (indices into [`UPU_VARIABLES`](pkm_design_problems::upu::UPU_VARIABLES)), the others at the
/// study's design and pose.
pub fn upu_problem(
    spec: &ThreeUpuSpec,
    pose: &PoseSpec,
    free: &[(usize, Bounds)],
    goal: Goal,
    twists: &[(f64, Twist)],
) -> UpuProblem {
    let [x, y, z] = pose.position.map(|v| v.0);
    let [rx, ry, rz] = pose.rotation_deg.map(|v| v.0);
    let [b1, g1, b2, g2, b3, g3] = spec.tilts_deg();
    let nominal = [
        spec.base_radius.0,
        spec.platform_radius.0,
        b1,
        g1,
        b2,
        g2,
        b3,
        g3,
        x,
        y,
        z,
        rx,
        ry,
        rz,
    ];
    let goal = match goal {
        Goal::Maximise | Goal::Minimise => UpuGoal::Task(twists.to_vec()),
        Goal::SingularitySigmaMin => UpuGoal::SigmaMin,
        Goal::SingularityDet => UpuGoal::Det,
    };
    let azimuths = spec.azimuths_deg.map(Degrees::radians);
    UpuProblem::new(azimuths, nominal, free, goal)
}
