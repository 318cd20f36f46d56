//! Deterministic workspace volume by columns (spec `stamper.md` §1): for fixed $(x, y)$ leg $i$
//! admits $(L - a)^2 - p_u^2 \le z^2 \le (L + a)^2 - p_u^2$, $L = d + e + \sqrt{b^2 - p_v^2}$;
//! the three intervals, $z \ge 0$ and the hemisphere $z \le \sqrt{R^2 - x^2 - y^2}$ of eq. 3
//! intersect in one interval whose length is integrated by the midpoint rule. Unlike the Monte
//! Carlo count, the result is continuous in the design, so it can be optimised.

use super::Tsai3Dof;
use pkm_traits::{BlockKernel, InvalidInput, run_block};

impl Tsai3Dof {
    /// Largest `ngrid` of [`Tsai3Dof::column_volume`]: 2¹⁴ per side, 2.7·10⁸ columns.
    pub const MAX_COLUMN_GRID: usize = 1 << 14;

    /// Workspace volume inside the hemisphere of radius [`Tsai3Dof::reach`], midpoint rule on
    /// `ngrid × ngrid` columns over $[-R, R]^2$.
    ///
    /// # Errors
    /// [`InvalidInput`] for `ngrid = 0` or `ngrid >` [`Tsai3Dof::MAX_COLUMN_GRID`] (refused
    /// before the `ngrid²` columns are visited).
    ///
    /// # Example
    /// ```
    /// use pkm_mechanisms::{Tsai3Dof, TsaiDesign};
    /// // Coincident legs, d+e = c-r = 0: W = π² a b² (Pappus).
    /// let coincident = TsaiDesign { a: 0.3, b: 0.7, d_plus_e: 0.0, c_minus_r: 0.0, phi2: 0.0, phi3: 0.0 };
    /// let d = Tsai3Dof::new(coincident).unwrap();
    /// let exact = std::f64::consts::PI.powi(2) * 0.3 * 0.49;
    /// assert!((d.column_volume(400).unwrap() / exact - 1.0).abs() < 1e-3);
    /// assert!(d.column_volume(0).is_err() && d.column_volume(usize::MAX).is_err());
    /// ```
    pub fn column_volume(&self, ngrid: usize) -> Result<f64, InvalidInput> {
        if ngrid == 0 {
            return Err(InvalidInput::new("ngrid", 0.0, "must be >= 1"));
        }
        InvalidInput::require_count_at_most(
            "ngrid",
            ngrid,
            Self::MAX_COLUMN_GRID,
            "at most MAX_COLUMN_GRID columns per side",
        )?;
        let r = self.reach();
        let cell = 2.0 * r / ngrid as f64;
        let total = run_block(&ColumnSum {
            design: self,
            ngrid,
            r,
            cell,
        });
        Ok(total * cell * cell)
    }

    /// The lengths of the workspace columns over $(x, y_l)$ within the hemisphere of radius
    /// `r` (module documentation), one per lane, without branches: a column is empty where the
    /// hemisphere or a leg's $|p_v| \le b$ excludes it.
    #[inline(always)]
    fn column_heights<const N: usize>(&self, x: f64, y: &[f64; N], r: f64) -> [f64; N] {
        let mut out = [0.0; N];
        for (l, height) in out.iter_mut().enumerate() {
            let y = y[l];
            let top = r * r - x * x - y * y;
            let (mut lo2, mut hi2, mut open) = (0.0_f64, top, top > 0.0);
            for &(c, s) in &self.trig {
                let (pu, pv) = (x * c + y * s + self.h, -x * s + y * c);
                let s3 = self.b * self.b - pv * pv;
                open &= s3 >= 0.0;
                let length = self.s + s3.sqrt();
                lo2 = lo2.max((length - self.a) * (length - self.a) - pu * pu);
                hi2 = hi2.min((length + self.a) * (length + self.a) - pu * pu);
            }
            let h = hi2.sqrt() - lo2.max(0.0).sqrt();
            *height = if open & (hi2 > lo2) { h } else { 0.0 };
        }
        out
    }

    /// One lane of [`Tsai3Dof::column_heights`], for the last columns of a row.
    fn column_height(&self, x: f64, y: f64, r: f64) -> f64 {
        self.column_heights(x, &[y], r)[0]
    }
}

/// Lanes of columns per group.
const COLUMN_LANES: usize = 8;

/// The sum of the column heights over the `ngrid × ngrid` grid, row after row and within a row
/// in order (the order of the point-by-point sum, so its bits), the heights [`COLUMN_LANES`]
/// at a time on the vector path of [`run_block`].
struct ColumnSum<'a> {
    design: &'a Tsai3Dof,
    ngrid: usize,
    r: f64,
    cell: f64,
}

impl BlockKernel for ColumnSum<'_> {
    type Output = f64;

    #[inline(always)]
    fn run(&self) -> f64 {
        let (r, cell) = (self.r, self.cell);
        let centre = |i: usize| -r + (i as f64 + 0.5) * cell;
        let whole = self.ngrid / COLUMN_LANES * COLUMN_LANES;
        let mut total = 0.0;
        for ix in 0..self.ngrid {
            let x = centre(ix);
            for first in (0..whole).step_by(COLUMN_LANES) {
                let y: [f64; COLUMN_LANES] = std::array::from_fn(|l| centre(first + l));
                for h in self.design.column_heights(x, &y, r) {
                    total += h;
                }
            }
            for iy in whole..self.ngrid {
                total += self.design.column_height(x, centre(iy), r);
            }
        }
        total
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{TsaiDesign, presets};
    use pkm_traits::{VectorPath, run_block_on};

    /// The sum of [`Tsai3Dof::column_height`] in grid order, one column at a time.
    fn point_by_point(design: &Tsai3Dof, ngrid: usize) -> f64 {
        let r = design.reach();
        let cell = 2.0 * r / ngrid as f64;
        let centre = |i: usize| -r + (i as f64 + 0.5) * cell;
        let mut total = 0.0;
        for ix in 0..ngrid {
            for iy in 0..ngrid {
                total += design.column_height(centre(ix), centre(iy), r);
            }
        }
        total
    }

    #[test]
    fn the_lane_column_sum_is_the_point_by_point_one_on_every_vector_path() {
        let designs = [
            Tsai3Dof::new(presets::stamper_max_gci()).unwrap(),
            Tsai3Dof::new(TsaiDesign::from_deg(0.3, 0.5, 0.1, -0.05, 100.0, 230.0)).unwrap(),
        ];
        for design in &designs {
            // Rows of whole lane groups, with a remainder, and shorter than one group.
            for ngrid in [64, 101, 5] {
                let want = point_by_point(design, ngrid);
                assert!(want > 0.0);
                let r = design.reach();
                let cell = 2.0 * r / ngrid as f64;
                let kernel = ColumnSum {
                    design,
                    ngrid,
                    r,
                    cell,
                };
                for path in VectorPath::available() {
                    let got = run_block_on(path, &kernel);
                    assert_eq!(got.to_bits(), want.to_bits(), "{ngrid} on {path:?}");
                }
            }
        }
    }
}
