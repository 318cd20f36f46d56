//! Gauss–Legendre nodes and weights on $[-1, 1]$.

use crate::IndexError;
use pkm_traits::InvalidInput;

/// An $n$-point Gauss–Legendre rule, exact for polynomials of degree $2n - 1$.
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// Largest order: building the rule costs $O(n^2)$ and a product rule visits $n^2$ nodes.
    pub const MAX_ORDER: usize = 1024;

    /// The $n$-point rule (Newton iteration on $P_n$ from Chebyshev guesses; nodes to round-off).
    /// `n = 0` gives the empty rule.
    ///
    /// # Errors
    /// [`IndexError::Invalid`] for `n >` [`GaussLegendre::MAX_ORDER`] (refused before
    /// allocating).
    pub fn new(n: usize) -> Result<Self, IndexError> {
        if n > Self::MAX_ORDER {
            return Err(InvalidInput::new(
                "quadrature order",
                n as f64,
                "must be at most GaussLegendre::MAX_ORDER",
            )
            .into());
        }
        let mut nodes = Vec::with_capacity(n);
        let mut weights = Vec::with_capacity(n);
        let nf = n as f64;
        for i in 0..n {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d.is_finite() { d } else { dp };
            nodes.push(x);
            weights.push(2.0 / ((1.0 - x * x) * dp * dp));
        }
        Ok(Self { nodes, weights })
    }

    /// $\int_a^b f \approx \sum_i w_i f(x_i)$, visiting the mapped nodes and weights.
    ///
    /// Every finite interval gives finite nodes and weights, ±`f64::MAX` included (the half
    /// width and the midpoint are formed from $a/2$ and $b/2$, the same bits as $(b - a)/2$ and
    /// $(a + b)/2$ wherever those do not overflow); NaN in, NaN out; never a panic.
    pub fn for_each_on(&self, a: f64, b: f64, mut visit: impl FnMut(f64, f64)) {
        let (half, mid) = (0.5 * b - 0.5 * a, 0.5 * a + 0.5 * b);
        for (x, w) in self.nodes.iter().zip(&self.weights) {
            visit(mid + half * x, half * w);
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the rule has no points.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
}

/// $P_n(x)$ and $P_n'(x)$ by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::GaussLegendre;

    #[test]
    fn integrates_polynomials_of_degree_2n_minus_1_exactly() {
        for n in [1, 2, 5, 16, 24, 48] {
            let rule = GaussLegendre::new(n).unwrap();
            let degree = 2 * n - 1;
            let mut sum = 0.0;
            rule.for_each_on(0.0, 2.0, |x, w| sum += w * x.powi(degree as i32));
            let exact = 2f64.powi(degree as i32 + 1) / (degree as f64 + 1.0);
            assert!(
                (sum / exact - 1.0).abs() < 1e-12,
                "n = {n}: {sum} vs {exact}"
            );
        }
    }
}
