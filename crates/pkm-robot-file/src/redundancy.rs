//! Redundant actuation: more actuators $m$ than task coordinates $n$. The Jacobian
//! $J = D^{-1}J_aT$ is $m \times n$ ([`RobotModel::screw_jacobians`]); forward kinematics from
//! all $m$ actuators is overdetermined, and the actuator efforts that hold a platform wrench
//! form an $(m - n)$-dimensional family.
//!
//! - **Least-squares forward kinematics**: Gauss–Newton on the actuator residual
//!   $r(x) = q - \mathrm{IK}(x)$ (each leg on the branch nearest its $q_i$),
//!   $\Delta x = J^{+} r$, halved until $\lVert r\rVert$ decreases; it ends where
//!   $J^\top r = 0$: the pose itself for actuator values a pose produced, else the
//!   least-squares pose with its residual reported (never a silent choice of $n$ actuators).
//! - **Force distribution**: the efforts $\tau$ with $J^\top \tau = F$ (virtual work:
//!   $\tau^\top \dot q = F^\top \dot x$), $F_k$ the power of the platform wrench on task
//!   twist $k$. Without limits, the minimum norm $\tau = (J^\top)^{+}F$; with limits, the
//!   efforts of least norm within them, the projection of 0 onto the intersection of the
//!   affine set and the box by Dykstra's algorithm (Boyle & Dykstra 1986), which converges to
//!   that projection whenever the intersection is not empty.

use crate::closure::Configuration;
use crate::model::RobotModel;
use crate::svd::bounded_svd;
use nalgebra::{DMatrix, DVector};
use pkm_traits::{InvalidInput, KinematicsError};

/// Most Gauss–Newton iterations of the least-squares forward kinematics.
const MAX_ITERATIONS: usize = 100;
/// Most step halvings in one iteration.
const MAX_HALVINGS: usize = 40;
/// Most sweeps of Dykstra's algorithm.
const MAX_SWEEPS: usize = 100_000;

/// The least-squares pose of overdetermined actuator coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct LeastSquaresPose {
    /// The configuration at the least-squares pose (each leg on its branch nearest `q`).
    pub configuration: Configuration,
    /// The task coordinates there.
    pub task: Vec<f64>,
    /// $q - \mathrm{IK}(x)$ there, per actuator (m or rad): zero to rounding for consistent
    /// actuator values.
    pub residual: DVector<f64>,
}

/// Actuator efforts for a platform wrench.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceDistribution {
    /// The efforts, per actuator (N for a prismatic actuator, N·m for a revolute one).
    pub efforts: DVector<f64>,
    /// Whether they hold the wrench within the given limits (imbalance at most 1e-9 of the
    /// largest generalised force, and every effort within its limits); always, without limits.
    pub held: bool,
    /// $\lVert J^\top \tau - F\rVert_\infty$: how far they are from holding the wrench (zero
    /// to rounding, unless no efforts within the limits hold it: then the efforts within the
    /// limits nearest to holding it, as Dykstra's iterates end).
    pub imbalance: f64,
}

impl RobotModel {
    /// The least-squares pose of actuator coordinates `q` from the task coordinates `guess`
    /// (module documentation): for a redundantly actuated robot, the pose that consistent
    /// values came from, or for inconsistent ones the pose of least $\lVert q -
    /// \mathrm{IK}(x)\rVert$ with that residual; for a square robot, its forward kinematics.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidInput`] / [`KinematicsError::NonFinite`] for a bad `q` or
    /// `guess`; as [`RobotModel::configuration_near`] and [`RobotModel::screw_jacobians`] at an
    /// iterate (out of reach, singular); [`KinematicsError::NotConverged`] when the iteration
    /// budget ends before $J^\top r$ vanishes.
    pub fn forward_kinematics_least_squares(
        &self,
        q: &[f64],
        guess: &[f64],
    ) -> Result<LeastSquaresPose, KinematicsError> {
        let mut x = guess.to_vec();
        let (mut config, mut r) = self.actuator_residual(&x, q)?;
        for _ in 0..MAX_ITERATIONS {
            let j = self.screw_jacobians(&config)?.j;
            let step = least_squares_solve(&j, &r).ok_or(KinematicsError::Singular {
                matrix: "J",
                sigma_min: 0.0,
            })?;
            let gradient = j.transpose() * &r;
            if !(gradient.amax() > 1e-13 * (1.0 + j.amax() * r.amax())) {
                return Ok(self.least_squares_pose(config, r));
            }
            let mut scale = 1.0;
            let mut accepted = false;
            for _ in 0..MAX_HALVINGS {
                let trial: Vec<f64> = x
                    .iter()
                    .zip(step.iter())
                    .map(|(a, d)| a + scale * d)
                    .collect();
                if let Ok((c, r_new)) = self.actuator_residual(&trial, q)
                    && r_new.norm() < r.norm()
                {
                    (x, config, r) = (trial, c, r_new);
                    accepted = true;
                    break;
                }
                scale *= 0.5;
            }
            if !accepted {
                // No decrease along the Gauss–Newton direction: a stationary point to rounding.
                return Ok(self.least_squares_pose(config, r));
            }
        }
        Err(KinematicsError::NotConverged {
            iterations: MAX_ITERATIONS,
            residual: r.amax(),
        })
    }

    /// The configuration at `x` on the branches nearest `q` and $q - \mathrm{IK}(x)$.
    fn actuator_residual(
        &self,
        x: &[f64],
        q: &[f64],
    ) -> Result<(Configuration, DVector<f64>), KinematicsError> {
        let config = self.configuration_near(x, q)?;
        let r = DVector::from_column_slice(q) - self.actuators_of(&config);
        Ok((config, r))
    }

    fn least_squares_pose(
        &self,
        configuration: Configuration,
        residual: DVector<f64>,
    ) -> LeastSquaresPose {
        let task = self.task.iter().map(|&k| configuration.pose[k]).collect();
        LeastSquaresPose {
            configuration,
            task,
            residual,
        }
    }

    /// The actuator efforts that hold the platform wrench `wrench` (`[f; m_O]`: force in N
    /// and moment about the base origin in N·m) at `config` (module documentation): of least
    /// norm, and within `limits` (per actuator `[min, max]`) when they are given and can hold
    /// it.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidInput`] for a non-finite wrench, limits of the wrong count,
    /// or a limit with `min > max`; as [`RobotModel::screw_jacobians`] (a singular
    /// configuration); [`KinematicsError::Singular`] when $J$ has no pseudo-inverse.
    pub fn force_distribution(
        &self,
        config: &Configuration,
        wrench: &[f64; 6],
        limits: Option<&[[f64; 2]]>,
    ) -> Result<ForceDistribution, KinematicsError> {
        if let Some(&value) = wrench.iter().find(|v| !v.is_finite()) {
            return Err(KinematicsError::NonFinite {
                what: "wrench",
                value,
            });
        }
        let jacobians = self.screw_jacobians(config)?;
        let j = &jacobians.j;
        // F_k: the power of [f; m_O] on task twist k = [ω; v_O].
        let force = DVector::from_fn(j.ncols(), |k, _| {
            let t = jacobians.t.column(k);
            (0..3)
                .map(|a| wrench[a] * t[3 + a] + wrench[3 + a] * t[a])
                .sum::<f64>()
        });
        let jt = j.transpose();
        let min_norm = least_squares_solve(&jt, &force).ok_or(KinematicsError::Singular {
            matrix: "J",
            sigma_min: 0.0,
        })?;
        let Some(limits) = limits else {
            let imbalance = (&jt * &min_norm - &force).amax();
            return Ok(ForceDistribution {
                efforts: min_norm,
                held: true,
                imbalance,
            });
        };
        let (lo, hi) = checked_limits(limits, j.nrows())?;
        let efforts = dykstra(&jt, &force, &min_norm, &lo, &hi);
        let imbalance = (&jt * &efforts - &force).amax();
        Ok(ForceDistribution {
            efforts,
            held: imbalance <= 1e-9 * force.amax().max(f64::MIN_POSITIVE),
            imbalance,
        })
    }
}

/// The lower and upper effort limits, checked.
fn checked_limits(
    limits: &[[f64; 2]],
    m: usize,
) -> Result<(DVector<f64>, DVector<f64>), KinematicsError> {
    if limits.len() != m {
        return Err(InvalidInput::new(
            "limits.len()",
            limits.len() as f64,
            "one [min, max] per actuator",
        )
        .into());
    }
    if let Some(bad) = limits.iter().find(|[l, h]| !(l <= h) || l.is_nan()) {
        return Err(InvalidInput::new("limits", bad[0], "each min <= max, not NaN").into());
    }
    Ok((
        DVector::from_iterator(m, limits.iter().map(|l| l[0])),
        DVector::from_iterator(m, limits.iter().map(|l| l[1])),
    ))
}

/// The least-squares (minimum-norm) solution of $A z = b$ by the SVD, singular values below
/// $10^{-12}\sigma_{\max}$ dropped; `None` when the SVD fails or $A$ vanishes.
fn least_squares_solve(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    let svd = bounded_svd(a.clone(), true, true)?;
    let largest = svd.singular_values.amax();
    if !(largest > 0.0) {
        return None;
    }
    svd.solve(b, 1e-12 * largest).ok()
}

/// Dykstra's projection of 0 onto $\{\tau : A\tau = F\} \cap [lo, hi]$, started at the affine
/// set's own projection `start`; the iterate after the last sweep when they do not meet.
fn dykstra(
    a: &DMatrix<f64>,
    force: &DVector<f64>,
    start: &DVector<f64>,
    lo: &DVector<f64>,
    hi: &DVector<f64>,
) -> DVector<f64> {
    // The projection onto {Aτ = F} is z + A⁺(F − Az): A⁺ once for every sweep.
    let pseudo_inverse = bounded_svd(a.clone(), true, true)
        .and_then(|svd| {
            let largest = svd.singular_values.amax();
            svd.pseudo_inverse(1e-12 * largest).ok()
        })
        .unwrap_or_else(|| DMatrix::zeros(a.ncols(), a.nrows()));
    let project_affine =
        |z: &DVector<f64>| -> DVector<f64> { z + &pseudo_inverse * (force - a * z) };
    let scale = start.amax().max(lo.amax()).max(hi.amax()).max(1.0);
    let mut x = start.clone();
    let (mut p, mut q) = (DVector::zeros(x.len()), DVector::zeros(x.len()));
    for _ in 0..MAX_SWEEPS {
        let y = (&x + &p).zip_zip_map(lo, hi, |v, l, h| v.clamp(l, h));
        p = &x + &p - &y;
        let next = project_affine(&(&y + &q));
        q = &y + &q - &next;
        let moved = (&next - &x).amax();
        x = next;
        if moved < 1e-15 * scale && (&x - &y).amax() < 1e-12 * scale {
            return x.zip_zip_map(lo, hi, |v, l, h| v.clamp(l, h));
        }
    }
    x.zip_zip_map(lo, hi, |v, l, h| v.clamp(l, h))
}
