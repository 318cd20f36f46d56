//! What the rotary Delta says about its workspace: a trigonometry-free reachability test, the
//! bend of its ball joints, and the clearance between neighbouring legs.

use super::{ElbowMode, RotaryDelta};
use pkm_traits::checked::{all_finite, min_propagating_nan};
use pkm_traits::workspace::{PLATFORM_LINK_CLEARANCE_SPAN, links_distance};
use pkm_traits::{ConstrainedWorkspace, ConstraintKind, InverseKinematics, Joints, Task};

/// The part of a forearm, from the elbow, on which leg clearance is measured (the span every
/// mechanism uses for the link that ends on the platform).
pub const FOREARM_CLEARANCE_SPAN: f64 = PLATFORM_LINK_CLEARANCE_SPAN;

impl ConstrainedWorkspace<3, 3> for RotaryDelta {
    fn name(&self) -> &'static str {
        "RotaryDelta"
    }

    /// Every kind: half-spaces, arm-angle ranges, ball-joint cones and leg clearance.
    fn supports(&self, _kind: ConstraintKind) -> bool {
        true
    }

    /// Leg $i$ reaches $x$ iff $K^2 \le a^2 + b^2$ (the arc cosine of the inverse kinematics
    /// exists), in either elbow mode: $D = x + c_i - A_i$, $K = (|D|^2 + L_a^2 - L_b^2)/(2L_a)$,
    /// $a = D\cdot u_i$, $b = -D\cdot w_i$; tested as $(|D|^2 + L_a^2 - L_b^2)^2 \le
    /// 4L_a^2 (a^2 + b^2)$, with no division, square root or trigonometry. Where a product of
    /// that test overflows (points beyond about 1e77 m) it asks the inverse kinematics, whose
    /// ratio $K/\rho$ does not; a non-finite $x$ is never reachable.
    fn reachable(&self, x: &Task<3>, mode: ElbowMode) -> bool {
        if !all_finite(x.iter()) {
            return false;
        }
        let offset = self.design.arm * self.design.arm - self.design.forearm * self.design.forearm;
        let scale = 4.0 * self.design.arm * self.design.arm;
        let mut overflowed = false;
        let cheap = self.legs.iter().all(|leg| {
            let d = x + (leg.plate_offset - leg.motor);
            let s = d.norm_squared() + offset;
            let (a, b) = (d.dot(&leg.u), d.dot(&leg.w));
            let rho2 = a * a + b * b;
            let (lhs, rhs) = (s * s, scale * rho2);
            overflowed |= !(lhs.is_finite() && rhs.is_finite());
            lhs <= rhs && rho2 > 0.0
        });
        if overflowed {
            return self.inverse_kinematics(x, mode).is_ok();
        }
        cheap
    }

    /// Reachability does not depend on the elbow mode: one test for any non-empty list.
    fn reachable_in_any(&self, x: &Task<3>, modes: &[ElbowMode]) -> bool {
        !modes.is_empty() && self.reachable(x, ElbowMode::Out)
    }

    /// The ball joints at both ends of forearm $i$ have their studs along the motor axis $e_i$
    /// (the parallelogram's pins), so a joint is unbent when the forearm lies in the plane
    /// normal to $e_i$; its bend is the forearm's angle out of that plane,
    /// $\gamma_i = \arcsin(|\hat v_i \cdot e_i|)$ with $v_i = C_i - B_i$.
    fn passive_joint_angles(&self, x: &Task<3>, q: &Joints<3>) -> Option<Joints<3>> {
        if !(all_finite(x.iter()) && all_finite(q.iter())) {
            return None;
        }
        let mut out = Joints::<3>::zeros();
        for (i, leg) in self.legs.iter().enumerate() {
            let v = self.forearm_vector(i, x, q[i]);
            // `f64::min` would turn a NaN sine (a zero or overflowing forearm) into 1.
            let sine = (v.dot(&leg.e) / v.norm()).abs();
            if sine.is_nan() {
                return None;
            }
            out[i] = sine.min(1.0).asin();
        }
        Some(out)
    }

    /// The smallest distance between the links of neighbouring legs $i$, $i + 1$: the arms
    /// $A_iB_i$ and the forearm mid-lines from $B_i$ over the first
    /// [`FOREARM_CLEARANCE_SPAN`] of the way to $C_i$ (forearms converge on the plate by design,
    /// their ends only $r\sqrt3$ apart, so the stretch next to the plate is not a collision).
    fn leg_clearance(&self, x: &Task<3>, q: &Joints<3>) -> Option<f64> {
        if !(all_finite(x.iter()) && all_finite(q.iter())) {
            return None;
        }
        let links = |i: usize| {
            let leg = &self.legs[i];
            let elbow = self.elbow(i, q[i]);
            let plate = x + leg.plate_offset;
            let reach = elbow + (plate - elbow) * FOREARM_CLEARANCE_SPAN;
            [(leg.motor, elbow), (elbow, reach)]
        };
        let mut clearance = f64::INFINITY;
        for i in 0..3 {
            let pair = links_distance(&links(i), &links((i + 1) % 3));
            clearance = min_propagating_nan(clearance, pair);
        }
        clearance.is_finite().then_some(clearance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets;
    use crate::rotary_delta::Placement;
    use nalgebra::Vector3;
    use proptest::prelude::*;

    fn nuwar() -> RotaryDelta {
        RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        #[test]
        fn reachability_agrees_with_inverse_kinematics(
            x in -0.8f64..0.8, y in -0.8f64..0.8, z in -1.2f64..0.6
        ) {
            let m = nuwar();
            let p = Vector3::new(x, y, z);
            let ik = m.inverse_kinematics(&p, ElbowMode::Out).is_ok();
            prop_assert_eq!(m.reachable(&p, ElbowMode::In), ik);
        }
    }

    #[test]
    fn ball_joints_of_the_delta_are_unbent_in_the_symmetric_plane() {
        // The Delta's forearm i lies in the plane normal to e_i when the plate is on the
        // centreline, so every bend is zero there.
        let m = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
        let p = Vector3::new(0.0, 0.0, -0.8);
        let q = m.inverse_kinematics(&p, ElbowMode::Out).unwrap();
        let bend = m.passive_joint_angles(&p, &q).unwrap();
        assert!(bend.amax() < 1e-12, "{bend}");
        let off = Vector3::new(0.1, 0.05, -0.8);
        let q = m.inverse_kinematics(&off, ElbowMode::Out).unwrap();
        assert!(m.passive_joint_angles(&off, &q).unwrap().amax() > 1e-3);
    }

    #[test]
    fn legs_are_apart_at_the_home_pose() {
        let m = nuwar();
        let p = Vector3::new(0.0, 0.0, -0.8);
        let q = m.inverse_kinematics(&p, ElbowMode::Out).unwrap();
        let c = m.leg_clearance(&p, &q).unwrap();
        assert!(c > 0.01 && c.is_finite(), "{c}");
    }
}
