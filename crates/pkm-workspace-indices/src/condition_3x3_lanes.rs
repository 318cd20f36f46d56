//! [`inverse_condition_number_3x3`] on `N` matrices at once, without trigonometric functions,
//! in [`Lanes`] so that the compiler vectorises it (no calls, no branches: every special case
//! is a select).
//!
//! The scalar routine finds the eigenvalues of $M = J^\top J$ as
//! $\lambda_k = q + 2p\cos\big(\varphi + \tfrac{2\pi k}{3}\big)$, $q = \operatorname{tr}M/3$,
//! $p = \sqrt{\operatorname{tr}(M - qI)^2/6}$, $\varphi = \tfrac13\arccos r$,
//! $r = \tfrac12\det\big((M - qI)/p\big) \in [-1, 1]$. Here $(\cos\varphi, \sin\varphi)$ is the
//! principal cube root $w$ of the unit complex number $z = r + i\sqrt{(1-r)(1+r)}$
//! ($\arg z = 3\varphi \in [0, \pi]$), found by Newton's method on $w^3 = z$,
//! $$ w \leftarrow \tfrac13\big(2w + z / w^2\big), $$
//! from $w_0 = c_0 + i\sqrt{1 - c_0^2}$ with the quadratic $c_0(r)$ through
//! $\cos\varphi$ at $r = -1, 0, 1$ (angular error below 0.02 rad). A cube root is a simple
//! root, so the iteration converges quadratically for every $r$ — unlike Newton on the
//! characteristic cubic, which stalls at a double eigenvalue — and four steps reach
//! $|w - e^{i\varphi}| < 5\cdot10^{-16}$ on all of $[-1, 1]$. Then
//! $\lambda_{\max} = q + 2p\cos\varphi$, $\lambda_{\mathrm{low}} = q - p(\cos\varphi +
//! \sqrt3\sin\varphi)$ $(= q + 2p\cos(\varphi + 2\pi/3))$, $\lambda_{\mathrm{mid}} = 3q -
//! \lambda_{\max} - \lambda_{\mathrm{low}}$ and
//! $\lambda_{\min} = \det(J)^2/(\lambda_{\max}\lambda_{\mathrm{mid}})$, exactly as in the scalar
//! routine, so both agree to rounding wherever the problem is well conditioned.
//!
//! `#[inline(always)]`, so that [`crate::evaluate`] compiles it into each vector path
//! ([`crate::VectorPath`]); only basic IEEE operations, no fused multiply-add, so every path
//! gives the same bits.

#[cfg(doc)]
use crate::inverse_condition_number_3x3;
use pkm_traits::{JacobianLanes, Lanes};

/// The lane count the batch kernels are tuned for: eight independent lanes (four SSE2 registers)
/// hide the latency of the dependent divisions in the Newton steps; on baseline x86-64 eight
/// lanes ran about 1.5 times as fast as four (`docs/performance.md`).
pub const LANES: usize = 8;

/// `N` $3\times3$ matrices in structure-of-arrays form: entry $(i, j)$ of the matrix in lane `l`
/// is `m[3 * i + j][l]` (row-major entries, lanes innermost).
pub type Matrix3Lanes<const N: usize> = [[f64; N]; 9];

/// Newton steps on $w^3 = z$ (see the module documentation).
const CUBE_ROOT_STEPS: usize = 4;

/// $1/\kappa$ of each of the `N` matrices (any lane count; [`LANES`] is the tuned one), as [`inverse_condition_number_3x3`] computes
/// it for one (the same special cases: 0 for a singular or non-finite matrix, 1 when the
/// eigenvalues of $J^\top J$ coincide to $10^{-15}$), but without trigonometric functions
/// (see the module documentation). Lanes are independent: a non-finite lane yields 0 and leaves
/// the others untouched.
///
/// On the same matrix it agrees with the scalar routine to $10^{-12}$ relative for
/// $\kappa \le 10^2$; beyond, both carry the rounding of $\lambda_{\mathrm{mid}}$, about
/// $\epsilon\,\kappa^2$ relative. Both routines amplify a perturbation of $J$ where two
/// eigenvalues of $J^\top J$ nearly coincide ($r \approx \pm1$), so Jacobians that differ by
/// rounding can give values that differ by more than that (see `docs/performance.md`).
///
/// # Example
/// ```
/// use pkm_workspace_indices::{LANES, inverse_condition_number_3x3_lanes};
/// let mut j = [[0.0; LANES]; 9];
/// for (l, scale) in [2.0, 4.0, 1.0, f64::NAN].into_iter().enumerate() {
///     j[0][l] = scale;
///     j[4][l] = 1.0;
///     j[8][l] = 0.5;
/// }
/// let r = inverse_condition_number_3x3_lanes(&j);
/// assert!((r[0] - 0.25).abs() < 1e-14 && (r[1] - 0.125).abs() < 1e-14);
/// assert!((r[2] - 0.5).abs() < 1e-14 && r[3] == 0.0);
/// ```
#[inline(always)]
pub fn inverse_condition_number_3x3_lanes<const N: usize>(j: &Matrix3Lanes<N>) -> [f64; N] {
    let original = j;
    let j = scaled_lanes(j);
    let finite: [bool; N] =
        std::array::from_fn(|l| j.iter().fold(true, |all, v| all & v.0[l].is_finite()));
    let gram = |a: usize, b: usize| j[a] * j[b] + j[3 + a] * j[3 + b] + j[6 + a] * j[6 + b];
    let (m00, m11, m22) = (gram(0, 0), gram(1, 1), gram(2, 2));
    let (m01, m02, m12) = (gram(0, 1), gram(0, 2), gram(1, 2));
    let p1 = m01 * m01 + m02 * m02 + m12 * m12;
    let q = (m00 + m11 + m22) / 3.0;
    let (d0, d1, d2) = (m00 - q, m11 - q, m22 - q);
    let p = ((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * p1) / 6.0).sqrt();
    let inv_p = p.recip();
    let (b00, b11, b22) = (d0 * inv_p, d1 * inv_p, d2 * inv_p);
    let (b01, b02, b12) = (m01 * inv_p, m02 * inv_p, m12 * inv_p);
    let det_b = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02)
        + b02 * (b01 * b12 - b11 * b02);
    let r = (0.5 * det_b).clamp(-1.0, 1.0);
    let (cos_phi, sin_phi) = principal_cube_root(r);
    let lambda_max = q + 2.0 * p * cos_phi;
    let lambda_low = q - p * (cos_phi + 3f64.sqrt() * sin_phi);
    let lambda_mid = 3.0 * q - lambda_max - lambda_low;
    let det = j[0] * (j[4] * j[8] - j[5] * j[7]) - j[1] * (j[3] * j[8] - j[5] * j[6])
        + j[2] * (j[3] * j[7] - j[4] * j[6]);
    let zero = Lanes::splat(0.0);
    let lambda_min = lambda_mid.select_gt(zero, det * det / (lambda_max * lambda_mid), zero);
    let general = (lambda_min / lambda_max).max(0.0).sqrt().min(1.0);
    let (q_positive, spread) = (q.gt(0.0), (p - 1e-15 * q).gt(0.0));
    std::array::from_fn(|l| {
        if !finite[l] || !q_positive[l] {
            0.0
        } else if !spread[l] {
            1.0
        } else if general.0[l] < crate::SVD_BELOW {
            // As the scalar routine: the SVD where the closed form loses digits (scalar code,
            // the same bits on every vector path).
            crate::inverse_condition_number(&nalgebra::Matrix3::from_fn(|r, c| {
                original[3 * r + c][l]
            }))
        } else {
            general.0[l]
        }
    })
}

/// $1/\kappa$ ([`inverse_condition_number_3x3_lanes`]) of each reachable lane of a batch
/// Jacobian, `None` in the others. The lanes not reached are set to the identity first: their
/// values are not used, and their entries, often huge, would send the kernel down its rare
/// scaling path (a logarithm per lane). The reachable lanes are untouched, so their values are
/// those of [`inverse_condition_number_3x3_lanes`] on the Jacobian as it is, bit for bit.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use pkm_mechanisms::{ElbowMode, Placement, RotaryDelta, presets};
/// use pkm_workspace_indices::{inverse_condition_number_3x3_lanes, inverse_condition_of_reachable_lanes};
/// let delta = RotaryDelta::new(presets::miller_delta(Placement::canonical()))?;
/// let j = delta.jacobian_lanes(&[Vector3::new(0.0, 0.1, -0.7), Vector3::new(0.0, 0.0, 9.0)], ElbowMode::Out);
/// let values = inverse_condition_of_reachable_lanes(&j);
/// assert_eq!(values[0], Some(inverse_condition_number_3x3_lanes(&j.jacobian)[0]));
/// assert_eq!(values[1], None);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[inline(always)]
pub fn inverse_condition_of_reachable_lanes<const N: usize>(
    j: &JacobianLanes<N>,
) -> [Option<f64>; N] {
    let values = if j.reachable.contains(&false) {
        let mut jacobian = j.jacobian;
        for (k, row) in jacobian.iter_mut().enumerate() {
            let unit = if k % 4 == 0 { 1.0 } else { 0.0 };
            *row = Lanes(*row).select(j.reachable, Lanes::splat(unit)).0;
        }
        inverse_condition_number_3x3_lanes(&jacobian)
    } else {
        inverse_condition_number_3x3_lanes(&j.jacobian)
    };
    std::array::from_fn(|l| j.reachable[l].then_some(values[l]))
}

/// Each lane scaled by the power of two of the scalar routine (`det(J)²` grows like the sixth
/// power of the entries), so that huge or tiny matrices neither overflow nor underflow; lanes
/// already near 1 are left as they are, bit for bit (their factors are 1). Computed entry by
/// entry into lanes rather than by copying the rows and scaling them in place, so that no lane
/// row is copied.
#[inline(always)]
fn scaled_lanes<const N: usize>(j: &Matrix3Lanes<N>) -> [Lanes<N>; 9] {
    let mut largest = Lanes::splat(0.0);
    for row in j {
        largest = largest.max_lanes(Lanes(*row).abs());
    }
    let (mut first, mut second) = (Lanes::splat(1.0), Lanes::splat(1.0));
    // `unit_scale(x, 40)` is `None` for x in [2^-40, 2^41) and for x that is not finite and
    // positive: decided here without its call (unreachable lanes are often infinite).
    let (low, high) = (1.0 / (1_u64 << 40) as f64, (1_u64 << 41) as f64);
    for l in 0..N {
        let x = largest.0[l];
        if (x >= low && x < high) || !(x > 0.0 && x.is_finite()) {
            continue;
        }
        if let Some((f, s)) = crate::condition::unit_scale(x, 40) {
            (first.0[l], second.0[l]) = (f, s);
        }
    }
    let entry = |k: usize| Lanes(j[k]) * first * second;
    [
        entry(0),
        entry(1),
        entry(2),
        entry(3),
        entry(4),
        entry(5),
        entry(6),
        entry(7),
        entry(8),
    ]
}

/// $(\cos\varphi, \sin\varphi)$ with $\varphi = \tfrac13\arccos r$, $r \in [-1, 1]$, by Newton's
/// method on $w^3 = z = r + i\sqrt{(1-r)(1+r)}$ (module documentation). The factored radicand
/// keeps $\sin 3\varphi$ accurate to rounding near $r = \pm1$.
#[inline(always)]
fn principal_cube_root<const N: usize>(r: Lanes<N>) -> (Lanes<N>, Lanes<N>) {
    let z_im = ((1.0 - r) * (1.0 + r)).max(0.0).sqrt();
    let half_sqrt3 = 0.5 * 3f64.sqrt();
    let c0 = half_sqrt3 + 0.25 * r + (0.75 - half_sqrt3) * r * r;
    let (mut a, mut b) = (c0, (1.0 - c0 * c0).max(0.0).sqrt());
    for _ in 0..CUBE_ROOT_STEPS {
        // z / w² = z · conj(w²) / |w²|².
        let (x, y) = (a * a - b * b, 2.0 * a * b);
        let inv = (x * x + y * y).recip();
        let (qx, qy) = ((r * x + z_im * y) * inv, (z_im * x - r * y) * inv);
        a = (2.0 * a + qx) * (1.0 / 3.0);
        b = (2.0 * b + qy) * (1.0 / 3.0);
    }
    (a, b)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::float_cmp)]
    use super::*;
    use crate::{inverse_condition_number, inverse_condition_number_3x3};
    use nalgebra::Matrix3;
    use proptest::prelude::*;

    fn lanes_of<const N: usize>(ms: &[Matrix3<f64>; N]) -> Matrix3Lanes<N> {
        std::array::from_fn(|k| std::array::from_fn(|l| ms[l][(k / 3, k % 3)]))
    }

    /// Tolerance of the module documentation: $10^{-12}$ relative up to $\kappa = 100$, then
    /// growing as $\epsilon\kappa^2$.
    fn agrees(batch: f64, scalar: f64) -> bool {
        let kappa = 1.0 / scalar.max(f64::MIN_POSITIVE);
        let tol = 1e-12_f64.max(8.0 * f64::EPSILON * kappa * kappa) * scalar;
        (batch - scalar).abs() <= tol
    }

    #[test]
    fn cube_root_is_accurate_on_all_of_minus_one_to_one() {
        let mut worst = 0.0_f64;
        for k in 0..=20_000 {
            let r = -1.0 + k as f64 / 10_000.0;
            let phi = r.acos() / 3.0;
            let (Lanes([c]), Lanes([s])) = principal_cube_root(Lanes([r]));
            worst = worst.max((c - phi.cos()).abs()).max((s - phi.sin()).abs());
        }
        for e in 1..=17 {
            for r in [1.0 - 10f64.powi(-e), -1.0 + 10f64.powi(-e)] {
                let phi = r.acos() / 3.0;
                let (Lanes([c]), Lanes([s])) = principal_cube_root(Lanes([r]));
                worst = worst.max((c - phi.cos()).abs()).max((s - phi.sin()).abs());
            }
        }
        assert!(worst < 1e-15, "{worst}");
    }

    #[test]
    fn special_cases_match_the_scalar_routine() {
        let cases = [
            Matrix3::identity() * 3.0,                                 // p = 0: 1
            Matrix3::zeros(),                                          // q = 0: 0
            Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0), // singular: 0
            Matrix3::from_diagonal(&[1.0, 1.0, 1e-3].into()),          // double eigenvalue
        ];
        let got = inverse_condition_number_3x3_lanes(&lanes_of(&cases));
        for (m, g) in cases.iter().zip(got) {
            let want = inverse_condition_number_3x3(m);
            assert!((g - want).abs() <= 1e-15, "{m} {g} {want}");
        }
    }

    fn entry() -> impl Strategy<Value = f64> {
        prop_oneof![
            8 => -10.0..10.0_f64,
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
            1 => Just(-1e300),
            1 => Just(0.0),
        ]
    }

    proptest! {
        #[test]
        fn each_lane_equals_the_scalar_routine(
            entries in proptest::collection::vec(-10.0..10.0_f64, 9 * LANES),
        ) {
            let ms: [Matrix3<f64>; LANES] =
                std::array::from_fn(|l| Matrix3::from_row_slice(&entries[9 * l..9 * l + 9]));
            let got = inverse_condition_number_3x3_lanes(&lanes_of(&ms));
            for (m, g) in ms.iter().zip(got) {
                let want = inverse_condition_number_3x3(m);
                prop_assert!(agrees(g, want), "{m} batch {g} scalar {want}");
                // and with the SVD, to the accuracy of the scalar routine's documentation
                let svd = inverse_condition_number(m);
                prop_assert!((g - svd).abs() <= 1e-10_f64.max(1e-3 * svd), "{g} {svd}");
            }
        }

        #[test]
        fn a_bad_lane_does_not_poison_the_others(
            entries in proptest::collection::vec(entry(), 9 * LANES),
        ) {
            let ms: [Matrix3<f64>; LANES] =
                std::array::from_fn(|l| Matrix3::from_row_slice(&entries[9 * l..9 * l + 9]));
            let got = inverse_condition_number_3x3_lanes(&lanes_of(&ms));
            for (m, g) in ms.iter().zip(got) {
                let want = inverse_condition_number_3x3(m);
                prop_assert!((0.0..=1.0).contains(&g), "{m} {g}");
                prop_assert!(agrees(g, want) || (g - want).abs() <= 1e-12, "{m} {g} {want}");
            }
        }
    }
}
