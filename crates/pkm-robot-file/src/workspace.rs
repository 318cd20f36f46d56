//! The robot as a workspace model: membership is the inverse kinematics in a working mode
//! (actuator `limits` of the file included), and half-spaces, joint ranges and passive-joint
//! cones apply as for every mechanism. Leg clearance is not modelled: the legs of a robot file
//! may meet by design (every arm of a point platform ends at one point), and the file states
//! no stretch of a link that may come close.

use crate::robot::Robot;
use pkm_traits::{ConstrainedWorkspace, ConstraintKind, Joints, Task};

impl<const N: usize> ConstrainedWorkspace<N, N> for Robot<N> {
    fn name(&self) -> &'static str {
        "a robot from a file"
    }

    fn supports(&self, kind: ConstraintKind) -> bool {
        matches!(
            kind,
            ConstraintKind::HalfSpace | ConstraintKind::JointRange | ConstraintKind::PassiveCone
        )
    }

    /// The bend of every leg's ball and universal joints ([`RobotModel::passive_bends`]) at
    /// the configuration on the branches nearest `q`.
    ///
    /// [`RobotModel::passive_bends`]: crate::RobotModel::passive_bends
    fn passive_joint_angles(&self, x: &Task<N>, q: &Joints<N>) -> Option<Joints<N>> {
        let config = self
            .model()
            .configuration_near(x.as_slice(), q.as_slice())
            .ok()?;
        let bends = self.model().passive_bends(&config)?;
        (bends.len() == N).then(|| Joints::<N>::from_column_slice(&bends))
    }
}
