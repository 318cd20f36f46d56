//! Monte Carlo workspace volume (eq. 3) and condition integral $\eta$ (eqs. 4, 8; GCI = η/W) over the
//! hemisphere of radius $R$ (Stamper, Tsai & Walsh 1997): the general estimator
//! ([`crate::workspace_volume_and_eta`]) on a [`crate::Region::Hemisphere`] whose unit points are
//! scaled by each design's radius,
//! $$ W = V_h \frac{n_{in}}{n}, \qquad \eta = \frac{V_h}{n}\sum_k f_k, \qquad
//!    V_h = \tfrac{2}{3}\pi R^3, $$
//! with $f_k$ the local index (e.g. $1/\kappa$) inside and 0 outside. Standard errors:
//! $V_h\sqrt{p(1-p)/n}$ and $V_h\,\mathrm{sd}(f)/\sqrt{n}$.

use crate::IndexError;
use crate::estimator::{integrate_blocks, point_by_point};
use nalgebra::Vector3;
use pkm_traits::{InvalidInput, Progress};
use std::borrow::Cow;
use std::f64::consts::PI;

/// Volume and global index estimated from one point set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HemisphereEstimate {
    /// Points sampled.
    pub n: u64,
    /// Points inside the workspace.
    pub n_inside: u64,
    /// Workspace volume $W$ (eq. 3).
    pub volume: f64,
    /// Standard error of $W$.
    pub volume_se: f64,
    /// The condition integral $\eta = \int f\, dW$ (eq. 8, Stamper's "global condition index";
    /// volume units, not divided by $W$: see [`HemisphereEstimate::gci`]).
    pub eta: f64,
    /// Standard error of $\eta$.
    pub eta_se: f64,
}

impl HemisphereEstimate {
    /// The global condition index of Gosselin & Angeles, $\mathrm{GCI} = \eta / W$ (the mean
    /// of $f$ over the workspace); `None` for an empty workspace.
    pub fn gci(&self) -> Option<f64> {
        (self.volume > 0.0).then(|| self.eta / self.volume)
    }
}

/// Estimates $W$ and $\eta$ from `unit_points` (in the unit hemisphere, see
/// [`crate::Sampler::unit_hemisphere_points`]) scaled by `radius`. `local(p)` is `None`
/// outside the workspace and `Some(f)` inside; a non-finite `f` counts as 0.
///
/// Parallel over fixed chunks ([`crate::chunked_reduce`]): bit-identical for any thread count.
///
/// # Errors
/// [`IndexError::EmptySample`] for no points, [`IndexError::Invalid`] for a radius that is
/// not finite and positive or whose hemisphere's volume overflows, [`IndexError::NonFinite`]
/// when $\eta$ or a standard error overflows, [`IndexError::Cancelled`].
///
/// # Example
/// ```
/// use pkm_traits::Silent;
/// use pkm_workspace_indices::{Sampler, hemisphere_estimate};
/// let points = Sampler::Sobol { seed: 1 }.unit_hemisphere_points(4096).unwrap();
/// // The ball of radius 1 inside a hemisphere of radius 2: W = 2π/3.
/// let e = hemisphere_estimate(&points, 2.0, &Silent, |p| (p.norm() <= 1.0).then_some(1.0)).unwrap();
/// assert!((e.volume - 2.0 * std::f64::consts::PI / 3.0).abs() < 0.02);
/// ```
pub fn hemisphere_estimate<F>(
    unit_points: &[Vector3<f64>],
    radius: f64,
    progress: &dyn Progress,
    local: F,
) -> Result<HemisphereEstimate, IndexError>
where
    F: Fn(&Vector3<f64>) -> Option<f64> + Sync,
{
    hemisphere_estimate_blocks(unit_points, radius, progress, point_by_point(local))
}

/// [`hemisphere_estimate`] with the local index asked for blocks of scaled points at once:
/// `values(block, out)` writes `local(block[k])` into `out[k]` (the same length).
pub(crate) fn hemisphere_estimate_blocks<F>(
    unit_points: &[Vector3<f64>],
    radius: f64,
    progress: &dyn Progress,
    values: F,
) -> Result<HemisphereEstimate, IndexError>
where
    F: Fn(&[Vector3<f64>], &mut [Option<f64>]) + Sync,
{
    if unit_points.is_empty() {
        return Err(IndexError::EmptySample { n_samples: 0 });
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(InvalidInput::new("radius", radius, "must be finite and > 0").into());
    }
    let v_h = 2.0 * PI * radius.powi(3) / 3.0;
    if !v_h.is_finite() {
        return Err(InvalidInput::new(
            "radius",
            radius,
            "the hemisphere's volume 2πR³/3 must be finite",
        )
        .into());
    }
    let block =
        |r: std::ops::Range<u64>| Cow::Borrowed(&unit_points[r.start as usize..r.end as usize]);
    let e = integrate_blocks(
        unit_points.len() as u64,
        block,
        1,
        v_h,
        progress,
        |block, out| {
            let scaled: Vec<Vector3<f64>> = block.iter().map(|p| p * radius).collect();
            values(&scaled, out);
        },
    )?;
    Ok(HemisphereEstimate {
        n: e.n_points,
        n_inside: e.n_inside,
        volume: e.volume,
        volume_se: e.volume_se,
        eta: e.eta.unwrap_or(0.0),
        eta_se: e.eta_se.unwrap_or(0.0),
    })
}
