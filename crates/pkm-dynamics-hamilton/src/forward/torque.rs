//! Torque histories sampled on a uniform grid, interpolated for forward dynamics.

use crate::DynamicsError;
use nalgebra::Vector3;
use pkm_traits::InvalidInput;

/// Torques $\tau_k$ at $t_k = k\,\Delta t$, read between samples by Catmull–Rom cubic
/// interpolation (exact for cubics, $C^1$).
///
/// # Example
/// ```
/// use pkm_dynamics_hamilton::forward::SampledTorques;
/// use nalgebra::Vector3;
/// let s = SampledTorques::new(0.5, (0..5).map(|k| Vector3::repeat(k as f64)).collect()).unwrap();
/// assert!((s.at(0.75).x - 1.5).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SampledTorques<V = Vector3<f64>> {
    dt: f64,
    values: Vec<V>,
}

impl<V> SampledTorques<V>
where
    V: Clone
        + std::ops::Add<Output = V>
        + std::ops::Sub<Output = V>
        + std::ops::Mul<f64, Output = V>,
{
    /// Wraps samples taken every `dt`.
    ///
    /// # Errors
    /// [`DynamicsError::Invalid`] for a non-positive step or fewer than 2 samples.
    pub fn new(dt: f64, values: Vec<V>) -> Result<Self, DynamicsError> {
        if !(dt > 0.0 && dt.is_finite() && values.len() >= 2) {
            return Err(InvalidInput::new(
                "dt",
                dt,
                "must be finite and > 0 with at least 2 samples",
            )
            .into());
        }
        Ok(Self { dt, values })
    }

    /// $\tau(t)$, constant beyond the ends.
    pub fn at(&self, t: f64) -> V {
        let last = self.values.len() - 1;
        let x = (t / self.dt).clamp(0.0, last as f64);
        let k = (x.floor() as usize).min(last - 1);
        let s = x - k as f64;
        let v = |i: isize| self.values[i.clamp(0, last as isize) as usize].clone();
        let k = k as isize;
        let (p0, p1, p2, p3) = (v(k - 1), v(k), v(k + 1), v(k + 2));
        let (s2, s3) = (s * s, s * s * s);
        (p1.clone() * 2.0
            + (p2.clone() - p0.clone()) * s
            + (p0.clone() * 2.0 - p1.clone() * 5.0 + p2.clone() * 4.0 - p3.clone()) * s2
            + (p1 * 3.0 - p0 - p2 * 3.0 + p3) * s3)
            * 0.5
    }
}
