//! The dynamics study against the same computation done directly through the library, against
//! the analytic cycle its CSV was sampled from, and its refusals: every setting checked, with
//! its key path, before any computation.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use nalgebra::{Vector3, Vector6};
use pkm_dynamics_hamilton::inverse::{self, Accelerations, Differencing};
use pkm_dynamics_hamilton::trajectory::presets::miller_pick_and_place;
use pkm_dynamics_hamilton::{ExtendedModel, MassParameters};
use pkm_mechanisms::{Placement, RotaryDelta, presets};
use pkm_study::dynamics::{DynamicsStudy, ForwardSpec, PickAndPlaceSpec, ReadingSpec};
use pkm_study::schema::units::Real;
use pkm_study::{Artifact, DynamicsResult, Outcome, StudyError, Table, dynamics, from_toml_str};
use pkm_traits::{Progress, Silent};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies")
}

/// `a` and `b` agree to `rel` relative (and 1e-300 absolute).
fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300
}

/// The rows `[t, x, y, z]` of the example's CSV trajectory.
fn csv_rows() -> Vec<[f64; 4]> {
    let text = std::fs::read_to_string(examples().join("nuwar_pick_and_place.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}

/// The example study with its CSV handed in as positions (what a front end does).
fn example_study() -> DynamicsStudy {
    let text = std::fs::read_to_string(examples().join("nuwar_dynamics_csv.toml")).unwrap();
    let mut study: DynamicsStudy = from_toml_str(&text).unwrap();
    assert_eq!(
        study.trajectory.csv.as_deref(),
        Some("nuwar_pick_and_place.csv")
    );
    study.trajectory.csv = None;
    study.trajectory.positions = Some(
        csv_rows()
            .into_iter()
            .map(|r| r.map(Real).to_vec())
            .collect(),
    );
    study
}

/// The example study on Miller's built-in cycle (0.5 s round trip) sampled every 1 ms.
fn cycle_study() -> DynamicsStudy {
    let mut study = example_study();
    study.trajectory.positions = None;
    study.trajectory.pick_and_place = Some(PickAndPlaceSpec {
        cycle_time: Real(0.5),
        reading: ReadingSpec::RoundTrip,
    });
    study.trajectory.dt = Some(1e-3);
    study
}

fn nuwar() -> ExtendedModel {
    let nuwar = RotaryDelta::new(presets::nuwar(Placement::canonical())).unwrap();
    ExtendedModel::new(nuwar, &MassParameters::miller2004()).unwrap()
}

fn table<'a>(outcome: &'a Outcome<DynamicsResult>, name: &str) -> &'a Table {
    outcome
        .artifacts
        .iter()
        .find_map(|a| match a {
            Artifact::Table { name: n, table } if n == name => Some(table),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no table {name}"))
}

/// Column `name` of `table` as numbers.
fn column(table: &Table, name: &str) -> Vec<f64> {
    table
        .column(name)
        .unwrap()
        .into_iter()
        .map(Option::unwrap)
        .collect()
}

fn peak(t: &[Vector3<f64>]) -> f64 {
    t.iter().map(|t| t.amax()).fold(0.0, f64::max)
}

#[test]
fn csv_positions_match_the_library_and_the_analytic_cycle() {
    let outcome = dynamics(&example_study(), &Silent).unwrap();
    let r = &outcome.result;
    let model = nuwar();
    // The same computation through the library: positions, velocities and accelerations by
    // central differences, the inverse kinematics, both formulations.
    let rows = csv_rows();
    let dt = rows[1][0] - rows[0][0];
    let p: Vec<Vector6<f64>> = rows
        .iter()
        .map(|r| Vector6::new(r[1], r[2], r[3], 0.0, 0.0, 0.0))
        .collect();
    let v = Differencing::Central.apply(&p, dt).unwrap();
    let a = Differencing::Central.apply(&v, dt).unwrap();
    let three = |x: &Vector6<f64>| Vector3::new(x[0], x[1], x[2]);
    let samples: Vec<_> = (0..p.len())
        .map(|k| {
            let s = model.joint_motion(&three(&p[k]), &three(&v[k]), &three(&a[k]));
            (rows[k][0], s.unwrap())
        })
        .collect();
    let hamilton = inverse::hamilton(&model, &samples, Differencing::Central).unwrap();
    let lagrange = inverse::lagrange(&model, &samples, Accelerations::Exact).unwrap();
    let torques = table(&outcome, "torques.csv");
    assert_eq!(torques.rows.len(), hamilton.len());
    for i in 0..3 {
        let written_h = column(torques, &format!("tau_hamilton_{}", i + 1));
        let written_l = column(torques, &format!("tau_lagrange_{}", i + 1));
        for (k, (h, l)) in hamilton.iter().zip(&lagrange).enumerate() {
            assert!(close(h[i], written_h[k], 1e-15) && close(l[i], written_l[k], 1e-15));
        }
    }
    assert_eq!(r.samples, rows.len());
    assert!(close(r.dt, dt, 1e-15));
    assert!(close(
        r.hamilton.as_ref().unwrap().max,
        peak(&hamilton),
        1e-15
    ));
    assert!(close(
        r.lagrange.as_ref().unwrap().max,
        peak(&lagrange),
        1e-15
    ));
    // Against the analytic cycle the CSV was sampled from: Hamilton's torques from differenced
    // positions differ from those of the exact velocities by the O(dt²) error of the central
    // differences. Measured at dt = 2 ms: 0.23 N m inside (0.4 % of the 60 N m peak) and
    // 1.16 N m (1.9 %) at the two samples at each end, where the one-sided differences have
    // four times the error constant; the bounds are about twice that.
    let cycle = miller_pick_and_place(0.5).unwrap();
    let exact = inverse::sample(&model, &cycle, dt).unwrap();
    let analytic = inverse::hamilton(&model, &exact, Differencing::Central).unwrap();
    let gaps: Vec<f64> = (hamilton.iter().zip(&analytic))
        .map(|(h, e)| (h - e).amax())
        .collect();
    let n = gaps.len();
    let interior = gaps[2..n - 2].iter().copied().fold(0.0, f64::max);
    let ends = (gaps[..2].iter().chain(&gaps[n - 2..]))
        .copied()
        .fold(0.0, f64::max);
    let scale = peak(&analytic);
    assert!(
        interior < 0.01 * scale,
        "interior gap {interior} vs peak {scale}"
    );
    assert!(ends < 0.04 * scale, "end gap {ends} vs peak {scale}");
    // The forward retrace follows the commanded positions within the interpolation and
    // differencing error of 2 ms torque samples: Miller's Fig. 9 run has 2.2e-4 m at 1 ms and
    // the error grows as dt² (measured here 7.8e-4 m); the Baumgarte-stabilised drift
    // (measured 2.3e-10 m) and the energy balance (1.7e-7 J) stay at the integrator's level.
    let f = r.forward.as_ref().unwrap();
    assert!(f.max_position_error < 2e-3, "{}", f.max_position_error);
    assert!(f.max_drift < 1e-8, "{}", f.max_drift);
    assert!(f.max_energy_balance < 1e-5, "{}", f.max_energy_balance);
    // The retrace table holds the same numbers per sample.
    let retrace = table(&outcome, "retrace.csv");
    let drift = column(retrace, "drift");
    assert_eq!(drift.len(), rows.len());
    assert_eq!(
        drift.iter().copied().fold(0.0, f64::max).to_bits(),
        f.max_drift.to_bits()
    );
    let names: Vec<&str> = outcome
        .artifacts
        .iter()
        .map(|a| match a {
            Artifact::Table { name, .. } | Artifact::Chart { name, .. } => name.as_str(),
            Artifact::Robot { .. } => "robot",
        })
        .collect();
    assert_eq!(
        names,
        [
            "torques.csv",
            "torques.svg",
            "retrace.csv",
            "retrace.svg",
            "robot"
        ]
    );
}

#[test]
fn the_built_in_cycle_gives_the_library_torques() {
    let r = dynamics(&cycle_study(), &Silent).unwrap().result;
    let model = nuwar();
    let cycle = miller_pick_and_place(0.5).unwrap();
    let samples = inverse::sample(&model, &cycle, 1e-3).unwrap();
    let hamilton = inverse::hamilton(&model, &samples, Differencing::Central).unwrap();
    let lagrange = inverse::lagrange(&model, &samples, Accelerations::Exact).unwrap();
    assert_eq!(r.samples, 501);
    assert!(close(
        r.hamilton.as_ref().unwrap().max,
        peak(&hamilton),
        1e-15
    ));
    assert!(close(
        r.lagrange.as_ref().unwrap().max,
        peak(&lagrange),
        1e-15
    ));
    // The 1 ms retrace of Miller's Fig. 9 (its experiment's budget: 4e-4 m).
    assert!(r.forward.unwrap().max_position_error < 4e-4);
}

/// A progress reporter that records whether any computation started.
#[derive(Default)]
struct Recorder(AtomicBool);

impl Progress for Recorder {
    fn phase(&self, _: &str) {
        self.0.store(true, Ordering::Relaxed);
    }
    fn start(&self, _: &str, _: u64) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// The key path of the error of `study`, after checking that nothing was computed.
#[track_caller]
fn refused_at(study: &DynamicsStudy) -> String {
    let recorder = Recorder::default();
    let e = dynamics(study, &recorder).expect_err("the study is invalid");
    assert!(
        !recorder.0.load(Ordering::Relaxed),
        "computed before refusing: {e}"
    );
    let StudyError::Invalid { path, .. } = &e else {
        panic!("not a setting error: {e:?}");
    };
    path.to_string()
}

#[test]
fn every_setting_is_refused_at_its_key_before_any_computation() {
    let edit = |change: &dyn Fn(&mut DynamicsStudy)| {
        let mut study = cycle_study();
        change(&mut study);
        refused_at(&study)
    };
    let in_toml = |from: &str, to: &str| {
        let text = std::fs::read_to_string(examples().join("nuwar_dynamics_csv.toml")).unwrap();
        assert!(text.contains(from), "{from}");
        let study: DynamicsStudy = from_toml_str(&text.replacen(from, to, 1)).unwrap();
        refused_at(&study)
    };
    assert_eq!(
        in_toml(
            "[mechanism.rotary_delta]",
            "[mechanism.rotary_delta]\nelbow = [\"in\"]"
        ),
        "mechanism.rotary_delta.elbow"
    );
    let tsai =
        |s: &mut DynamicsStudy| s.mechanism = from_toml_str("tsai = { a = 0.2, b = 0.3 }").unwrap();
    assert_eq!(edit(&tsai), "mechanism");
    assert_eq!(in_toml("plate = 0.2807", "plate = -0.2807"), "masses.plate");
    assert_eq!(in_toml("elbow = 0.0099", "elbow = -1.0"), "masses.elbow");
    assert_eq!(
        in_toml("csv = \"nuwar_pick_and_place.csv\"", ""),
        "trajectory"
    );
    assert_eq!(
        in_toml(
            "[trajectory]",
            "[trajectory]\npick_and_place = { cycle_time = 0.5 }"
        ),
        "trajectory"
    );
    // A file name alone: the study layer reads no files.
    assert_eq!(in_toml("[trajectory]", "[trajectory]"), "trajectory.csv");
    assert_eq!(edit(&|s| s.trajectory.dt = Some(0.0)), "trajectory.dt");
    assert_eq!(edit(&|s| s.trajectory.dt = Some(f64::NAN)), "trajectory.dt");
    assert_eq!(edit(&|s| s.trajectory.dt = Some(0.4)), "trajectory.dt");
    // 5e8 samples would take about 500 GB: refused before allocating.
    assert_eq!(edit(&|s| s.trajectory.dt = Some(1e-9)), "trajectory.dt");
    let cycle_time = |t| {
        move |s: &mut DynamicsStudy| {
            s.trajectory.pick_and_place.as_mut().unwrap().cycle_time = Real(t);
        }
    };
    assert_eq!(
        edit(&cycle_time(-1.0)),
        "trajectory.pick_and_place.cycle_time"
    );
    let forward = |change: fn(&mut ForwardSpec)| {
        move |s: &mut DynamicsStudy| change(s.dynamics.forward.as_mut().unwrap())
    };
    assert_eq!(
        edit(&forward(|f| f.kappa = Real(-1.0))),
        "dynamics.forward.kappa"
    );
    assert_eq!(
        edit(&forward(|f| f.rtol = Real(0.0))),
        "dynamics.forward.rtol"
    );
    assert_eq!(
        edit(&forward(|f| f.atol = Real(-1e-11))),
        "dynamics.forward.atol"
    );
    assert_eq!(
        edit(&forward(|f| f.max_steps = 0)),
        "dynamics.forward.max_steps"
    );
}

#[test]
fn segments_and_positions_are_refused_at_the_offending_entry() {
    let segments = |extra: &str| {
        let text = format!(
            "[mechanism.rotary_delta]\nbase_radius = 0.194\nplate_offset = 0.03\narm = 0.26\n\
             forearm = 0.48\n[masses]\nplate = 0.28\narm_inertia = 0.018\narm_mass = 0.98\n\
             arm_centre_of_mass = 0.13\nelbow = 0.01\nforearm = 0.03\n\
             [[trajectory.segments]]\nlaw = \"cycloidal\"\nduration = 0.2\n\
             path = {{ line = {{ start = [0.0, 0.0, -0.5], end = [0.0, 0.05, -0.5] }} }}\n\
             [[trajectory.segments]]\n{extra}"
        );
        let study: DynamicsStudy = from_toml_str(&text).unwrap();
        refused_at(&study)
    };
    let arc = "path = { ellipse = { centre = [0.0, 0.0, -0.5], axis_1 = [0.0, 0.05, 0.0], \
               axis_2 = [0.0, 0.0, 0.05], start_angle_deg = 0.0, sweep_deg = 0.0 } }";
    assert_eq!(
        segments(&format!("law = \"parabolic\"\nduration = 0.2\n{arc}")),
        "trajectory.segments[1].path"
    );
    let line = "path = { line = { start = [0.0, 0.05, -0.5], end = [0.0, 0.0, -0.5] } }";
    assert_eq!(
        segments(&format!("law = \"parabolic\"\nduration = 0.0\n{line}")),
        "trajectory.segments[1].duration"
    );
    let positions = |rows: &[[f64; 4]], dt: Option<f64>| {
        let mut study = example_study();
        study.trajectory.positions = Some(rows.iter().map(|r| r.map(Real).to_vec()).collect());
        study.trajectory.dt = dt;
        refused_at(&study)
    };
    let p = |t: f64| [t, 0.0, -0.2, -0.9];
    assert_eq!(positions(&[p(0.0), p(0.002)], None), "trajectory.positions");
    assert_eq!(
        positions(&[p(0.0), p(0.002), p(0.005), p(0.006)], None),
        "trajectory.positions[2]"
    );
    assert_eq!(
        positions(&[p(0.0), p(0.0), p(0.0)], None),
        "trajectory.positions[1]"
    );
    assert_eq!(
        positions(&[p(0.0), p(0.002), [0.004, f64::NAN, 0.0, 0.0]], None),
        "trajectory.positions[2]"
    );
    assert_eq!(
        positions(&[p(0.0), p(0.002), p(0.004)], Some(1e-3)),
        "trajectory.dt"
    );
}

#[test]
fn an_unreachable_sample_is_a_dynamics_error_with_its_time() {
    let mut study = example_study();
    let mut rows = csv_rows();
    rows[3][3] = -3.0; // 3 m below the motors: out of reach
    study.trajectory.positions = Some(rows.iter().map(|r| r.map(Real).to_vec()).collect());
    let e = dynamics(&study, &Silent).unwrap_err();
    assert!(matches!(e, StudyError::Dynamics(_)), "{e:?}");
    assert!(e.to_string().contains("t = 0.006 s"), "{e}");
}

/// A progress reporter that asks to stop at once.
struct Stop;

impl Progress for Stop {
    fn is_cancelled(&self) -> bool {
        true
    }
}

#[test]
fn a_cancelled_study_stops() {
    assert!(matches!(
        dynamics(&example_study(), &Stop),
        Err(StudyError::Cancelled)
    ));
}

#[test]
fn a_study_with_inline_positions_reads_from_json_as_from_toml() {
    let study = example_study();
    let json = serde_json::to_string(&study).unwrap();
    let back: DynamicsStudy = pkm_study::from_json_str(&json).unwrap();
    assert_eq!(back, study);
}
