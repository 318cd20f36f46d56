//! Lane kernels on groups of [`LANES`] points, run on the vector path of
//! [`pkm_traits::vector_path`] (the widest vector unit of the processor, the same bits on every
//! path).

use crate::LANES;
use nalgebra::Vector3;
use pkm_traits::vector_path::{BlockKernel, VectorPath, run_block_on};

/// A computation on [`LANES`] points at once, written in [`pkm_traits::Lanes`] (for example
/// a batch Jacobian followed by [`crate::inverse_condition_number_3x3_lanes`]).
///
/// For [`evaluate_on`] to compile the whole computation for each path, `evaluate` must be
/// `#[inline(always)]` and call only `#[inline(always)]` kernels (as the batch Jacobians of
/// `pkm-mechanisms` and the lane $1/\kappa$ are); a call that is not inlined runs on the
/// baseline, with the same result, only slower.
pub trait LaneKernel: Sync {
    /// What the kernel returns for the [`LANES`] points.
    type Output;
    /// The kernel on `points`.
    fn evaluate(&self, points: &[Vector3<f64>; LANES]) -> Self::Output;
}

/// A [`LaneKernel`] on one group of points, as a [`BlockKernel`].
struct OneGroup<'a, K>(&'a K, &'a [Vector3<f64>; LANES]);

impl<K: LaneKernel> BlockKernel for OneGroup<'_, K> {
    type Output = K::Output;
    #[inline(always)]
    fn run(&self) -> K::Output {
        self.0.evaluate(self.1)
    }
}

/// `kernel` on `points` compiled for `path`, or for the baseline when this processor cannot
/// run `path`. The result is the same on every path, bit for bit (module documentation).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_workspace_indices::{LANES, LaneKernel, VectorPath, evaluate_on};
/// struct Norms;
/// impl LaneKernel for Norms {
///     type Output = [f64; LANES];
///     #[inline(always)]
///     fn evaluate(&self, points: &[Vector3<f64>; LANES]) -> [f64; LANES] {
///         points.map(|p| (p.x * p.x + p.y * p.y + p.z * p.z).sqrt())
///     }
/// }
/// let points = std::array::from_fn(|l| Vector3::new(l as f64, 0.1, if l == 3 { f64::NAN } else { -0.5 }));
/// let baseline = evaluate_on(VectorPath::Baseline, &Norms, &points);
/// for path in VectorPath::available() {
///     assert_eq!(evaluate_on(path, &Norms, &points).map(f64::to_bits), baseline.map(f64::to_bits));
/// }
/// ```
#[inline]
pub fn evaluate_on<K: LaneKernel>(
    path: VectorPath,
    kernel: &K,
    points: &[Vector3<f64>; LANES],
) -> K::Output {
    run_block_on(path, &OneGroup(kernel, points))
}

/// `kernel` on `points` on [`VectorPath::selected`].
#[inline]
pub fn evaluate<K: LaneKernel>(kernel: &K, points: &[Vector3<f64>; LANES]) -> K::Output {
    evaluate_on(VectorPath::selected(), kernel, points)
}
