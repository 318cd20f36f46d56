//! `pkm-traits`: bounds and Newton's forward kinematics.

use super::{all_finite, config, extreme_finite, hostile_f64, hostile_vec3, judge, judge_value};
use nalgebra::Vector3;
use pkm_mechanisms::{Tsai3Dof, presets};
use pkm_traits::{Bounds, ClosedChain, NewtonSettings, newton_forward_kinematics};
use proptest::prelude::*;

fn tsai() -> Tsai3Dof {
    Tsai3Dof::new(presets::stamper_max_gci()).unwrap()
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn bounds_are_finite_ordered_and_measurable(lower in hostile_f64(), upper in hostile_f64()) {
        judge("Bounds::new", || Bounds::new(lower, upper), |b| {
            b.width().is_finite() && b.width() >= 0.0 && b.contains(b.clamp(0.0))
        })?;
    }

    #[test]
    fn bounds_helpers_stay_inside(
        lower in extreme_finite(), width in extreme_finite(), x in extreme_finite(), step in 1e-9..0.1f64,
    ) {
        if let Ok(b) = Bounds::new(lower, lower + width.abs()) {
            judge_value("Bounds::clamp", || b.clamp(x), |v| b.contains(*v))?;
            judge_value("Bounds::difference_points", || b.difference_points(x, step), |(hi, lo)| {
                b.contains(*hi) && b.contains(*lo) && hi >= lo
            })?;
        }
    }

    #[test]
    fn newton_forward_kinematics_ends_typed_or_closed(
        q in hostile_vec3(), guess in hostile_vec3(), tolerance in hostile_f64(), iterations in 0..40usize,
    ) {
        let mechanism = tsai();
        let settings = NewtonSettings { tolerance, max_iterations: iterations };
        judge("newton_forward_kinematics", || newton_forward_kinematics(&mechanism, &q, &guess, &settings), |x| {
            all_finite(x.iter()) && all_finite(mechanism.closure(x, &q).iter())
        })?;
    }

    #[test]
    fn newton_forward_kinematics_from_a_reachable_pose(
        guess in (-0.5..0.5f64, -0.5..0.5f64, 0.2..0.9f64), tolerance in hostile_f64(),
    ) {
        use pkm_traits::InverseKinematics;
        use pkm_mechanisms::Elbow;
        let mechanism = tsai();
        let p = Vector3::new(0.05, -0.03, 0.6);
        let q = mechanism.inverse_kinematics(&p, [Elbow::Out; 3]).unwrap();
        let guess = Vector3::new(guess.0, guess.1, guess.2);
        let settings = NewtonSettings { tolerance, max_iterations: 30 };
        judge("newton_forward_kinematics (reachable)", || newton_forward_kinematics(&mechanism, &q, &guess, &settings), |x| {
            all_finite(x.iter()) && mechanism.closure(x, &q).amax() <= tolerance.abs().max(1e-9)
        })?;
    }
}
