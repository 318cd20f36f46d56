//! Operation counts of the inverse-dynamics kernels, by running them on [`Counted`], an `f64`
//! that counts every addition, subtraction, multiplication, division and negation it takes part
//! in (constants of the model enter through `From<f64>`, which is free). The trigonometric
//! functions are outside the kernels: three `sin_cos` per sample for every variant.
//!
//! Per sample of a sweep on the 1 ms grid (the cost of one sample when every sample is processed
//! once):
//! * Hamilton: the legs and the momentum $p_{k+1} = M\dot q_{k+1}$ of the next sample, the
//!   central difference $(p_{k+1} - p_{k-1})\cdot\frac{1}{2\Delta t}$ (as `Differencing::apply`), steps 2–3 at sample $k$ (whose legs were
//!   formed when it was the next sample);
//! * Lagrange, $\ddot q$ given: the legs and [`lagrange_torques`];
//! * Lagrange with the acceleration-level IK: the same plus [`joint_accelerations`].
//!
//! Run `cargo test -p pkm-dynamics-hamilton operation_counts -- --nocapture` to print them.

use super::{
    Arithmetic, Constants, hamilton_torques, joint_accelerations, lagrange_torques, legs, momentum,
};
use nalgebra::{Vector3, Vector6};
use std::cell::Cell;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Operations counted since the last [`reset`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Operations {
    pub add: usize,
    pub mul: usize,
    pub div: usize,
    pub neg: usize,
}

impl Operations {
    /// Additions, subtractions, multiplications and divisions (negations are sign flips and not
    /// counted as floating-point operations).
    pub(crate) fn flops(&self) -> usize {
        self.add + self.mul + self.div
    }
}

thread_local! {
    static COUNT: Cell<Operations> = Cell::new(Operations::default());
}

fn tally(f: impl FnOnce(&mut Operations)) {
    COUNT.with(|c| {
        let mut o = c.get();
        f(&mut o);
        c.set(o);
    });
}

fn bump(n: &mut usize) {
    *n += 1;
}

/// Resets the counter of this thread and returns what it held.
pub(crate) fn reset() -> Operations {
    COUNT.with(|c| c.replace(Operations::default()))
}

/// An `f64` that counts its arithmetic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Counted(pub f64);

impl From<f64> for Counted {
    fn from(v: f64) -> Self {
        Self(v)
    }
}

macro_rules! binary {
    ($trait:ident, $method:ident, $assign:ident, $assign_method:ident, $op:tt, $field:ident) => {
        impl $trait for Counted {
            type Output = Self;
            fn $method(self, rhs: Self) -> Self {
                tally(|o| bump(&mut o.$field));
                Self(self.0 $op rhs.0)
            }
        }
        impl $assign for Counted {
            fn $assign_method(&mut self, rhs: Self) {
                *self = *self $op rhs;
            }
        }
    };
}

binary!(Add, add, AddAssign, add_assign, +, add);
binary!(Sub, sub, SubAssign, sub_assign, -, add);
binary!(Mul, mul, MulAssign, mul_assign, *, mul);
binary!(Div, div, DivAssign, div_assign, /, div);

impl Neg for Counted {
    type Output = Self;
    fn neg(self) -> Self {
        tally(|o| bump(&mut o.neg));
        Self(-self.0)
    }
}

impl Arithmetic for Counted {}

fn counted<const N: usize>(v: &nalgebra::SVector<f64, N>) -> nalgebra::SVector<Counted, N> {
    v.map(Counted)
}

fn trig(q: &Vector6<f64>) -> [(Counted, Counted); 3] {
    std::array::from_fn(|i| {
        let (s, c) = q[3 + i].sin_cos();
        (Counted(s), Counted(c))
    })
}

fn task(q: &Vector6<f64>) -> Vector3<Counted> {
    Vector3::new(Counted(q[0]), Counted(q[1]), Counted(q[2]))
}

/// The three per-sample counts (Hamilton, Lagrange with $\ddot q$, Lagrange with the
/// acceleration-level IK) at the states `(q, q̇, q̈)` of samples k − 1, k, k + 1, and the torques
/// they computed (to check that the counted code computes what the `f64` code does).
pub(crate) fn per_sample(
    k: &Constants,
    samples: [(Vector6<f64>, Vector6<f64>, Vector6<f64>); 3],
    dt: f64,
) -> [(Operations, Vector3<f64>); 3] {
    let [(q0, qd0, _), (q1, qd1, qdd1), (q2, qd2, _)] = samples;
    let legs_prev = legs(k, &task(&q0), trig(&q0));
    let p_prev = momentum(k, &legs_prev, &counted(&qd0));
    let legs_now = legs(k, &task(&q1), trig(&q1));
    reset();
    let legs_next = legs(k, &task(&q2), trig(&q2));
    let p_next = momentum(k, &legs_next, &counted(&qd2));
    let rate = (p_next - p_prev) * Counted(0.5 / dt);
    let (hamilton, _) = hamilton_torques(k, &legs_now, &counted(&qd1), &rate);
    let hamilton_ops = reset();
    let legs_now = legs(k, &task(&q1), trig(&q1));
    let (lagrange, _) = lagrange_torques(k, &legs_now, &counted(&qd1), &counted(&qdd1));
    let lagrange_ops = reset();
    let legs_now = legs(k, &task(&q1), trig(&q1));
    let a = Vector3::new(Counted(qdd1[0]), Counted(qdd1[1]), Counted(qdd1[2]));
    let qdd = joint_accelerations(k, &legs_now, &counted(&qd1), &a);
    let (with_ik, _) = lagrange_torques(k, &legs_now, &counted(&qd1), &qdd);
    let with_ik_ops = reset();
    let value = |v: Vector3<Counted>| v.map(|c| c.0);
    [
        (hamilton_ops, value(hamilton)),
        (lagrange_ops, value(lagrange)),
        (with_ik_ops, value(with_ik)),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inverse::{self, Differencing};
    use crate::{ExtendedModel, MassParameters};
    use pkm_mechanisms::{Placement, RotaryDelta, presets};

    #[test]
    #[allow(clippy::print_stdout)]
    fn operation_counts() {
        let model = ExtendedModel::new(
            RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap(),
            &MassParameters::miller2004(),
        )
        .unwrap();
        let trajectory = crate::trajectory::tests::ellipse_cycle(0.5);
        let dt = 1e-3;
        let samples = inverse::sample(&model, &trajectory, dt).unwrap();
        let state = |k: usize| (samples[k].1.q, samples[k].1.qd, samples[k].1.qdd);
        let [hamilton, lagrange, with_ik] =
            per_sample(model.constants(), [state(135), state(136), state(137)], dt);
        // The counted code computes what the f64 code computes.
        let h = inverse::hamilton(&model, &samples, Differencing::Central).unwrap();
        let s = &samples[136].1;
        let l = inverse::lagrange_torques(&model, &s.q, &s.qd, &s.qdd).unwrap();
        let a = s.qdd.fixed_rows::<3>(0).into();
        let qdd = model.joint_accelerations(&s.q, &s.qd, &a).unwrap();
        let l_ik = inverse::lagrange_torques(&model, &s.q, &s.qd, &qdd).unwrap();
        for (counted, f) in [(hamilton.1, h[136]), (lagrange.1, l), (with_ik.1, l_ik)] {
            assert!((counted - f).amax() <= 1e-12 * f.amax(), "{counted} vs {f}");
        }
        let saving =
            |other: &Operations| 100.0 * (1.0 - hamilton.0.flops() as f64 / other.flops() as f64);
        println!("per sample (+ 3 sin_cos each):");
        for (name, o) in [
            ("hamilton", hamilton.0),
            ("lagrange, qdd given", lagrange.0),
            ("lagrange with acceleration IK", with_ik.0),
        ] {
            println!(
                "{name}: {} flops ({} add/sub, {} mul, {} div; {} negations)",
                o.flops(),
                o.add,
                o.mul,
                o.div,
                o.neg
            );
        }
        println!(
            "Hamilton saves {:.1} % against Lagrange with qdd given, {:.1} % against Lagrange with the acceleration IK",
            saving(&lagrange.0),
            saving(&with_ik.0)
        );
        assert_eq!(
            [hamilton.0.flops(), lagrange.0.flops(), with_ik.0.flops()],
            [247, 235, 325],
            "update the counts in docs/performance.md and here"
        );
    }
}
