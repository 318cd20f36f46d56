//! The embedded Dormand–Prince 5(4) pair with step-size control and dense output.

use nalgebra::SVector;
use pkm_traits::{IntegrationError, Integrator, StepReport, VectorField};

use crate::tableau::{A2, A3, A4, A5, A6, B, C, D, E, combine};
use crate::{AdaptiveSettings, DenseSegment, Scheme, Start, require_finite_state};

/// Safety factor and bounds of the step-size ratio (Hairer, Nørsett & Wanner, eq. II.4.13).
const SAFETY: f64 = 0.9;
const SHRINK_MIN: f64 = 0.2;
const GROW_MAX: f64 = 5.0;

/// Explicit Runge–Kutta pair of orders 5 and 4 by Dormand & Prince (1980), the method of
/// MATLAB's `ode45` and of Hairer's `dopri5`: 7 stages, first-same-as-last (6 new evaluations
/// per accepted step), local extrapolation (the 5th-order solution is propagated), a
/// fourth-order continuous extension ([`DenseSegment`]), and the standard step-size controller
/// $h_{\text{new}} = h \min\bigl(5, \max(0.2,\ 0.9\, \mathrm{err}^{-1/5})\bigr)$ with no growth
/// right after a rejection. Settings: [`AdaptiveSettings`].
///
/// [`Integrator::step`] tries the given step and shrinks it until the error test passes; its
/// report proposes the next step.
///
/// # Example
/// ```
/// use pkm_integrators::{AdaptiveSettings, DormandPrince54, test_problems::ExponentialDecay};
/// use pkm_traits::Integrator;
/// let decay = ExponentialDecay::new(1.0)?;
/// let mut dopri = DormandPrince54::new(AdaptiveSettings::default().with_rtol(1e-10)?);
/// let mut z = nalgebra::Vector1::new(1.0);
/// let report = dopri.step(&decay, 0.0, &mut z, 0.01)?;
/// assert!((z[0] - (-report.h_taken).exp()).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct DormandPrince54<const M: usize> {
    settings: AdaptiveSettings,
    /// $(t, z, f(t, z))$ at the end of the last accepted step, reused as the next first stage.
    fsal: Option<(f64, SVector<f64, M>, SVector<f64, M>)>,
    dense: Option<DenseSegment<M>>,
}

/// One attempted step: new state, the seven stages and the weighted error norm.
struct Attempt<const M: usize> {
    z1: SVector<f64, M>,
    k: [SVector<f64, M>; 7],
    error: f64,
}

impl<const M: usize> DormandPrince54<M> {
    /// The integrator with the given settings.
    pub fn new(settings: AdaptiveSettings) -> Self {
        Self {
            settings,
            fsal: None,
            dense: None,
        }
    }

    /// Its settings.
    pub fn settings(&self) -> &AdaptiveSettings {
        &self.settings
    }

    /// Weighted RMS norm $\sqrt{\tfrac1M \sum_i (v_i / s_i)^2}$,
    /// $s_i = \mathrm{atol} + \mathrm{rtol}\max(|a_i|, |b_i|)$.
    fn weighted_norm(&self, v: &SVector<f64, M>, a: &SVector<f64, M>, b: &SVector<f64, M>) -> f64 {
        let (rtol, atol) = (self.settings.rtol(), self.settings.atol());
        let sum: f64 = (0..M)
            .map(|i| (v[i] / (atol + rtol * a[i].abs().max(b[i].abs()))).powi(2))
            .sum();
        (sum / M.max(1) as f64).sqrt()
    }

    /// Stages 2–7 from `k1`, the 5th-order solution and its error estimate.
    fn attempt<F: VectorField<M> + ?Sized>(
        &self,
        field: &F,
        t: f64,
        z: &SVector<f64, M>,
        k1: &SVector<f64, M>,
        h: f64,
    ) -> Result<Attempt<M>, IntegrationError> {
        let mut k = [*k1; 7];
        field.rhs(t + C[1] * h, &(z + combine(&A2, &k) * h), &mut k[1])?;
        field.rhs(t + C[2] * h, &(z + combine(&A3, &k) * h), &mut k[2])?;
        field.rhs(t + C[3] * h, &(z + combine(&A4, &k) * h), &mut k[3])?;
        field.rhs(t + C[4] * h, &(z + combine(&A5, &k) * h), &mut k[4])?;
        field.rhs(t + C[5] * h, &(z + combine(&A6, &k) * h), &mut k[5])?;
        let z1 = z + combine(&B, &k) * h;
        field.rhs(t + h, &z1, &mut k[6])?;
        let error = if z1.iter().all(|v| v.is_finite()) {
            self.weighted_norm(&(combine(&E, &k) * h), z, &z1)
        } else {
            f64::NAN // an infinite z1 would make the weights infinite and the norm 0
        };
        Ok(Attempt { z1, k, error })
    }

    /// Step-size ratio proposed by an error norm (no growth when `after_rejection`).
    fn ratio(error: f64, after_rejection: bool) -> f64 {
        let grow_max = if after_rejection { 1.0 } else { GROW_MAX };
        (SAFETY * error.powf(-0.2)).clamp(SHRINK_MIN, grow_max)
    }

    /// $f(t, z)$, reused from the previous step when it ended at exactly $(t, z)$.
    fn first_stage<F: VectorField<M> + ?Sized>(
        &self,
        field: &F,
        t: f64,
        z: &SVector<f64, M>,
        evaluations: &mut usize,
    ) -> Result<SVector<f64, M>, IntegrationError> {
        if let Some((t_end, z_end, f_end)) = &self.fsal
            && t_end.to_bits() == t.to_bits()
            && z_end == z
        {
            return Ok(*f_end);
        }
        let mut k1 = SVector::zeros();
        field.rhs(t, z, &mut k1)?;
        *evaluations += 1;
        Ok(k1)
    }

    /// Hairer's starting-step heuristic (`hinit`, Hairer, Nørsett & Wanner §II.4): two
    /// evaluations; the first is kept for the first step.
    fn automatic_initial_step<F: VectorField<M> + ?Sized>(
        &mut self,
        field: &F,
        t0: f64,
        z0: &SVector<f64, M>,
        h_cap: f64,
    ) -> Result<f64, IntegrationError> {
        let mut f0 = SVector::zeros();
        field.rhs(t0, z0, &mut f0)?;
        require_finite_state(t0, &f0)?;
        self.fsal = Some((t0, *z0, f0));
        let d0 = self.weighted_norm(z0, z0, z0);
        let d1 = self.weighted_norm(&f0, z0, z0);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        let h0 = h0.min(h_cap);
        let mut f1 = SVector::zeros();
        field.rhs(t0 + h0, &(z0 + f0 * h0), &mut f1)?;
        let d2 = self.weighted_norm(&(f1 - f0), z0, z0) / h0;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(0.2)
        };
        Ok((100.0 * h0).min(h1).min(h_cap))
    }

    /// Keeps the accepted step for dense output and FSAL.
    fn accept(&mut self, t: f64, h: f64, z0: &SVector<f64, M>, attempt: &Attempt<M>) {
        let k = &attempt.k;
        let dz = attempt.z1 - z0;
        let r3 = k[0] * h - dz;
        let r4 = dz - k[6] * h - r3;
        let r5 = combine(&D, k) * h;
        self.dense = Some(DenseSegment {
            t0: t,
            h,
            r: [*z0, dz, r3, r4, r5],
        });
        self.fsal = Some((t + h, attempt.z1, k[6]));
    }
}

impl<const M: usize> Integrator<M> for DormandPrince54<M> {
    /// Tries a step of `h` (capped at `h_max`; negative integrates backwards) and shrinks it
    /// until the weighted local error is at most 1.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] for a non-finite `t`, or an `h` that is zero, not
    /// finite or too small to move `t`;
    /// [`IntegrationError::Rhs`] when the field fails; [`IntegrationError::NonFinite`] when the
    /// state is not finite, or when attempts stay non-finite down to the smallest step (a
    /// non-finite attempt is otherwise rejected and the step shrunk by 5);
    /// [`IntegrationError::StepSizeUnderflow`] when a rejected step would have to shrink below
    /// `max(h_min, 16 ε |t|)` (and never below the smallest normal `f64`).
    fn step<F: VectorField<M> + ?Sized>(
        &mut self,
        field: &F,
        t: f64,
        z: &mut SVector<f64, M>,
        h: f64,
    ) -> Result<StepReport, IntegrationError> {
        crate::require_step(t, h)?;
        require_finite_state(t, z)?;
        let mut evaluations = 0;
        let k1 = self.first_stage(field, t, z, &mut evaluations)?;
        require_finite_state(t, &k1)?;
        let direction = if h < 0.0 { -1.0 } else { 1.0 };
        let mut h_abs = h.abs().min(self.settings.h_max());
        // At least the smallest normal step, so that shrinking by 0.2 always reaches the floor.
        let h_floor = self
            .settings
            .h_min()
            .max(16.0 * f64::EPSILON * t.abs())
            .max(f64::MIN_POSITIVE);
        let mut rejections = 0;
        loop {
            let attempt = self.attempt(field, t, z, &k1, direction * h_abs)?;
            evaluations += 6;
            if attempt.error <= 1.0 {
                let h_taken = direction * h_abs;
                self.accept(t, h_taken, z, &attempt);
                *z = attempt.z1;
                let h_next =
                    (h_abs * Self::ratio(attempt.error, rejections > 0)).min(self.settings.h_max());
                return Ok(StepReport {
                    h_taken,
                    h_next: direction * h_next,
                    error_estimate: attempt.error,
                    evaluations,
                    rejections,
                });
            }
            rejections += 1;
            // A non-finite attempt (a stage left the field's domain) is rejected like a huge error.
            let finite = attempt.error.is_finite();
            h_abs *= if finite {
                Self::ratio(attempt.error, true)
            } else {
                SHRINK_MIN
            };
            if h_abs < h_floor {
                return Err(if finite {
                    IntegrationError::StepSizeUnderflow {
                        t,
                        h: h_abs,
                        h_min: h_floor,
                    }
                } else {
                    IntegrationError::NonFinite { t }
                });
            }
        }
    }
}

impl<const M: usize> Scheme<M> for DormandPrince54<M> {
    /// Forgets the previous run and picks `h_initial`, or Hairer's estimate when it is 0.
    fn start<F: VectorField<M> + ?Sized>(
        &mut self,
        field: &F,
        t0: f64,
        z0: &SVector<f64, M>,
        t1: f64,
    ) -> Result<Start, IntegrationError> {
        self.fsal = None;
        self.dense = None;
        let h_cap = self.settings.h_max().min((t1 - t0).abs());
        if self.settings.h_initial() > 0.0 {
            return Ok(Start {
                h: self.settings.h_initial().min(h_cap),
                evaluations: 0,
            });
        }
        let h = self.automatic_initial_step(field, t0, z0, h_cap)?;
        Ok(Start {
            h: h.max(self.settings.h_min()),
            evaluations: 2,
        })
    }

    fn max_steps(&self) -> usize {
        self.settings.max_steps()
    }

    fn dense_output(&self) -> Option<&DenseSegment<M>> {
        self.dense.as_ref()
    }

    fn has_dense_output(&self) -> bool {
        true
    }
}
