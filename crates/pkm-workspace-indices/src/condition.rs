//! Condition number of a Jacobian, $\kappa = \|J\|_2 \|J^{-1}\|_2 = \sigma_{\max} / \sigma_{\min}$.

use nalgebra::{SMatrix, SVector};

/// Marker type that carries a matrix size for [`FixedSvd`].
#[derive(Debug, Clone, Copy)]
pub struct Dim<const N: usize>;

/// Singular values of a fixed-size square matrix, and the fastest accurate $1/\kappa$ of that
/// size.
///
/// nalgebra's `singular_values` needs type-level bounds that do not compile in code generic over
/// `const N`; this helper trait, implemented for the sizes pkm uses, keeps one readable bound in
/// generic code (see `docs/ARCHITECTURE.md`).
pub trait FixedSvd<const N: usize> {
    /// The singular values of `m`, in no particular order.
    fn singular_values(m: &SMatrix<f64, N, N>) -> SVector<f64, N>;

    /// $1/\kappa(m) \in [0, 1]$ by the fastest routine of this size: the closed form
    /// [`crate::inverse_condition_number_3x3`] for $3 \times 3$ (the kernel of the workspace
    /// studies), the SVD of [`inverse_condition_number`] otherwise.
    fn inverse_condition(m: &SMatrix<f64, N, N>) -> f64;
}

macro_rules! impl_fixed_svd {
    ($($n:literal),*) => {$(
        impl FixedSvd<$n> for Dim<$n> {
            fn singular_values(m: &SMatrix<f64, $n, $n>) -> SVector<f64, $n> {
                m.singular_values()
            }

            fn inverse_condition(m: &SMatrix<f64, $n, $n>) -> f64 {
                inverse_condition_number(m)
            }
        }
    )*};
}
impl_fixed_svd!(1, 2, 4, 5, 6);

impl FixedSvd<3> for Dim<3> {
    fn singular_values(m: &SMatrix<f64, 3, 3>) -> SVector<f64, 3> {
        m.singular_values()
    }

    fn inverse_condition(m: &SMatrix<f64, 3, 3>) -> f64 {
        crate::inverse_condition_number_3x3(m)
    }
}

/// $1/\kappa = \sigma_{\min} / \sigma_{\max} \in [0, 1]$ of a square Jacobian.
///
/// $1/\kappa$ is scale-invariant, so a matrix whose largest entry lies outside $[2^{-100},
/// 2^{100}]$ is first scaled by a power of two (exactly) to avoid overflow and underflow.
///
/// Returns 0 for a singular matrix, the zero matrix, or a matrix with non-finite entries, so
/// that integrals of $1/\kappa$ over a workspace stay finite at its boundary (Stamper, Tsai &
/// Walsh 1997, eq. 4; Miller 2004, eq. 1). Rank cutoff: the singular values carry an absolute
/// error of order $\varepsilon\,\sigma_{\max}$, so a $1/\kappa$ below about 1e-15 is not
/// resolved, and 0 means "rank-deficient to working precision".
///
/// # Example
/// ```
/// use nalgebra::Matrix2;
/// let j = Matrix2::new(2.0, 0.0, 0.0, 0.5);
/// assert!((pkm_workspace_indices::inverse_condition_number(&j) - 0.25).abs() < 1e-15);
/// ```
pub fn inverse_condition_number<const N: usize>(j: &SMatrix<f64, N, N>) -> f64
where
    Dim<N>: FixedSvd<N>,
{
    if !j.iter().all(|v| v.is_finite()) {
        return 0.0;
    }
    let sigma = <Dim<N> as FixedSvd<N>>::singular_values(&scaled_to_unit(j, 100));
    let (sigma_min, sigma_max) = (sigma.min(), sigma.max());
    if sigma_max > 0.0 {
        (sigma_min / sigma_max).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// $\kappa = \sigma_{\max} / \sigma_{\min} \ge 1$; infinite for a singular matrix.
///
/// # Example
/// ```
/// use nalgebra::Matrix2;
/// let j = Matrix2::new(2.0, 0.0, 0.0, 0.5);
/// assert!((pkm_workspace_indices::condition_number(&j) - 4.0).abs() < 1e-14);
/// ```
pub fn condition_number<const N: usize>(j: &SMatrix<f64, N, N>) -> f64
where
    Dim<N>: FixedSvd<N>,
{
    let inverse = inverse_condition_number(j);
    if inverse > 0.0 {
        1.0 / inverse
    } else {
        f64::INFINITY
    }
}

/// `j` times the power of two $2^{-e}$ that brings its largest entry into $[1, 2)$, when that
/// entry lies outside $[2^{-k}, 2^{k}]$; `j` itself otherwise. Scaling by a power of two is
/// exact (barring subnormal entries), so scale-invariant quantities do not change.
pub(crate) fn scaled_to_unit<const R: usize, const C: usize>(
    j: &SMatrix<f64, R, C>,
    k: i32,
) -> SMatrix<f64, R, C> {
    match unit_scale(j.amax(), k) {
        Some((first, second)) => j * first * second,
        None => *j,
    }
}

/// The two factors of [`scaled_to_unit`] for a matrix whose largest entry is `largest`, `None`
/// when no scaling is needed (or possible: zero or non-finite).
pub(crate) fn unit_scale(largest: f64, k: i32) -> Option<(f64, f64)> {
    // |floor(log2 x)| <= k exactly when 2^-k <= x < 2^(k+1): decided without the logarithm
    // on the common path (the hot 1/κ kernels call this per matrix).
    if !(largest > 0.0 && largest.is_finite())
        || (largest >= power_of_two(-k) && largest < power_of_two(k + 1))
    {
        return None;
    }
    let exponent = largest.log2().floor();
    // |exponent| <= 1075 for a finite positive f64: the cast is exact, and 2^-exponent is
    // applied in two halves so that neither factor overflows or is subnormal.
    let e = exponent as i32;
    let (first, second) = (e / 2, e - e / 2);
    Some((power_of_two(-first), power_of_two(-second)))
}

/// $2^n$ exactly for $-1022 \le n \le 1023$ (the normal range, where it is `2f64.powi(n)` bit
/// for bit; `n` outside is clamped to it), built from the exponent bits rather than by
/// `powi`'s library call: the lane $1/\kappa$ kernel scales many lanes of unreachable points.
fn power_of_two(n: i32) -> f64 {
    f64::from_bits(u64::from((n.clamp(-1022, 1023) + 1023).unsigned_abs()) << 52)
}

/// $1/\kappa$ of the velocity Jacobian $J$ ($NQ \times 3$, $\dot q = J \dot p$) of a
/// translational workspace with `NQ` actuated joints: the local index of
/// [`crate::Workspace`].
///
/// For $NQ = 3$ it is the closed form [`crate::inverse_condition_number_3x3`]. For a redundant
/// set of legs ($NQ > 3$, a Stewart–Gough platform at a fixed orientation) it is
/// $\sigma_3 / \sigma_1$ of the three singular values of the tall $J$
/// ([`inverse_condition_number_tall`]): the least over the greatest leg speed $|\dot q|$ per unit
/// platform speed $|\dot p|$, 0 where $J$ loses rank (a direction of motion no leg sees).
pub trait TranslationalCondition<const NQ: usize> {
    /// $1/\kappa(j) \in [0, 1]$, 0 for a rank-deficient or non-finite `j`.
    fn inverse_condition(j: &SMatrix<f64, NQ, 3>) -> f64;
}

impl TranslationalCondition<3> for Dim<3> {
    fn inverse_condition(j: &SMatrix<f64, 3, 3>) -> f64 {
        crate::inverse_condition_number_3x3(j)
    }
}

impl TranslationalCondition<6> for Dim<6> {
    fn inverse_condition(j: &SMatrix<f64, 6, 3>) -> f64 {
        inverse_condition_number_tall(j)
    }
}

/// $1/\kappa = \sigma_3 / \sigma_1 \in [0, 1]$ of a $6 \times 3$ matrix from its SVD (after the
/// exact power-of-two scaling of [`inverse_condition_number`]); 0 for a matrix of rank below 3,
/// the zero matrix, or one with non-finite entries.
///
/// # Example
/// ```
/// use nalgebra::SMatrix;
/// let mut j = SMatrix::<f64, 6, 3>::zeros();
/// j[(0, 0)] = 2.0;
/// j[(1, 1)] = 1.0;
/// j[(2, 2)] = 0.5;
/// assert!((pkm_workspace_indices::inverse_condition_number_tall(&j) - 0.25).abs() < 1e-15);
/// ```
pub fn inverse_condition_number_tall(j: &SMatrix<f64, 6, 3>) -> f64 {
    if !j.iter().all(|v| v.is_finite()) {
        return 0.0;
    }
    let sigma = scaled_to_unit(j, 100).singular_values();
    let (sigma_min, sigma_max) = (sigma.min(), sigma.max());
    if sigma_max > 0.0 {
        (sigma_min / sigma_max).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_of_two_is_powi_bit_for_bit_on_the_normal_range() {
        for n in -1022..=1023 {
            assert_eq!(power_of_two(n).to_bits(), 2f64.powi(n).to_bits(), "2^{n}");
        }
        assert_eq!(power_of_two(-5000).to_bits(), power_of_two(-1022).to_bits());
        assert_eq!(
            power_of_two(i32::MAX).to_bits(),
            power_of_two(1023).to_bits()
        );
    }
}
