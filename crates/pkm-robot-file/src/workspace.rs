//! The robot as a workspace model: membership is the inverse kinematics in a working mode
//! (actuator `limits` of the file included), and half-spaces, joint ranges, passive-joint
//! cones and leg clearance apply as for every mechanism.
//!
//! **Leg clearance** is the smallest distance between the links of neighbouring legs $i$ and
//! $i + 1$ (cyclically; the one pair of a two-legged robot once), each link the straight
//! segment between consecutive stations of [`RobotModel::leg_points`]: every segment but a
//! rail's (from its origin to the carriage: the rail is base structure), the one that ends on
//! the platform over its first [`PLATFORM_LINK_CLEARANCE_SPAN`] only, as the hand-written
//! Delta's forearms (legs converge on the platform by design). Legs that share a joint point by
//! design (a 6-3 Stewart–Gough platform's pairs) have clearance 0 there.

use crate::closure::Configuration;
use crate::model::RobotModel;
use crate::points::LegPointKind;
use crate::robot::Robot;
use nalgebra::Vector3;
use pkm_traits::checked::min_propagating_nan;
use pkm_traits::{
    ConstrainedWorkspace, ConstraintKind, Joints, PLATFORM_LINK_CLEARANCE_SPAN, Task,
    links_distance,
};

impl RobotModel {
    /// The leg clearance at `config` (module documentation, m); `None` for a configuration
    /// that does not fit the robot, a non-finite distance or a robot with one leg.
    pub fn leg_clearance(&self, config: &Configuration) -> Option<f64> {
        let n = self.legs.len();
        if n < 2 {
            return None;
        }
        let links = (0..n)
            .map(|leg| self.clearance_links(leg, config))
            .collect::<Option<Vec<_>>>()?;
        let pairs = if n == 2 { 1 } else { n };
        let mut clearance = f64::INFINITY;
        for i in 0..pairs {
            let pair = links_distance(&links[i], &links[(i + 1) % n]);
            clearance = min_propagating_nan(clearance, pair);
        }
        clearance.is_finite().then_some(clearance)
    }

    /// The links of leg `leg` on which clearance is measured (module documentation).
    fn clearance_links(
        &self,
        leg: usize,
        config: &Configuration,
    ) -> Option<Vec<(Vector3<f64>, Vector3<f64>)>> {
        let legs = self.leg_points(leg, config)?;
        let links = legs
            .segments
            .iter()
            .filter(|s| legs.points[s.from].kind != LegPointKind::RailOrigin)
            .map(|s| {
                let (a, b) = (legs.points[s.from].position, legs.points[s.to].position);
                if legs.points[s.to].kind == LegPointKind::Platform {
                    (a, a + (b - a) * PLATFORM_LINK_CLEARANCE_SPAN)
                } else {
                    (a, b)
                }
            })
            .collect();
        Some(links)
    }
}

impl<const N: usize> ConstrainedWorkspace<N, N> for Robot<N> {
    fn name(&self) -> &'static str {
        "a robot from a file"
    }

    fn supports(&self, kind: ConstraintKind) -> bool {
        matches!(
            kind,
            ConstraintKind::HalfSpace
                | ConstraintKind::JointRange
                | ConstraintKind::PassiveCone
                | ConstraintKind::LegClearance
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

    /// [`RobotModel::leg_clearance`] at the configuration on the branches nearest `q`.
    fn leg_clearance(&self, x: &Task<N>, q: &Joints<N>) -> Option<f64> {
        let config = self
            .model()
            .configuration_near(x.as_slice(), q.as_slice())
            .ok()?;
        self.model().leg_clearance(&config)
    }
}
