//! A planar section of a local index: values on a regular grid of the plane $z = z_0$
//! (Stamper, Tsai & Walsh 1997, Figs. 5–6: $1/\kappa$ at $z = 0.5$).

use crate::IndexError;
use rayon::prelude::*;

/// A local index on the grid `x × y` of the plane $z = z_0$.
#[derive(Debug, Clone, PartialEq)]
pub struct Slice {
    /// Height of the plane.
    pub z: f64,
    /// Cell centres along $x$.
    pub x: Vec<f64>,
    /// Cell centres along $y$.
    pub y: Vec<f64>,
    /// `values[iy * x.len() + ix]`; `None` outside the workspace.
    pub values: Vec<Option<f64>>,
}

impl Slice {
    /// Largest grid side `n` of [`Slice::square`]: 2¹², so at most 2²⁴ values.
    pub const MAX_SIDE: usize = 1 << 12;

    /// Samples `local` at the centres of `n × n` cells covering $[-h, h]^2$ at height `z`,
    /// rows in parallel.
    ///
    /// # Errors
    /// [`IndexError::EmptySample`] when `n = 0`; [`IndexError::Invalid`] for a non-finite or
    /// non-positive half-width, a non-finite `z`, or `n >` [`Slice::MAX_SIDE`].
    ///
    /// # Example
    /// ```
    /// use pkm_workspace_indices::Slice;
    /// let s = Slice::square(0.5, 1.0, 4, |x, y, _| (x * x + y * y < 0.25).then_some(1.0)).unwrap();
    /// assert_eq!(s.values.iter().flatten().count(), 4);
    /// ```
    pub fn square<F>(z: f64, half_width: f64, n: usize, local: F) -> Result<Self, IndexError>
    where
        F: Fn(f64, f64, f64) -> Option<f64> + Sync,
    {
        if n == 0 {
            return Err(IndexError::EmptySample { n_samples: 0 });
        }
        if n > Self::MAX_SIDE {
            return Err(IndexError::Invalid {
                what: "slice grid side",
                value: n as f64,
                requirement: "must be at most Slice::MAX_SIDE (refused before allocating n² values)",
            });
        }
        // Up to f64::MAX / 4, so that the span 2·half_width of the nodes stays finite.
        if !(half_width.is_finite()
            && half_width > 0.0
            && half_width <= f64::MAX / 4.0
            && z.is_finite())
        {
            return Err(IndexError::Invalid {
                what: "slice half-width or height",
                value: if z.is_finite() { half_width } else { z },
                requirement: "must be finite, 0 < half-width <= f64::MAX / 4",
            });
        }
        let axis: Vec<f64> = (0..n)
            .map(|k| -half_width + (k as f64 + 0.5) * 2.0 * half_width / n as f64)
            .collect();
        let values = (0..n * n)
            .into_par_iter()
            .map(|k| local(axis[k % n], axis[k / n], z))
            .collect();
        Ok(Self {
            z,
            x: axis.clone(),
            y: axis,
            values,
        })
    }

    /// The largest value and its $(x, y)$, `None` when no cell is inside.
    pub fn max(&self) -> Option<(f64, f64, f64)> {
        let n = self.x.len();
        self.values
            .iter()
            .enumerate()
            .filter_map(|(k, v)| v.map(|v| (v, self.x[k % n], self.y[k / n])))
            .fold(None, |best, c| match best {
                Some(b) if b.0 >= c.0 => Some(b),
                _ => Some(c),
            })
    }
}
