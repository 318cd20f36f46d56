//! The workspace view ([`ConstrainedWorkspace`]) of the translational mechanisms (the 3-UPU in
//! its fixed-orientation model) whose only
//! limits are their inverse kinematics (the rotary Delta adds ball-joint cones and leg clearance
//! in its own module): half-spaces and actuated-joint ranges apply, reachability is the IK.

use crate::{Elbow, JacobianLanes, LinearDelta, ThreeUpu, Tsai3Dof};
use pkm_traits::{ConstrainedWorkspace, Task};

impl ConstrainedWorkspace<3, 3> for Tsai3Dof {
    fn name(&self) -> &'static str {
        "Tsai3Dof"
    }

    /// Eq. 7 on the elbow-out branch of every leg ([`Tsai3Dof::velocity_jacobian_elbow_out_lanes`]);
    /// no lane kernel for the other modes.
    #[inline(always)]
    fn velocity_jacobian_lanes<const N: usize>(
        &self,
        x: &[Task<3>; N],
        mode: [Elbow; 3],
    ) -> Option<JacobianLanes<N>> {
        // No closure (`bool::then`): it would not be inlined into a caller's vector path.
        if mode == [Elbow::Out; 3] {
            Some(self.velocity_jacobian_elbow_out_lanes(x))
        } else {
            None
        }
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
