//! The robot as a workspace model: membership is the inverse kinematics in a working mode
//! (actuator `limits` of the file included), and half-spaces and joint ranges apply as for
//! every mechanism; passive-joint cones and leg clearance are not modelled.

use crate::robot::Robot;
use pkm_traits::ConstrainedWorkspace;

impl<const N: usize> ConstrainedWorkspace<N, N> for Robot<N> {
    fn name(&self) -> &'static str {
        "a robot from a file"
    }
}
