//! Any parallel robot from a file.
//!
//! A robot file (TOML, `docs/robots.md`) describes one rigid base, one rigid platform and its
//! legs, each a serial chain of R, P, U, S and C joints given as screw axes at the home pose.
//! This crate reads it ([`RobotModel::from_toml`]), checks the architecture name and the
//! mobility, and provides:
//! - inverse kinematics per leg, in closed form for the distance and arm classes (every branch
//!   labelled in a [`WorkingMode`]) and by damped Newton on the SE(3) closure otherwise, with
//!   the dependent pose coordinates of lower-mobility robots solved;
//! - forward kinematics from an assembly mode, by continuation from home, and every assembly
//!   mode by seeded multistart ([`RobotModel::assembly_modes`]);
//! - Jacobians from screws, $J_a$, $J_c$, $D$, $T$ and $J = D^{-1}J_aT$
//!   ([`RobotModel::screw_jacobians`]), and three singularity margins
//!   ([`RobotModel::singularity_margins`]);
//! - the joint points of every leg at a configuration ([`RobotModel::leg_points`], for
//!   drawings) and a bound on the reachable platform positions ([`RobotModel::reach_box`]);
//! - the shared kinematics traits through [`Robot`].
//!
//! # Example
//! ```
//! use pkm_robot_file::RobotModel;
//! let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/robots/three_prs.toml")).unwrap();
//! let robot = RobotModel::from_toml(&text).unwrap();
//! assert_eq!(robot.task_names(), ["z", "tilt_x", "tilt_y"]);
//! let c = robot.inverse_kinematics_configuration(&[0.5, 0.05, -0.02], robot.home_mode()).unwrap();
//! let torsion = c.pose()[5];
//! assert!(torsion.abs() < 1e-9);
//! ```
//!
//! # References
//! Lynch & Park, *Modern Robotics* (2017), ch. 4 (product of exponentials); Joshi & Tsai,
//! "Jacobian analysis of limited-DOF parallel manipulators", ASME J. Mech. Des. 124(2), 2002;
//! Gosselin & Angeles 1990 (type I/II singularities); `spec/general-robots.md`.

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod chain;
mod closed_form;
mod closure;
mod dynamics;
mod error;
mod export;
mod file;
mod fk;
mod ik;
mod jacobian;
mod leg_ik;
mod lm;
mod mass;
mod mjcf;
mod mobility;
mod model;
mod name;
mod paden_kahan;
mod parameters;
mod passive;
mod pointing;
mod points;
mod polynomial;
mod pose;
mod redundancy;
mod robot;
mod self_motion;
mod svd;
mod task_workspace;
mod workspace;

pub use chain::{Joint, LegActuator, LegChain};
pub use closure::Configuration;
pub use dynamics::{DynamicsError, ForwardDynamics, InverseDynamics, TaskDynamics};
pub use error::RobotFileError;
pub use export::UrdfExport;
pub use file::{
    HomeSpec, JointSpec, JointType, LegSpec, MAX_FILE_BYTES, MAX_LEGS, RobotFile, SymmetrySpec,
    check_size,
};
pub use fk::{AssemblyMode, AssemblySearch, EnumerationSettings, MAX_STARTS, ModeSearch};
pub use jacobian::{ScrewJacobians, SingularityMargins};
pub use lm::SolverSettings;
pub use mass::{Body, MassProperties};
pub use model::{MAX_JOINTS_PER_LEG, MIN_CHARACTERISTIC_LENGTH, RobotModel, WorkingMode};
pub use points::{LegPoint, LegPointKind, LegPoints, LegSegment};
pub use polynomial::{AllSolutions, HomotopyReport};
pub use pose::{CoordinateRole, OrientationKind, PoseCoordinates, platform_pose};
pub use redundancy::{ForceDistribution, LeastSquaresPose};
pub use robot::{Robot, task_of};
pub use self_motion::SelfMotion;
pub use task_workspace::{MarginLimits, OrientationLevels, OrientationSet, TaskWorkspace};
