//! Parallel mechanisms: validated designs with closed-form inverse kinematics, forward
//! kinematics, and the loop-closure Jacobians $J_x$, $J_q$ of [`pkm_traits::ClosedChain`].
//!
//! One file per mechanism: the rotary Delta/NUWAR, the Linear Delta (Miller 2004), the Tsai
//! 3-DOF translational platform (Stamper, Tsai & Walsh 1997), the Stewart–Gough platform and the
//! 3-UPU (Wolf & Shoham).
#![warn(missing_docs)]

mod tsai3dof;

pub use tsai3dof::{Elbow, LegAngles, LegBranch, Tsai3Dof};
