//! Common random points: one fixed set of sample points in a [`Domain`], reused for every
//! design of a study so that volume ratios and arg-maxes are not sampling noise.
//!
//! A set holds $R$ replicates of $m$ points. Replicate $r$ draws points $0..m$ of the sampler
//! re-seeded with `seed + r` (an independent Monte Carlo stream, or an independent random
//! digital shift of the Sobol sequence: randomised quasi-Monte Carlo), so the spread of the
//! $R$ replicate estimates gives an honest standard error for QMC too.

use crate::{Domain, IndexError, Sampler};
use nalgebra::Vector3;
use pkm_traits::InvalidInput;
use rayon::prelude::*;

/// Largest number of points a set may hold (2.4 GB of coordinates, within
/// [`pkm_traits::MEMORY_BUDGET_BYTES`]): larger requests are refused with
/// [`IndexError::TooLarge`] before anything is allocated.
pub const MAX_POINTS: u64 = 100_000_000;

/// Largest number of replicates.
pub const MAX_REPLICATES: u32 = 64;

/// Sample points in a [`Domain`], in replicates.
#[derive(Debug, Clone, PartialEq)]
pub struct PointSet {
    domain: Domain,
    points: Vec<Vector3<f64>>,
    replicates: u32,
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
        let points = (0..total)
            .into_par_iter()
            .map(|k| {
                let (r, i) = (k / per_replicate, k % per_replicate);
                domain.map(sampler.reseeded(r).unit_cube(i))
            })
            .collect();
        Ok(Self {
            domain,
            points,
            replicates,
        })
    }

    /// The domain the points fill.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// All points, replicate after replicate.
    pub fn points(&self) -> &[Vector3<f64>] {
        &self.points
    }

    /// Number of replicates $R$.
    pub fn replicates(&self) -> u32 {
        self.replicates
    }

    /// Points per replicate $m$.
    pub fn per_replicate(&self) -> usize {
        self.points.len() / self.replicates as usize
    }
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
