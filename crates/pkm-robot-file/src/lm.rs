//! Damped Gauss–Newton (Levenberg–Marquardt with Marquardt's diagonal scaling) with step limits,
//! an iteration cap and stagnation detection: the numerical solver behind every closure
//! problem of the crate (leg IK, dependent pose coordinates, forward kinematics).
//!
//! Step $\delta = -(J^\top J + \lambda\,\mathrm{diag}(J^\top J))^{-1} J^\top r$, scaled down so
//! that no unknown moves by more than its limit (Schappler's "maximal relative step", so a leg
//! does not fold over), accepted when it lowers $|r|^2$ ($\lambda \leftarrow \lambda/3$), else
//! retried with $\lambda \leftarrow 4\lambda$.

use nalgebra::{DMatrix, DVector};
use pkm_traits::KinematicsError;

/// Squared column norm, relative to the largest, below which an unknown is held (a null
/// direction of the Jacobian to rounding).
const NULL_COLUMN: f64 = 1e-24;

/// Settings of `levenberg_marquardt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Stop when $\|r\|_\infty$ falls below this (m and rad). Default 1e-12: three orders below
    /// the 1e-9 agreement the tests ask for.
    pub tolerance: f64,
    /// Residual and Jacobian evaluations allowed. Default 200: Gauss–Newton needs under 10 near
    /// a solution, the rest is the damped approach from a far start.
    pub max_evaluations: usize,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            max_evaluations: 200,
        }
    }
}

/// A nonlinear least-squares problem on a state that is updated by increments.
pub(crate) trait LeastSquares {
    /// The unknowns (joint values, pose coordinates).
    type State: Clone;
    /// The residual and its Jacobian with respect to the increments; `None` when not finite.
    fn evaluate(&self, state: &Self::State) -> Option<(DVector<f64>, DMatrix<f64>)>;
    /// The largest step allowed for each unknown.
    fn step_limits(&self) -> DVector<f64>;
    /// The state moved by `delta`.
    fn apply(&self, state: &Self::State, delta: &DVector<f64>) -> Self::State;
}

/// Solves `problem` from `start`; returns the state and its residual $\|r\|_\infty$.
///
/// # Errors
/// [`KinematicsError::NotConverged`] with the residual reached, when the evaluation budget is
/// spent or the damping grows beyond $10^{12}$ without progress (stagnation);
/// [`KinematicsError::NonFinite`] when the start itself does not evaluate.
pub(crate) fn levenberg_marquardt<P: LeastSquares>(
    problem: &P,
    start: P::State,
    settings: &SolverSettings,
) -> Result<(P::State, f64), KinematicsError> {
    let Some((mut r, mut j)) = problem.evaluate(&start) else {
        return Err(KinematicsError::NonFinite {
            what: "closure residual at the start",
            value: f64::NAN,
        });
    };
    let limits = problem.step_limits();
    let mut state = start;
    let mut lambda = 1e-6;
    let mut evaluations = 1;
    while evaluations < settings.max_evaluations {
        if r.amax() < settings.tolerance {
            return Ok((state, r.amax()));
        }
        let jt = j.transpose();
        let normal = &jt * &j;
        let gradient = &jt * &r;
        let cost = r.norm_squared();
        loop {
            evaluations += 1;
            let Some(delta) = damped_step(&normal, &gradient, lambda, &limits) else {
                lambda *= 4.0;
                if lambda > 1e12 || evaluations >= settings.max_evaluations {
                    return not_converged(evaluations, &r);
                }
                continue;
            };
            let trial = problem.apply(&state, &delta);
            match problem.evaluate(&trial) {
                Some((r_new, j_new)) if r_new.norm_squared() < cost => {
                    (state, r, j) = (trial, r_new, j_new);
                    lambda = (lambda / 3.0).max(1e-15);
                    break;
                }
                _ => {
                    lambda *= 4.0;
                    if lambda > 1e12 || evaluations >= settings.max_evaluations {
                        return not_converged(evaluations, &r);
                    }
                }
            }
        }
    }
    if r.amax() < settings.tolerance {
        Ok((state, r.amax()))
    } else {
        not_converged(evaluations, &r)
    }
}

/// Up to `steps` Gauss–Newton steps from a converged `state` (residual `residual`), each kept
/// only while it lowers $\|r\|_\infty$: a solution converged to the tolerance moved down to
/// rounding. What is solved at it with the same tolerance then closes (a leg's passive joints
/// at a pose whose dependent coordinates were solved with that leg: left at 1.08e-12 by the
/// pose, the leg could not reach 1e-12).
pub(crate) fn polish<P: LeastSquares>(
    problem: &P,
    mut state: P::State,
    mut residual: f64,
    steps: usize,
) -> (P::State, f64) {
    let limits = problem.step_limits();
    for _ in 0..steps {
        let Some((r, j)) = problem.evaluate(&state) else {
            break;
        };
        let jt = j.transpose();
        let Some(delta) = damped_step(&(&jt * &j), &(&jt * &r), 1e-15, &limits) else {
            break;
        };
        let trial = problem.apply(&state, &delta);
        match problem.evaluate(&trial) {
            Some((r_new, _)) if r_new.amax() < residual => {
                residual = r_new.amax();
                state = trial;
            }
            _ => break,
        }
    }
    (state, residual)
}

/// The damped step, scaled to the step limits; `None` when the system cannot be factored.
///
/// An unknown whose Jacobian column is zero to rounding ($\|J_k\|^2 \le 10^{-24}
/// \max_l \|J_l\|^2$: it does not move the residual, as a joint through the point that a
/// position-only stage places) is held: left in the system, its rounding-level gradient
/// divided by a rounding-level diagonal would give a huge step, and scaling the step to the
/// limits would then shrink every useful component to nothing.
fn damped_step(
    normal: &DMatrix<f64>,
    gradient: &DVector<f64>,
    lambda: f64,
    limits: &DVector<f64>,
) -> Option<DVector<f64>> {
    let mut a = normal.clone();
    let mut g = gradient.clone();
    let scale = normal.diagonal().amax().max(1e-300);
    for k in 0..a.nrows() {
        if normal[(k, k)] <= NULL_COLUMN * scale {
            a.row_mut(k).fill(0.0);
            a.column_mut(k).fill(0.0);
            a[(k, k)] = 1.0;
            g[k] = 0.0;
        } else {
            a[(k, k)] += lambda * normal[(k, k)].max(1e-9 * scale);
        }
    }
    let delta = -a.cholesky()?.solve(&g);
    let ratio = delta
        .iter()
        .zip(limits.iter())
        .map(|(d, l)| d.abs() / l)
        .fold(0.0, f64::max);
    if !ratio.is_finite() {
        return None;
    }
    Some(if ratio > 1.0 { delta / ratio } else { delta })
}

fn not_converged<S>(iterations: usize, r: &DVector<f64>) -> Result<S, KinematicsError> {
    Err(KinematicsError::NotConverged {
        iterations,
        residual: r.amax(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// $x^2 = 2$ by increments.
    struct Root(f64);

    impl LeastSquares for Root {
        type State = f64;
        fn evaluate(&self, x: &f64) -> Option<(DVector<f64>, DMatrix<f64>)> {
            let r = x * x - self.0;
            r.is_finite().then(|| {
                (
                    DVector::from_element(1, r),
                    DMatrix::from_element(1, 1, 2.0 * x),
                )
            })
        }
        fn step_limits(&self) -> DVector<f64> {
            DVector::from_element(1, 0.5)
        }
        fn apply(&self, x: &f64, d: &DVector<f64>) -> f64 {
            x + d[0]
        }
    }

    /// $x^2 = 2$ with a spectator unknown $y$ that moves the residual by rounding only.
    struct RootWithSpectator;

    impl LeastSquares for RootWithSpectator {
        type State = (f64, f64);
        fn evaluate(&self, &(x, y): &(f64, f64)) -> Option<(DVector<f64>, DMatrix<f64>)> {
            let r = x * x - 2.0 + 1e-17 * y;
            Some((
                DVector::from_element(1, r),
                DMatrix::from_row_slice(1, 2, &[2.0 * x, 1e-17]),
            ))
        }
        fn step_limits(&self) -> DVector<f64> {
            DVector::from_element(2, 0.5)
        }
        fn apply(&self, &(x, y): &(f64, f64), d: &DVector<f64>) -> (f64, f64) {
            (x + d[0], y + d[1])
        }
    }

    /// A null column is held: without that, its huge step scaled to the limit left the useful
    /// component at 1e-8 of what it should be, and the solve stalled.
    #[test]
    fn a_null_direction_does_not_stall_the_others() {
        let ((x, y), _) =
            levenberg_marquardt(&RootWithSpectator, (3.0, 0.0), &SolverSettings::default())
                .unwrap();
        assert!((x - 2f64.sqrt()).abs() < 1e-12 && y == 0.0, "{x} {y}");
    }

    #[test]
    fn converges_and_reports_stagnation() {
        let s = SolverSettings::default();
        let (x, _) = levenberg_marquardt(&Root(2.0), 3.0, &s).unwrap();
        assert!((x - 2f64.sqrt()).abs() < 1e-12);
        // x² = −1 has no root: the damping stalls at the minimum x = 0 of |r|².
        let err = levenberg_marquardt(&Root(-1.0), 3.0, &s).unwrap_err();
        assert!(
            matches!(err, KinematicsError::NotConverged { residual, .. } if residual >= 1.0 - 1e-6)
        );
        assert!(levenberg_marquardt(&Root(2.0), f64::NAN, &s).is_err());
    }
}
