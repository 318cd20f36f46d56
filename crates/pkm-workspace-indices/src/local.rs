//! Local indices of any mechanism at a pose, from its velocity Jacobian $J = -J_q^{-1}J_x$
//! ($\dot q = J\dot x$, [`InverseKinematics::velocity_jacobian_at`], so a mechanism's closed
//! form is used where it has one). With $\sigma_1 \ge \dots \ge \sigma_N$ the singular values
//! of $J$:
//!
//! | index | formula | source |
//! |---|---|---|
//! | inverse condition number (local conditioning index) | $1/\kappa = \sigma_N / \sigma_1 \in [0, 1]$ | Gosselin & Angeles 1991; Stamper, Tsai & Walsh 1997, eq. 4; Miller 2004, eq. 1 |
//! | smallest and largest singular value | $\sigma_{\min} = \sigma_N$, $\sigma_{\max} = \sigma_1$: the least and greatest joint speed $\lvert\dot q\rvert$ per unit task speed $\lvert\dot x\rvert$ | Klein & Blaho 1987 |
//! | manipulability | $w = \sqrt{\det(J J^\top)} = \prod_i \sigma_i = \lvert\det J\rvert$ | Yoshikawa 1985 |
//!
//! $J$ here maps task to joint rates, so Yoshikawa's measure of the forward map
//! $\dot x = J^{-1}\dot q$ is $1/w$; $w \to 0$ at a direct-kinematic singularity ($J_x$
//! singular) and $J$ is undefined at an inverse-kinematic one ($J_q$ singular), where $1/\kappa$
//! tends to 0.

use crate::{Dim, FixedSvd};
use pkm_traits::{InverseKinematics, KinematicsError, Task};

/// The local indices of $J$ at one pose (see the module documentation for the formulas).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalIndices {
    /// $1/\kappa = \sigma_{\min}/\sigma_{\max} \in [0, 1]$, from the SVD (it agrees with the
    /// closed form of [`inverse_condition_at`] to about $10^{-11}$ for $3 \times 3$, $10^{-8}$
    /// where two singular values coincide).
    pub inverse_condition: f64,
    /// Smallest singular value $\sigma_{\min}$ of $J$.
    pub sigma_min: f64,
    /// Largest singular value $\sigma_{\max}$ of $J$.
    pub sigma_max: f64,
    /// Manipulability $w = \sqrt{\det(JJ^\top)} = \prod_i \sigma_i$ (0 where the product
    /// underflows).
    pub manipulability: f64,
}

/// $1/\kappa(J)$ at `x` assembled in `mode`: the local index of every condition integral,
/// through the mechanism's own (possibly closed-form) velocity Jacobian and, for $3 \times 3$,
/// the closed-form [`crate::inverse_condition_number_3x3`].
///
/// Where the mechanism assembles but $J$ is undefined (an inverse-kinematic singularity,
/// [`KinematicsError::Singular`]) the value is its limit 0, so integrals of $1/\kappa$ over a
/// workspace stay finite at its boundary.
///
/// # Errors
/// As [`InverseKinematics::inverse_kinematics`] where `x` does not assemble in `mode`
/// ([`KinematicsError::Unreachable`], [`KinematicsError::NonFinite`]).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_mechanisms::{Elbow, Tsai3Dof, presets};
/// use pkm_workspace_indices::inverse_condition_at;
/// let tsai = Tsai3Dof::new(presets::stamper_max_gci())?;
/// // Spec §1: 1/κ = 0.803344 at the centre, z = 0.5.
/// let r = inverse_condition_at(&tsai, &Vector3::new(0.0, 0.0, 0.5), [Elbow::Out; 3])?;
/// assert!((r - 0.803344).abs() < 1e-6);
/// assert!(inverse_condition_at(&tsai, &Vector3::new(0.0, 0.0, 3.0), [Elbow::Out; 3]).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn inverse_condition_at<M, const N: usize>(
    mechanism: &M,
    x: &Task<N>,
    mode: M::WorkingMode,
) -> Result<f64, KinematicsError>
where
    M: InverseKinematics<N, N> + ?Sized,
    Dim<N>: FixedSvd<N>,
{
    match mechanism.velocity_jacobian_at(x, mode) {
        Ok(j) => Ok(<Dim<N> as FixedSvd<N>>::inverse_condition(&j)),
        Err(KinematicsError::Singular { .. }) => Ok(0.0),
        Err(e) => Err(e),
    }
}

/// $1/\kappa$, $\sigma_{\min}$, $\sigma_{\max}$ and the manipulability of $J$ at `x` assembled
/// in `mode`, from one SVD (of $J$ scaled by an exact power of two when its entries lie outside
/// $[2^{-100}, 2^{100}]$, so that it neither overflows nor underflows).
///
/// # Errors
/// As [`InverseKinematics::velocity_jacobian_at`]: [`KinematicsError::Unreachable`] or
/// [`KinematicsError::NonFinite`] where `x` does not assemble, [`KinematicsError::Singular`]
/// where $J$ is undefined, or so large that $\sigma_{\max}$ or $w$ overflows (a numerically
/// singular $J_q$).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_mechanisms::{ThreeUpu, presets};
/// use pkm_traits::InverseKinematics;
/// use pkm_workspace_indices::local_indices;
/// let upu = ThreeUpu::new(presets::park_3upu())?;
/// let p = Vector3::new(1.0, -2.0, 50.0);
/// let local = local_indices(&upu, &p, ())?;
/// // For a square J, √det(JJᵀ) = |det J|.
/// let det = upu.velocity_jacobian_at(&p, ())?.determinant();
/// assert!((local.manipulability - det.abs()).abs() < 1e-12);
/// assert!(local.sigma_min <= local.sigma_max && local.inverse_condition <= 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn local_indices<M, const N: usize>(
    mechanism: &M,
    x: &Task<N>,
    mode: M::WorkingMode,
) -> Result<LocalIndices, KinematicsError>
where
    M: InverseKinematics<N, N> + ?Sized,
    Dim<N>: FixedSvd<N>,
{
    let j = mechanism.velocity_jacobian_at(x, mode)?;
    let (scaled, unscale) = match crate::condition::unit_scale(j.amax(), 100) {
        Some((first, second)) => (j * first * second, 1.0 / first / second),
        None => (j, 1.0),
    };
    let mut sigma = <Dim<N> as FixedSvd<N>>::singular_values(&scaled).map(|s| s * unscale);
    sigma.as_mut_slice().sort_by(f64::total_cmp);
    let (sigma_min, sigma_max) = (sigma[0], sigma[N - 1]);
    let manipulability: f64 = sigma.iter().product();
    if !(sigma_max.is_finite() && manipulability.is_finite() && sigma_min >= 0.0) {
        return Err(KinematicsError::Singular {
            matrix: "J_q",
            sigma_min: 0.0,
        });
    }
    Ok(LocalIndices {
        inverse_condition: if sigma_max > 0.0 {
            (sigma_min / sigma_max).clamp(0.0, 1.0)
        } else {
            0.0
        },
        sigma_min,
        sigma_max,
        manipulability,
    })
}
