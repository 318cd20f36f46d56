//! Bounding regions of a workspace estimate, with an optional $n$-fold symmetry sector.
//!
//! Points are drawn uniformly in a region by a volume-preserving map from the unit cube
//! $u \in [0, 1)^3$, so any [`crate::Sampler`] (grid, Sobol, Monte Carlo) gives uniform points:
//!
//! | region | map | volume |
//! |---|---|---|
//! | box $[l, h]$ | $l + (h - l) \circ u$ | $\prod (h - l)$ |
//! | vertical cylinder | $\rho = R\sqrt{u_0}$, $\varphi = \varphi_0 + \Phi u_1$, $z = z_{lo} + (z_{hi} - z_{lo}) u_2$ | $\pi R^2 (z_{hi} - z_{lo})$ |
//! | upper hemisphere | $\cos\vartheta = u_0$, $\varphi = \varphi_0 + \Phi u_1$, $r = R u_2^{1/3}$ | $\tfrac23 \pi R^3$ |
//! | ball | $\cos\vartheta = 1 - 2u_0$, $\varphi = \varphi_0 + \Phi u_1$, $r = R u_2^{1/3}$ | $\tfrac43 \pi R^3$ |
//!
//! A region of revolution about the vertical axis through its centre may be restricted to the
//! sector $\varphi \in [\varphi_0, \varphi_0 + 2\pi/n)$ ($\Phi = 2\pi/n$): for a mechanism with
//! $n$-fold symmetry about that axis the workspace volume is $n$ times the sector's.

use crate::IndexError;
use nalgebra::Vector3;
use pkm_traits::InvalidInput;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// The shape of a bounding region (validated by [`Domain::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Region {
    /// The axis-aligned box `[lower, upper]`.
    Box {
        /// Lower corner.
        lower: Vector3<f64>,
        /// Upper corner.
        upper: Vector3<f64>,
    },
    /// The vertical cylinder of `radius` about the axis through `(axis_x, axis_y)`, from `z_min`
    /// to `z_max`.
    Cylinder {
        /// $x$ of the axis.
        axis_x: f64,
        /// $y$ of the axis.
        axis_y: f64,
        /// Radius.
        radius: f64,
        /// Lower end.
        z_min: f64,
        /// Upper end.
        z_max: f64,
    },
    /// The upper half ($z \ge$ centre) of the ball of `radius` about `center` (the hemisphere
    /// of Stamper, Tsai & Walsh 1997, eq. 3).
    Hemisphere {
        /// Centre of the flat face.
        center: Vector3<f64>,
        /// Radius.
        radius: f64,
    },
    /// The ball of `radius` about `center`.
    Ball {
        /// Centre.
        center: Vector3<f64>,
        /// Radius.
        radius: f64,
    },
}

impl Region {
    /// The vertical cylinder of `radius` about the $z$ axis, from `z_min` to `z_max`.
    pub fn axial_cylinder(radius: f64, z_min: f64, z_max: f64) -> Self {
        Self::Cylinder {
            axis_x: 0.0,
            axis_y: 0.0,
            radius,
            z_min,
            z_max,
        }
    }

    /// The smallest axis-aligned box that contains the region (the hemisphere's from its flat
    /// face up).
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_workspace_indices::Region;
    /// let b = Region::Hemisphere { center: Vector3::new(0.0, 0.0, 1.0), radius: 2.0 }.bounding_box();
    /// assert_eq!((b.lower, b.upper), (Vector3::new(-2.0, -2.0, 1.0), Vector3::new(2.0, 2.0, 3.0)));
    /// ```
    pub fn bounding_box(&self) -> BoundingBox {
        let (lower, upper) = match *self {
            Self::Box { lower, upper } => (lower, upper),
            Self::Cylinder {
                axis_x,
                axis_y,
                radius,
                z_min,
                z_max,
            } => (
                Vector3::new(axis_x - radius, axis_y - radius, z_min),
                Vector3::new(axis_x + radius, axis_y + radius, z_max),
            ),
            Self::Hemisphere { center, radius } => (
                center - Vector3::new(radius, radius, 0.0),
                center + Vector3::repeat(radius),
            ),
            Self::Ball { center, radius } => (
                center - Vector3::repeat(radius),
                center + Vector3::repeat(radius),
            ),
        };
        BoundingBox { lower, upper }
    }
}

/// The axis-aligned box `[lower, upper]` (from [`Region::bounding_box`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoundingBox {
    /// Lower corner.
    pub lower: Vector3<f64>,
    /// Upper corner.
    pub upper: Vector3<f64>,
}

impl BoundingBox {
    /// The centre $(l + h)/2$.
    pub fn centre(&self) -> Vector3<f64> {
        (self.lower + self.upper) / 2.0
    }
}

/// A validated [`Region`], possibly restricted to a symmetry sector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    region: Region,
    folds: u32,
    start_azimuth: f64,
}

fn finite_point(name: &'static str, p: &Vector3<f64>) -> Result<(), IndexError> {
    p.iter()
        .try_for_each(|v| InvalidInput::require_finite(name, *v).map(drop))
        .map_err(Into::into)
}

impl Domain {
    /// The whole `region`.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for a non-finite coordinate, a non-positive radius, an empty or
    /// inverted extent, or a region whose volume overflows.
    pub fn new(region: Region) -> Result<Self, IndexError> {
        match region {
            Region::Box { lower, upper } => {
                finite_point("box corner", &lower)?;
                finite_point("box corner", &upper)?;
                for k in 0..3 {
                    InvalidInput::require_positive("box extent", upper[k] - lower[k])?;
                }
            }
            Region::Cylinder {
                axis_x,
                axis_y,
                radius,
                z_min,
                z_max,
            } => {
                InvalidInput::require_finite("cylinder axis", axis_x)?;
                InvalidInput::require_finite("cylinder axis", axis_y)?;
                InvalidInput::require_positive("cylinder radius", radius)?;
                InvalidInput::require_finite("z_min", z_min)?;
                InvalidInput::require_positive("cylinder height", z_max - z_min)?;
            }
            Region::Hemisphere { center, radius } | Region::Ball { center, radius } => {
                finite_point("centre", &center)?;
                InvalidInput::require_positive("radius", radius)?;
            }
        }
        let domain = Self {
            region,
            folds: 1,
            start_azimuth: 0.0,
        };
        InvalidInput::require_positive("region volume", domain.volume())?;
        Ok(domain)
    }

    /// Restricts a region of revolution to the sector $[\varphi_0, \varphi_0 + 2\pi/n)$.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for a box (not a region of revolution), `folds = 0` or a
    /// non-finite start azimuth.
    pub fn with_sector(self, folds: u32, start_azimuth: f64) -> Result<Self, IndexError> {
        if matches!(self.region, Region::Box { .. }) {
            let requirement = "a box is not a region of revolution";
            return Err(InvalidInput::new("sector", f64::from(folds), requirement).into());
        }
        if folds == 0 {
            return Err(InvalidInput::new("folds", 0.0, "must be at least 1").into());
        }
        Ok(Self {
            folds,
            start_azimuth: InvalidInput::require_finite("start azimuth", start_azimuth)?,
            ..self
        })
    }

    /// The region.
    pub fn region(&self) -> Region {
        self.region
    }

    /// The symmetry order $n$ (1: the whole region).
    pub fn folds(&self) -> u32 {
        self.folds
    }

    /// Volume of the whole region (all $n$ sectors).
    pub fn volume(&self) -> f64 {
        match self.region {
            Region::Box { lower, upper } => (upper - lower).product(),
            Region::Cylinder {
                radius,
                z_min,
                z_max,
                ..
            } => PI * radius * radius * (z_max - z_min),
            Region::Hemisphere { radius, .. } => 2.0 * PI * radius.powi(3) / 3.0,
            Region::Ball { radius, .. } => 4.0 * PI * radius.powi(3) / 3.0,
        }
    }

    /// The point of the sampled sector (or region) that unit-cube point `u` maps to.
    pub fn map(&self, u: [f64; 3]) -> Vector3<f64> {
        let azimuth = || self.start_azimuth + TAU / f64::from(self.folds) * u[1];
        match self.region {
            Region::Box { lower, upper } => {
                lower + (upper - lower).component_mul(&Vector3::from(u))
            }
            Region::Cylinder {
                axis_x,
                axis_y,
                radius,
                z_min,
                z_max,
            } => {
                let (s, c) = azimuth().sin_cos();
                let rho = radius * u[0].sqrt();
                Vector3::new(
                    axis_x + rho * c,
                    axis_y + rho * s,
                    z_min + (z_max - z_min) * u[2],
                )
            }
            Region::Hemisphere { center, radius } => {
                center + spherical(u[0], azimuth(), u[2]) * radius
            }
            Region::Ball { center, radius } => {
                center + spherical(1.0 - 2.0 * u[0], azimuth(), u[2]) * radius
            }
        }
    }
}

/// The point at $\cos\vartheta$ = `cos_polar`, azimuth $\varphi$ and radius $u^{1/3}$ of the
/// unit ball (written as in `Sampler::in_unit_hemisphere`, so the hemisphere of Stamper et al.
/// keeps its bits).
fn spherical(cos_polar: f64, azimuth: f64, u: f64) -> Vector3<f64> {
    let (sin_az, cos_az) = azimuth.sin_cos();
    let horizontal = (1.0 - cos_polar * cos_polar).max(0.0).sqrt();
    Vector3::new(horizontal * cos_az, horizontal * sin_az, cos_polar) * u.cbrt()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Every sampled point of each region lies in its bounding box, and the samples come
    /// within 1 % of the extent of every face (the box is the smallest one).
    #[test]
    fn the_bounding_box_is_the_tightest_box_around_the_sampled_points() {
        let center = Vector3::new(0.3, -0.2, 1.5);
        for region in [
            Region::Box {
                lower: Vector3::new(-1.0, 0.0, 2.0),
                upper: Vector3::new(1.0, 0.5, 4.0),
            },
            Region::Cylinder {
                axis_x: 0.3,
                axis_y: -0.2,
                radius: 0.7,
                z_min: -1.0,
                z_max: 0.5,
            },
            Region::Hemisphere {
                center,
                radius: 0.8,
            },
            Region::Ball {
                center,
                radius: 0.8,
            },
        ] {
            let b = region.bounding_box();
            let domain = Domain::new(region).unwrap();
            let n = 40;
            let (mut low, mut high) = (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN));
            for i in 0..(n + 1) * (n + 1) * (n + 1) {
                let u = [
                    i % (n + 1),
                    (i / (n + 1)) % (n + 1),
                    i / ((n + 1) * (n + 1)),
                ]
                .map(|k| k as f64 / n as f64);
                let p = domain.map(u);
                low = low.inf(&p);
                high = high.sup(&p);
            }
            let tol = 1e-2 * (b.upper - b.lower).amax();
            for k in 0..3 {
                assert!(b.lower[k] <= low[k] + 1e-12 && high[k] <= b.upper[k] + 1e-12);
                assert!(
                    low[k] - b.lower[k] < tol && b.upper[k] - high[k] < tol,
                    "{region:?}"
                );
            }
        }
    }
}
