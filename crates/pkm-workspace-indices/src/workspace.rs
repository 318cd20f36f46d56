//! The workspace of any translational mechanism with closed-form inverse kinematics: the
//! positions at which one of the allowed working modes assembles and every
//! [`WorkspaceConstraint`] holds; its volume $W$, the condition integral
//! $\eta = \int 1/\kappa\, dW$ and the global condition index $\mathrm{GCI} = \eta / W$ over a
//! [`PointSet`] of any [`crate::Domain`] ([`Workspace::volume_and_eta`]) or over unit points
//! scaled per design ([`Workspace::hemisphere_estimate`]), and sections of $1/\kappa$ on any
//! coordinate plane ([`Workspace::inverse_condition_slice`]). This is the one path from a
//! mechanism to its workspace indices: mechanism → velocity Jacobian → $1/\kappa$ → estimator.
//!
//! The local index is $1/\kappa(J)$ of the velocity Jacobian $J = -J_q^{-1} J_x$ at the first
//! mode that assembles ([`crate::inverse_condition_at`], through
//! [`pkm_traits::InverseKinematics::velocity_jacobian_at`], which a mechanism may override with
//! a closed form), 0 at an inverse-kinematic singularity. With constraints on the joints the
//! Jacobian is [`pkm_traits::ClosedChain::jacobian`] at the joints that satisfy them.
//!
//! The number of actuated joints `NQ` may exceed the three task coordinates (a Stewart–Gough
//! platform at a fixed orientation, `NQ = 6`): $J$ is then $NQ \times 3$ and $1/\kappa$ is
//! $\sigma_3/\sigma_1$ of its singular values ([`TranslationalCondition`]). `NQ` defaults to 3.

use crate::PointSource;
use crate::estimator::{count_volume, integrate_blocks};
use crate::point_groups::PointGroups;
use crate::volume::hemisphere_estimate_blocks;
use crate::{
    BlockKernel, BoundingBox, Dim, HemisphereEstimate, IndexError, LANES, LaneKernel, Plane,
    PointSet, Slice, TranslationalCondition, VolumeEstimate, evaluate,
    inverse_condition_of_reachable_lanes, run_block,
};
use nalgebra::Vector3;
use pkm_traits::{
    ConstrainedWorkspace, InvalidInput, Joints, KinematicsError, Lanes, Progress,
    WorkspaceConstraint,
};

/// How many points of `groups` belong to a workspace: the mechanism's lane reachability, then,
/// for the lanes it reaches, the position constraints and (where some constraint needs the
/// joints) the assembly, per lane. Exact: a mechanism's reachability agrees with its inverse
/// kinematics ([`ConstrainedWorkspace::reachable`]), so no point it rejects can assemble.
struct CountInside<'a, 'm, M: ConstrainedWorkspace<3, NQ>, const NQ: usize> {
    workspace: &'a Workspace<'m, M, NQ>,
    groups: &'a [[Lanes<LANES>; 3]],
}

impl<M, const NQ: usize> BlockKernel for CountInside<'_, '_, M, NQ>
where
    M: ConstrainedWorkspace<3, NQ> + Sync,
    Dim<NQ>: TranslationalCondition<NQ>,
{
    type Output = u64;

    #[inline(always)]
    fn run(&self) -> u64 {
        let ws = self.workspace;
        let mut count = 0;
        for group in self.groups {
            count += ws
                .inside_group(group)
                .into_iter()
                .map(u64::from)
                .sum::<u64>();
        }
        count
    }
}

/// [`Workspace::count_inside`]: the points transposed into lanes group by group, as they are
/// read (one pass needs no transposed copy).
struct CountInsidePoints<'a, 'm, M: ConstrainedWorkspace<3, NQ>, const NQ: usize> {
    workspace: &'a Workspace<'m, M, NQ>,
    points: &'a [Vector3<f64>],
}

impl<M, const NQ: usize> BlockKernel for CountInsidePoints<'_, '_, M, NQ>
where
    M: ConstrainedWorkspace<3, NQ> + Sync,
    Dim<NQ>: TranslationalCondition<NQ>,
{
    type Output = u64;

    #[inline(always)]
    fn run(&self) -> u64 {
        let ws = self.workspace;
        let groups = self.points.chunks_exact(LANES);
        let rest = groups.remainder();
        let mut count = rest.iter().filter(|x| ws.contains(x)).count() as u64;
        for group in groups.filter_map(|g| <&[Vector3<f64>; LANES]>::try_from(g).ok()) {
            let inside = ws.inside_group(&Lanes::coordinates(group));
            count += inside.into_iter().map(u64::from).sum::<u64>();
        }
        count
    }
}

/// Point `l` of a group whose coordinates are in lanes.
#[inline(always)]
fn lane_point(group: &[Lanes<LANES>; 3], l: usize) -> Vector3<f64> {
    Vector3::new(group[0].0[l], group[1].0[l], group[2].0[l])
}

/// [`Workspace::contains`] at one group of [`LANES`] points.
struct ContainsLanes<'a, 'm, M: ConstrainedWorkspace<3, NQ>, const NQ: usize> {
    workspace: &'a Workspace<'m, M, NQ>,
    points: &'a [Vector3<f64>; LANES],
}

impl<M, const NQ: usize> BlockKernel for ContainsLanes<'_, '_, M, NQ>
where
    M: ConstrainedWorkspace<3, NQ> + Sync,
    Dim<NQ>: TranslationalCondition<NQ>,
{
    type Output = [bool; LANES];

    #[inline(always)]
    fn run(&self) -> [bool; LANES] {
        self.workspace
            .inside_group(&Lanes::coordinates(self.points))
    }
}

/// [`Workspace::inverse_condition`] at [`LANES`] points by the mechanism's lane Jacobians and
/// the lane $1/\kappa$, for a workspace whose constraints are all on the position; `None`
/// when the mechanism has no lane kernel for one of the modes it needs.
struct ConditionLanes<'w, 'm, M: ConstrainedWorkspace<3, NQ>, const NQ: usize>(
    &'w Workspace<'m, M, NQ>,
);

impl<M, const NQ: usize> LaneKernel for ConditionLanes<'_, '_, M, NQ>
where
    M: ConstrainedWorkspace<3, NQ> + Sync,
    Dim<NQ>: TranslationalCondition<NQ>,
{
    type Output = Option<[Option<f64>; LANES]>;

    #[inline(always)]
    fn evaluate(&self, points: &[Vector3<f64>; LANES]) -> Self::Output {
        let ws = self.0;
        let mut out = [None; LANES];
        let mut pending: [bool; LANES] = std::array::from_fn(|l| ws.position_allowed(&points[l]));
        for mode in &ws.modes {
            if !pending.contains(&true) {
                break;
            }
            let j = ws.mechanism.velocity_jacobian_lanes(points, *mode)?;
            let values = inverse_condition_of_reachable_lanes(&j);
            for l in 0..LANES {
                if pending[l] && values[l].is_some() {
                    out[l] = values[l];
                    pending[l] = false;
                }
            }
        }
        Some(out)
    }
}

/// A mechanism, the working modes it may use and the constraints of its workspace.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_traits::{Silent, WorkspaceConstraint};
/// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
/// use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, Workspace};
/// let delta = RotaryDelta::new(presets::miller_delta(Placement { motor_plane_z: 0.0, azimuth_motor_1: 0.0 }))?;
/// let below = WorkspaceConstraint::below(0.0)?;
/// let arm_limits = WorkspaceConstraint::joint_range(-0.5, 1.5)?;
/// let ws = Workspace::new(&delta, &[ElbowMode::Out], &[below, arm_limits])?;
/// let domain = Domain::new(Region::axial_cylinder(0.9, -0.8, 0.0))?
///     .with_sector(3, 0.0)?;
/// let points = PointSet::new(domain, Sampler::Sobol { seed: 1 }, 4096, 4)?;
/// let v = ws.volume(&points, &Silent)?;
/// assert!(v.volume > 0.0 && v.volume_se < 0.05 * v.volume);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Workspace<'m, M, const NQ: usize = 3>
where
    M: ConstrainedWorkspace<3, NQ>,
{
    mechanism: &'m M,
    modes: Vec<M::WorkingMode>,
    on_position: Vec<WorkspaceConstraint>,
    on_joints: Vec<WorkspaceConstraint>,
}

impl<'m, M, const NQ: usize> Workspace<'m, M, NQ>
where
    M: ConstrainedWorkspace<3, NQ> + Sync,
    Dim<NQ>: TranslationalCondition<NQ>,
{
    /// The workspace of `mechanism` in any of `modes` under `constraints`.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for no mode; [`IndexError::Constraint`] for a constraint the
    /// mechanism cannot evaluate.
    pub fn new(
        mechanism: &'m M,
        modes: &[M::WorkingMode],
        constraints: &[WorkspaceConstraint],
    ) -> Result<Self, IndexError> {
        if modes.is_empty() {
            return Err(InvalidInput::new("working modes", 0.0, "at least one mode").into());
        }
        for c in constraints {
            c.check_applies(mechanism)?;
        }
        let (on_joints, on_position) = constraints.iter().partition(|c| c.needs_joints());
        Ok(Self {
            mechanism,
            modes: modes.to_vec(),
            on_position,
            on_joints,
        })
    }

    /// The mechanism.
    pub fn mechanism(&self) -> &M {
        self.mechanism
    }

    /// Whether `x` belongs to the workspace.
    pub fn contains(&self, x: &Vector3<f64>) -> bool {
        if !self.position_allowed(x) {
            return false;
        }
        if self.on_joints.is_empty() {
            self.mechanism.reachable_in_any(x, &self.modes)
        } else {
            self.assemble(x).is_some()
        }
    }

    /// How many of `points` belong to the workspace: [`Workspace::contains`] at each, the
    /// mechanism's lane test [`ConstrainedWorkspace::reachable_in_any_lanes`] asked first,
    /// [`LANES`] points at a time on the vector path of [`crate::run_block`], and the
    /// constraints only where it reaches. The count is that of `contains`, point for point.
    ///
    /// # Example
    /// ```
    /// use pkm_traits::WorkspaceConstraint;
    /// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
    /// use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, Workspace};
    /// let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical()))?;
    /// let ws = Workspace::new(&delta, &[ElbowMode::Out], &[WorkspaceConstraint::below(0.0)?])?;
    /// let domain = Domain::new(Region::axial_cylinder(0.9, -1.2, 0.2))?;
    /// let points = PointSet::new(domain, Sampler::Sobol { seed: 1 }, 1001, 1)?;
    /// let one_by_one = points.points().iter().filter(|x| ws.contains(x)).count() as u64;
    /// assert_eq!(ws.count_inside(points.points()), one_by_one);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn count_inside(&self, points: &[Vector3<f64>]) -> u64 {
        run_block(&CountInsidePoints {
            workspace: self,
            points,
        })
    }

    /// [`Workspace::contains`] at [`LANES`] points at once, the mechanism's lane test
    /// [`ConstrainedWorkspace::reachable_in_any_lanes`] asked first on the vector path of
    /// [`crate::run_block`] (as [`Workspace::count_inside`]): the same answers.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
    /// use pkm_workspace_indices::{LANES, Workspace};
    /// let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical()))?;
    /// let ws = Workspace::new(&delta, &[ElbowMode::Out], &[])?;
    /// let points = std::array::from_fn(|l| Vector3::new(0.0, 0.1 * l as f64, -0.7));
    /// let inside = ws.contains_lanes(&points);
    /// assert!((0..LANES).all(|l| inside[l] == ws.contains(&points[l])));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn contains_lanes(&self, points: &[Vector3<f64>; LANES]) -> [bool; LANES] {
        run_block(&ContainsLanes {
            workspace: self,
            points,
        })
    }

    /// [`Workspace::contains`] at the points of one group (coordinates in lanes).
    #[inline(always)]
    fn inside_group(&self, group: &[Lanes<LANES>; 3]) -> [bool; LANES] {
        let reachable = self.mechanism.reachable_in_any_lanes(group, &self.modes);
        std::array::from_fn(|l| reachable[l] && self.inside_if_reachable(&lane_point(group, l)))
    }

    /// [`Workspace::contains`] at a point that the mechanism reaches in one of the modes.
    #[inline]
    fn inside_if_reachable(&self, x: &Vector3<f64>) -> bool {
        self.position_allowed(x) && (self.on_joints.is_empty() || self.assemble(x).is_some())
    }

    /// [`Workspace::count_inside`] of the points of `points`.
    pub(crate) fn count_in_groups(&self, points: &PointGroups) -> u64 {
        let kernel = CountInside {
            workspace: self,
            groups: &points.groups,
        };
        let rest = points.rest.iter().filter(|x| self.contains(x)).count() as u64;
        run_block(&kernel) + rest
    }

    /// The joints of the first listed mode that assembles at `x` within every constraint.
    pub fn assembly(&self, x: &Vector3<f64>) -> Option<Joints<NQ>> {
        if self.position_allowed(x) {
            self.assemble(x)
        } else {
            None
        }
    }

    fn position_allowed(&self, x: &Vector3<f64>) -> bool {
        self.on_position.iter().all(|c| c.holds_at_position(x))
    }

    /// [`Workspace::assembly`] for a position that satisfies the position constraints.
    fn assemble(&self, x: &Vector3<f64>) -> Option<Joints<NQ>> {
        self.modes.iter().find_map(|mode| {
            let q = self.mechanism.inverse_kinematics(x, *mode).ok()?;
            self.on_joints
                .iter()
                .all(|c| c.holds(self.mechanism, x, &q))
                .then_some(q)
        })
    }

    /// $1/\kappa(J)$ at `x` (0 at a singular $J_q$), `None` outside the workspace.
    pub fn inverse_condition(&self, x: &Vector3<f64>) -> Option<f64> {
        if !self.position_allowed(x) {
            return None;
        }
        if self.on_joints.is_empty() {
            return self.modes.iter().find_map(|mode| {
                // As crate::inverse_condition_at: 0 where J is undefined.
                match self.mechanism.velocity_jacobian_at(x, *mode) {
                    Ok(j) => Some(<Dim<NQ> as TranslationalCondition<NQ>>::inverse_condition(
                        &j,
                    )),
                    Err(KinematicsError::Singular { .. }) => Some(0.0),
                    Err(_) => None,
                }
            });
        }
        let q = self.assemble(x)?;
        Some(self.mechanism.jacobian(x, &q).map_or(0.0, |j| {
            <Dim<NQ> as TranslationalCondition<NQ>>::inverse_condition(&j)
        }))
    }

    /// [`Workspace::inverse_condition`] at [`LANES`] points at once. Where the mechanism has
    /// lane Jacobians for every mode ([`ConstrainedWorkspace::velocity_jacobian_lanes`]),
    /// $J$ is square and no constraint needs the joints, they and
    /// [`crate::inverse_condition_number_3x3_lanes`] run on the vector path of
    /// [`crate::evaluate`]; otherwise point by point. The lane kernels equal the point-by-point
    /// ones to rounding: $1/\kappa$ to about $10^{-12}$ relative for $\kappa \le 10^2$, and
    /// membership may differ only within rounding of the workspace boundary.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
    /// use pkm_workspace_indices::{LANES, Workspace};
    /// let tsai = Tsai3Dof::new(presets::stamper_max_gci())?;
    /// let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[])?;
    /// let points = std::array::from_fn(|l| Vector3::new(0.02 * l as f64, -0.1, 0.4));
    /// for (x, lane) in points.iter().zip(ws.inverse_condition_lanes(&points)) {
    ///     let one = ws.inverse_condition(x).unwrap();
    ///     assert!((lane.unwrap() - one).abs() < 1e-12);
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn inverse_condition_lanes(&self, points: &[Vector3<f64>; LANES]) -> [Option<f64>; LANES] {
        let lanes = (NQ == 3 && self.on_joints.is_empty())
            .then(|| evaluate(&ConditionLanes(self), points))
            .flatten();
        lanes.unwrap_or_else(|| std::array::from_fn(|l| self.inverse_condition(&points[l])))
    }

    /// [`Workspace::inverse_condition_lanes`] over `points`, [`LANES`] at a time, into `out`
    /// (the same length); the remainder point by point.
    fn inverse_condition_block(&self, points: &[Vector3<f64>], out: &mut [Option<f64>]) {
        let groups = points.chunks_exact(LANES);
        let rest = points.len() - groups.remainder().len();
        for (group, values) in groups.zip(out.chunks_exact_mut(LANES)) {
            if let Ok(group) = <&[Vector3<f64>; LANES]>::try_from(group) {
                values.copy_from_slice(&self.inverse_condition_lanes(group));
            }
        }
        for (x, value) in points[rest..].iter().zip(&mut out[rest..]) {
            *value = self.inverse_condition(x);
        }
    }

    /// The workspace volume over `points`.
    ///
    /// # Errors
    /// [`IndexError::Cancelled`].
    pub fn volume(
        &self,
        points: &PointSet,
        progress: &dyn Progress,
    ) -> Result<VolumeEstimate, IndexError> {
        count_volume(points, progress, |block| self.count_inside(block))
    }

    /// The workspace volume and $\eta = \int 1/\kappa\, dW$ over `points` (GCI = η/W by
    /// [`VolumeEstimate::gci`]).
    ///
    /// # Errors
    /// [`IndexError::Cancelled`].
    pub fn volume_and_eta<P: PointSource + ?Sized>(
        &self,
        points: &P,
        progress: &dyn Progress,
    ) -> Result<VolumeEstimate, IndexError> {
        integrate_blocks(
            points.count(),
            |range| points.block(range),
            points.replicates() as usize,
            points.domain().volume(),
            progress,
            |block, out| self.inverse_condition_block(block, out),
        )
    }

    /// $W$ and $\eta = \int 1/\kappa\, dW$ over the hemisphere of `radius` about the origin,
    /// from `unit_points` in the unit hemisphere scaled by `radius`
    /// ([`crate::hemisphere_estimate`]): the common random points of a study whose designs
    /// differ in reach (Stamper, Tsai & Walsh 1997). GCI = η/W by [`HemisphereEstimate::gci`].
    ///
    /// # Errors
    /// As [`crate::hemisphere_estimate`].
    ///
    /// # Example
    /// ```
    /// use pkm_traits::Silent;
    /// use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
    /// use pkm_workspace_indices::{Sampler, Workspace};
    /// let tsai = Tsai3Dof::new(presets::stamper_max_gci())?;
    /// let unit = Sampler::Sobol { seed: 7 }.unit_hemisphere_points(20_000)?;
    /// let e = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[])?
    ///     .hemisphere_estimate(&unit, tsai.reach(), &Silent)?;
    /// let gci = e.gci().unwrap();
    /// assert!(e.volume > 0.0 && gci > 0.0 && gci < 1.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn hemisphere_estimate(
        &self,
        unit_points: &[Vector3<f64>],
        radius: f64,
        progress: &dyn Progress,
    ) -> Result<HemisphereEstimate, IndexError> {
        hemisphere_estimate_blocks(unit_points, radius, progress, |block, out| {
            self.inverse_condition_block(block, out);
        })
    }

    /// $1/\kappa$ on the `n × n` cell centres of `plane` at offset `at` over the extent of
    /// `bounds` in that plane ([`Slice::on_plane`]), `None` outside the workspace.
    ///
    /// # Errors
    /// As [`Slice::on_plane`].
    ///
    /// # Example
    /// ```
    /// use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
    /// use pkm_workspace_indices::{Plane, Region, Workspace};
    /// let tsai = Tsai3Dof::new(presets::stamper_max_gci())?;
    /// let ws = Workspace::new(&tsai, &[[Elbow::Out; 3]], &[])?;
    /// let reach = Region::Ball { center: nalgebra::Vector3::zeros(), radius: tsai.reach() };
    /// let side = ws.inverse_condition_slice(Plane::Xz, 0.0, &reach.bounding_box(), 24)?;
    /// let (best, _, _) = side.max().unwrap();
    /// assert!(best > 0.0 && best <= 1.0);
    /// assert!(side.values.iter().any(Option::is_none)); // the corners of the box are outside
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn inverse_condition_slice(
        &self,
        plane: Plane,
        at: f64,
        bounds: &BoundingBox,
        n: usize,
    ) -> Result<Slice, IndexError> {
        Slice::on_plane(plane, at, bounds, n, |p| self.inverse_condition(p))
    }
}
