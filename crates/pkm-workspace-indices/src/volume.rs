//! Monte Carlo workspace volume (eq. 3) and global condition index (eqs. 4, 8) over the
//! hemisphere of radius $R$ (Stamper, Tsai & Walsh 1997):
//! $$ W = V_h \frac{n_{in}}{n}, \qquad \eta = \frac{V_h}{n}\sum_k f_k, \qquad
//!    V_h = \tfrac{2}{3}\pi R^3, $$
//! with $f_k$ the local index (e.g. $1/\kappa$) inside and 0 outside. Standard errors:
//! $V_h\sqrt{p(1-p)/n}$ and $V_h\,\mathrm{sd}(f)/\sqrt{n}$.

use crate::{Accumulator, IndexError, chunked_reduce};
use nalgebra::Vector3;
use pkm_traits::Progress;
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
    /// Global index $\eta = \int f\, dW$ (eq. 8; volume units, not divided by $W$).
    pub gci: f64,
    /// Standard error of $\eta$.
    pub gci_se: f64,
}

#[derive(Default)]
struct Sums {
    inside: u64,
    f: f64,
    f2: f64,
}

impl Accumulator for Sums {
    fn merge(&mut self, later: Self) {
        self.inside += later.inside;
        self.f += later.f;
        self.f2 += later.f2;
    }
}

/// Estimates $W$ and $\eta$ from `unit_points` (in the unit hemisphere, see
/// [`crate::Sampler::unit_hemisphere_points`]) scaled by `radius`. `local(p)` is `None`
/// outside the workspace and `Some(f)` inside; a non-finite `f` counts as 0.
///
/// Parallel over fixed chunks ([`chunked_reduce`]): bit-identical for any thread count.
///
/// # Errors
/// [`IndexError::EmptySample`] for no points, [`IndexError::Invalid`] for a radius that is
/// not finite and positive, [`IndexError::Cancelled`].
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
    if unit_points.is_empty() {
        return Err(IndexError::EmptySample { n_samples: 0 });
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(IndexError::Invalid {
            what: "radius",
            value: radius,
            requirement: "must be finite and > 0",
        });
    }
    let n = unit_points.len() as u64;
    let sums = chunked_reduce(n, progress, |acc: &mut Sums, i| {
        if let Some(f) = local(&(unit_points[i as usize] * radius)) {
            let f = if f.is_finite() { f } else { 0.0 };
            acc.inside += 1;
            acc.f += f;
            acc.f2 += f * f;
        }
    })?;
    let v_h = 2.0 * PI * radius.powi(3) / 3.0;
    let nf = n as f64;
    let p = sums.inside as f64 / nf;
    let mean = sums.f / nf;
    let variance = (sums.f2 / nf - mean * mean).max(0.0);
    Ok(HemisphereEstimate {
        n,
        n_inside: sums.inside,
        volume: v_h * p,
        volume_se: v_h * (p * (1.0 - p) / nf).sqrt(),
        gci: v_h * mean,
        gci_se: v_h * (variance / nf).sqrt(),
    })
}
