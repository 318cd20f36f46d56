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

use crate::{
    BoundingBox, Dim, HemisphereEstimate, IndexError, Plane, PointSet, Slice,
    TranslationalCondition, VolumeEstimate, hemisphere_estimate, workspace_volume,
    workspace_volume_and_eta,
};
use nalgebra::Vector3;
use pkm_traits::{
    ConstrainedWorkspace, InvalidInput, Joints, KinematicsError, Progress, WorkspaceConstraint,
};

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

    /// The workspace volume over `points`.
    ///
    /// # Errors
    /// [`IndexError::Cancelled`].
    pub fn volume(
        &self,
        points: &PointSet,
        progress: &dyn Progress,
    ) -> Result<VolumeEstimate, IndexError> {
        workspace_volume(points, progress, |x| self.contains(x))
    }

    /// The workspace volume and $\eta = \int 1/\kappa\, dW$ over `points` (GCI = η/W by
    /// [`VolumeEstimate::gci`]).
    ///
    /// # Errors
    /// [`IndexError::Cancelled`].
    pub fn volume_and_eta(
        &self,
        points: &PointSet,
        progress: &dyn Progress,
    ) -> Result<VolumeEstimate, IndexError> {
        workspace_volume_and_eta(points, progress, |x| self.inverse_condition(x))
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
        hemisphere_estimate(unit_points, radius, progress, |x| self.inverse_condition(x))
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
