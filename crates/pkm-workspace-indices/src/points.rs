//! Common random points: one fixed set of sample points in a [`Domain`], reused for every
//! design of a study so that volume ratios and arg-maxes are not sampling noise.
//!
//! A set holds $R$ replicates of $m$ points. Replicate $r$ draws points $0..m$ of the sampler
//! re-seeded with `seed + r` (an independent Monte Carlo stream, or an independent random
//! digital shift of the Sobol sequence: randomised quasi-Monte Carlo), so the spread of the
//! $R$ replicate estimates gives an honest standard error for QMC too.

use crate::{Domain, IndexError, Sampler};
use nalgebra::Vector3;
use pkm_traits::{Cancelled, InvalidInput, Progress, Silent};
use rayon::prelude::*;
use std::borrow::Cow;

/// Largest number of points a set may hold (2.4 GB of coordinates, within
/// [`pkm_traits::MEMORY_BUDGET_BYTES`]): larger requests are refused with
/// [`IndexError::TooLarge`] before anything is allocated.
pub const MAX_POINTS: u64 = 100_000_000;

/// Largest number of replicates.
pub const MAX_REPLICATES: u32 = 64;

/// Points generated between two cancellation checks (one rayon task each).
const BLOCK: usize = 4096;

/// Sample points in a [`Domain`], in replicates.
#[derive(Debug, Clone, PartialEq)]
pub struct PointSet {
    /// What the points are: domain, sampler and counts.
    stream: PointStream,
    points: Vec<Vector3<f64>>,
}

impl PointSet {
    /// `replicates` × `per_replicate` points of `sampler` in `domain` (computed in parallel,
    /// deterministic).
    ///
    /// A [`Sampler::Grid`] must have `per_replicate = per_axis³` and one replicate.
    ///
    /// # Errors
    /// [`IndexError::EmptySample`] for zero points or replicates, [`IndexError::TooLarge`]
    /// above [`MAX_POINTS`] or [`MAX_REPLICATES`], [`IndexError::Invalid`] for a grid whose
    /// size does not match.
    pub fn new(
        domain: Domain,
        sampler: Sampler,
        per_replicate: u64,
        replicates: u32,
    ) -> Result<Self, IndexError> {
        Self::new_cancellable(domain, sampler, per_replicate, replicates, &Silent)
    }

    /// [`new`](Self::new), checking `progress` for cancellation before each block of 4096
    /// points, so that generating even [`MAX_POINTS`] points stops within moments of a
    /// Ctrl-C. Point $k$ is a function of $k$ alone, so the set has the same bits as `new`'s
    /// whatever the blocks and threads.
    ///
    /// # Errors
    /// As [`new`](Self::new); [`IndexError::Cancelled`] when `progress` asks to stop.
    pub fn new_cancellable(
        domain: Domain,
        sampler: Sampler,
        per_replicate: u64,
        replicates: u32,
        progress: &dyn Progress,
    ) -> Result<Self, IndexError> {
        let stream = PointStream::new(domain, sampler, per_replicate, replicates)?;
        let points = generate(&domain, sampler, per_replicate, stream.count(), progress)?;
        Ok(Self { stream, points })
    }

    /// The domain the points fill.
    pub fn domain(&self) -> &Domain {
        &self.stream.domain
    }

    /// All points, replicate after replicate.
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }

    /// Number of replicates $R$.
    pub fn replicates(&self) -> u32 {
        self.stream.replicates
    }

    /// Points per replicate $m$.
    pub fn per_replicate(&self) -> usize {
        self.stream.per_replicate as usize
    }
}

/// The points of a [`PointSet`] generated block by block as an estimator reads them, never all
/// held: an estimate over a stream needs the memory of its chunks, whatever the number of
/// points. Point $k$ is the set's point $k$, so an estimate over the stream has the bits of
/// the same estimate over the set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointStream {
    domain: Domain,
    sampler: Sampler,
    per_replicate: u64,
    replicates: u32,
}

impl PointStream {
    /// The points of [`PointSet::new`] with the same arguments, generated when read.
    ///
    /// # Errors
    /// As [`PointSet::new`].
    pub fn new(
        domain: Domain,
        sampler: Sampler,
        per_replicate: u64,
        replicates: u32,
    ) -> Result<Self, IndexError> {
        check_counts(per_replicate, replicates)?;
        check_grid(sampler, per_replicate, replicates)?;
        Ok(Self {
            domain,
            sampler,
            per_replicate,
            replicates,
        })
    }

    /// Points per replicate $m$.
    pub fn per_replicate(&self) -> u64 {
        self.per_replicate
    }
}

/// Sample points that an estimator reads block by block: a stored [`PointSet`] or a
/// [`PointStream`].
pub trait PointSource: Sync {
    /// What the points are: domain, sampler and counts.
    fn stream(&self) -> &PointStream;
    /// Points `range` (indices into all points, replicate after replicate).
    fn block(&self, range: std::ops::Range<u64>) -> Cow<'_, [Vector3<f64>]>;
    /// The domain the points fill.
    fn domain(&self) -> &Domain {
        &self.stream().domain
    }
    /// Number of replicates $R$.
    fn replicates(&self) -> u32 {
        self.stream().replicates
    }
    /// Number of points, all replicates.
    fn count(&self) -> u64 {
        self.stream().per_replicate * u64::from(self.stream().replicates)
    }
}

impl PointSource for PointSet {
    fn stream(&self) -> &PointStream {
        &self.stream
    }
    fn block(&self, range: std::ops::Range<u64>) -> Cow<'_, [Vector3<f64>]> {
        Cow::Borrowed(&self.points[range.start as usize..range.end as usize])
    }
}

impl PointSource for PointStream {
    fn stream(&self) -> &PointStream {
        self
    }
    fn block(&self, range: std::ops::Range<u64>) -> Cow<'_, [Vector3<f64>]> {
        Cow::Owned(
            range
                .map(|k| point(&self.domain, self.sampler, self.per_replicate, k))
                .collect(),
        )
    }
}

/// Checks that a grid sampler has `per_axis³` points and one replicate.
///
/// # Errors
/// [`IndexError::Invalid`] for a grid of another size or several replicates.
fn check_grid(sampler: Sampler, per_replicate: u64, replicates: u32) -> Result<(), IndexError> {
    if let Sampler::Grid { per_axis } = sampler {
        // Checked: (2³²)³ overflows u64.
        let cells = u64::from(per_axis).checked_pow(3);
        if replicates != 1 || cells != Some(per_replicate) {
            return Err(InvalidInput::new(
                "grid points",
                per_replicate as f64,
                "a grid takes per_axis³ points and one replicate",
            )
            .into());
        }
    }
    Ok(())
}

/// Point $k$: point $k \bmod m$ of replicate $\lfloor k/m \rfloor$, $m$ = `per_replicate`.
fn point(domain: &Domain, sampler: Sampler, per_replicate: u64, k: u64) -> Vector3<f64> {
    let (r, i) = (k / per_replicate, k % per_replicate);
    domain.map(sampler.reseeded(r).unit_cube(i))
}

/// Points `0..total` ([`point`]), in parallel blocks of [`BLOCK`], each block after a
/// cancellation check. `total` ≤ [`MAX_POINTS`] was checked by the caller.
fn generate(
    domain: &Domain,
    sampler: Sampler,
    per_replicate: u64,
    total: u64,
    progress: &dyn Progress,
) -> Result<Vec<Vector3<f64>>, Cancelled> {
    let mut points = vec![Vector3::zeros(); total as usize];
    points
        .par_chunks_mut(BLOCK)
        .enumerate()
        .try_for_each(|(b, block)| {
            progress.check()?;
            for (j, p) in block.iter_mut().enumerate() {
                *p = point(domain, sampler, per_replicate, (b * BLOCK + j) as u64);
            }
            Ok(())
        })?;
    Ok(points)
}

impl Sampler {
    /// The sampler of replicate `r`: seed `seed + r` (a grid has no seed).
    pub fn reseeded(&self, r: u64) -> Self {
        match *self {
            Self::MonteCarlo { seed } => Self::MonteCarlo {
                seed: seed.wrapping_add(r),
            },
            Self::Sobol { seed } => Self::Sobol {
                seed: seed.wrapping_add(r),
            },
            grid @ Self::Grid { .. } => grid,
        }
    }
}

/// Checks the counts of a point set: at least one point, at most [`MAX_REPLICATES`] replicates
/// and [`MAX_POINTS`] points in all; the number of points.
///
/// # Errors
/// [`IndexError::EmptySample`] for no point, [`IndexError::TooLarge`] for too many.
pub(crate) fn check_counts(per_replicate: u64, replicates: u32) -> Result<u64, IndexError> {
    if per_replicate == 0 || replicates == 0 {
        return Err(IndexError::EmptySample {
            n_samples: per_replicate * u64::from(replicates),
        });
    }
    if replicates > MAX_REPLICATES {
        return Err(IndexError::TooLarge {
            what: "replicates",
            requested: u64::from(replicates),
            limit: u64::from(MAX_REPLICATES),
        });
    }
    let total = per_replicate.saturating_mul(u64::from(replicates));
    if total > MAX_POINTS {
        return Err(IndexError::TooLarge {
            what: "points",
            requested: total,
            limit: MAX_POINTS,
        });
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Region;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// Cancels after `left` checks.
    struct CancelAfter {
        left: AtomicUsize,
    }

    impl Progress for CancelAfter {
        fn is_cancelled(&self) -> bool {
            self.left
                .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| n.checked_sub(1))
                .is_err()
        }
    }

    fn domain() -> Domain {
        Domain::new(Region::axial_cylinder(0.7, -0.6, 0.0)).unwrap()
    }

    #[test]
    fn cancellable_generation_has_the_same_bits_and_stops_when_asked() {
        let sobol = Sampler::Sobol { seed: 42 };
        // Two replicates of a size that is not a multiple of the block: the last block is short.
        let m = 3 * BLOCK as u64 + 17;
        let reference: Vec<Vector3<f64>> = (0..2 * m)
            .map(|k| domain().map(sobol.reseeded(k / m).unit_cube(k % m)))
            .collect();
        let never = CancelAfter {
            left: AtomicUsize::new(usize::MAX),
        };
        let set = PointSet::new_cancellable(domain(), sobol, m, 2, &never).unwrap();
        assert_eq!(set.points(), reference.as_slice());
        assert_eq!(PointSet::new(domain(), sobol, m, 2).unwrap(), set);
        for checks in [0, 1, 5] {
            let cancel = CancelAfter {
                left: AtomicUsize::new(checks),
            };
            let stopped = PointSet::new_cancellable(domain(), sobol, m, 2, &cancel);
            assert_eq!(stopped, Err(IndexError::Cancelled), "after {checks} checks");
        }
    }

    /// A stream holds the set's points (every block equal to the set's slice, bit for bit, for
    /// each sampler and block boundary), and an estimate over it has the set's bits.
    #[test]
    fn a_stream_is_the_set_generated_when_read() {
        for sampler in [Sampler::Sobol { seed: 3 }, Sampler::MonteCarlo { seed: 9 }] {
            let set = PointSet::new(domain(), sampler, 5_000, 3).unwrap();
            let stream = PointStream::new(domain(), sampler, 5_000, 3).unwrap();
            assert_eq!(stream.count(), 15_000);
            for range in [0..1, 4_999..5_001, 0..15_000, 14_000..15_000] {
                assert_eq!(stream.block(range.clone()), set.block(range));
            }
            let local = |x: &Vector3<f64>| (x.z > -0.3).then_some(x.norm());
            let on_set = crate::workspace_volume_and_eta(&set, &Silent, local).unwrap();
            let on_stream = crate::workspace_volume_and_eta(&stream, &Silent, local).unwrap();
            assert_eq!(on_set, on_stream);
        }
        let grid = Sampler::Grid { per_axis: 4 };
        assert!(PointStream::new(domain(), grid, 64, 1).is_ok());
        assert!(PointStream::new(domain(), grid, 65, 1).is_err());
        assert!(PointStream::new(domain(), grid, 64, 2).is_err());
        assert!(PointStream::new(domain(), Sampler::Sobol { seed: 0 }, 0, 1).is_err());
    }
}
