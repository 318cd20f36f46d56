//! Planar sections of a local index: values at the cell centres of a regular grid on a
//! coordinate plane $x = c$, $y = c$ or $z = c$ (Stamper, Tsai & Walsh 1997, Figs. 5–6:
//! $1/\kappa$ at $z = 0.5$), over the extent of a [`BoundingBox`] in that plane.

use crate::{BoundingBox, IndexError};
use nalgebra::Vector3;
use pkm_traits::InvalidInput;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// A coordinate plane, named by its two in-plane axes (`xy` is $z = c$).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Plane {
    /// $z = c$: a horizontal section, in-plane axes $(x, y)$.
    Xy,
    /// $y = c$: a vertical section, in-plane axes $(x, z)$.
    Xz,
    /// $x = c$: a vertical section, in-plane axes $(y, z)$.
    Yz,
}

impl Plane {
    /// The coordinate indices `(u, v, normal)`: the first and second in-plane axes and the
    /// normal axis (0 = $x$, 1 = $y$, 2 = $z$).
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Self::Xy => (0, 1, 2),
            Self::Xz => (0, 2, 1),
            Self::Yz => (1, 2, 0),
        }
    }

    /// The point with in-plane coordinates $(u, v)$ on the plane at offset `at`.
    pub fn point(self, u: f64, v: f64, at: f64) -> Vector3<f64> {
        let (a, b, normal) = self.axes();
        let mut p = Vector3::zeros();
        p[a] = u;
        p[b] = v;
        p[normal] = at;
        p
    }
}

/// A local index on the `n × n` cell centres of a coordinate plane.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Slice {
    /// The plane.
    pub plane: Plane,
    /// Its offset along the normal axis.
    pub at: f64,
    /// Cell centres along the first in-plane axis ([`Plane::axes`]).
    pub u: Vec<f64>,
    /// Cell centres along the second in-plane axis.
    pub v: Vec<f64>,
    /// `values[iv * u.len() + iu]`; `None` outside the workspace.
    pub values: Vec<Option<f64>>,
}

impl Slice {
    /// Largest grid side `n` of [`Slice::on_plane`]: 2¹², so at most 2²⁴ values.
    pub const MAX_SIDE: usize = 1 << 12;

    /// Samples `local` at the centres of `n × n` equal cells covering the extent of `bounds`
    /// in `plane` (centre $k$ of $[l, h]$ at $l + (k + \tfrac12)(h - l)/n$), at offset `at`
    /// along the plane's normal, rows in parallel and collected in order.
    ///
    /// # Errors
    /// [`IndexError::EmptySample`] when `n = 0`; [`IndexError::Invalid`] for
    /// `n >` [`Slice::MAX_SIDE`] (refused before allocating), a non-finite `at`, or in-plane
    /// bounds that are not finite and increasing with $n(h - l)$ finite.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// use pkm_workspace_indices::{BoundingBox, Plane, Slice};
    /// let bounds = BoundingBox { lower: Vector3::repeat(-1.0), upper: Vector3::repeat(1.0) };
    /// let disc = |p: &Vector3<f64>| (p.x * p.x + p.z * p.z < 0.25).then_some(1.0);
    /// let s = Slice::on_plane(Plane::Xz, 0.3, &bounds, 4, disc).unwrap();
    /// assert_eq!((s.u[0], s.v[3]), (-0.75, 0.75));
    /// assert_eq!(s.values.iter().flatten().count(), 4);
    /// ```
    pub fn on_plane<F>(
        plane: Plane,
        at: f64,
        bounds: &BoundingBox,
        n: usize,
        local: F,
    ) -> Result<Self, IndexError>
    where
        F: Fn(&Vector3<f64>) -> Option<f64> + Sync,
    {
        if n == 0 {
            return Err(IndexError::EmptySample { n_samples: 0 });
        }
        let requirement = "must be at most Slice::MAX_SIDE (refused before allocating n² values)";
        InvalidInput::require_count_at_most("slice grid side", n, Self::MAX_SIDE, requirement)?;
        InvalidInput::require_finite("slice offset", at)?;
        let (a, b, _) = plane.axes();
        let u = centres(bounds.lower[a], bounds.upper[a], n)?;
        let v = centres(bounds.lower[b], bounds.upper[b], n)?;
        let values = (0..n * n)
            .into_par_iter()
            .map(|k| local(&plane.point(u[k % n], v[k / n], at)))
            .collect();
        Ok(Self {
            plane,
            at,
            u,
            v,
            values,
        })
    }

    /// The largest value and its in-plane coordinates $(u, v)$, `None` when no cell is inside.
    pub fn max(&self) -> Option<(f64, f64, f64)> {
        let n = self.u.len();
        self.values
            .iter()
            .enumerate()
            .filter_map(|(k, v)| v.map(|v| (v, self.u[k % n], self.v[k / n])))
            .fold(None, |best, c| match best {
                Some(b) if b.0 >= c.0 => Some(b),
                _ => Some(c),
            })
    }
}

/// The centres of `n` equal cells over `[lo, hi]`.
fn centres(lo: f64, hi: f64, n: usize) -> Result<Vec<f64>, IndexError> {
    InvalidInput::require_finite("slice bound", lo)?;
    // n·(hi − lo) finite bounds every (k + 1/2)(hi − lo) below.
    let spans = (hi - lo) * n as f64;
    if !(hi > lo && spans.is_finite()) {
        let requirement = "must be finite and above the lower bound, with n·(upper − lower) finite";
        return Err(InvalidInput::new("slice upper bound", hi, requirement).into());
    }
    Ok((0..n)
        .map(|k| lo + (k as f64 + 0.5) * (hi - lo) / n as f64)
        .collect())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;

    /// A box whose three extents differ, so that a mixed-up axis changes the centres.
    fn bounds() -> BoundingBox {
        BoundingBox {
            lower: Vector3::new(-1.0, 2.0, -8.0),
            upper: Vector3::new(3.0, 4.0, 0.0),
        }
    }

    #[test]
    fn every_plane_samples_its_in_plane_axes_at_its_offset() {
        // The value encodes the point, so each cell tells where it was evaluated.
        let encode = |p: &Vector3<f64>| Some(p.x + 10.0 * p.y + 100.0 * p.z);
        for (plane, normal) in [(Plane::Xy, 2), (Plane::Xz, 1), (Plane::Yz, 0)] {
            let s = Slice::on_plane(plane, 0.25, &bounds(), 4, encode).unwrap();
            let (a, b, n) = plane.axes();
            assert_eq!(n, normal);
            // Cell centres of [l, h] in 4 cells: l + (k + 1/2)(h − l)/4.
            let centre = |axis: usize, k: usize| {
                let (l, h) = (bounds().lower[axis], bounds().upper[axis]);
                l + (k as f64 + 0.5) * (h - l) / 4.0
            };
            for k in 0..16 {
                let mut p = Vector3::repeat(0.25);
                p[a] = centre(a, k % 4);
                p[b] = centre(b, k / 4);
                assert_eq!(s.values[k], encode(&p), "{plane:?} cell {k}");
                assert_eq!((s.u[k % 4], s.v[k / 4]), (p[a], p[b]));
            }
        }
    }

    #[test]
    fn bad_grids_are_refused_before_sampling() {
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let count = |_: &Vector3<f64>| {
            calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            Some(1.0)
        };
        let flat = BoundingBox {
            upper: Vector3::new(3.0, 2.0, 0.0),
            ..bounds()
        };
        let huge = BoundingBox {
            lower: Vector3::repeat(-f64::MAX),
            upper: Vector3::repeat(f64::MAX),
        };
        assert!(matches!(
            Slice::on_plane(Plane::Xy, 0.0, &bounds(), 0, count),
            Err(IndexError::EmptySample { .. })
        ));
        for (plane, at, b, n) in [
            (Plane::Xy, 0.0, bounds(), Slice::MAX_SIDE + 1),
            (Plane::Xy, f64::NAN, bounds(), 4),
            (Plane::Xy, 0.0, flat, 4),
            (Plane::Xz, 0.0, huge, 4),
        ] {
            let e = Slice::on_plane(plane, at, &b, n, count).unwrap_err();
            assert!(matches!(e, IndexError::Invalid(_)), "{e:?}");
        }
        // The flat box is fine on a plane that does not span its flat axis.
        assert!(Slice::on_plane(Plane::Xz, 2.0, &flat, 4, count).is_ok());
        assert_eq!(calls.into_inner(), 16);
    }
}
