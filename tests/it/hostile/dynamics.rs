//! `pkm-dynamics-hamilton`: trajectories, the extended model at one configuration, sampling and
//! inverse dynamics, the forward forms' gains. An error at a sample of a trajectory carries the
//! real, finite time of that sample (never a placeholder).

use super::{all_finite, config, hostile_f64, hostile_vec3, judge};
use nalgebra::Vector3;
use pkm::dynamics_hamilton::forward::{AccelerationForm, HamiltonForm};
use pkm::dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm::dynamics_hamilton::trajectory::{MotionLaw, Path, Segment, Trajectory};
use pkm::dynamics_hamilton::{DynamicsError, ExtendedModel, MassParameters};
use pkm::mechanisms::{Placement, RotaryDelta, presets};
use pkm::papers::miller2004::dynamics::{CycleReading, pick_and_place};
use proptest::prelude::*;

fn nuwar() -> ExtendedModel {
    let mechanism = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
    ExtendedModel::new(mechanism, &MassParameters::miller2004()).unwrap()
}

/// The time an error names, if it names one: finite whenever present.
fn time_is_real(e: &DynamicsError) -> bool {
    match e {
        DynamicsError::Unreachable { t, .. }
        | DynamicsError::Singular { t, .. }
        | DynamicsError::NonFinite { t, .. } => t.is_finite(),
        _ => true,
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn one_configuration_is_checked(p in hostile_vec3(), v in hostile_vec3(), a in hostile_vec3()) {
        let model = nuwar();
        judge("ExtendedModel::joint_motion", || model.joint_motion(&p, &v, &a), |s| {
            all_finite(s.q.iter()) && all_finite(s.qd.iter()) && all_finite(s.qdd.iter())
                && model.constraints(&s.q).amax() < 1e-9
        })?;
        if let Ok(s) = model.joint_motion(&p, &Vector3::zeros(), &Vector3::zeros()) {
            judge("inverse::lagrange_torques", || inverse::lagrange_torques(&model, &s.q, &s.qd, &s.qdd), |tau| all_finite(tau.iter()))?;
        }
    }

    #[test]
    fn trajectories_are_checked(
        start in hostile_vec3(), end in hostile_vec3(), duration in hostile_f64(), cycle in hostile_f64(),
        each_leg in prop::bool::ANY,
    ) {
        judge("Trajectory::new", || {
            let path = Path::line(start, end)?;
            Trajectory::new(vec![Segment { path, law: MotionLaw::Cycloidal, duration, reverse: false }])
        }, |t| t.duration().is_finite() && t.duration() > 0.0)?;
        let reading = if each_leg { CycleReading::EachLeg } else { CycleReading::RoundTrip };
        judge("pick_and_place", || pick_and_place(cycle, reading), |t| {
            t.duration().is_finite() && t.duration() > 0.0 && all_finite(t.sample(0.0).p.iter())
        })?;
    }

    #[test]
    fn sampling_and_inverse_dynamics_name_real_times(
        dt in hostile_f64(), end in hostile_vec3(), kappa in hostile_f64(), omega in hostile_f64(),
    ) {
        let model = nuwar();
        // From the middle of the workspace to a hostile end point: reachable, or unreachable
        // at a named finite time.
        let start = Vector3::new(0.0, 0.0, -0.75);
        let Ok(path) = Path::line(start, end) else { return Ok(()) };
        let Ok(trajectory) = Trajectory::new(vec![Segment { path, law: MotionLaw::Polynomial345, duration: 0.05, reverse: false }]) else {
            return Ok(());
        };
        let sampled = inverse::sample(&model, &trajectory, dt);
        if let Err(e) = &sampled {
            prop_assert!(time_is_real(e), "{e:?}");
        }
        judge("inverse::sample", || sampled.clone(), |s| {
            s.len() >= 3 && s.iter().all(|(t, x)| t.is_finite() && all_finite(x.q.iter()))
        })?;
        if let Ok(samples) = &sampled {
            for differencing in [Differencing::Backward, Differencing::Central] {
                let tau = inverse::hamilton(&model, samples, differencing);
                if let Err(e) = &tau {
                    prop_assert!(time_is_real(e), "{e:?}");
                }
                judge("inverse::hamilton", || tau, |tau| tau.iter().all(|t| all_finite(t.iter())))?;
                let lagrange = inverse::lagrange(&model, samples, Accelerations::Differenced(differencing));
                if let Err(e) = &lagrange {
                    prop_assert!(time_is_real(e), "{e:?}");
                }
                judge("inverse::lagrange", || lagrange, |tau| tau.iter().all(|t| all_finite(t.iter())))?;
            }
        }
        judge("HamiltonForm::new", || HamiltonForm::new(&model, |_| Vector3::zeros(), kappa).map(|f| f.kappa()), |k| {
            k.is_finite() && *k >= 0.0
        })?;
        judge("AccelerationForm::new", || AccelerationForm::new(&model, |_| Vector3::zeros(), omega).map(|f| f.omega()), |w| {
            w.is_finite() && *w >= 0.0
        })?;
    }
}

/// A cycloidal move along the line from `start` to `end` in one second.
fn one_second_line(start: Vector3<f64>, end: Vector3<f64>) -> Trajectory {
    let segment = Segment {
        path: Path::line(start, end).unwrap(),
        law: MotionLaw::Cycloidal,
        duration: 1.0,
        reverse: false,
    };
    Trajectory::new(vec![segment]).unwrap()
}

#[test]
fn an_unreachable_trajectory_point_reports_its_real_time_and_leg() {
    let model = nuwar();
    // Straight away from motor 1 until leg 1 (index 0) cannot reach.
    let radial = model.mechanism().legs()[0].plate_offset.normalize();
    let start = Vector3::new(0.0, 0.0, -0.75);
    let trajectory = one_second_line(start, start - radial);
    let dt = 1e-3;
    let Err(DynamicsError::Unreachable { t, source }) = inverse::sample(&model, &trajectory, dt)
    else {
        panic!("the line leaves the workspace");
    };
    let pkm::traits::KinematicsError::Unreachable { leg, .. } = source else {
        panic!("expected a leg that cannot reach, got {source:?}");
    };
    assert_eq!(leg, 0);
    // The time is a grid time, the first out of reach.
    let k = (t / dt).round();
    assert!((t - k * dt).abs() < 1e-15 && t > 0.0 && t < 1.0, "t = {t}");
    let at = |t: f64| {
        let m = trajectory.sample(t);
        model.joint_motion(&m.p, &m.v, &m.a)
    };
    assert!(at(t - dt).is_ok() && at(t).is_err());
    // Attached by the sample loop: the model's own error has no time to carry.
    let Err(bare) = at(t) else { unreachable!() };
    assert_eq!(bare.at(t), DynamicsError::Unreachable { t, source });
}

/// A sample count under the 1e8 guard but beyond the library's memory budget is refused before
/// anything is allocated (9.9e7 samples of an extended state once took 5.1 GB and aborted).
#[test]
fn sampling_beyond_the_memory_budget_is_refused() {
    let model = nuwar();
    let start = Vector3::new(0.0, 0.0, -0.75);
    let trajectory = one_second_line(start, start + Vector3::new(0.0, 0.0, -0.01));
    let refused = inverse::sample(&model, &trajectory, 1.0 / 9.9e7);
    assert!(
        matches!(refused, Err(DynamicsError::Invalid(_))),
        "{:?}",
        refused.map(|s| s.len())
    );
}

/// A clothoid is evaluated to its accuracy or refused: a sharpness whose quadrature would need
/// more than `MAX_CLOTHOID_TURNS` panels is refused (1e20 was off by a factor of 4e5), and
/// direction vectors of any finite size give the same path as unit ones (norm 1e200 gave zeros).
#[test]
fn clothoids_are_accurate_or_refused() {
    use pkm::dynamics_hamilton::trajectory::MAX_CLOTHOID_TURNS;
    let (start, x, y) = (Vector3::zeros(), Vector3::x(), Vector3::y());
    for sharpness in [1e20, 1e15, -1e16] {
        let path = Path::clothoid(start, x, y, 0.0, sharpness, 1.0);
        assert!(
            matches!(path, Err(DynamicsError::Invalid(_))),
            "sharpness {sharpness}: {path:?}"
        );
    }
    // Within the bound (c L = 1e5 of MAX_CLOTHOID_TURNS): the end point is the Fresnel
    // integral ∫₀¹ cos(c s²/2) ds = √(π/c)/2 + sin(c/2)/c + O(c⁻²).
    let c = 1e5;
    assert!(c <= MAX_CLOTHOID_TURNS);
    let path = Path::clothoid(start, x, y, 0.0, c, 1.0).unwrap();
    let [end, _, _] = path.eval(1.0);
    let fresnel = (std::f64::consts::PI / c).sqrt() / 2.0 + (c / 2.0).sin() / c;
    assert!((end.x - fresnel).abs() < 1e-8, "{end:?} vs {fresnel}");
    let unit = Path::clothoid(start, x, y, 0.5, std::f64::consts::PI, 1.0).unwrap();
    for scale in [1e200, 1e-200, 1e150] {
        let scaled = Path::clothoid(start, x * scale, y * scale, 0.5, std::f64::consts::PI, 1.0);
        let scaled = scaled.unwrap();
        for u in [0.0, 0.3, 1.0] {
            let (a, b) = (unit.eval(u), scaled.eval(u));
            for k in 0..3 {
                assert!(
                    (a[k] - b[k]).norm() < 1e-12,
                    "scale {scale}, u {u}: {a:?} vs {b:?}"
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(config())]

    /// A trajectory sampled at any time keeps its documented contract: a finite motion for
    /// every time that is not NaN (clamped to the trajectory), a NaN position for a NaN time,
    /// never a panic.
    #[test]
    fn trajectories_sampled_at_any_time_keep_their_contract(t in hostile_f64()) {
        let trajectory = pick_and_place(0.5, CycleReading::RoundTrip).unwrap();
        let m = trajectory.sample(t);
        if t.is_nan() {
            prop_assert!(m.p.iter().all(|v| v.is_nan()), "{m:?}");
        } else {
            prop_assert!(all_finite(m.p.iter().chain(m.v.iter()).chain(m.a.iter())), "t = {t}: {m:?}");
        }
    }

    /// The extended model's energies keep their documented contract: finite for finite
    /// coordinates and rates below 1e150, NaN in gives NaN out, never a panic.
    #[test]
    fn energies_keep_their_contract(q in prop::array::uniform6(-10.0..10.0f64), qd in prop::array::uniform6(-1e140..1e140f64), nan in prop::bool::ANY) {
        let model = nuwar();
        let (q, mut qd) = (nalgebra::Vector6::from(q), nalgebra::Vector6::from(qd));
        if nan {
            qd[2] = f64::NAN;
        }
        let (t, e) = (model.kinetic_energy(&q, &qd), model.energy(&q, &qd));
        prop_assert_eq!(t.is_finite() && e.is_finite(), !nan, "T = {}, E = {}", t, e);
    }
}
