//! Workspace volume and condition integral over a [`PointSet`]:
//! $$ W = V_D\,\frac{n_{in}}{n}, \qquad \eta = \int_W f\,dW \approx \frac{V_D}{n}\sum_k f_k, $$
//! with $V_D$ the volume of the whole domain (all symmetry sectors: by symmetry the sector's
//! fraction is the region's), $f_k$ the local index (e.g. $1/\kappa$) inside and 0 outside.
//!
//! Standard errors: with one replicate the i.i.d. formulas $V_D\sqrt{p(1-p)/n}$ and
//! $V_D\,\mathrm{sd}(f)/\sqrt n$ (exact for Monte Carlo, conservative for quasi-Monte Carlo);
//! with $R > 1$ replicates the spread of the replicate estimates, $\mathrm{sd}_r/\sqrt R$.

use crate::parallel::chunked_reduce_ranges;
use crate::points::MAX_REPLICATES;
use crate::{Accumulator, CHUNK_SIZE, IndexError, PointSet, PointSource};
use nalgebra::Vector3;
use pkm_traits::checked::finite_or;
use pkm_traits::{Cancelled, Progress};
use rayon::prelude::*;
use std::borrow::Cow;

/// How a standard error was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorModel {
    /// The i.i.d. (binomial) formula on one replicate.
    Iid,
    /// The spread of this many independent replicates.
    Replicates(u32),
}

/// A workspace volume, optionally with $\eta = \int 1/\kappa\, dW$, and their standard errors.
#[derive(Debug, Clone, PartialEq)]
pub struct VolumeEstimate {
    /// Points sampled.
    pub n_points: u64,
    /// Points inside the workspace.
    pub n_inside: u64,
    /// Workspace volume $W$.
    pub volume: f64,
    /// Standard error of $W$.
    pub volume_se: f64,
    /// $\eta = \int f\, dW$ (volume units), when a local index was integrated.
    pub eta: Option<f64>,
    /// Standard error of $\eta$.
    pub eta_se: Option<f64>,
    /// How the standard errors were obtained.
    pub error_model: ErrorModel,
    /// $W$ of each replicate (one entry with one replicate).
    pub replicate_volumes: Vec<f64>,
}

impl VolumeEstimate {
    /// The global condition index of Gosselin & Angeles, $\mathrm{GCI} = \eta / W$; `None`
    /// without $\eta$ or for an empty workspace.
    pub fn gci(&self) -> Option<f64> {
        self.eta
            .filter(|_| self.volume > 0.0)
            .map(|e| e / self.volume)
    }
}

/// Per-replicate sums of the indicator, of $f$ and of $f^2$.
#[derive(Clone)]
pub(crate) struct Sums {
    pub(crate) inside: [u64; MAX_REPLICATES as usize],
    pub(crate) f: [f64; MAX_REPLICATES as usize],
    pub(crate) f2: [f64; MAX_REPLICATES as usize],
}

impl Default for Sums {
    fn default() -> Self {
        Self {
            inside: [0; MAX_REPLICATES as usize],
            f: [0.0; MAX_REPLICATES as usize],
            f2: [0.0; MAX_REPLICATES as usize],
        }
    }
}

impl Accumulator for Sums {
    fn merge(&mut self, later: Self) {
        for r in 0..MAX_REPLICATES as usize {
            self.inside[r] += later.inside[r];
            self.f[r] += later.f[r];
            self.f2[r] += later.f2[r];
        }
    }
}

/// The volume of $\{x : \texttt{contains}(x)\}$ over `points`.
///
/// Counted in parallel over blocks of [`CHUNK_SIZE`] points; counts are integers, so the
/// estimate is bit-identical for any thread count.
///
/// # Errors
/// [`IndexError::Cancelled`].
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_traits::Silent;
/// use pkm_workspace_indices::{Domain, PointSet, Region, Sampler, workspace_volume};
/// // The unit ball inside a cylinder, in 4 randomly shifted Sobol replicates.
/// let domain = Domain::new(Region::axial_cylinder(1.0, -1.0, 1.0))?;
/// let points = PointSet::new(domain, Sampler::Sobol { seed: 3 }, 1 << 14, 4)?;
/// let e = workspace_volume(&points, &Silent, |p| p.norm() <= 1.0)?;
/// assert!((e.volume - 4.0 * std::f64::consts::PI / 3.0).abs() < 5.0 * e.volume_se.max(1e-3));
/// # Ok::<(), pkm_workspace_indices::IndexError>(())
/// ```
pub fn workspace_volume<F>(
    points: &PointSet,
    progress: &dyn Progress,
    contains: F,
) -> Result<VolumeEstimate, IndexError>
where
    F: Fn(&Vector3<f64>) -> bool + Sync,
{
    count_volume(points, progress, |block| {
        block.iter().filter(|x| contains(x)).count() as u64
    })
}

/// The volume of the points that `count_inside` counts, asked for blocks of at most
/// [`CHUNK_SIZE`] points of one replicate, in parallel. Counts are integers, so the estimate
/// is the same, bit for bit, whatever the thread count or the split.
///
/// # Errors
/// [`IndexError::Cancelled`] (checked once per block).
pub(crate) fn count_volume<F>(
    points: &PointSet,
    progress: &dyn Progress,
    count_inside: F,
) -> Result<VolumeEstimate, IndexError>
where
    F: Fn(&[Vector3<f64>]) -> u64 + Sync,
{
    let m = points.per_replicate();
    let mut sums = Sums::default();
    for (r, block) in points.points().chunks_exact(m).enumerate() {
        sums.inside[r] = block
            .par_chunks(CHUNK_SIZE as usize)
            .map(|chunk| {
                progress.check()?;
                let n = count_inside(chunk);
                progress.advance(chunk.len() as u64);
                Ok(n)
            })
            .try_reduce(|| 0, |a, b| Ok::<u64, Cancelled>(a + b))?;
    }
    let mut e = summarise(
        &sums,
        points.replicates() as usize,
        m as u64,
        points.domain().volume(),
    )?;
    e.eta = None;
    e.eta_se = None;
    Ok(e)
}

/// The volume of $\{x : \texttt{local}(x) \ne \text{None}\}$ and $\eta = \int f\, dW$ with
/// $f$ = `local(x)` (a non-finite $f$ counts as 0 and the point as inside).
///
/// # Errors
/// [`IndexError::Cancelled`]; [`IndexError::NonFinite`] when $\eta$ or its standard error
/// overflows (finite values of $f$ near `f64::MAX`).
pub fn workspace_volume_and_eta<P, F>(
    points: &P,
    progress: &dyn Progress,
    local: F,
) -> Result<VolumeEstimate, IndexError>
where
    P: PointSource + ?Sized,
    F: Fn(&Vector3<f64>) -> Option<f64> + Sync,
{
    integrate_blocks(
        points.count(),
        |range| points.block(range),
        points.replicates() as usize,
        points.domain().volume(),
        progress,
        point_by_point(local),
    )
}

/// `local` asked point by point, as the `values` of [`integrate_blocks`].
pub(crate) fn point_by_point<F>(local: F) -> impl Fn(&[Vector3<f64>], &mut [Option<f64>]) + Sync
where
    F: Fn(&Vector3<f64>) -> Option<f64> + Sync,
{
    move |block, out| {
        for (x, f) in block.iter().zip(out) {
            *f = local(x);
        }
    }
}

/// The estimator on `points` (`replicates` equal consecutive blocks) of a domain of volume
/// `v_domain`; the one loop behind [`workspace_volume_and_eta`] and
/// [`crate::hemisphere_estimate`]. `values(block, out)` writes the local index of each point
/// of a block (at most [`CHUNK_SIZE`] consecutive points) into `out`, `None` outside; the
/// values are then summed point by point in index order, so the bits do not depend on how
/// `values` computes them (one point or a lane kernel at a time) nor on the thread count.
pub(crate) fn integrate_blocks<'p, B, F>(
    n: u64,
    points: B,
    replicates: usize,
    v_domain: f64,
    progress: &dyn Progress,
    values: F,
) -> Result<VolumeEstimate, IndexError>
where
    B: Fn(std::ops::Range<u64>) -> Cow<'p, [Vector3<f64>]> + Sync,
    F: Fn(&[Vector3<f64>], &mut [Option<f64>]) + Sync,
{
    if replicates > MAX_REPLICATES as usize {
        return Err(IndexError::TooLarge {
            what: "replicates",
            requested: replicates as u64,
            limit: u64::from(MAX_REPLICATES),
        });
    }
    if n == 0 || replicates == 0 || !n.is_multiple_of(replicates as u64) {
        return Err(IndexError::EmptySample { n_samples: n });
    }
    let m = n / replicates as u64;
    let sums = chunked_reduce_ranges(n, progress, |acc: &mut Sums, range| {
        let block = points(range.clone());
        let mut out = vec![None; block.len()];
        values(&block, &mut out);
        // The replicate of index i is i / m, tracked by its next boundary rather than divided.
        let (mut r, mut next) = ((range.start / m) as usize, (range.start / m + 1) * m);
        for (i, f) in range.zip(out) {
            if i == next {
                (r, next) = (r + 1, next + m);
            }
            if let Some(f) = f {
                let f = if f.is_finite() { f } else { 0.0 };
                acc.inside[r] += 1;
                acc.f[r] += f;
                acc.f2[r] += f * f;
            }
        }
    })?;
    summarise(&sums, replicates, m, v_domain)
}

/// Mean and standard error from per-replicate sums.
///
/// # Errors
/// [`IndexError::NonFinite`] when a mean or a standard error overflowed (values of $f$ whose
/// sum or square is beyond `f64`): never an infinite estimate, nor an error term that a NaN
/// variance turned into 0.
pub(crate) fn summarise(
    sums: &Sums,
    replicates: usize,
    m: u64,
    v_domain: f64,
) -> Result<VolumeEstimate, IndexError> {
    let mf = m as f64;
    let volumes: Vec<f64> = (0..replicates)
        .map(|r| v_domain * (sums.inside[r] as f64 / mf))
        .collect();
    let etas: Vec<f64> = (0..replicates)
        .map(|r| v_domain * (sums.f[r] / mf))
        .collect();
    let n_inside: u64 = sums.inside[..replicates].iter().sum();
    let (volume, eta) = (mean(&volumes), mean(&etas));
    let (volume_se, eta_se, error_model) = if replicates == 1 {
        let p = sums.inside[0] as f64 / mf;
        let f_mean = sums.f[0] / mf;
        // `max` clamps the round-off of a zero variance; a NaN (∞ − ∞) is kept for the check.
        let variance = (sums.f2[0] / mf - f_mean * f_mean).max(0.0);
        let variance = if sums.f2[0].is_finite() {
            variance
        } else {
            f64::INFINITY
        };
        (
            v_domain * (p * (1.0 - p) / mf).sqrt(),
            v_domain * (variance / mf).sqrt(),
            ErrorModel::Iid,
        )
    } else {
        (
            standard_error(&volumes),
            standard_error(&etas),
            ErrorModel::Replicates(replicates as u32),
        )
    };
    let results = [
        ("volume", volume),
        ("volume standard error", volume_se),
        ("eta", eta),
        ("eta standard error", eta_se),
    ];
    for (what, value) in results {
        finite_or(value, |value| IndexError::NonFinite { what, value })?;
    }
    Ok(VolumeEstimate {
        n_points: m * replicates as u64,
        n_inside,
        volume,
        volume_se,
        eta: Some(eta),
        eta_se: Some(eta_se),
        error_model,
        replicate_volumes: volumes,
    })
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// $\mathrm{sd}/\sqrt R$ of replicate estimates ($R \ge 2$).
pub(crate) fn standard_error(values: &[f64]) -> f64 {
    let r = values.len() as f64;
    let mu = mean(values);
    let ss: f64 = values.iter().map(|v| (v - mu) * (v - mu)).sum();
    (ss / (r - 1.0) / r).sqrt()
}
