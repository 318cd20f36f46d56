//! Workspace constraints: the limits a real robot adds to pure reachability.
//!
//! A translational mechanism's workspace is the set of platform positions $x$ at which some
//! working mode assembles ($q = \mathrm{IK}(x)$ exists) **and** every stated constraint holds:
//!
//! | constraint | holds when | depends on |
//! |---|---|---|
//! | [`WorkspaceConstraint::half_space`] | $n \cdot x \le c$ (e.g. the plate below the motor plane) | $x$ |
//! | [`WorkspaceConstraint::joint_range`] | $q_{lo} \le q_i \le q_{hi}$ for every (or one) actuated joint | $q$ |
//! | [`WorkspaceConstraint::passive_cone`] | every passive spherical joint is bent by at most $\gamma_{max}$ | mechanism |
//! | [`WorkspaceConstraint::leg_clearance`] | neighbouring legs' links stay at least $d$ apart | mechanism |
//!
//! Constraints are values a user states for their own robot; each mechanism says through
//! [`ConstrainedWorkspace::supports`] which ones it can evaluate, so a cone limit on a
//! mechanism without spherical joints is a typed error ([`ConstraintError::Unsupported`]),
//! never a silently ignored limit.

use crate::checked::all_finite;
use crate::kinematics::{InverseKinematics, Joints, Task};
use crate::{JacobianLanes, Lanes};
use nalgebra::Vector3;
use thiserror::Error;

/// Which kind of limit a [`WorkspaceConstraint`] states.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConstraintKind {
    /// A half-space of task positions.
    HalfSpace,
    /// A range of actuated-joint coordinates.
    JointRange,
    /// A cone limit of the passive spherical joints.
    PassiveCone,
    /// A minimum distance between neighbouring legs.
    LegClearance,
}

/// One validated workspace constraint (construct with the named functions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkspaceConstraint(Limit);

#[derive(Debug, Clone, Copy, PartialEq)]
enum Limit {
    HalfSpace {
        normal: Vector3<f64>,
        offset: f64,
    },
    JointRange {
        joint: Option<usize>,
        lower: f64,
        upper: f64,
        /// A revolute joint: the range holds an angle modulo $2\pi$.
        periodic: bool,
    },
    PassiveCone {
        max_angle: f64,
    },
    LegClearance {
        distance: f64,
    },
}

/// Whether `v` lies in `[lower, upper]`, modulo $2\pi$ for a periodic (revolute) range: the
/// offset $(v - lower) \bmod 2\pi \in [0, 2\pi)$ is at most the width. Without a wrap the
/// offset is $v - lower$ exactly as computed, so an angle already in the range holds as in the
/// plain test.
fn in_range(v: f64, lower: f64, upper: f64, periodic: bool) -> bool {
    if !periodic || (lower <= v && v <= upper) {
        return lower <= v && v <= upper;
    }
    let width = upper - lower;
    width >= std::f64::consts::TAU || (v - lower).rem_euclid(std::f64::consts::TAU) <= width
}

/// A constraint that cannot be built or cannot be applied to a mechanism.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ConstraintError {
    /// A parameter violates its requirement.
    #[error("invalid constraint: {name} = {value} ({requirement})")]
    Invalid {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// The mechanism cannot evaluate this kind of constraint.
    #[error("{mechanism} does not support {kind:?} constraints")]
    Unsupported {
        /// The mechanism's name.
        mechanism: &'static str,
        /// The unsupported kind.
        kind: ConstraintKind,
    },
    /// A joint range names a joint the mechanism does not have.
    #[error("joint {joint} does not exist (the mechanism has {joints})")]
    NoSuchJoint {
        /// The joint index given.
        joint: usize,
        /// How many actuated joints there are.
        joints: usize,
    },
}

fn invalid(name: &'static str, value: f64, requirement: &'static str) -> ConstraintError {
    ConstraintError::Invalid {
        name,
        value,
        requirement,
    }
}

impl WorkspaceConstraint {
    /// The half-space $n \cdot x \le c$ of task positions; `normal` need not be unit length.
    ///
    /// # Errors
    /// [`ConstraintError::Invalid`] for a non-finite or zero normal or a non-finite offset.
    pub fn half_space(normal: Vector3<f64>, offset: f64) -> Result<Self, ConstraintError> {
        if let Some(v) = normal.iter().copied().find(|v| !v.is_finite()) {
            return Err(invalid("normal", v, "must be finite"));
        }
        let length = normal.amax();
        if !(length > 0.0) {
            return Err(invalid("normal", length, "must not be zero"));
        }
        if !offset.is_finite() {
            return Err(invalid("offset", offset, "must be finite"));
        }
        // Scaled by the largest component, so that 1e300-sized normals neither overflow nor
        // change the half-space.
        Ok(Self(Limit::HalfSpace {
            normal: normal / length,
            offset: offset / length,
        }))
    }

    /// Positions at or below height `z`: the half-space $x_3 \le z$.
    ///
    /// # Errors
    /// [`ConstraintError::Invalid`] for a non-finite `z`.
    pub fn below(z: f64) -> Result<Self, ConstraintError> {
        Self::half_space(Vector3::z(), z)
    }

    /// Every actuated joint within `[lower, upper]` (rad or m, the joint's own unit).
    ///
    /// # Errors
    /// [`ConstraintError::Invalid`] for a NaN bound or `lower > upper`.
    pub fn joint_range(lower: f64, upper: f64) -> Result<Self, ConstraintError> {
        Self::range(None, lower, upper, false)
    }

    /// Every actuated revolute joint within `[lower, upper]` (rad) modulo $2\pi$: an angle
    /// $q$ holds when $q + 2\pi k \in [lower, upper]$ for some integer $k$ (a motor at
    /// $-320°$ is at $40°$), so a range $2\pi$ wide or wider holds every angle, whatever
    /// interval the inverse kinematics reports its angles in.
    ///
    /// # Errors
    /// As [`WorkspaceConstraint::joint_range`].
    pub fn angle_range(lower: f64, upper: f64) -> Result<Self, ConstraintError> {
        Self::range(None, lower, upper, true)
    }

    /// Actuated revolute joint `joint` (from 0) within `[lower, upper]` modulo $2\pi$
    /// ([`WorkspaceConstraint::angle_range`]).
    ///
    /// # Errors
    /// As [`WorkspaceConstraint::joint_range`].
    pub fn angle_range_of(joint: usize, lower: f64, upper: f64) -> Result<Self, ConstraintError> {
        Self::range(Some(joint), lower, upper, true)
    }

    /// Actuated joint `joint` (from 0) within `[lower, upper]`.
    ///
    /// # Errors
    /// As [`WorkspaceConstraint::joint_range`].
    pub fn joint_range_of(joint: usize, lower: f64, upper: f64) -> Result<Self, ConstraintError> {
        Self::range(Some(joint), lower, upper, false)
    }

    fn range(
        joint: Option<usize>,
        lower: f64,
        upper: f64,
        periodic: bool,
    ) -> Result<Self, ConstraintError> {
        if lower.is_nan() {
            return Err(invalid("lower", lower, "must not be NaN"));
        }
        if upper.is_nan() {
            return Err(invalid("upper", upper, "must not be NaN"));
        }
        if !(lower <= upper) {
            return Err(invalid("lower", lower, "must not exceed upper"));
        }
        Ok(Self(Limit::JointRange {
            joint,
            lower,
            upper,
            periodic,
        }))
    }

    /// Every passive spherical joint bent by at most `max_angle` (rad, in $(0, \pi]$); what
    /// "bent" means is the mechanism's [`ConstrainedWorkspace::passive_joint_angles`].
    ///
    /// # Errors
    /// [`ConstraintError::Invalid`] outside $(0, \pi]$ or NaN.
    pub fn passive_cone(max_angle: f64) -> Result<Self, ConstraintError> {
        if !(max_angle > 0.0 && max_angle <= std::f64::consts::PI) {
            return Err(invalid("max_angle", max_angle, "must lie in (0, π]"));
        }
        Ok(Self(Limit::PassiveCone { max_angle }))
    }

    /// Neighbouring legs' links at least `distance` apart (m, finite and ≥ 0): a collision
    /// test with links modelled as segments of diameter `distance`.
    ///
    /// # Errors
    /// [`ConstraintError::Invalid`] for a negative or non-finite distance.
    pub fn leg_clearance(distance: f64) -> Result<Self, ConstraintError> {
        if !(distance.is_finite() && distance >= 0.0) {
            return Err(invalid("distance", distance, "must be finite and ≥ 0"));
        }
        Ok(Self(Limit::LegClearance { distance }))
    }

    /// The kind of limit.
    pub fn kind(&self) -> ConstraintKind {
        match self.0 {
            Limit::HalfSpace { .. } => ConstraintKind::HalfSpace,
            Limit::JointRange { .. } => ConstraintKind::JointRange,
            Limit::PassiveCone { .. } => ConstraintKind::PassiveCone,
            Limit::LegClearance { .. } => ConstraintKind::LegClearance,
        }
    }

    /// The actuated joint a range constrains, `None` for a range of every joint or another kind.
    pub fn joint(&self) -> Option<usize> {
        match self.0 {
            Limit::JointRange { joint, .. } => joint,
            _ => None,
        }
    }

    /// Whether the constraint needs the joint coordinates (all but the half-space).
    pub fn needs_joints(&self) -> bool {
        self.kind() != ConstraintKind::HalfSpace
    }

    /// Checks that `mechanism` can evaluate this constraint.
    ///
    /// # Errors
    /// [`ConstraintError::Unsupported`] or [`ConstraintError::NoSuchJoint`].
    pub fn check_applies<M, const NQ: usize>(&self, mechanism: &M) -> Result<(), ConstraintError>
    where
        M: ConstrainedWorkspace<3, NQ> + ?Sized,
    {
        if let Limit::JointRange {
            joint: Some(joint), ..
        } = self.0
            && joint >= NQ
        {
            return Err(ConstraintError::NoSuchJoint { joint, joints: NQ });
        }
        if mechanism.supports(self.kind()) {
            Ok(())
        } else {
            Err(ConstraintError::Unsupported {
                mechanism: mechanism.name(),
                kind: self.kind(),
            })
        }
    }

    /// Whether the position alone satisfies the constraint (`true` for constraints on joints).
    /// No constraint holds at a position with a NaN or infinite coordinate.
    #[inline]
    pub fn holds_at_position(&self, x: &Vector3<f64>) -> bool {
        if !all_finite(x.iter()) {
            return false;
        }
        match self.0 {
            Limit::HalfSpace { normal, offset } => normal.dot(x) <= offset,
            _ => true,
        }
    }

    /// Whether the assembled configuration `(x, q)` satisfies the constraint. No constraint
    /// holds at a configuration with a NaN or infinite coordinate, and NaN angles or distances
    /// fail it.
    pub fn holds<M, const NQ: usize>(&self, mechanism: &M, x: &Task<3>, q: &Joints<NQ>) -> bool
    where
        M: ConstrainedWorkspace<3, NQ> + ?Sized,
    {
        self.holds_at(
            x,
            q.as_slice(),
            || {
                mechanism
                    .passive_joint_angles(x, q)
                    .map(|a| a.iter().copied().collect())
            },
            || mechanism.leg_clearance(x, q),
        )
    }

    /// Whether a configuration satisfies the constraint, given the platform position, the
    /// actuated joints `q`, and (asked only by the constraints that need them) the bends of the
    /// passive joints and the leg clearance: the test of [`WorkspaceConstraint::holds`] for a
    /// mechanism whose task is not the platform position (a robot from a file in any task
    /// space). No constraint holds at a NaN or infinite position or joint; NaN angles or
    /// distances fail it.
    pub fn holds_at(
        &self,
        position: &Vector3<f64>,
        q: &[f64],
        passive_angles: impl FnOnce() -> Option<Vec<f64>>,
        clearance: impl FnOnce() -> Option<f64>,
    ) -> bool {
        if !(all_finite(position.iter()) && all_finite(q.iter())) {
            return false;
        }
        match self.0 {
            Limit::HalfSpace { .. } => self.holds_at_position(position),
            Limit::JointRange {
                joint,
                lower,
                upper,
                periodic,
            } => {
                let within = |v: &f64| in_range(*v, lower, upper, periodic);
                match joint {
                    Some(j) => q.get(j).is_some_and(within),
                    None => q.iter().all(within),
                }
            }
            Limit::PassiveCone { max_angle } => {
                passive_angles().is_some_and(|a| a.iter().all(|v| *v <= max_angle))
            }
            Limit::LegClearance { distance } => clearance().is_some_and(|d| d >= distance),
        }
    }
}

/// What a translational mechanism ($x$ = platform position) can say about its workspace.
///
/// Half-spaces and joint ranges need nothing from the mechanism; it opts into the others by
/// overriding [`ConstrainedWorkspace::supports`] and the matching method.
pub trait ConstrainedWorkspace<const NX: usize, const NQ: usize>:
    InverseKinematics<NX, NQ>
{
    /// A short name for error messages (`"RotaryDelta"`).
    fn name(&self) -> &'static str;

    /// Whether [`WorkspaceConstraint`]s of `kind` can be evaluated.
    fn supports(&self, kind: ConstraintKind) -> bool {
        matches!(kind, ConstraintKind::HalfSpace | ConstraintKind::JointRange)
    }

    /// Whether the mechanism assembles at `x` in `mode`. The default asks the inverse
    /// kinematics; a mechanism may override it with a cheaper test (no trigonometry) that must
    /// agree with the inverse kinematics for every `x`, NaN, ±∞ and points whose squares
    /// overflow included (`tests/it/hostile/edges.rs` checks it).
    fn reachable(&self, x: &Task<NX>, mode: Self::WorkingMode) -> bool {
        self.inverse_kinematics(x, mode).is_ok()
    }

    /// Whether the mechanism assembles at `x` in at least one of `modes` (default: asks
    /// [`ConstrainedWorkspace::reachable`] for each). A mechanism whose reachability does not
    /// depend on the mode overrides it to test once.
    fn reachable_in_any(&self, x: &Task<NX>, modes: &[Self::WorkingMode]) -> bool {
        modes.iter().any(|m| self.reachable(x, *m))
    }

    /// [`ConstrainedWorkspace::reachable_in_any`] at `N` points given by their coordinates in
    /// lanes (lane `l` of `x[c]` is coordinate `c` of point `l`). The default asks point by
    /// point. A mechanism may override it with a lane kernel (in [`crate::Lanes`],
    /// `#[inline(always)]`, so that a caller compiled for a wider vector unit vectorises it)
    /// that must give the same answer as the point-by-point test at every point, non-finite
    /// and overflowing ones included.
    #[inline(always)]
    fn reachable_in_any_lanes<const N: usize>(
        &self,
        x: &[Lanes<N>; NX],
        modes: &[Self::WorkingMode],
    ) -> [bool; N] {
        std::array::from_fn(|l| self.reachable_in_any(&Task::from_fn(|c, _| x[c].0[l]), modes))
    }

    /// The velocity Jacobians $J = -J_q^{-1}J_x$ at `N` points in `mode` by a lane kernel, with
    /// each lane's reachability, or `None` (the default) when the mechanism has no lane kernel
    /// for `mode` (then callers ask [`InverseKinematics::velocity_jacobian_at`] point by
    /// point). An override is `#[inline(always)]`; lane `l` must agree with
    /// `velocity_jacobian_at(&x[l], mode)` to rounding: reachable where that call does not
    /// report the point unreachable (up to rounding at the workspace boundary), with the same
    /// matrix, or non-finite entries where it reports a singular Jacobian.
    #[inline(always)]
    fn velocity_jacobian_lanes<const N: usize>(
        &self,
        _x: &[Task<NX>; N],
        _mode: Self::WorkingMode,
    ) -> Option<JacobianLanes<N>> {
        None
    }

    /// The bend of each passive spherical joint (rad) at an assembled configuration; `None`
    /// when the mechanism has none (the default) or the configuration is not finite.
    fn passive_joint_angles(&self, _x: &Task<NX>, _q: &Joints<NQ>) -> Option<Joints<NQ>> {
        None
    }

    /// The smallest distance between links of neighbouring legs (m); `None` when not modelled
    /// (the default) or the configuration is not finite.
    fn leg_clearance(&self, _x: &Task<NX>, _q: &Joints<NQ>) -> Option<f64> {
        None
    }
}

/// The fraction of the link that ends on the platform, from its far end, on which
/// [`ConstrainedWorkspace::leg_clearance`] is measured: legs converge on the platform by design
/// (a Delta's forearms end $r\sqrt3$ apart), so the stretch next to it is not a collision.
pub const PLATFORM_LINK_CLEARANCE_SPAN: f64 = 0.75;

/// The distance between segments $[p_0, p_1]$ and $[q_0, q_1]$ (Ericson, *Real-Time Collision
/// Detection*, §5.1.9: the closest points by clamped parameters). A point is a segment of zero
/// length. NaN in, NaN out.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_traits::workspace::segment_distance;
/// let (o, x) = (Vector3::zeros(), Vector3::x());
/// let up = Vector3::new(0.5, 1.0, 2.0);
/// assert!((segment_distance((o, x), (up, up + x)) - 5.0_f64.sqrt()).abs() < 1e-15);
/// ```
pub fn segment_distance(
    (p0, p1): (Vector3<f64>, Vector3<f64>),
    (q0, q1): (Vector3<f64>, Vector3<f64>),
) -> f64 {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    const TINY: f64 = 1e-30;
    let (s, t) = if a <= TINY && e <= TINY {
        (0.0, 0.0)
    } else if a <= TINY {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&r);
        if e <= TINY {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s = if denom > TINY * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    ((p0 + d1 * s) - (q0 + d2 * t)).norm()
}

/// The smallest [`segment_distance`] between a segment of `a` and one of `b` (the clearance
/// between two legs' links); NaN when any distance is NaN, $+\infty$ when a side is empty.
pub fn links_distance(
    a: &[(Vector3<f64>, Vector3<f64>)],
    b: &[(Vector3<f64>, Vector3<f64>)],
) -> f64 {
    a.iter()
        .flat_map(|s| b.iter().map(move |t| segment_distance(*s, *t)))
        .fold(f64::INFINITY, crate::checked::min_propagating_nan)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Brute force: the minimum over a fine grid of both parameters.
    fn brute(a: (Vector3<f64>, Vector3<f64>), b: (Vector3<f64>, Vector3<f64>)) -> f64 {
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                let d = (a.0 + (a.1 - a.0) * s) - (b.0 + (b.1 - b.0) * t);
                best = best.min(d.norm());
            }
        }
        best
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        #[test]
        fn segment_distance_matches_brute_force(
            c in proptest::array::uniform12(-1.0f64..1.0)
        ) {
            let v = |k: usize| Vector3::new(c[k], c[k + 1], c[k + 2]);
            let (a, b) = ((v(0), v(3)), (v(6), v(9)));
            let exact = segment_distance(a, b);
            // The grid step is 1/400 of segments of length < 3.5.
            prop_assert!(exact <= brute(a, b) + 1e-12);
            prop_assert!(brute(a, b) - exact < 0.01);
        }
    }

    #[test]
    fn parallel_segments_and_points() {
        let o = Vector3::zeros();
        let x = Vector3::x();
        let up = Vector3::new(0.0, 0.0, 2.0);
        assert!((segment_distance((o, x), (up, up + x)) - 2.0).abs() < 1e-15);
        assert!((segment_distance((o, o), (up, up)) - 2.0).abs() < 1e-15);
        assert!((segment_distance((o, o), (up, up + x)) - 2.0).abs() < 1e-15);
        let nan = Vector3::new(f64::NAN, 0.0, 0.0);
        assert!(links_distance(&[(o, x), (up, up + x)], &[(up, up)]).abs() < 1e-15);
        assert!(links_distance(&[(o, x)], &[]).is_infinite());
        assert!(links_distance(&[(o, x), (nan, x)], &[(up, up)]).is_nan());
    }
}
