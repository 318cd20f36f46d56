//! The `[sampling]` section: which points fill which bounding region for the workspace
//! estimator (`pkm_workspace_indices::{Domain, PointSet}`).

use super::units::{Degrees, Metres, PositiveMetres};
use crate::StudyError;
use nalgebra::Vector3;
use pkm_traits::{Progress, Silent};
use pkm_workspace_indices::{Domain, IndexError, PointSet, PointStream, Region, Sampler};
use serde::{Deserialize, Serialize};

/// How workspace points are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SamplerKind {
    /// Randomly shifted Sobol points, one independent shift per replicate.
    #[default]
    Sobol,
    /// Pseudo-random points (ChaCha8).
    MonteCarlo,
    /// Cell centres of a regular grid of `per_axis`³ cells (one replicate).
    Grid,
}

/// A bounding region, lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum RegionSpec {
    /// The box `[lower, upper]`.
    Box {
        /// Lower corner (m).
        lower: [Metres; 3],
        /// Upper corner (m).
        upper: [Metres; 3],
    },
    /// A vertical cylinder.
    Cylinder {
        /// Radius (m).
        radius: PositiveMetres,
        /// Lower end (m).
        z_min: Metres,
        /// Upper end (m).
        z_max: Metres,
        /// Axis position, x (m).
        #[serde(default = "zero")]
        axis_x: Metres,
        /// Axis position, y (m).
        #[serde(default = "zero")]
        axis_y: Metres,
    },
    /// The upper half of a ball.
    Hemisphere {
        /// Centre of the flat face (m).
        center: [Metres; 3],
        /// Radius (m).
        radius: PositiveMetres,
    },
    /// A ball.
    Ball {
        /// Centre (m).
        center: [Metres; 3],
        /// Radius (m).
        radius: PositiveMetres,
    },
}

fn zero() -> Metres {
    Metres(0.0)
}

fn vector(p: &[Metres; 3]) -> Vector3<f64> {
    Vector3::new(p[0].0, p[1].0, p[2].0)
}

impl RegionSpec {
    /// The library region.
    pub fn region(&self) -> Region {
        match self {
            Self::Box { lower, upper } => Region::Box {
                lower: vector(lower),
                upper: vector(upper),
            },
            Self::Cylinder {
                radius,
                z_min,
                z_max,
                axis_x,
                axis_y,
            } => Region::Cylinder {
                axis_x: axis_x.0,
                axis_y: axis_y.0,
                radius: radius.0,
                z_min: z_min.0,
                z_max: z_max.0,
            },
            Self::Hemisphere { center, radius } => Region::Hemisphere {
                center: vector(center),
                radius: radius.0,
            },
            Self::Ball { center, radius } => Region::Ball {
                center: vector(center),
                radius: radius.0,
            },
        }
    }
}

/// The `[sampling]` section.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SamplingSpec {
    /// `sobol` (default), `monte_carlo` or `grid`.
    #[serde(default)]
    pub sampler: SamplerKind,
    /// Seed of the random shift or generator; replicate r uses `seed + r`.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Points per replicate (Sobol, Monte Carlo).
    #[serde(default = "default_points")]
    pub points: u64,
    /// Replicates (Sobol, Monte Carlo); their spread is the standard error.
    #[serde(default = "default_replicates")]
    pub replicates: u32,
    /// Cells per axis of a `grid` sampler.
    #[serde(default = "default_per_axis")]
    pub per_axis: u32,
    /// The bounding region; the mechanism's own reach region when absent.
    pub region: Option<RegionSpec>,
    /// Sample one sector of an n-fold symmetric region of revolution (1: the whole region).
    /// Only valid when the mechanism and every constraint share that symmetry.
    #[serde(default = "default_folds")]
    pub symmetry_folds: u32,
    /// Start azimuth of the sector (degrees).
    #[serde(default = "default_azimuth")]
    pub sector_start_deg: Degrees,
}

fn default_seed() -> u64 {
    1
}
fn default_points() -> u64 {
    1 << 14
}
fn default_replicates() -> u32 {
    4
}
fn default_per_axis() -> u32 {
    32
}
fn default_folds() -> u32 {
    1
}
fn default_azimuth() -> Degrees {
    Degrees(0.0)
}

impl Default for SamplingSpec {
    fn default() -> Self {
        Self {
            sampler: SamplerKind::default(),
            seed: default_seed(),
            points: default_points(),
            replicates: default_replicates(),
            per_axis: default_per_axis(),
            region: None,
            symmetry_folds: default_folds(),
            sector_start_deg: default_azimuth(),
        }
    }
}

impl SamplingSpec {
    /// The domain: the study's region, or `fallback` (the mechanism's reach region), with the
    /// symmetry sector.
    ///
    /// # Errors
    /// [`StudyError::Index`] for an invalid region or sector; [`StudyError::Invalid`] when there is
    /// neither a region nor a fallback.
    pub fn domain(&self, fallback: Option<Region>) -> Result<Domain, StudyError> {
        let region = match (self.region, fallback) {
            (Some(spec), _) => spec.region(),
            (None, Some(region)) => region,
            (None, None) => {
                return Err(StudyError::invalid(
                    "sampling.region",
                    "this mechanism has no reach region of its own: give [sampling.region] \
                     (lengths in metres)",
                ));
            }
        };
        let domain = Domain::new(region)?;
        if self.symmetry_folds == 1 {
            Ok(domain)
        } else {
            Ok(domain.with_sector(self.symmetry_folds, self.sector_start_deg.radians())?)
        }
    }

    /// The common points of a study in `domain`.
    ///
    /// # Errors
    /// [`StudyError::Index`] for zero or too many points.
    pub fn point_set(&self, domain: Domain) -> Result<PointSet, StudyError> {
        self.point_set_cancellable(domain, &Silent)
    }

    /// [`point_set`](Self::point_set), generated in blocks that each check `progress` first.
    ///
    /// # Errors
    /// As [`point_set`](Self::point_set); [`StudyError::Cancelled`] when `progress` asks to stop.
    pub fn point_set_cancellable(
        &self,
        domain: Domain,
        progress: &dyn Progress,
    ) -> Result<PointSet, StudyError> {
        let (sampler, per_replicate, replicates) = self.counts();
        PointSet::new_cancellable(domain, sampler, per_replicate, replicates, progress)
            .map_err(|e| self.count_error(e))
    }

    /// The points of [`point_set`](Self::point_set), generated as an estimate reads them
    /// (the memory of one estimate stays that of its chunks, whatever `points`).
    ///
    /// # Errors
    /// As [`point_set`](Self::point_set).
    pub fn point_stream(&self, domain: Domain) -> Result<PointStream, StudyError> {
        let (sampler, per_replicate, replicates) = self.counts();
        PointStream::new(domain, sampler, per_replicate, replicates)
            .map_err(|e| self.count_error(e))
    }

    /// The sampler, the points per replicate and the replicates of this table.
    fn counts(&self) -> (Sampler, u64, u32) {
        match self.sampler {
            SamplerKind::Sobol => (
                Sampler::Sobol { seed: self.seed },
                self.points,
                self.replicates,
            ),
            SamplerKind::MonteCarlo => (
                Sampler::MonteCarlo { seed: self.seed },
                self.points,
                self.replicates,
            ),
            SamplerKind::Grid => {
                let n = u64::from(self.per_axis);
                (
                    Sampler::Grid {
                        per_axis: self.per_axis,
                    },
                    n.saturating_mul(n).saturating_mul(n),
                    1,
                )
            }
        }
    }

    /// An estimator's refusal of the counts at the key that sets them (`sampling.points`,
    /// `sampling.replicates`, or `sampling.per_axis` for a grid); any other error as it is.
    pub fn count_error(&self, e: IndexError) -> StudyError {
        let key = match &e {
            IndexError::TooLarge {
                what: "replicates", ..
            } => "sampling.replicates",
            IndexError::TooLarge { .. } | IndexError::EmptySample { .. } => match self.sampler {
                SamplerKind::Grid => "sampling.per_axis",
                _ if self.replicates == 0 => "sampling.replicates",
                _ => "sampling.points",
            },
            _ => return StudyError::from(e),
        };
        StudyError::invalid(key, e.to_string())
    }
}
