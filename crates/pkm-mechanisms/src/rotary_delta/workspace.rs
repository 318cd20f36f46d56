//! What the rotary Delta says about its workspace: a trigonometry-free reachability test, the
//! bend of its ball joints, and the clearance between neighbouring legs.

use super::{ElbowMode, RotaryDelta};
use nalgebra::Vector3;
use pkm_traits::checked::{all_finite, min_propagating_nan};
use pkm_traits::workspace::{PLATFORM_LINK_CLEARANCE_SPAN, links_distance};
use pkm_traits::{
    ConstrainedWorkspace, ConstraintKind, InverseKinematics, JacobianLanes, Joints, Lanes, Task,
};

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
    /// ratio $K/\rho$ does not; a non-finite $x$ is never reachable. The mode does not matter.
    /// One lane of [`RotaryDelta::reachable_lanes`].
    fn reachable(&self, x: &Task<3>, _mode: ElbowMode) -> bool {
        self.reachable_lanes(&[Lanes([x.x]), Lanes([x.y]), Lanes([x.z])])[0]
    }

    /// Reachability does not depend on the elbow mode: one test for any non-empty list.
    fn reachable_in_any(&self, x: &Task<3>, modes: &[ElbowMode]) -> bool {
        !modes.is_empty() && self.reachable(x, ElbowMode::Out)
    }

    /// [`RotaryDelta::reachable_lanes`] (the point test, lane by lane).
    #[inline(always)]
    fn reachable_in_any_lanes<const N: usize>(
        &self,
        x: &[Lanes<N>; 3],
        modes: &[ElbowMode],
    ) -> [bool; N] {
        if modes.is_empty() {
            return [false; N];
        }
        self.reachable_lanes(x)
    }

    /// [`RotaryDelta::jacobian_lanes`], in either mode.
    #[inline(always)]
    fn velocity_jacobian_lanes<const N: usize>(
        &self,
        x: &[Task<3>; N],
        mode: ElbowMode,
    ) -> Option<JacobianLanes<N>> {
        Some(self.jacobian_lanes(x, mode))
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

/// Relative width of the band around $4L_a^2\rho^2 - s^2 = 0$ within which the rounding of the
/// lane test (about $2|s|\,\delta s$ on $s^2$, $\delta s \le 4\epsilon(|D|^2 + |L_a^2 -
/// L_b^2|)$) or of the inverse kinematics' $|K/\rho| \le 1$ (a few $\epsilon$ on the ratio, so
/// $8\epsilon$ times $4L_a^2\rho^2$ on the difference) could decide the sign: $64\epsilon$, with
/// room to spare.
const BOUNDARY_ROUNDING: f64 = 64.0 * f64::EPSILON;

/// $\rho^2$ below which it may have underflowed where $\rho = \operatorname{hypot}(a, b)$ did
/// not: the inverse kinematics decides.
const TINY_RHO2: f64 = 1e-280;

impl RotaryDelta {
    /// Whether each of `N` points (coordinates in lanes) is reachable: the test behind
    /// [`ConstrainedWorkspace::reachable`] (one lane) and
    /// [`ConstrainedWorkspace::reachable_in_any_lanes`]. A lane is inside where every leg has $4L_a^2\rho^2 - s^2 \ge 0$ (the sign of a difference of
    /// finite values is that of the comparison) and $\rho^2 > 0$. A lane whose products are
    /// not finite (a non-finite point, or one beyond about 1e77 m; caught as a NaN in
    /// $\sum 0 \cdot s^2 + 0 \cdot r$) is answered by the inverse kinematics, whose ratio
    /// $K/\rho$ does not overflow, and so is a lane within the rounding band of the boundary on
    /// some leg (`BOUNDARY_ROUNDING` = 64ε), so that the two tests agree at every point, one ulp
    /// from the boundary included. The legs after one that no settled lane passes are skipped.
    ///
    /// # Example
    /// ```
    /// use pkm_mechanisms::{Placement, RotaryDelta, presets};
    /// use pkm_traits::Lanes;
    /// let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
    /// let x = [Lanes([0.0, 0.0, f64::NAN]), Lanes([0.1, 0.1, 0.0]), Lanes([-0.7, 5.0, -0.7])];
    /// assert_eq!(delta.reachable_lanes(&x), [true, false, false]);
    /// ```
    #[inline(always)]
    pub fn reachable_lanes<const N: usize>(&self, x: &[Lanes<N>; 3]) -> [bool; N] {
        let offset = self.design.arm * self.design.arm - self.design.forearm * self.design.forearm;
        let scale = 4.0 * self.design.arm * self.design.arm;
        // Per lane: the smallest 4L_a²ρ² − s² and ρ² over the legs, and a sum that is NaN
        // where a product was not finite. One fused loop over the lanes per leg, so that the
        // compiler vectorises across lanes.
        let (mut margin, mut rho2_min, mut poison) =
            ([f64::INFINITY; N], [f64::INFINITY; N], [0.0; N]);
        // Lanes whose margin on some leg lies within the rounding of both tests: answered by
        // the inverse kinematics, so that the two agree at every point.
        let mut unsure = [false; N];
        for leg in &self.legs {
            let (o, u, w) = (leg.plate_offset - leg.motor, leg.u, leg.w);
            let mut open = false;
            for l in 0..N {
                let d = [x[0].0[l] + o.x, x[1].0[l] + o.y, x[2].0[l] + o.z];
                let s = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + offset;
                let a = d[0] * u.x + d[1] * u.y + d[2] * u.z;
                let b = d[0] * w.x + d[1] * w.y + d[2] * w.z;
                let rho2 = a * a + b * b;
                let (lhs, rhs) = (s * s, scale * rho2);
                poison[l] = poison[l] + lhs * 0.0 + rhs * 0.0;
                let gap = rhs - lhs;
                let size = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + offset.abs();
                let band = BOUNDARY_ROUNDING * (rhs + s.abs() * size);
                unsure[l] |= (gap.abs() <= band) | (rho2 < TINY_RHO2);
                margin[l] = if gap < margin[l] { gap } else { margin[l] };
                rho2_min[l] = if rho2 < rho2_min[l] {
                    rho2
                } else {
                    rho2_min[l]
                };
                open |= (margin[l] >= 0.0) & (rho2_min[l] > 0.0) & (poison[l] == 0.0);
            }
            if !open {
                break;
            }
        }
        let inside = std::array::from_fn(|l| (margin[l] >= 0.0) & (rho2_min[l] > 0.0));
        let settled = std::array::from_fn::<bool, N, _>(|l| (poison[l] == 0.0) & !unsure[l]);
        if settled.iter().all(|s| *s) {
            return inside;
        }
        std::array::from_fn(|l| {
            if settled[l] {
                inside[l]
            } else {
                let point = Vector3::new(x[0].0[l], x[1].0[l], x[2].0[l]);
                self.inverse_kinematics(&point, ElbowMode::Out).is_ok()
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets;
    use crate::rotary_delta::Placement;
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

    /// Any float (NaN, ±∞, huge and subnormal included) or a coordinate near the workspace.
    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![-1.5f64..1.5, proptest::num::f64::ANY]
    }

    fn lanes_agree_with_the_point_test(m: &RotaryDelta, points: &[Vector3<f64>; 8]) {
        let modes = [ElbowMode::Out, ElbowMode::In];
        let lanes = m.reachable_in_any_lanes(&Lanes::coordinates(points), &modes);
        for (p, inside) in points.iter().zip(lanes) {
            assert_eq!(inside, m.reachable_in_any(p, &modes), "{p:?}");
        }
        assert_eq!(
            m.reachable_in_any_lanes(&Lanes::coordinates(points), &[]),
            [false; 8]
        );
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        #[test]
        fn reachability_in_lanes_is_the_point_test(
            c in proptest::collection::vec(coordinate(), 24)
        ) {
            let points = std::array::from_fn(|l| Vector3::new(c[3 * l], c[3 * l + 1], c[3 * l + 2]));
            lanes_agree_with_the_point_test(&nuwar(), &points);
        }
    }

    /// Pairs of points one ulp apart across the boundary, found by bisection along rays from
    /// a reachable point: where a reordered sum would flip the answer.
    #[test]
    fn reachability_in_lanes_is_the_point_test_at_the_boundary() {
        let m = RotaryDelta::new(presets::miller_delta(Placement::canonical())).unwrap();
        let centre = Vector3::new(0.0, 0.0, -0.7);
        assert!(m.reachable(&centre, ElbowMode::Out));
        let mut pairs = Vec::new();
        for k in 0..48 {
            let (polar, azimuth) = (0.3 + 0.05 * f64::from(k), 0.7 * f64::from(k));
            let dir = Vector3::new(
                polar.sin() * azimuth.cos(),
                polar.sin() * azimuth.sin(),
                polar.cos(),
            );
            let (mut inside, mut outside) = (0.0f64, 4.0f64);
            while outside.next_down() > inside {
                let mid = 0.5 * (inside + outside);
                let mid = if mid <= inside || mid >= outside {
                    inside.next_up()
                } else {
                    mid
                };
                if m.reachable(&(centre + dir * mid), ElbowMode::Out) {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            pairs.extend([centre + dir * inside, centre + dir * outside]);
        }
        let mut flips = 0;
        for chunk in pairs.chunks_exact(8) {
            let points: [Vector3<f64>; 8] = std::array::from_fn(|l| chunk[l]);
            lanes_agree_with_the_point_test(&m, &points);
            flips += points
                .iter()
                .filter(|p| m.reachable(p, ElbowMode::Out))
                .count();
        }
        assert_eq!(flips, 48, "one point of each pair inside");
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
