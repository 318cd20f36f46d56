//! `N` `f64` lanes with element-wise arithmetic, the number type of the batch (lane-parallel)
//! kernels. Every operation is a fixed-length loop over the lanes with no branch and no call,
//! which the compiler turns into SIMD instructions (SSE2 on the baseline target, AVX where
//! enabled), so a kernel written once in `Lanes<N>` is vectorised without `unsafe` or a SIMD
//! crate. Conditions are selects ([`Lanes::select`], [`Lanes::select_gt`]); lanes never
//! interact, so NaN or infinity in one lane cannot reach another. [`JacobianLanes`] is what the
//! batch Jacobian kernels of the mechanisms return.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `N` independent `f64` values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lanes<const N: usize>(pub [f64; N]);

impl<const N: usize> Lanes<N> {
    /// Every lane `value`.
    #[inline(always)]
    pub fn splat(value: f64) -> Self {
        Self([value; N])
    }

    /// Lane `l` is `f(l)`.
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        Self(std::array::from_fn(f))
    }

    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Self::from_fn(|l| f(self.0[l]))
    }

    #[inline(always)]
    fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Self::from_fn(|l| f(self.0[l], other.0[l]))
    }

    /// The coordinates $(x, y, z)$ of the `N` points, each as lanes (lane `l` of the first is
    /// `points[l].x`).
    #[inline(always)]
    pub fn coordinates(points: &[nalgebra::Vector3<f64>; N]) -> [Self; 3] {
        [
            Self::from_fn(|l| points[l].x),
            Self::from_fn(|l| points[l].y),
            Self::from_fn(|l| points[l].z),
        ]
    }

    /// Square root per lane.
    #[inline(always)]
    pub fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }

    /// Absolute value per lane.
    #[inline(always)]
    pub fn abs(self) -> Self {
        self.map(f64::abs)
    }

    /// [`f64::signum`] per lane.
    #[inline(always)]
    pub fn signum(self) -> Self {
        self.map(f64::signum)
    }

    /// [`f64::max`] with `value` per lane (a NaN lane becomes `value`).
    #[inline(always)]
    pub fn max(self, value: f64) -> Self {
        self.map(|v| v.max(value))
    }

    /// [`f64::max`] lane by lane (a NaN lane takes the other's value).
    #[inline(always)]
    pub fn max_lanes(self, other: Self) -> Self {
        self.zip(other, f64::max)
    }

    /// [`f64::min`] with `value` per lane (a NaN lane becomes `value`).
    #[inline(always)]
    pub fn min(self, value: f64) -> Self {
        self.map(|v| v.min(value))
    }

    /// [`f64::clamp`] per lane (a NaN lane stays NaN), without its panic: for limits that are
    /// NaN or inverted (`lo > hi`) a lane below `lo` becomes `lo`, then one above `hi` becomes
    /// `hi`; for valid limits the bits are [`f64::clamp`]'s.
    #[inline(always)]
    pub fn clamp(self, lo: f64, hi: f64) -> Self {
        let below = std::array::from_fn(|l| self.0[l] < lo);
        let above = std::array::from_fn(|l| self.0[l] > hi);
        Self::splat(lo).select(below, Self::splat(hi).select(above, self))
    }

    /// Per lane: `self` where `mask` is true, else `otherwise`; by bit masks, so that it stays
    /// vectorised where a branch per lane would not (the compiler turned the branches of
    /// [`Lanes::clamp`] into scalar code in the AVX2 kernels).
    #[inline(always)]
    pub fn select(self, mask: [bool; N], otherwise: Self) -> Self {
        Self::from_fn(|l| {
            let keep = u64::from(mask[l]).wrapping_neg();
            f64::from_bits((self.0[l].to_bits() & keep) | (otherwise.0[l].to_bits() & !keep))
        })
    }

    /// $1/x$ per lane.
    #[inline(always)]
    pub fn recip(self) -> Self {
        // `1.0 / v`: what `f64::recip` computes, bit for bit.
        self.map(|v| 1.0 / v)
    }

    /// Per lane: `if_true` where `self > bound`, else `if_false` (NaN compares false).
    #[inline(always)]
    pub fn select_gt(self, bound: Self, if_true: Self, if_false: Self) -> Self {
        Self::from_fn(|l| {
            if self.0[l] > bound.0[l] {
                if_true.0[l]
            } else {
                if_false.0[l]
            }
        })
    }

    /// Per lane: whether `self > bound` (NaN compares false).
    #[inline(always)]
    pub fn gt(self, bound: f64) -> [bool; N] {
        std::array::from_fn(|l| self.0[l] > bound)
    }

    /// Per lane: whether `self <= bound` (NaN compares false).
    #[inline(always)]
    pub fn le(self, bound: f64) -> [bool; N] {
        std::array::from_fn(|l| self.0[l] <= bound)
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const N: usize> $trait for Lanes<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                self.zip(other, |a, b| a $op b)
            }
        }
        impl<const N: usize> $trait<f64> for Lanes<N> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: f64) -> Self {
                self.map(|a| a $op other)
            }
        }
        impl<const N: usize> $trait<Lanes<N>> for f64 {
            type Output = Lanes<N>;
            #[inline(always)]
            fn $method(self, other: Lanes<N>) -> Lanes<N> {
                other.map(|b| self $op b)
            }
        }
    };
}

lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl<const N: usize> Neg for Lanes<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|v| -v)
    }
}

/// `N` velocity Jacobians $J = -J_q^{-1}J_x$ of a 3-DOF mechanism in structure-of-arrays form,
/// lanes innermost, with the reachability of each lane: the output of the batch Jacobian
/// kernels. The layout is `pkm_workspace_indices::Matrix3Lanes`, so `jacobian` feeds
/// `inverse_condition_number_3x3_lanes` directly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianLanes<const N: usize> {
    /// Entry $(i, j)$ of the Jacobian in lane `l` is `jacobian[3 * i + j][l]`; meaningless (often
    /// NaN or infinite) in a lane that is not reachable.
    pub jacobian: [[f64; N]; 9],
    /// Whether lane `l` is a finite point where every leg's inverse kinematics has a solution
    /// at which $J$ is defined.
    pub reachable: [bool; N],
}

impl<const N: usize> JacobianLanes<N> {
    /// The Jacobian of lane `lane` as a matrix, `None` when that lane is not reachable or
    /// `lane >= N`.
    pub fn matrix(&self, lane: usize) -> Option<nalgebra::Matrix3<f64>> {
        (*self.reachable.get(lane)?)
            .then(|| nalgebra::Matrix3::from_fn(|i, j| self.jacobian[3 * i + j][lane]))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::float_cmp)]
    use super::*;

    #[test]
    fn operations_act_lane_by_lane_and_nan_stays_in_its_lane() {
        let a = Lanes([1.0, 4.0, f64::NAN, -9.0]);
        let b = Lanes::splat(2.0);
        assert_eq!((a * b + 1.0).0[..2], [3.0, 9.0]);
        assert_eq!((a / b - b).0[1], 0.0);
        assert_eq!((1.0 - a).0[0], 0.0);
        assert_eq!(a.abs().sqrt().0[3], 3.0);
        assert_eq!(a.max(0.0).0, [1.0, 4.0, 0.0, 0.0]);
        assert_eq!(a.min(2.0).0, [1.0, 2.0, 2.0, -9.0]);
        let m = a.max_lanes(-a).0;
        assert!(m[..2] == [1.0, 4.0] && m[2].is_nan() && m[3] == 9.0);
        assert_eq!(a.max_lanes(b).0, [2.0, 4.0, 2.0, 2.0]);
        let points = [
            nalgebra::Vector3::new(1.0, 2.0, 3.0),
            nalgebra::Vector3::new(4.0, 5.0, 6.0),
        ];
        assert_eq!(
            Lanes::coordinates(&points).map(|c| c.0),
            [[1.0, 4.0], [2.0, 5.0], [3.0, 6.0]]
        );
        assert!(a.clamp(0.0, 2.0).0[2].is_nan());
        assert_eq!(a.signum().0[3], -1.0);
        assert_eq!((-a).recip().0[0], -1.0);
        assert_eq!(a.gt(1.5), [false, true, false, false]);
        assert_eq!(a.le(1.5), [true, false, false, true]);
        let m = Lanes([1.0, -0.0, f64::NAN, 2.0]).select([true, true, false, false], a);
        assert!(m.0[..2] == [1.0, -0.0] && m.0[1].is_sign_negative() && m.0[2].is_nan());
        assert_eq!(m.0[3], -9.0);
        assert_eq!(
            Lanes([-2.0, 0.5, 3.0, -1.0]).clamp(-1.0, 1.0).0,
            [-1.0, 0.5, 1.0, -1.0]
        );
        assert_eq!(Lanes([-2.0, 0.5, 3.0]).clamp(1.0, -1.0).0, [1.0, 1.0, -1.0]);
        let picked = a.select_gt(b, Lanes::splat(1.0), Lanes::splat(0.0));
        assert_eq!(picked.0, [0.0, 1.0, 0.0, 0.0]);
        assert!((a + b).0[2].is_nan() && (a + b).0[3] == -7.0);
    }
}
