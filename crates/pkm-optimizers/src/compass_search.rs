//! Compass search: a derivative-free local search for objectives that finite differences
//! cannot serve, such as a Monte Carlo estimate on common random numbers (piecewise constant in
//! the design: its differences are 0 or jumps).
//!
//! Kolda, Lewis & Torczon, "Optimization by direct search", *SIAM Review* 45(3), 2003,
//! Algorithm 3.2. In the scaled variables $z_j = (x_j - l_j)/(u_j - l_j)$ the poll set of step
//! $\Delta$ is $\{z \pm \Delta e_j\}$, clipped to the box $[0, 1]^n$. Every poll point is
//! evaluated (a complete poll, in the fixed order $+e_1, -e_1, +e_2, \dots$); the best one
//! becomes the incumbent when it strictly improves on it, otherwise $\Delta \leftarrow \Delta/2$.
//! The search stops when $\Delta$ falls below `min_step` (converged) or after `max_evaluations`
//! evaluations. An infeasible design is never better than a feasible one (the *extreme barrier*
//! of §8.1), so constraints enter as infeasible designs.
//!
//! What it guarantees: the returned design is at least as good as every design of its final
//! poll set, i.e. no coordinate step of $2\Delta_{\mathrm{final}}$ box widths (clipped to the box)
//! improves it. For a continuously differentiable objective on a box, the steps $\Delta \to 0$
//! imply a stationary point (Kolda et al., Theorem 3.3 with the bound-conforming coordinate
//! directions); for general linear constraints handled by the barrier the coordinate directions
//! need not conform to them and the search may stop on a constraint short of a stationary point.

use crate::multistart::LocalResult;
use crate::{OptimizeError, Sense, Termination};
use pkm_traits::{InvalidInput, Objective, ObjectiveError, Progress};
use serde::{Deserialize, Serialize};

/// Settings of [`compass_search`]. In a study file every key is optional, with the defaults
/// below.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, default)]
pub struct CompassSettings {
    /// First step $\Delta_0$, a fraction of each variable's range in $(0, 1]$. Default 0.25.
    pub initial_step: f64,
    /// The search has converged once $\Delta$ is below this fraction of each range, in
    /// $(0, $ `initial_step`$]$. Default 1e-3.
    pub min_step: f64,
    /// Most evaluations of the objective, start included, at least 1 and at most
    /// [`CompassSettings::MAX_EVALUATIONS`]. Default 1000.
    pub max_evaluations: usize,
}

impl Default for CompassSettings {
    fn default() -> Self {
        Self {
            initial_step: 0.25,
            min_step: 1e-3,
            max_evaluations: 1000,
        }
    }
}

impl CompassSettings {
    /// Largest `max_evaluations`.
    pub const MAX_EVALUATIONS: usize = 1_000_000;

    /// Checks the settings.
    ///
    /// # Errors
    /// [`OptimizeError::Invalid`] for a step outside its range or an evaluation budget outside
    /// `1..=MAX_EVALUATIONS`.
    pub fn validate(&self) -> Result<(), OptimizeError> {
        if !(self.initial_step > 0.0 && self.initial_step <= 1.0) {
            let requirement = "a fraction of each range in (0, 1]";
            return Err(InvalidInput::new("initial_step", self.initial_step, requirement).into());
        }
        if !(self.min_step > 0.0 && self.min_step <= self.initial_step) {
            let requirement = "a fraction of each range in (0, initial_step]";
            return Err(InvalidInput::new("min_step", self.min_step, requirement).into());
        }
        if !(1..=Self::MAX_EVALUATIONS).contains(&self.max_evaluations) {
            let requirement = "an evaluation budget in 1..=1000000";
            let value = self.max_evaluations as f64;
            return Err(InvalidInput::new("max_evaluations", value, requirement).into());
        }
        Ok(())
    }
}

/// The end of a compass search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompassResult {
    /// The design.
    pub design: Vec<f64>,
    /// The objective there.
    pub value: f64,
    /// Evaluations made, start included.
    pub evaluations: usize,
    /// Poll points that were infeasible.
    pub infeasible: usize,
    /// The last step $\Delta$ (a fraction of each range).
    pub final_step: f64,
    /// Why it stopped.
    pub termination: Termination,
}

impl LocalResult for CompassResult {
    fn design(&self) -> &[f64] {
        &self.design
    }
    fn value(&self) -> f64 {
        self.value
    }
    fn termination(&self) -> Termination {
        self.termination
    }
}

/// Compass search from `start` toward the smallest or largest value (`sense`) of `objective`
/// (module documentation). Deterministic: the same evaluations in the same order for the same
/// inputs.
///
/// # Errors
/// [`OptimizeError::Invalid`] for invalid settings or a start of the wrong length, not finite
/// or outside the bounds; [`OptimizeError::Objective`] when the start itself is infeasible or
/// its value is not finite; [`OptimizeError::Cancelled`] when `progress` asks to stop (checked
/// before every evaluation).
///
/// # Example
/// The largest value of $-(x - 0.3)^2 - (y + 0.1)^2$ on $[-1, 1]^2$:
/// ```
/// use pkm_optimizers::{CompassSettings, Sense, compass_search};
/// use pkm_traits::{Bounds, Objective, ObjectiveError, Silent};
/// struct Bowl([Bounds; 2]);
/// impl Objective for Bowl {
///     fn dimension(&self) -> usize { 2 }
///     fn bounds(&self) -> &[Bounds] { &self.0 }
///     fn value(&self, p: &[f64]) -> Result<f64, ObjectiveError> {
///         Ok(-(p[0] - 0.3).powi(2) - (p[1] + 0.1).powi(2))
///     }
/// }
/// let unit = Bounds::new(-1.0, 1.0)?;
/// let settings = CompassSettings { min_step: 1e-6, ..CompassSettings::default() };
/// let r = compass_search(&Bowl([unit; 2]), Sense::Maximise, &[0.0, 0.0], &settings, &Silent)?;
/// assert!((r.design[0] - 0.3).abs() < 1e-5 && (r.design[1] + 0.1).abs() < 1e-5);
/// assert!(r.termination.converged());
/// # Ok::<(), pkm_optimizers::OptimizeError>(())
/// ```
pub fn compass_search<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    start: &[f64],
    settings: &CompassSettings,
    progress: &dyn Progress,
) -> Result<CompassResult, OptimizeError> {
    settings.validate()?;
    check_start(objective, start)?;
    progress.check()?;
    let value = finite_value(objective, start)?;
    let mut state = CompassResult {
        design: start.to_vec(),
        value,
        evaluations: 1,
        infeasible: 0,
        final_step: settings.initial_step,
        termination: Termination::MaxIterations,
    };
    while state.final_step >= settings.min_step {
        match best_poll_point(objective, sense, &mut state, settings, progress)? {
            Poll::Improved(design, value) => (state.design, state.value) = (design, value),
            Poll::NoImprovement => state.final_step *= 0.5,
            Poll::OutOfBudget => return Ok(state),
        }
    }
    state.termination = Termination::Converged {
        criterion: "step below min_step",
    };
    Ok(state)
}

/// What one poll found.
enum Poll {
    /// A strictly better design and its value.
    Improved(Vec<f64>, f64),
    /// No poll point improves: the step is halved.
    NoImprovement,
    /// The evaluation budget ran out during the poll.
    OutOfBudget,
}

/// Evaluates the poll set of `state` in order and returns its best point when it strictly
/// improves on the incumbent (the first of equal values).
fn best_poll_point<O: Objective + ?Sized>(
    objective: &O,
    sense: Sense,
    state: &mut CompassResult,
    settings: &CompassSettings,
    progress: &dyn Progress,
) -> Result<Poll, OptimizeError> {
    let mut best: Option<(Vec<f64>, f64)> = None;
    for (j, bounds) in objective.bounds().iter().enumerate() {
        for sign in [1.0, -1.0] {
            let moved = bounds.clamp(state.design[j] + sign * state.final_step * bounds.width());
            if moved.total_cmp(&state.design[j]).is_eq() {
                continue;
            }
            if state.evaluations >= settings.max_evaluations {
                return Ok(Poll::OutOfBudget);
            }
            progress.check()?;
            let mut point = state.design.clone();
            point[j] = moved;
            state.evaluations += 1;
            match objective.value(&point) {
                Ok(v) if v.is_finite() => {
                    let incumbent = best.as_ref().map_or(state.value, |b| b.1);
                    if sense.improves(v, incumbent) {
                        best = Some((point, v));
                    }
                }
                Ok(_) | Err(ObjectiveError::Infeasible { .. }) => state.infeasible += 1,
                Err(e) => return Err(e.into()),
            }
        }
    }
    Ok(best.map_or(Poll::NoImprovement, |(x, v)| Poll::Improved(x, v)))
}

/// Checks the start's length, finiteness and bounds.
fn check_start<O: Objective + ?Sized>(objective: &O, start: &[f64]) -> Result<(), OptimizeError> {
    if start.len() != objective.dimension() {
        let requirement = "one value per design variable";
        return Err(InvalidInput::new("start", start.len() as f64, requirement).into());
    }
    let outside = start
        .iter()
        .zip(objective.bounds())
        .find(|(x, b)| !(x.is_finite() && b.contains(**x)));
    match outside {
        Some((&x, _)) => {
            let requirement = "finite and within the objective's bounds";
            Err(InvalidInput::new("start", x, requirement).into())
        }
        None => Ok(()),
    }
}

/// The objective at `x`, refused when it is not finite.
fn finite_value<O: Objective + ?Sized>(objective: &O, x: &[f64]) -> Result<f64, OptimizeError> {
    let value = objective.value(x)?;
    if value.is_finite() {
        Ok(value)
    } else {
        let reason = format!("the objective is not finite at the start ({value})");
        Err(ObjectiveError::infeasible(reason).into())
    }
}
