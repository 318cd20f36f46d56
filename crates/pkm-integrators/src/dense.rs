//! Continuous extension of one Dormand–Prince step.

use nalgebra::SVector;

/// The fourth-order continuous extension of the Dormand–Prince 5(4) pair over one accepted step
/// $[t_0, t_0 + h]$ (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., §II.6, eq. 6.12 and
/// Shampine's coefficients as used in `dopri5`):
/// $$ z(t_0 + \theta h) = r_1 + \theta\bigl(r_2 + (1-\theta)\bigl(r_3 + \theta\,(r_4 + (1-\theta)\, r_5)\bigr)\bigr),
/// \qquad \theta \in [0, 1]. $$
/// It matches $z_0$, $z_1$ and the derivatives at both ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseSegment<const M: usize> {
    pub(crate) t0: f64,
    pub(crate) h: f64,
    pub(crate) r: [SVector<f64, M>; 5],
}

impl<const M: usize> DenseSegment<M> {
    /// Start of the step.
    pub fn t_start(&self) -> f64 {
        self.t0
    }

    /// End of the step.
    pub fn t_end(&self) -> f64 {
        self.t0 + self.h
    }

    /// The interpolated state at `t` (meant for $t$ in the step; outside it extrapolates).
    pub fn evaluate(&self, t: f64) -> SVector<f64, M> {
        let theta = (t - self.t0) / self.h;
        let theta1 = 1.0 - theta;
        let [r1, r2, r3, r4, r5] = &self.r;
        r1 + (r2 + (r3 + (r4 + r5 * theta1) * theta) * theta1) * theta
    }
}
