//! The output of the batch (lane-parallel) Jacobian kernels: `N` velocity Jacobians in
//! structure-of-arrays form and which lanes are reachable.

/// `N` velocity Jacobians $J = -J_q^{-1}J_x$ of a 3-DOF mechanism, lanes innermost, with the
/// reachability of each lane. The layout is `pkm_workspace_indices::Matrix3Lanes`, so
/// `jacobian` feeds `inverse_condition_number_3x3_lanes` directly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianLanes<const N: usize> {
    /// Entry $(i, j)$ of the Jacobian in lane `l` is `jacobian[3 * i + j][l]`; meaningless (often
    /// NaN or infinite) in a lane that is not reachable.
    pub jacobian: [[f64; N]; 9],
    /// Whether lane `l` is a finite point where every leg's inverse kinematics has a solution
    /// at which $J$ is defined.
    pub reachable: [bool; N],
}

impl<const N: usize> JacobianLanes<N> {
    /// The Jacobian of lane `lane` as a matrix, `None` when that lane is not reachable or
    /// `lane >= N`.
    pub fn matrix(&self, lane: usize) -> Option<nalgebra::Matrix3<f64>> {
        (*self.reachable.get(lane)?)
            .then(|| nalgebra::Matrix3::from_fn(|i, j| self.jacobian[3 * i + j][lane]))
    }
}
