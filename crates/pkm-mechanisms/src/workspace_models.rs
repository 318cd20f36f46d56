//! The workspace view ([`ConstrainedWorkspace`]) of the translational mechanisms (the 3-UPU in
//! its fixed-orientation model) whose only
//! limits are their inverse kinematics (the rotary Delta adds ball-joint cones and leg clearance
//! in its own module): half-spaces and actuated-joint ranges apply, reachability is the IK.

use crate::{LinearDelta, ThreeUpu, Tsai3Dof};
use pkm_traits::ConstrainedWorkspace;

impl ConstrainedWorkspace<3, 3> for Tsai3Dof {
    fn name(&self) -> &'static str {
        "Tsai3Dof"
    }
}

impl ConstrainedWorkspace<3, 3> for LinearDelta {
    fn name(&self) -> &'static str {
        "LinearDelta"
    }
}

impl ConstrainedWorkspace<3, 3> for ThreeUpu {
    fn name(&self) -> &'static str {
        "ThreeUpu"
    }
}
