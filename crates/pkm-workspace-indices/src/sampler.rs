//! Point samplers over the unit cube, boxes and the hemisphere of eq. 3 (Stamper, Tsai & Walsh
//! 1997): uniform grid, Monte Carlo and quasi-Monte Carlo (Sobol). Point $i$ is a pure function
//! of `(seed, i)`, so a fixed point set serves as common random numbers across designs.

use crate::IndexError;
use crate::sobol::sobol3;
use nalgebra::Vector3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// How points in the unit cube $[0, 1)^3$ are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampler {
    /// Pseudo-random: point $i$ uses ChaCha8 stream $i$ of `seed`.
    MonteCarlo {
        /// Seed of the generator.
        seed: u64,
    },
    /// The Sobol sequence (Joe–Kuo direction numbers) with a random digital shift from `seed`
    /// (`seed = 0`: unshifted).
    Sobol {
        /// Seed of the digital shift.
        seed: u64,
    },
    /// Cell centres of a regular grid of `per_axis`³ cells, in lexicographic order ($x$ slowest).
    Grid {
        /// Cells per axis (0 is read as 1: a grid has at least one cell; [`crate::PointSet::new`]
        /// refuses it).
        per_axis: u32,
    },
}

impl Sampler {
    /// Point $i$ in the unit cube. The Sobol sequence is 32-bit: its points repeat for
    /// $i \ge 2^{32}$ (a [`crate::PointSet`] holds at most [`crate::MAX_POINTS`] $< 2^{32}$).
    pub fn unit_cube(&self, i: u64) -> [f64; 3] {
        match *self {
            Self::MonteCarlo { seed } => {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                rng.set_stream(i);
                [rng.random(), rng.random(), rng.random()]
            }
            Self::Sobol { seed } => sobol3(i, seed),
            Self::Grid { per_axis } => {
                // At least one cell; indices beyond the n³ cells wrap (n² and n³ may exceed u64,
                // so the slowest digit is taken modulo n too).
                let n = u64::from(per_axis.max(1));
                let cell = [(i / n / n) % n, (i / n) % n, i % n];
                cell.map(|c| (c as f64 + 0.5) / n as f64)
            }
        }
    }

    /// Point $i$ in the box `[lower, upper]`.
    pub fn in_box(&self, i: u64, lower: &Vector3<f64>, upper: &Vector3<f64>) -> Vector3<f64> {
        let u = Vector3::from(self.unit_cube(i));
        lower + (upper - lower).component_mul(&u)
    }

    /// Point $i$ uniform in the unit upper hemisphere $|p| \le 1$, $z \ge 0$: the direction
    /// has $z = u_0$ (Archimedes: uniform on the half sphere), azimuth $2\pi u_1$, and the
    /// radius is $u_2^{1/3}$. The map preserves volume, so a [`Sampler::Grid`] maps to the centres of a warped
    /// grid of equal-volume cells. Rounding of the sine, cosine and cube root may put a point a
    /// few ulps outside $|p| \le 1$ (kept: membership is the mechanism's test).
    pub fn in_unit_hemisphere(&self, i: u64) -> Vector3<f64> {
        let [u0, u1, u2] = self.unit_cube(i);
        let (sin_az, cos_az) = (TAU * u1).sin_cos();
        let horizontal = (1.0 - u0 * u0).max(0.0).sqrt();
        Vector3::new(horizontal * cos_az, horizontal * sin_az, u0) * u2.cbrt()
    }

    /// The first `n` points in the unit hemisphere, computed in parallel: the common random
    /// numbers that [`crate::hemisphere_estimate`] scales by each design's radius.
    ///
    /// # Errors
    /// [`IndexError::EmptySample`] when `n = 0`, [`IndexError::TooLarge`] above
    /// [`crate::MAX_POINTS`] (refused before allocating).
    pub fn unit_hemisphere_points(&self, n: u64) -> Result<Vec<Vector3<f64>>, IndexError> {
        if n == 0 {
            return Err(IndexError::EmptySample { n_samples: 0 });
        }
        if n > crate::MAX_POINTS {
            return Err(IndexError::TooLarge {
                what: "points",
                requested: n,
                limit: crate::MAX_POINTS,
            });
        }
        Ok((0..n)
            .into_par_iter()
            .map(|i| self.in_unit_hemisphere(i))
            .collect())
    }
}
