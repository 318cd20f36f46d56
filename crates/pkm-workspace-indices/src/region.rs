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
}

/// A validated [`Region`], possibly restricted to a symmetry sector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    region: Region,
    folds: u32,
    start_azimuth: f64,
}

fn invalid(what: &'static str, value: f64, requirement: &'static str) -> IndexError {
    IndexError::Invalid {
        what,
        value,
        requirement,
    }
}

fn finite(what: &'static str, v: f64) -> Result<f64, IndexError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(what, v, "must be finite"))
    }
}

fn positive(what: &'static str, v: f64) -> Result<f64, IndexError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(invalid(what, v, "must be finite and > 0"))
    }
}

fn finite_point(what: &'static str, p: &Vector3<f64>) -> Result<(), IndexError> {
    p.iter().try_for_each(|v| finite(what, *v).map(|_| ()))
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
                    positive("box extent", upper[k] - lower[k])?;
                }
            }
            Region::Cylinder {
                axis_x,
                axis_y,
                radius,
                z_min,
                z_max,
            } => {
                finite("cylinder axis", axis_x)?;
                finite("cylinder axis", axis_y)?;
                positive("cylinder radius", radius)?;
                finite("z_min", z_min)?;
                positive("cylinder height", z_max - z_min)?;
            }
            Region::Hemisphere { center, radius } | Region::Ball { center, radius } => {
                finite_point("centre", &center)?;
                positive("radius", radius)?;
            }
        }
        let domain = Self {
            region,
            folds: 1,
            start_azimuth: 0.0,
        };
        positive("region volume", domain.volume())?;
        Ok(domain)
    }

    /// Restricts a region of revolution to the sector $[\varphi_0, \varphi_0 + 2\pi/n)$.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for a box (not a region of revolution), `folds = 0` or a
    /// non-finite start azimuth.
    pub fn with_sector(self, folds: u32, start_azimuth: f64) -> Result<Self, IndexError> {
        if matches!(self.region, Region::Box { .. }) {
            return Err(invalid(
                "sector",
                f64::from(folds),
                "a box is not a region of revolution",
            ));
        }
        if folds == 0 {
            return Err(invalid("folds", 0.0, "must be at least 1"));
        }
        Ok(Self {
            folds,
            start_azimuth: finite("start azimuth", start_azimuth)?,
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
