//! Planar regions described by their vertical slices: the workspace cross-sections of
//! translation-invariant mechanisms (Miller 2004, §2.2: the Linear Delta's $y$–$z$ section),
//! and [`CrossSectionWorkspace`], the mechanisms whose workspace is such a section.

use crate::{InverseKinematics, JacobianLanes};
use nalgebra::Vector3;

/// Axis-aligned extents $[y_{\min}, y_{\max}] \times [z_{\min}, z_{\max}]$ of a planar set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extents {
    /// Smallest $y$.
    pub y_min: f64,
    /// Largest $y$.
    pub y_max: f64,
    /// Smallest $z$.
    pub z_min: f64,
    /// Largest $z$.
    pub z_max: f64,
}

impl Extents {
    /// The smallest extents that contain `self` and the point `(y, z)`.
    pub fn including(self, y: f64, z: f64) -> Self {
        Self {
            y_min: self.y_min.min(y),
            y_max: self.y_max.max(y),
            z_min: self.z_min.min(z),
            z_max: self.z_max.max(z),
        }
    }

    /// Area $(y_{\max} - y_{\min})(z_{\max} - z_{\min})$.
    pub fn area(&self) -> f64 {
        (self.y_max - self.y_min) * (self.z_max - self.z_min)
    }
}

/// A closed, bounded, non-empty region of the $(y, z)$ plane whose vertical slices are intervals
/// (a convex region, for instance), with the abscissae where the curves bounding the slices
/// change.
///
/// Between two consecutive [`SlicedRegion::breakpoints`] the lower and upper bounds of the slice
/// are smooth functions of $y$, so a quadrature on each such interval converges fast.
pub trait SlicedRegion: Sync {
    /// The slice $\{z : (y, z) \in W\} = [\text{lo}(y), \text{hi}(y)]$, or `None` when it is
    /// empty.
    fn slice(&self, y: f64) -> Option<(f64, f64)>;

    /// Sorted abscissae, from $y_{\min}$ to $y_{\max}$ inclusive, between which the slice bounds
    /// are smooth.
    fn breakpoints(&self) -> &[f64];

    /// Axis-aligned extents of the region.
    fn extents(&self) -> Extents;

    /// Exact area of the region.
    fn area(&self) -> f64;

    /// Whether `(y, z)` lies in the region (closed test, no tolerance).
    fn contains(&self, y: f64, z: f64) -> bool {
        self.slice(y).is_some_and(|(lo, hi)| lo <= z && z <= hi)
    }
}

/// A mechanism whose workspace is a prism along $x$: the task is invariant under translations
/// along $x$ (the actuators slide on rails parallel to it), so the workspace is $W \times
/// \mathbb{R}$ for a planar cross-section $W$ in the $(y, z)$ plane and its indices are area
/// means over $W$ (the Linear Delta of Miller 2004, §2.2: $\eta_1$, eq. 1, and $\eta_2$, eq. 2).
///
/// Implemented by a mechanism so that `pkm-workspace-indices` computes its cross-section
/// indices without naming it.
pub trait CrossSectionWorkspace: InverseKinematics<3, 3> {
    /// The exact cross-section.
    type CrossSection: SlicedRegion;

    /// The workspace cross-section $W$ in the $(y, z)$ plane, for the working modes the
    /// cross-section describes.
    fn cross_section(&self) -> Self::CrossSection;

    /// The fixed points $(y, z)$ of the actuators in the section plane (the rails), which the
    /// machine's footprint contains besides $W$ (eq. 2).
    fn actuator_points(&self) -> Vec<[f64; 2]>;

    /// The velocity Jacobians $J$ at the `N` points $(0, y, z_l)$ of one slice of $W$, in
    /// [`JacobianLanes`] (a lane is unreachable where $J$ is not defined). $J$ does not depend
    /// on $x$. Callers ask only at points of $W$.
    ///
    /// The default calls [`InverseKinematics::velocity_jacobian_at`] lane by lane; a mechanism
    /// with a batch kernel overrides it with the same floating-point operations.
    fn cross_section_jacobian_lanes<const N: usize>(
        &self,
        y: f64,
        z: &[f64; N],
        mode: Self::WorkingMode,
    ) -> JacobianLanes<N> {
        let mut lanes = JacobianLanes {
            jacobian: [[0.0; N]; 9],
            reachable: [false; N],
        };
        for (lane, &z) in z.iter().enumerate() {
            if let Ok(j) = self.velocity_jacobian_at(&Vector3::new(0.0, y, z), mode) {
                for (entry, value) in lanes.jacobian.iter_mut().zip(j.transpose().iter()) {
                    entry[lane] = *value;
                }
                lanes.reachable[lane] = true;
            }
        }
        lanes
    }
}
