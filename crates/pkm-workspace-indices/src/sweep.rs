//! Volumes of many designs over one [`PointSet`]: the common random points make differences and
//! ratios between designs free of independent sampling noise, and the arg-max of a sweep a
//! property of the designs, not of the draw.
//!
//! Designs are evaluated in parallel (rayon), each over all points serially, and collected in
//! input order: the result is bit-identical for any thread count. Progress advances by one per
//! design; cancellation is checked before each design.

use crate::estimator::{Sums, summarise};
use crate::point_groups::PointGroups;
use crate::{Dim, IndexError, PointSet, TranslationalCondition, VolumeEstimate, Workspace};
use nalgebra::Vector3;
use pkm_traits::{ConstrainedWorkspace, Progress};
use rayon::prelude::*;

/// The workspace volume of every design in `designs`, `contains(design, x)` being its
/// membership test.
///
/// # Errors
/// [`IndexError::Cancelled`]; [`IndexError::EmptySample`] for no designs.
///
/// # Example
/// ```
/// use pkm_traits::Silent;
/// use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, sweep_volumes};
/// use nalgebra::Vector3;
/// let domain = Domain::new(Region::Ball { center: Vector3::zeros(), radius: 1.0 })?;
/// let points = PointSet::new(domain, Sampler::Sobol { seed: 9 }, 1 << 12, 2)?;
/// let radii = [0.5, 0.8];
/// let v = sweep_volumes(&radii, &points, &Silent, |r, x| x.norm() <= *r)?;
/// let ratio = v[1].volume / v[0].volume; // (0.8 / 0.5)³ = 4.096
/// assert!((ratio - 4.096).abs() < 0.1);
/// # Ok::<(), pkm_workspace_indices::IndexError>(())
/// ```
pub fn sweep_volumes<D, F>(
    designs: &[D],
    points: &PointSet,
    progress: &dyn Progress,
    contains: F,
) -> Result<Vec<VolumeEstimate>, IndexError>
where
    D: Sync,
    F: Fn(&D, &Vector3<f64>) -> bool + Sync,
{
    sweep_counts(designs, points, progress, |design, _, block| {
        block.iter().filter(|x| contains(design, x)).count() as u64
    })
}

/// The volume of every workspace in `workspaces`: [`sweep_volumes`] with
/// [`Workspace::count_inside`], which asks the mechanism's lane test where it has one (the
/// same counts, faster).
///
/// # Errors
/// As [`sweep_volumes`].
///
/// # Example
/// ```
/// use pkm_traits::{Silent, WorkspaceConstraint};
/// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
/// use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, Workspace, sweep_volumes, sweep_workspace_volumes};
/// let place = Placement::canonical();
/// let robots = [RotaryDelta::new(presets::miller_delta(place))?, RotaryDelta::new(presets::nuwar(place))?];
/// let below = [WorkspaceConstraint::below(place.motor_plane_z)?];
/// let ws: Vec<_> = robots.iter().map(|r| Workspace::new(r, &[ElbowMode::Out], &below)).collect::<Result<_, _>>()?;
/// let domain = Domain::new(Region::axial_cylinder(1.0, -1.5, 0.0))?;
/// let points = PointSet::new(domain, Sampler::Sobol { seed: 5 }, 4000, 2)?;
/// let fast = sweep_workspace_volumes(&ws, &points, &Silent)?;
/// assert_eq!(fast, sweep_volumes(&ws, &points, &Silent, |w, x| w.contains(x))?);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn sweep_workspace_volumes<M, const NQ: usize>(
    workspaces: &[Workspace<'_, M, NQ>],
    points: &PointSet,
    progress: &dyn Progress,
) -> Result<Vec<VolumeEstimate>, IndexError>
where
    M: ConstrainedWorkspace<3, NQ> + Sync,
    Dim<NQ>: TranslationalCondition<NQ>,
{
    // Each replicate transposed into lanes once for all designs, in Morton order (a count
    // does not depend on the order, and near points in a group let the kernels stop early).
    let replicates: Vec<PointGroups> = points
        .points()
        .chunks_exact(points.per_replicate())
        .map(PointGroups::in_morton_order)
        .collect();
    sweep_counts(workspaces, points, progress, |w, r, _| {
        w.count_in_groups(&replicates[r])
    })
}

/// The estimate of each design from `count(design, r, block)`, the number of points of
/// replicate `r`'s block inside its workspace.
fn sweep_counts<D, F>(
    designs: &[D],
    points: &PointSet,
    progress: &dyn Progress,
    count: F,
) -> Result<Vec<VolumeEstimate>, IndexError>
where
    D: Sync,
    F: Fn(&D, usize, &[Vector3<f64>]) -> u64 + Sync,
{
    if designs.is_empty() {
        return Err(IndexError::EmptySample { n_samples: 0 });
    }
    let all = points.points();
    let m = points.per_replicate();
    let replicates = points.replicates() as usize;
    let v_domain = points.domain().volume();
    designs
        .par_iter()
        .map(|design| {
            progress.check()?;
            let mut sums = Sums::default();
            for (r, block) in all.chunks_exact(m).enumerate() {
                sums.inside[r] = count(design, r, block);
            }
            progress.advance(1);
            let mut e = summarise(&sums, replicates, m as u64, v_domain)?;
            e.eta = None;
            e.eta_se = None;
            Ok(e)
        })
        .collect()
}

/// $\mathrm{sd}/\sqrt R$ of the per-replicate ratios $W_r(a)/W_r(b)$ of two estimates over the
/// same replicated [`PointSet`] (common points, so the ratio's error is far below either
/// volume's); `None` with fewer than two replicates, an empty $W_r(b)$, or a ratio or spread
/// that overflows.
pub fn ratio_standard_error(a: &VolumeEstimate, b: &VolumeEstimate) -> Option<f64> {
    if a.replicate_volumes.len() < 2 || a.replicate_volumes.len() != b.replicate_volumes.len() {
        return None;
    }
    let ratios: Option<Vec<f64>> = a
        .replicate_volumes
        .iter()
        .zip(&b.replicate_volumes)
        .map(|(x, y)| (*y > 0.0).then(|| x / y))
        .collect();
    ratios
        .map(|r| crate::estimator::standard_error(&r))
        .filter(|se| se.is_finite())
}
