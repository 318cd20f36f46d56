//! Parallel mechanisms: validated designs with closed-form inverse kinematics, forward
//! kinematics, and the loop-closure Jacobians $J_x$, $J_q$ of [`pkm_traits::ClosedChain`].
//!
//! One file per mechanism: the rotary Delta/NUWAR, the Linear Delta (Miller 2004), the Tsai
//! 3-DOF translational platform (Stamper, Tsai & Walsh 1997), the Stewart–Gough platform and the
//! 3-UPU (Wolf & Shoham), and the Stewart–Gough platform at a constant orientation
//! ([`ConstantOrientation`], its standard workspace). Each mechanism is built from a named
//! design struct (SI units and radians) by `new(design)`; the papers' designs are in
//! [`presets`].

// The README is the crate's page on crates.io; this makes `cargo test --doc` run its example.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod linear_delta;
mod linear_delta_cross_section;
pub mod presets;
pub mod rotary_delta;
mod skeleton;
mod stewart_gough;
mod stewart_layout;
mod stewart_orientation;
mod stewart_task;
mod three_upu;
mod tsai3dof;
mod workspace_models;
mod wrench_system;

pub use linear_delta::{LinearDelta, LinearDeltaDesign, LinearDeltaMode, LinearDeltaRatios};
pub use linear_delta_cross_section::CrossSection;
pub use pkm_traits::JacobianLanes;
pub use rotary_delta::{
    ElbowMode, FOREARM_CLEARANCE_SPAN, Leg, Placement, RotaryDelta, RotaryDeltaDesign,
};
pub use skeleton::{Link, LinkKind, PointKind, Skeleton, SkeletonPoint};
pub use stewart_gough::{StewartDesign, StewartGough, platform_pose, pose_from_task};
pub use stewart_layout::{AngleMode, JointLayout, Pairing};
pub use stewart_orientation::ConstantOrientation;
pub use stewart_task::{StewartDesignVariable, StewartTaskProblem};
pub use three_upu::{ThreeUpu, ThreeUpuDesign, UJointAxes};
pub use tsai3dof::{Elbow, LegAngles, LegBranch, Tsai3Dof, TsaiDesign};
pub use wrench_system::WrenchSystem;
