//! Conformance checks that every mechanism's tests call (feature `testkit`): closure, Jacobians
//! against central differences, the velocity Jacobian against its default, IK → FK round trip.
//!
//! Each check runs over a sample of poses, skips the poses the mechanism reports as unreachable,
//! and refuses to pass when fewer than [`MIN_SAMPLES`] poses were actually checked (non-vacuity
//! guard). A check returns what it measured, so that a test can print it.
//!
//! ```
//! # use pkm_traits::{ClosedChain, InverseKinematics, KinematicsError, Joints, Task};
//! # use nalgebra::{SMatrix, Vector1};
//! # struct Slider;
//! # impl ClosedChain<1, 1> for Slider {
//! #     fn closure(&self, x: &Task<1>, q: &Joints<1>) -> Joints<1> { q - x }
//! #     fn jacobian_x(&self, _: &Task<1>, _: &Joints<1>) -> SMatrix<f64, 1, 1> { -SMatrix::identity() }
//! #     fn jacobian_q(&self, _: &Task<1>, _: &Joints<1>) -> SMatrix<f64, 1, 1> { SMatrix::identity() }
//! # }
//! # impl InverseKinematics<1, 1> for Slider {
//! #     type WorkingMode = ();
//! #     fn inverse_kinematics(&self, x: &Task<1>, _: ()) -> Result<Joints<1>, KinematicsError> { Ok(*x) }
//! # }
//! use pkm_traits::testkit;
//! let poses: Vec<_> = (0..5).map(|i| Vector1::new(0.1 * i as f64)).collect();
//! let report = testkit::check_closure(&Slider, (), &poses, 1e-12).unwrap();
//! assert_eq!(report.checked, 5);
//! ```

use crate::kinematics::{ForwardKinematics, InverseKinematics, NewtonSettings, Task};
use nalgebra::SMatrix;
use std::fmt;

/// Fewest poses a check must actually test before it may pass.
pub const MIN_SAMPLES: usize = 3;

/// What a passing check measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConformanceReport {
    /// Poses actually checked.
    pub checked: usize,
    /// Poses skipped because inverse kinematics reported them unreachable or singular.
    pub skipped: usize,
    /// Largest error found (its meaning depends on the check).
    pub max_error: f64,
}

/// Why a check failed.
#[derive(Debug, Clone, PartialEq)]
pub enum ConformanceFailure {
    /// Fewer than [`MIN_SAMPLES`] poses could be checked: the test would be vacuous.
    Vacuous {
        /// Poses checked.
        checked: usize,
        /// Poses skipped.
        skipped: usize,
    },
    /// An error exceeded its tolerance.
    Exceeded {
        /// Name of the check.
        check: &'static str,
        /// Index of the pose in the sample.
        pose: usize,
        /// The error found.
        error: f64,
        /// The tolerance.
        tolerance: f64,
    },
}

impl fmt::Display for ConformanceFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Vacuous { checked, skipped } => write!(
                f,
                "vacuous test: only {checked} poses checked ({skipped} skipped), need {MIN_SAMPLES}"
            ),
            Self::Exceeded {
                check,
                pose,
                error,
                tolerance,
            } => {
                write!(
                    f,
                    "{check}: error {error:.3e} > {tolerance:.3e} at pose {pose}"
                )
            }
        }
    }
}

impl std::error::Error for ConformanceFailure {}

/// Runs `measure` on every pose, keeps the worst error, and applies the non-vacuity guard.
fn run_check<const NX: usize>(
    check: &'static str,
    poses: &[Task<NX>],
    tolerance: f64,
    mut measure: impl FnMut(&Task<NX>) -> Option<f64>,
) -> Result<ConformanceReport, ConformanceFailure> {
    let mut report = ConformanceReport {
        checked: 0,
        skipped: 0,
        max_error: 0.0,
    };
    for (pose, x) in poses.iter().enumerate() {
        let Some(error) = measure(x) else {
            report.skipped += 1;
            continue;
        };
        if !(error <= tolerance) {
            return Err(ConformanceFailure::Exceeded {
                check,
                pose,
                error,
                tolerance,
            });
        }
        report.checked += 1;
        report.max_error = report.max_error.max(error);
    }
    if report.checked < MIN_SAMPLES {
        return Err(ConformanceFailure::Vacuous {
            checked: report.checked,
            skipped: report.skipped,
        });
    }
    Ok(report)
}

/// $\|\Phi(x, \mathrm{IK}(x))\|_\infty \le$ `tolerance` at every reachable pose.
///
/// # Errors
/// [`ConformanceFailure`] when the residual exceeds the tolerance or the check is vacuous.
pub fn check_closure<M, const NX: usize, const NQ: usize>(
    mechanism: &M,
    mode: M::WorkingMode,
    poses: &[Task<NX>],
    tolerance: f64,
) -> Result<ConformanceReport, ConformanceFailure>
where
    M: InverseKinematics<NX, NQ>,
{
    run_check("closure", poses, tolerance, |x| {
        let q = mechanism.inverse_kinematics(x, mode).ok()?;
        Some(mechanism.closure(x, &q).amax())
    })
}

/// $J_x$ and $J_q$ agree with central differences of $\Phi$ (step `h`) to a relative error
/// `rel_tol`, measured as $\max|J - J_{FD}| / \max(1, \max|J|)$.
///
/// Central differences have truncation error $O(h^2)$, so `rel_tol` should be a few times
/// $h^2$ times the scale of the third derivatives (1e-6 with h = 1e-6 for metre-sized machines).
///
/// # Errors
/// [`ConformanceFailure`] when either Jacobian deviates or the check is vacuous.
pub fn check_jacobians_against_central_differences<M, const NX: usize, const NQ: usize>(
    mechanism: &M,
    mode: M::WorkingMode,
    poses: &[Task<NX>],
    h: f64,
    rel_tol: f64,
) -> Result<ConformanceReport, ConformanceFailure>
where
    M: InverseKinematics<NX, NQ>,
{
    run_check("jacobians vs central differences", poses, rel_tol, |x| {
        let q = mechanism.inverse_kinematics(x, mode).ok()?;
        let mut j_x_fd = SMatrix::<f64, NQ, NX>::zeros();
        for k in 0..NX {
            let (mut xp, mut xm) = (*x, *x);
            xp[k] += h;
            xm[k] -= h;
            let column = (mechanism.closure(&xp, &q) - mechanism.closure(&xm, &q)) / (2.0 * h);
            j_x_fd.set_column(k, &column);
        }
        let mut j_q_fd = SMatrix::<f64, NQ, NQ>::zeros();
        for k in 0..NQ {
            let (mut qp, mut qm) = (q, q);
            qp[k] += h;
            qm[k] -= h;
            let column = (mechanism.closure(x, &qp) - mechanism.closure(x, &qm)) / (2.0 * h);
            j_q_fd.set_column(k, &column);
        }
        let j_x = mechanism.jacobian_x(x, &q);
        let j_q = mechanism.jacobian_q(x, &q);
        let scale = 1.0_f64.max(j_x.amax()).max(j_q.amax());
        Some((j_x - j_x_fd).amax().max((j_q - j_q_fd).amax()) / scale)
    })
}

/// [`InverseKinematics::velocity_jacobian_at`] (a mechanism's closed form, where it overrides
/// it) equals its default, $-J_q^{-1}J_x$ at $q = \mathrm{IK}(x)$, to a relative error
/// `rel_tol` measured as $\max|J - J_{\text{default}}| / \max(1, \max|J_{\text{default}}|)$, and
/// fails exactly where the default fails. Poses where both fail are skipped.
///
/// # Errors
/// [`ConformanceFailure`] when the two disagree or the check is vacuous.
pub fn check_velocity_jacobian_at<M, const NX: usize, const NQ: usize>(
    mechanism: &M,
    mode: M::WorkingMode,
    poses: &[Task<NX>],
    rel_tol: f64,
) -> Result<ConformanceReport, ConformanceFailure>
where
    M: InverseKinematics<NX, NQ>,
{
    run_check(
        "velocity_jacobian_at vs -J_q⁻¹J_x",
        poses,
        rel_tol,
        |x| {
            let reference = mechanism
                .inverse_kinematics(x, mode)
                .and_then(|q| mechanism.jacobian(x, &q));
            match (mechanism.velocity_jacobian_at(x, mode), reference) {
                (Ok(j), Ok(r)) => Some((j - r).amax() / 1.0_f64.max(r.amax())),
                (Err(_), Err(_)) => None,
                _ => Some(f64::INFINITY),
            }
        },
    )
}

/// Forward kinematics started from a perturbed pose recovers $x$ from $q = \mathrm{IK}(x)$:
/// $\|\mathrm{FK}(\mathrm{IK}(x)) - x\|_\infty \le$ `tolerance`.
///
/// The guess is $x$ shifted by `perturbation` in every coordinate, so the check exercises the
/// solver and not only its first residual evaluation.
///
/// # Errors
/// [`ConformanceFailure`] when FK fails or misses the pose, or the check is vacuous.
pub fn check_ik_fk_round_trip<M, const N: usize>(
    mechanism: &M,
    mode: M::WorkingMode,
    poses: &[Task<N>],
    perturbation: f64,
    tolerance: f64,
) -> Result<ConformanceReport, ConformanceFailure>
where
    M: InverseKinematics<N, N> + ForwardKinematics<N>,
{
    let settings = NewtonSettings::default();
    run_check("IK → FK round trip", poses, tolerance, |x| {
        let q = mechanism.inverse_kinematics(x, mode).ok()?;
        let guess = x.add_scalar(perturbation);
        match mechanism.forward_kinematics(&q, &guess, &settings) {
            Ok(x_fk) => Some((x_fk - x).amax()),
            Err(_) => Some(f64::INFINITY),
        }
    })
}

/// Compile-time check that a model can be shared across threads and printed.
pub fn check_traits<M: Send + Sync + Clone + fmt::Debug>() {}
