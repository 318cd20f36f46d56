//! Settings of the adaptive Dormand–Prince integrator.

use pkm_traits::{IntegrationError, InvalidInput};

/// Error control and step limits of [`crate::DormandPrince54`].
///
/// A step is accepted when the weighted RMS norm of its local error estimate is at most 1, with
/// weights $\mathrm{atol} + \mathrm{rtol}\,\max(|z_{0,i}|, |z_{1,i}|)$ (Hairer, Nørsett & Wanner,
/// *Solving ODEs I*, §II.4, eq. 4.10–4.11).
///
/// | field | default | why |
/// |---|---|---|
/// | `rtol` | `1e-3` | MATLAB `ode45`'s default, which Miller 2004 used |
/// | `atol` | `1e-6` | MATLAB `ode45`'s default |
/// | `h_initial` | `0` (automatic) | Hairer's `hinit` estimate adapts to the problem's scale |
/// | `h_min` | `0` | the floor is then $16\,\varepsilon\,|t|$, as in `ode45`: smaller steps do not move $t$ |
/// | `h_max` | `∞` | the driver already clamps steps to the remaining interval |
/// | `max_steps` | `100 000` | `dopri5`'s `nmax`: a run that needs more is usually stiff or blowing up |
///
/// # Example
/// ```
/// use pkm_integrators::AdaptiveSettings;
/// let settings = AdaptiveSettings::default().with_rtol(1e-9)?.with_atol(1e-12)?;
/// assert!(AdaptiveSettings::default().with_rtol(-1.0).is_err());
/// # Ok::<(), pkm_traits::IntegrationError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveSettings {
    rtol: f64,
    atol: f64,
    h_initial: f64,
    h_min: f64,
    h_max: f64,
    max_steps: usize,
}

impl Default for AdaptiveSettings {
    fn default() -> Self {
        Self {
            rtol: 1e-3,
            atol: 1e-6,
            h_initial: 0.0,
            h_min: 0.0,
            h_max: f64::INFINITY,
            max_steps: 100_000,
        }
    }
}

impl AdaptiveSettings {
    /// Validated settings from all fields.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] when a tolerance is not finite and positive, a step
    /// limit is negative or NaN, `h_min > h_max`, or `max_steps` is 0.
    pub fn new(
        rtol: f64,
        atol: f64,
        h_initial: f64,
        h_min: f64,
        h_max: f64,
        max_steps: usize,
    ) -> Result<Self, IntegrationError> {
        Self::default()
            .with_rtol(rtol)?
            .with_atol(atol)?
            .with_h_initial(h_initial)?
            .with_h_max(h_max)?
            .with_h_min(h_min)?
            .with_max_steps(max_steps)
    }

    /// Relative tolerance.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless finite and `> 0`.
    pub fn with_rtol(self, rtol: f64) -> Result<Self, IntegrationError> {
        Ok(Self {
            rtol: InvalidInput::require_positive("rtol", rtol)?,
            ..self
        })
    }

    /// Absolute tolerance.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless finite and `> 0`.
    pub fn with_atol(self, atol: f64) -> Result<Self, IntegrationError> {
        Ok(Self {
            atol: InvalidInput::require_positive("atol", atol)?,
            ..self
        })
    }

    /// First step to try; 0 chooses it automatically.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless finite and `≥ 0`.
    pub fn with_h_initial(self, h_initial: f64) -> Result<Self, IntegrationError> {
        if !(h_initial.is_finite() && h_initial >= 0.0) {
            let requirement = "must be finite and >= 0 (0 = automatic)";
            return Err(InvalidInput::new("h_initial", h_initial, requirement).into());
        }
        Ok(Self { h_initial, ..self })
    }

    /// Smallest admissible step.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless finite, `≥ 0` and `≤ h_max`.
    pub fn with_h_min(self, h_min: f64) -> Result<Self, IntegrationError> {
        if !(h_min.is_finite() && h_min >= 0.0) {
            return Err(InvalidInput::new("h_min", h_min, "must be finite and >= 0").into());
        }
        if h_min > self.h_max {
            return Err(InvalidInput::new("h_min", h_min, "must not exceed h_max").into());
        }
        Ok(Self { h_min, ..self })
    }

    /// Largest admissible step (`∞` allowed).
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] unless `> 0` and `≥ h_min`.
    pub fn with_h_max(self, h_max: f64) -> Result<Self, IntegrationError> {
        if !(h_max > 0.0 && h_max >= self.h_min) {
            return Err(InvalidInput::new("h_max", h_max, "must be > 0 and >= h_min").into());
        }
        Ok(Self { h_max, ..self })
    }

    /// Budget of accepted steps per run.
    ///
    /// # Errors
    /// [`IntegrationError::Invalid`] when 0.
    pub fn with_max_steps(self, max_steps: usize) -> Result<Self, IntegrationError> {
        InvalidInput::require_nonzero_count("max_steps", max_steps)?;
        Ok(Self { max_steps, ..self })
    }

    /// Relative tolerance.
    pub fn rtol(&self) -> f64 {
        self.rtol
    }
    /// Absolute tolerance.
    pub fn atol(&self) -> f64 {
        self.atol
    }
    /// First step (0 = automatic).
    pub fn h_initial(&self) -> f64 {
        self.h_initial
    }
    /// Smallest admissible step.
    pub fn h_min(&self) -> f64 {
        self.h_min
    }
    /// Largest admissible step.
    pub fn h_max(&self) -> f64 {
        self.h_max
    }
    /// Budget of accepted steps per run.
    pub fn max_steps(&self) -> usize {
        self.max_steps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[track_caller]
    fn assert_invalid(result: Result<AdaptiveSettings, IntegrationError>, name: &str) {
        match result {
            Err(IntegrationError::Invalid(e)) => assert_eq!(e.name, name),
            other => panic!("expected Invalid({name}), got {other:?}"),
        }
    }

    #[test]
    fn invalid_settings_are_rejected_with_their_name() {
        let d = AdaptiveSettings::default();
        assert_invalid(d.with_rtol(0.0), "rtol");
        assert_invalid(d.with_rtol(f64::NAN), "rtol");
        assert_invalid(d.with_atol(-1e-6), "atol");
        assert_invalid(d.with_h_initial(-1.0), "h_initial");
        assert_invalid(d.with_h_min(f64::INFINITY), "h_min");
        assert_invalid(d.with_h_max(1.0).and_then(|s| s.with_h_min(2.0)), "h_min");
        assert_invalid(d.with_h_min(1.0).and_then(|s| s.with_h_max(0.5)), "h_max");
        assert_invalid(d.with_h_max(f64::NAN), "h_max");
        assert_invalid(d.with_max_steps(0), "max_steps");
        assert_invalid(
            AdaptiveSettings::new(1e-3, 1e-6, 0.0, 0.1, 0.01, 10),
            "h_min",
        );
    }

    #[test]
    fn new_round_trips_the_fields() {
        let s = AdaptiveSettings::new(1e-9, 1e-12, 1e-4, 1e-10, 0.1, 500).unwrap();
        assert_eq!(
            (
                s.rtol(),
                s.atol(),
                s.h_initial(),
                s.h_min(),
                s.h_max(),
                s.max_steps()
            ),
            (1e-9, 1e-12, 1e-4, 1e-10, 0.1, 500)
        );
    }
}
