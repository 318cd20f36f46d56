//! Area means over a planar workspace cross-section: the manipulability index
//! $\eta_1 = \int_{A_W} (1/\kappa)\,dA / A_W$ of translation-invariant mechanisms (Miller 2004,
//! eqs. 1 and 4), by an accurate product Gauss–Legendre quadrature and by the paper's uniform
//! grid rule.

use crate::{IndexError, LANES, gauss_legendre::GaussLegendre};
use pkm_traits::{InvalidInput, SlicedRegion};

/// Nodes of one slice $y$ gathered [`LANES`] at a time for a batch integrand
/// $f(y, [z_0, \dots, z_{L-1}])$, with their weights; [`LaneBatch::flush`] adds
/// $\sum_l w_l f(y, z_l)$ to a running sum in node order, so the sum is the one a node-by-node
/// loop forms.
struct LaneBatch {
    z: [f64; LANES],
    weight: [f64; LANES],
    len: usize,
}

impl LaneBatch {
    fn new() -> Self {
        Self {
            z: [0.0; LANES],
            weight: [0.0; LANES],
            len: 0,
        }
    }

    /// Queues node `z` with weight `w`, evaluating the batch once [`LANES`] nodes are queued.
    fn push<F>(&mut self, z: f64, w: f64, y: f64, f: &F, sum: &mut f64)
    where
        F: Fn(f64, &[f64; LANES]) -> [f64; LANES],
    {
        self.z[self.len] = z;
        self.weight[self.len] = w;
        self.len += 1;
        if self.len == LANES {
            self.flush(y, f, sum);
        }
    }

    /// Evaluates the queued nodes (the unused lanes repeat the last node and are ignored) and
    /// adds their weighted values to `sum` in order.
    fn flush<F>(&mut self, y: f64, f: &F, sum: &mut f64)
    where
        F: Fn(f64, &[f64; LANES]) -> [f64; LANES],
    {
        if self.len == 0 {
            return;
        }
        let last = self.z[self.len - 1];
        self.z[self.len..].fill(last);
        let values = f(y, &self.z);
        for (w, v) in self.weight[..self.len].iter().zip(&values) {
            *sum += w * v;
        }
        self.len = 0;
    }
}

fn require_area(region: &impl SlicedRegion) -> Result<f64, IndexError> {
    let area = region.area();
    if area > 0.0 && area.is_finite() {
        Ok(area)
    } else {
        Err(InvalidInput::new(
            "workspace cross-section area",
            area,
            "must be > 0 (the workspace is empty)",
        )
        .into())
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
    require_area(region)?;
    mean_by_quadrature_lanes(region, one_node_at_a_time(f), &GaussLegendre::new(n)?)
}

/// [`mean_by_quadrature`] by a prebuilt `rule` (so a caller integrating many regions builds it
/// once), with an integrand evaluated at [`LANES`] nodes of one slice at once:
/// `f(y, &z)[l]` $= f(y, z_l)$. The nodes of each slice are passed in order, [`LANES`] at a
/// time (unused lanes of the last batch repeat its last node and are ignored), and the weighted
/// values are summed in node order, so with `f` mapping a scalar integrand over the lanes the
/// result is bit-identical to [`mean_by_quadrature`].
///
/// # Errors
/// [`IndexError::Invalid`] when the region is empty or the rule has no node.
pub fn mean_by_quadrature_lanes(
    region: &impl SlicedRegion,
    f: impl Fn(f64, &[f64; LANES]) -> [f64; LANES],
    rule: &GaussLegendre,
) -> Result<f64, IndexError> {
    let area = require_area(region)?;
    if rule.is_empty() {
        return Err(InvalidInput::new("quadrature points", 0.0, "must be >= 1").into());
    }
    let mut integral = 0.0;
    let mut batch = LaneBatch::new();
    for piece in region.breakpoints().windows(2) {
        rule.for_each_on(piece[0], piece[1], |y, wy| {
            if let Some((lo, hi)) = region.slice(y) {
                let mut inner = 0.0;
                rule.for_each_on(lo, hi, |z, wz| batch.push(z, wz, y, &f, &mut inner));
                batch.flush(y, &f, &mut inner);
                integral += wy * inner;
            }
        });
    }
    Ok(integral / area)
}

/// A scalar integrand as a batch one: `f` mapped over the lanes.
fn one_node_at_a_time(f: impl Fn(f64, f64) -> f64) -> impl Fn(f64, &[f64; LANES]) -> [f64; LANES] {
    move |y, z| z.map(|z| f(y, z))
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
    mean_by_grid_lanes(region, one_node_at_a_time(f), rule)
}

/// [`mean_by_grid`] with an integrand evaluated at [`LANES`] nodes of one grid row at once
/// (`f(y, &z)[l]` $= f(y, z_l)$), the nodes of each row in $W$ passed in order and summed in
/// order, so with `f` mapping a scalar integrand over the lanes the result is bit-identical to
/// [`mean_by_grid`].
///
/// # Errors
/// As [`mean_by_grid`].
pub fn mean_by_grid_lanes(
    region: &impl SlicedRegion,
    f: impl Fn(f64, &[f64; LANES]) -> [f64; LANES],
    rule: &GridRule,
) -> Result<GridMean, IndexError> {
    let area = require_area(region)?;
    if !(rule.shrink > 0.0 && rule.shrink < 1.0) || rule.target_points == 0 {
        return Err(InvalidInput::new(
            "grid rule shrink factor",
            rule.shrink,
            "must lie in (0, 1) with target_points >= 1",
        )
        .into());
    }
    for (what, count) in [
        ("grid rule min_points", rule.min_points),
        ("grid rule target_points", rule.target_points),
    ] {
        if count > MAX_GRID_POINTS {
            return Err(InvalidInput::new(what, count as f64, "must be at most 2^22").into());
        }
    }
    let e = region.extents();
    let (width, height) = (e.y_max - e.y_min, e.z_max - e.z_min);
    if !(width.is_finite() && height.is_finite() && width >= 0.0 && height >= 0.0) {
        return Err(InvalidInput::new(
            "cross-section extents",
            if width.is_finite() { height } else { width },
            "must be finite and ordered",
        )
        .into());
    }
    let mut h = (area / rule.target_points as f64).sqrt();
    for _ in 0..MAX_GRID_PASSES {
        // Nodes visited by this pass: refuse a grid that could not be swept in reasonable time.
        let nodes = (width / h + 1.0) * (height / h + 1.0);
        if !(nodes <= 16.0 * MAX_GRID_POINTS as f64) {
            break;
        }
        let (mut sum, mut n_points) = (0.0, 0usize);
        let mut batch = LaneBatch::new();
        let mut y = e.y_min + 0.5 * h;
        while y < e.y_max {
            if let Some((lo, hi)) = region.slice(y) {
                let mut z = e.z_min + 0.5 * h;
                while z < e.z_max {
                    if lo <= z && z <= hi {
                        batch.push(z, 1.0, y, &f, &mut sum);
                        n_points += 1;
                    }
                    z += h;
                }
                batch.flush(y, &f, &mut sum);
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
    Err(InvalidInput::new(
        "grid rule shrink factor",
        rule.shrink,
        "must reach more than min_points nodes within 1000 grids of at most 2^26 nodes",
    )
    .into())
}

/// Largest [`GridRule::min_points`] and [`GridRule::target_points`] of [`mean_by_grid`]: 2²².
const MAX_GRID_POINTS: usize = 1 << 22;

/// Most grids [`mean_by_grid`] tries before giving up (with the default shrink 0.95, the
/// spacing falls by 10²² over them).
const MAX_GRID_PASSES: usize = 1000;

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;
    use pkm_traits::Extents;

    /// The triangle $0 \le z \le y \le 1$, area 1/2.
    struct Triangle;

    impl SlicedRegion for Triangle {
        fn slice(&self, y: f64) -> Option<(f64, f64)> {
            (0.0..=1.0).contains(&y).then_some((0.0, y))
        }
        fn breakpoints(&self) -> &[f64] {
            &[0.0, 1.0]
        }
        fn extents(&self) -> Extents {
            Extents {
                y_min: 0.0,
                y_max: 1.0,
                z_min: 0.0,
                z_max: 1.0,
            }
        }
        fn area(&self) -> f64 {
            0.5
        }
    }

    fn integrand(y: f64, z: f64) -> f64 {
        (3.0 * y - z).sin() + y * z * z
    }

    /// [`integrand`] at every lane's node.
    fn batch_integrand(y: f64, z: &[f64; LANES]) -> [f64; LANES] {
        z.map(|z| integrand(y, z))
    }

    /// The node-by-node product rule (the definition of [`mean_by_quadrature`]).
    fn node_by_node_quadrature(n: usize) -> f64 {
        let rule = GaussLegendre::new(n).unwrap();
        let mut integral = 0.0;
        rule.for_each_on(0.0, 1.0, |y, wy| {
            let mut inner = 0.0;
            rule.for_each_on(0.0, y, |z, wz| inner += wz * integrand(y, z));
            integral += wy * inner;
        });
        integral / 0.5
    }

    #[test]
    fn batched_quadrature_sums_the_nodes_in_order_for_every_padding() {
        for n in 1..=3 * LANES + 1 {
            let rule = GaussLegendre::new(n).unwrap();
            let batched = mean_by_quadrature_lanes(&Triangle, batch_integrand, &rule).unwrap();
            assert_eq!(batched, node_by_node_quadrature(n), "n = {n}");
            assert_eq!(
                mean_by_quadrature(&Triangle, integrand, n).unwrap(),
                batched
            );
        }
        // Exact for a polynomial: ∫∫ y z² = 1/15 over the triangle, mean 2/15.
        let rule = GaussLegendre::new(3).unwrap();
        let cubic =
            mean_by_quadrature_lanes(&Triangle, |y, z| z.map(|z| y * z * z), &rule).unwrap();
        assert!((cubic - 2.0 / 15.0).abs() < 1e-15);
    }

    #[test]
    fn batched_grid_sums_the_nodes_of_each_row_in_order() {
        let rule = GridRule::default();
        let batched = mean_by_grid_lanes(&Triangle, batch_integrand, &rule).unwrap();
        // Node by node at the step the batched rule settled on.
        let h = batched.step;
        let (mut sum, mut count) = (0.0, 0usize);
        let mut y = 0.5 * h;
        while y < 1.0 {
            let mut z = 0.5 * h;
            while z < 1.0 {
                if z <= y {
                    sum += integrand(y, z);
                    count += 1;
                }
                z += h;
            }
            y += h;
        }
        assert_eq!(batched.n_points, count);
        assert_eq!(batched.mean, sum / count as f64);
        assert_eq!(mean_by_grid(&Triangle, integrand, &rule).unwrap(), batched);
    }
}
