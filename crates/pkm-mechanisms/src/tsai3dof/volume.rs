//! Deterministic workspace volume by columns (spec `stamper.md` §1): for fixed $(x, y)$ leg $i$
//! admits $(L - a)^2 - p_u^2 \le z^2 \le (L + a)^2 - p_u^2$, $L = d + e + \sqrt{b^2 - p_v^2}$;
//! the three intervals, $z \ge 0$ and the hemisphere $z \le \sqrt{R^2 - x^2 - y^2}$ of eq. 3
//! intersect in one interval whose length is integrated by the midpoint rule. Unlike the Monte
//! Carlo count, the result is continuous in the design, so it can be optimised.

use super::Tsai3Dof;
use nalgebra::Vector3;
use pkm_traits::InvalidInput;

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
        let mut total = 0.0;
        for ix in 0..ngrid {
            let x = -r + (ix as f64 + 0.5) * cell;
            for iy in 0..ngrid {
                let y = -r + (iy as f64 + 0.5) * cell;
                total += self.column_height(x, y, r);
            }
        }
        Ok(total * cell * cell)
    }

    /// Length of the workspace column over $(x, y)$ within the hemisphere of radius `r`.
    fn column_height(&self, x: f64, y: f64, r: f64) -> f64 {
        let top = r * r - x * x - y * y;
        if top <= 0.0 {
            return 0.0;
        }
        let (mut lo2, mut hi2) = (0.0_f64, top);
        for i in 0..3 {
            let (pu, pv, _) = self.leg_coordinates(i, &Vector3::new(x, y, 0.0));
            let s3 = self.b * self.b - pv * pv;
            if s3 < 0.0 {
                return 0.0;
            }
            let l = self.s + s3.sqrt();
            lo2 = lo2.max((l - self.a).powi(2) - pu * pu);
            hi2 = hi2.min((l + self.a).powi(2) - pu * pu);
        }
        if hi2 > lo2 {
            hi2.sqrt() - lo2.max(0.0).sqrt()
        } else {
            0.0
        }
    }
}
