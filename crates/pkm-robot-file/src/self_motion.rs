//! Self-motions among the solutions of a multistart: singular solutions at one set of actuator
//! coordinates that lie on one continuum (the platform moves while every actuator is held, as a
//! 3-RPR with congruent base and platform translating on a circle) are one result, not one per
//! start that happened to land on it.
//!
//! Two singular solutions $a$, $b$ are linked when the continuum joins them: the midpoint of
//! the segment between their configurations, projected onto the closure with the actuators
//! held (damped Newton), is singular again and within a quarter of the segment's length of
//! the midpoint, and each half is linked in turn, down to segments shorter than
//! [`LINK_LENGTH`] (at most [`LINK_DEPTH`] halvings). Linked solutions are merged (union–find)
//! in Borůvka's rounds: each component tries its [`NEIGHBOURS`] nearest components through
//! their closest pair of solutions, nearest pairs first, until a round merges none; so a
//! continuum sampled in clusters (as the starts of a multistart fall) is one component. A
//! singular solution within half a link length of one already kept joins it unlinked, which
//! bounds the work by the continuum's extent instead of the number of starts.

use crate::chain::{Joint, JointValue};
use crate::closure::Configuration;
use crate::leg_ik::wrap_angle;
use crate::model::RobotModel;
use nalgebra::{UnitQuaternion, Vector3};

/// Direct margin below which a solution is singular, a candidate point of a self-motion.
pub(crate) const SINGULAR_MARGIN: f64 = 1e-6;
/// Segments shorter than this (pose distance: positions in robot sizes, rotations as the
/// largest entry of the difference of the rotation matrices) need no further halving.
const LINK_LENGTH: f64 = 1e-2;
/// Most halvings of a segment between two solutions.
const LINK_DEPTH: usize = 6;
/// Nearest singular solutions each one is tried against.
const NEIGHBOURS: usize = 6;

/// A continuum of assembly modes at one set of actuator coordinates: the platform moves while
/// every actuator is held.
#[derive(Debug, Clone, PartialEq)]
pub struct SelfMotion {
    /// How many of the distinct solutions found lie on it (every one was a start's solution).
    pub samples: usize,
    /// The largest distance between two of them: the larger of their position difference in
    /// robot sizes (its largest coordinate) and the largest entry of the difference of their
    /// rotation matrices (a lower bound of the span of the continuum).
    pub extent: f64,
}

impl RobotModel {
    /// The groups of `singular` (indices into `solutions`) that lie on one self-motion at the
    /// actuator coordinates `q`: each group of two or more, in the order of its first member.
    pub(crate) fn self_motions(
        &self,
        q: &[f64],
        solutions: &[Configuration],
        singular: &[usize],
    ) -> Vec<Vec<usize>> {
        let at = |k: usize| &solutions[singular[k]];
        // Thinning: a solution within half a link length of a kept one joins it.
        let mut kept: Vec<usize> = Vec::new();
        let owner: Vec<usize> = (0..singular.len())
            .map(|k| {
                let near = |&r: &usize| self.pose_distance(at(r), at(k)) < 0.5 * LINK_LENGTH;
                kept.iter().position(near).unwrap_or_else(|| {
                    kept.push(k);
                    kept.len() - 1
                })
            })
            .collect();
        let n = kept.len();
        let mut parent: Vec<usize> = (0..n).collect();
        // Borůvka's rounds: each component tries its nearest components (through their
        // closest pair of solutions), until a round merges none.
        loop {
            let roots: Vec<usize> = (0..n).map(|a| root(&mut parent, a)).collect();
            let mut nearest: Vec<Vec<(f64, usize, usize, usize)>> = vec![Vec::new(); n];
            for a in 0..n {
                for b in a + 1..n {
                    let (ra, rb) = (roots[a], roots[b]);
                    if ra != rb {
                        let d = self.pose_distance(at(kept[a]), at(kept[b]));
                        offer(&mut nearest[ra], (d, a, b, rb));
                        offer(&mut nearest[rb], (d, a, b, ra));
                    }
                }
            }
            let mut tried: Vec<(f64, usize, usize)> = nearest
                .into_iter()
                .flatten()
                .map(|(d, a, b, _)| (d, a, b))
                .collect();
            tried.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
            tried.dedup();
            let mut merged = false;
            for (_, a, b) in tried {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                if ra != rb && self.linked(q, at(kept[a]), at(kept[b]), 0) {
                    parent[ra.max(rb)] = ra.min(rb);
                    merged = true;
                }
            }
            if !merged {
                break;
            }
        }
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut group_of_root = vec![usize::MAX; n];
        for (k, &r) in owner.iter().enumerate() {
            let r = root(&mut parent, r);
            if group_of_root[r] == usize::MAX {
                group_of_root[r] = groups.len();
                groups.push(Vec::new());
            }
            groups[group_of_root[r]].push(singular[k]);
        }
        groups.retain(|g| g.len() >= 2);
        groups
    }

    /// The largest pose distance between two members of `group`.
    pub(crate) fn extent(&self, solutions: &[Configuration], group: &[usize]) -> f64 {
        let mut extent: f64 = 0.0;
        for (k, &a) in group.iter().enumerate() {
            for &b in &group[..k] {
                extent = extent.max(self.pose_distance(&solutions[a], &solutions[b]));
            }
        }
        extent
    }

    /// Whether the continuum of singular solutions at `q` joins `a` and `b` (module docs).
    fn linked(&self, q: &[f64], a: &Configuration, b: &Configuration, depth: usize) -> bool {
        let d = self.pose_distance(a, b);
        if depth > 0 && d < LINK_LENGTH {
            return true;
        }
        if depth == LINK_DEPTH {
            return false;
        }
        let middle = self.midpoint(a, b);
        let Ok(m) = self.forward_kinematics_from(q, &middle) else {
            return false;
        };
        let singular = self
            .singularity_margins(&m)
            .is_ok_and(|margins| margins.direct < SINGULAR_MARGIN);
        singular
            && self.pose_distance(&m, &middle) <= 0.25 * d
            && self.linked(q, a, &m, depth + 1)
            && self.linked(q, &m, b, depth + 1)
    }

    /// The configuration halfway between `a` and `b`: pose coordinates and prismatic joints
    /// linearly, revolute joints along the shorter arc, spherical joints by slerp.
    fn midpoint(&self, a: &Configuration, b: &Configuration) -> Configuration {
        let mut m = a.clone();
        for k in 0..6 {
            m.pose[k] = 0.5 * (a.pose[k] + b.pose[k]);
        }
        for (i, leg) in self.legs.iter().enumerate() {
            for (j, joint) in leg.joints.iter().enumerate() {
                m.joints[i][j] = match (a.joints[i][j], b.joints[i][j]) {
                    (JointValue::Scalar(x), JointValue::Scalar(y)) => {
                        let d = match joint {
                            Joint::Revolute { .. } => wrap_angle(y - x),
                            _ => y - x,
                        };
                        JointValue::Scalar(x + 0.5 * d)
                    }
                    (JointValue::Ball(x), JointValue::Ball(y)) => {
                        let (x, y) = (
                            UnitQuaternion::from_rotation_matrix(&x),
                            UnitQuaternion::from_rotation_matrix(&y),
                        );
                        JointValue::Ball(x.slerp(&y, 0.5).to_rotation_matrix())
                    }
                    (x, _) => x,
                };
            }
        }
        m
    }

    /// The distance of two platform poses: positions in robot sizes, rotations as the largest
    /// entry of the difference of their rotation matrices; the larger of the two.
    fn pose_distance(&self, a: &Configuration, b: &Configuration) -> f64 {
        let position = (0..3)
            .map(|k| (a.pose[k] - b.pose[k]).abs())
            .fold(0.0, f64::max)
            / self.size;
        let rotation = |c: &Configuration| {
            self.orientation
                .rotation(&Vector3::new(c.pose[3], c.pose[4], c.pose[5]))
        };
        position.max((rotation(a).matrix() - rotation(b).matrix()).amax())
    }
}

/// Keeps in `best` the [`NEIGHBOURS`] nearest other components (the last entry of `pair`),
/// each through its closest pair.
fn offer(best: &mut Vec<(f64, usize, usize, usize)>, pair: (f64, usize, usize, usize)) {
    if let Some(same) = best.iter_mut().find(|e| e.3 == pair.3) {
        if pair.0 < same.0 {
            *same = pair;
        }
    } else if best.len() < NEIGHBOURS {
        best.push(pair);
    } else if let Some(worst) = best.iter_mut().max_by(|x, y| x.0.total_cmp(&y.0))
        && pair.0 < worst.0
    {
        *worst = pair;
    }
}

/// The root of `a` in the union–find forest `parent`, halving the path on the way.
fn root(parent: &mut [usize], mut a: usize) -> usize {
    while parent[a] != a {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    a
}
