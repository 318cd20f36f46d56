//! A forward run of the dynamics from a known state, sampled at requested times with its
//! diagnostics: the platform position, the constraint drift and the energy balance
//! $E(t) - W(t) - (E(t_0) - W(t_0))$, which is 0 along an exact solution ($W$ the motor work).
//!
//! Fed with the torques of an inverse-dynamics run ([`retrace_sampled`]), the run retraces the
//! commanded motion: the check of Miller 2004, §3.5 and Fig. 9 that inverse and forward
//! dynamics agree.

use super::{ForwardForm, HamiltonForm, SampledTorques};
use crate::inverse::sample_step;
use crate::{DynamicsError, ExtendedModel, ExtendedState};
use nalgebra::{SVector, Vector3};
use pkm_integrators::{OutputTimes, Scheme, integrate};
use pkm_traits::{IntegrationError, InvalidInput, Progress};
use serde::{Deserialize, Serialize};

/// What a forward run did, at each output time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Retrace {
    /// Output times (s).
    pub times: Vec<f64>,
    /// Platform positions $p(t)$ (m).
    pub positions: Vec<Vector3<f64>>,
    /// Constraint drift $\max_i |\Phi_i| / (2 L_b)$ (m, [`ForwardForm::drift`]).
    pub drift: Vec<f64>,
    /// Energy balance $E(t) - W(t) - (E(t_0) - W(t_0))$ (J).
    pub energy_balance: Vec<f64>,
    /// Accepted integrator steps.
    pub steps: usize,
    /// Right-hand-side evaluations.
    pub evaluations: usize,
}

impl Retrace {
    /// The largest drift (m).
    pub fn max_drift(&self) -> f64 {
        self.drift.iter().copied().fold(0.0, f64::max)
    }

    /// The largest $|E - W - (E_0 - W_0)|$ (J).
    pub fn max_energy_balance(&self) -> f64 {
        self.energy_balance
            .iter()
            .fold(0.0, |largest, e| largest.max(e.abs()))
    }

    /// $p(t_k) - p_{\mathrm{commanded},k}$ at each output time for which a commanded position
    /// is given (m).
    pub fn position_errors(&self, commanded: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        self.positions
            .iter()
            .zip(commanded)
            .map(|(p, c)| p - c)
            .collect()
    }

    /// The largest $|p(t_k) - p_{\mathrm{commanded},k}|$ (m).
    pub fn max_position_error(&self, commanded: &[Vector3<f64>]) -> f64 {
        self.position_errors(commanded)
            .iter()
            .map(Vector3::norm)
            .fold(0.0, f64::max)
    }
}

/// Integrates `form` with `scheme` over `t_span` from `start` (its $q$ and $\dot q$; work 0),
/// and samples it at `output` with its diagnostics.
///
/// # Errors
/// [`DynamicsError::Integration`] when the integrator fails or is cancelled through `progress`
/// (with [`IntegrationError::Cancelled`]), for an invalid span or output times, or when the
/// form cannot be evaluated at a sample.
pub fn retrace<F: ForwardForm, S: Scheme<13>>(
    form: &F,
    start: &ExtendedState,
    t_span: (f64, f64),
    output: &OutputTimes,
    scheme: &mut S,
    progress: &dyn Progress,
) -> Result<Retrace, DynamicsError> {
    let z0 = form.initial_state(&start.q, &start.qd);
    let run = integrate(form, scheme, t_span, &z0, output, progress)?;
    let balance =
        |t: f64, z: &SVector<f64, 13>| form.energy_minus_work(t, z).map_err(IntegrationError::from);
    let (Some(&t0), Some(z0)) = (run.times.first(), run.states.first()) else {
        return Err(InvalidInput::new("output times", 0.0, "at least one").into());
    };
    let e0 = balance(t0, z0)?;
    let energy_balance = run
        .times
        .iter()
        .zip(&run.states)
        .map(|(t, z)| Ok(balance(*t, z)? - e0))
        .collect::<Result<Vec<_>, DynamicsError>>()?;
    Ok(Retrace {
        positions: run
            .states
            .iter()
            .map(|z| z.fixed_rows::<3>(0).into())
            .collect(),
        drift: run.states.iter().map(|z| form.drift(z)).collect(),
        energy_balance,
        times: run.times,
        steps: run.stats.steps,
        evaluations: run.stats.evaluations,
    })
}

/// The retrace of an inverse-dynamics run: the Hamilton form (eqs. 16–19, Baumgarte gain
/// `kappa`) fed with `torques` sampled at the samples' times (Catmull–Rom,
/// [`SampledTorques`]), from the first sample's state, output at the samples' times.
///
/// # Errors
/// [`DynamicsError::Invalid`] for samples that are too few or not equally spaced
/// ([`sample_step`]), a torque count other than the sample count, or a gain that is not finite
/// and $\ge 0$; otherwise as [`retrace`].
///
/// # Example
/// ```
/// use pkm_dynamics_hamilton::forward::retrace_sampled;
/// use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
/// use pkm_dynamics_hamilton::{ExtendedModel, MassParameters, inverse};
/// use pkm_integrators::{AdaptiveSettings, DormandPrince54};
/// use pkm_mechanisms::{Placement, RotaryDelta, presets};
/// use pkm_traits::Silent;
/// let robot = RotaryDelta::new(presets::nuwar(Placement::canonical()))?;
/// let model = ExtendedModel::new(robot, &MassParameters::miller2004())?;
/// let cycle = miller_pick_and_place(0.5)?;
/// let samples = inverse::sample(&model, &cycle, 1e-3)?;
/// let torques = inverse::hamilton(&model, &samples, inverse::Differencing::Central)?;
/// let settings = AdaptiveSettings::default().with_rtol(1e-8)?.with_atol(1e-11)?;
/// let run = retrace_sampled(&model, &samples, &torques, 20.0, &mut DormandPrince54::new(settings), &Silent)?;
/// let commanded: Vec<_> = samples.iter().map(|(t, _)| cycle.sample(*t).p).collect();
/// assert!(run.max_position_error(&commanded) < 4e-4); // m, Fig. 9
/// assert!(run.max_drift() < 1e-6 && run.max_energy_balance() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn retrace_sampled<S: Scheme<13>>(
    model: &ExtendedModel,
    samples: &[(f64, ExtendedState)],
    torques: &[Vector3<f64>],
    kappa: f64,
    scheme: &mut S,
    progress: &dyn Progress,
) -> Result<Retrace, DynamicsError> {
    let dt = sample_step(samples)?;
    if torques.len() != samples.len() {
        let requirement = "one torque per sample";
        return Err(InvalidInput::new("torques", torques.len() as f64, requirement).into());
    }
    let [(t0, start), .., (t_end, _)] = samples else {
        return Err(InvalidInput::new("samples", samples.len() as f64, "at least 3").into());
    };
    let tau = SampledTorques::new(dt, torques.to_vec())?;
    let form = HamiltonForm::new(model, |t| tau.at(t - t0), kappa)?;
    let times = OutputTimes::Times(samples.iter().map(|(t, _)| *t).collect());
    retrace(&form, start, (*t0, *t_end), &times, scheme, progress)
}
