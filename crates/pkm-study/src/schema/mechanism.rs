//! The `[mechanism.<kind>]` table of every study: the registry of mechanisms, one line per kind
//! (each kind's table, builder and study impl live in its own file of `schema/kinds/`; a robot
//! file's in `schema/robot_file.rs`). The names are re-exported here, where studies find them.

pub use super::constraints::{ConstraintsSpec, HalfSpaceSpec, JointRangeDegSpec, JointRangeSpec};
pub use super::kinds::linear_delta::LinearDeltaSpec;
pub use super::kinds::rotary_delta::RotaryDeltaSpec;
pub use super::kinds::stewart_gough::{StewartSpec, stewart_layout};
pub use super::kinds::three_upu::ThreeUpuSpec;
pub use super::kinds::tsai::TsaiSpec;
pub use crate::registry::{BuildError, WorkspaceVisitor};

crate::mechanisms! {
    /// The `[mechanism.<kind>]` table: exactly one kind, one line per mechanism.
    pub enum MechanismSpec {
        /// Rotary Delta / NUWAR family (Miller 2004): motors inclined by α and turned by β.
        RotaryDelta(RotaryDeltaSpec),
        /// The Tsai 3-DOF translational platform (Stamper, Tsai & Walsh 1997).
        Tsai(TsaiSpec),
        /// The Linear Delta (Miller 2004 §2.2): three parallel rails along x.
        LinearDelta(LinearDeltaSpec),
        /// The 3-UPU (Wolf & Shoham §4.4) in its translational model: platform at $R = I$.
        ThreeUpu(ThreeUpuSpec),
        /// The Stewart–Gough platform (Wolf & Shoham Fig. 3) at one fixed orientation.
        StewartGough(StewartSpec),
        /// Any translational robot from a robot file (`docs/robots.md`), inline or by `file`.
        RobotFile(super::robot_file::RobotFileSpec),
    }
}
