//! Area means over a planar workspace cross-section: the manipulability index
//! $\eta_1 = \int_{A_W} (1/\kappa)\,dA / A_W$ of translation-invariant mechanisms (Miller 2004,
//! eqs. 1 and 4), by an accurate product Gauss–Legendre quadrature and by the paper's uniform
//! grid rule.

use crate::{IndexError, gauss_legendre::GaussLegendre};
use pkm_traits::SlicedRegion;

fn require_area(region: &impl SlicedRegion) -> Result<f64, IndexError> {
    let area = region.area();
    if area > 0.0 && area.is_finite() {
        Ok(area)
    } else {
        Err(IndexError::Invalid {
            what: "workspace cross-section area",
            value: area,
            requirement: "must be > 0 (the workspace is empty)",
        })
    }
}

/// $\int_W f\,dA / A_W$ by an $n \times n$ Gauss–Legendre product rule on every piece between
/// consecutive [`SlicedRegion::breakpoints`] ($z$ nodes mapped onto each slice), divided by the
/// exact area.
///
/// With $f = 1/\kappa$ of the Linear Delta, $n = 24$ is converged to about 3e-6 (against
/// $n = 48$): two orders below the grid rule's noise.
///
/// # Errors
/// [`IndexError::Invalid`] when the region is empty, `n = 0` or
/// `n >` [`GaussLegendre::MAX_ORDER`].
///
/// # Example
/// ```
/// # use pkm_traits::{Extents, SlicedRegion};
/// struct Square;
/// impl SlicedRegion for Square {
///     fn slice(&self, y: f64) -> Option<(f64, f64)> { (0.0..=1.0).contains(&y).then_some((0.0, 1.0)) }
///     fn breakpoints(&self) -> &[f64] { &[0.0, 1.0] }
///     fn extents(&self) -> Extents { Extents { y_min: 0.0, y_max: 1.0, z_min: 0.0, z_max: 1.0 } }
///     fn area(&self) -> f64 { 1.0 }
/// }
/// let mean = pkm_workspace_indices::mean_by_quadrature(&Square, |y, z| y * z, 4).unwrap();
/// assert!((mean - 0.25).abs() < 1e-14);
/// ```
pub fn mean_by_quadrature(
    region: &impl SlicedRegion,
    f: impl Fn(f64, f64) -> f64,
    n: usize,
) -> Result<f64, IndexError> {
    let area = require_area(region)?;
    if n == 0 {
        return Err(IndexError::Invalid {
            what: "quadrature points",
            value: 0.0,
            requirement: "must be >= 1",
        });
    }
    let rule = GaussLegendre::new(n)?;
    let mut integral = 0.0;
    for piece in region.breakpoints().windows(2) {
        rule.for_each_on(piece[0], piece[1], |y, wy| {
            if let Some((lo, hi)) = region.slice(y) {
                let mut inner = 0.0;
                rule.for_each_on(lo, hi, |z, wz| inner += wz * f(y, z));
                integral += wy * inner;
            }
        });
    }
    Ok(integral / area)
}

/// Settings of the paper's grid rule ([`mean_by_grid`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridRule {
    /// Keep refining until more than this many nodes lie in $W$. Default 5000: "$N_a > 5000$"
    /// (Miller 2004, §2.2.3).
    pub min_points: usize,
    /// The first step is $h = \sqrt{A_W / \text{target}}$. Default 6000.
    pub target_points: usize,
    /// Factor applied to $h$ while too few nodes lie in $W$. Default 0.95.
    pub shrink: f64,
}

impl Default for GridRule {
    fn default() -> Self {
        Self {
            min_points: 5000,
            target_points: 6000,
            shrink: 0.95,
        }
    }
}

/// What the grid rule measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridMean {
    /// $\sum_{a} f(a) / N_a$ (eq. 4).
    pub mean: f64,
    /// $N_a$, the nodes in $W$.
    pub n_points: usize,
    /// The grid step $h$.
    pub step: f64,
    /// $A_W \approx h^2 N_a$ (eq. 5).
    pub area: f64,
}

/// The mean of $f$ over the nodes of a cell-centred square grid that fall in $W$ (Miller 2004,
/// eqs. 4–5): nodes $y_j = y_{\min} + (j + \tfrac12)h$, $z_k = z_{\min} + (k + \tfrac12)h$ over
/// the extents of $W$, with $h$ shrunk until $N_a$ exceeds [`GridRule::min_points`].
///
/// # Errors
/// [`IndexError::Invalid`] for an empty region or a rule that cannot terminate: counts above
/// 2²², or no grid of at most 2²⁶ nodes within 1000 passes that holds more than `min_points`
/// nodes of the region.
pub fn mean_by_grid(
    region: &impl SlicedRegion,
    f: impl Fn(f64, f64) -> f64,
    rule: &GridRule,
) -> Result<GridMean, IndexError> {
    let area = require_area(region)?;
    if !(rule.shrink > 0.0 && rule.shrink < 1.0) || rule.target_points == 0 {
        return Err(IndexError::Invalid {
            what: "grid rule shrink factor",
            value: rule.shrink,
            requirement: "must lie in (0, 1) with target_points >= 1",
        });
    }
    for (what, count) in [
        ("grid rule min_points", rule.min_points),
        ("grid rule target_points", rule.target_points),
    ] {
        if count > MAX_GRID_POINTS {
            return Err(IndexError::Invalid {
                what,
                value: count as f64,
                requirement: "must be at most 2^22",
            });
        }
    }
    let e = region.extents();
    let (width, height) = (e.y_max - e.y_min, e.z_max - e.z_min);
    if !(width.is_finite() && height.is_finite() && width >= 0.0 && height >= 0.0) {
        return Err(IndexError::Invalid {
            what: "cross-section extents",
            value: if width.is_finite() { height } else { width },
            requirement: "must be finite and ordered",
        });
    }
    let mut h = (area / rule.target_points as f64).sqrt();
    for _ in 0..MAX_GRID_PASSES {
        // Nodes visited by this pass: refuse a grid that could not be swept in reasonable time.
        let nodes = (width / h + 1.0) * (height / h + 1.0);
        if !(nodes <= 16.0 * MAX_GRID_POINTS as f64) {
            break;
        }
        let (mut sum, mut n_points) = (0.0, 0usize);
        let mut y = e.y_min + 0.5 * h;
        while y < e.y_max {
            if let Some((lo, hi)) = region.slice(y) {
                let mut z = e.z_min + 0.5 * h;
                while z < e.z_max {
                    if lo <= z && z <= hi {
                        sum += f(y, z);
                        n_points += 1;
                    }
                    z += h;
                }
            }
            y += h;
        }
        if n_points > rule.min_points {
            return Ok(GridMean {
                mean: sum / n_points as f64,
                n_points,
                step: h,
                area: h * h * n_points as f64,
            });
        }
        h *= rule.shrink;
    }
    Err(IndexError::Invalid {
        what: "grid rule shrink factor",
        value: rule.shrink,
        requirement: "must reach more than min_points nodes within 1000 grids of at most 2^26 nodes",
    })
}

/// Largest [`GridRule::min_points`] and [`GridRule::target_points`] of [`mean_by_grid`]: 2²².
const MAX_GRID_POINTS: usize = 1 << 22;

/// Most grids [`mean_by_grid`] tries before giving up (with the default shrink 0.95, the
/// spacing falls by 10²² over them).
const MAX_GRID_PASSES: usize = 1000;
