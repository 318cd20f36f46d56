//! Issue 31: the dynamics study of a robot file: the Delta file's motor torques against the
//! hand-written Delta study's Lagrange torques, sampled positions against the exact trajectory,
//! and the refusals (key paths, and the sample where the dynamics fails).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use pkm_study::dynamics::{DynamicsStudy, PickAndPlaceSpec, ReadingSpec};
use pkm_study::schema::mechanism::MechanismSpec;
use pkm_study::schema::units::Real;
use pkm_study::{Artifact, DynamicsResult, Outcome, StudyError, dynamics, from_toml_str};
use pkm_traits::Silent;

fn studies() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies")
}

/// An example study with its robot file resolved (what a front end does).
fn example(name: &str) -> DynamicsStudy {
    let text = std::fs::read_to_string(studies().join(name)).unwrap();
    let mut study: DynamicsStudy = from_toml_str(&text).unwrap();
    let MechanismSpec::RobotFile(spec) = &mut study.mechanism else {
        panic!("{name}: a robot file")
    };
    spec.resolve_file(&pkm_study::load::Directory(studies()))
        .unwrap();
    study
}

fn column(outcome: &Outcome<DynamicsResult>, table: &str, name: &str) -> Vec<f64> {
    let t = outcome
        .artifacts
        .iter()
        .find_map(|a| match a {
            Artifact::Table { name: n, table: t } if n == table => Some(t),
            _ => None,
        })
        .unwrap();
    t.column(name)
        .unwrap()
        .into_iter()
        .map(Option::unwrap)
        .collect()
}

/// The Delta file's study gives, sample by sample, the Lagrange torques of the hand-written
/// Delta study on the same cycle (Miller's masses, exact accelerations) to 1e-9 N·m.
#[test]
fn the_delta_file_study_gives_the_hand_written_torques() {
    let file = dynamics(&example("rotary_delta_file_dynamics.toml"), &Silent).unwrap();
    let hand: DynamicsStudy = from_toml_str(
        r#"
[mechanism.rotary_delta]
base_radius = 0.194
plate_offset = 0.03
arm = 0.26
forearm = 0.48
alpha_deg = 0.0
beta_deg = 0.0
motor_plane_z = -0.2928
azimuth_motor_1_deg = 300.0
[masses]
plate = 0.2807
arm_inertia = 0.01822
arm_mass = 0.977
arm_centre_of_mass = 0.13
elbow = 0.0099
forearm = 0.0296
[trajectory]
dt = 0.002
[trajectory.pick_and_place]
cycle_time = 0.5
"#,
    )
    .unwrap();
    let hand = dynamics(&hand, &Silent).unwrap();
    assert_eq!(file.result.samples, hand.result.samples);
    let mut largest = 0.0_f64;
    for motor in 0..3 {
        let ours = column(
            &file,
            "efforts.csv",
            &format!("effort legs[{motor}].joints[0]"),
        );
        let theirs = column(&hand, "torques.csv", &format!("tau_lagrange_{}", motor + 1));
        for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
            assert!(
                (a - b).abs() < 1e-9,
                "motor {motor}, sample {k}: {a} vs {b}"
            );
            largest = largest.max(b.abs());
        }
    }
    assert!(largest > 10.0, "{largest}");
    let efforts = file.result.efforts.clone().unwrap();
    assert!(efforts.formulation_difference < 1e-12);
    assert_eq!(efforts.actuators[0].unit, "N m");
    // The forward dynamics fed with those torques retraces the cycle from its first state to
    // 1 mm (measured 0.31 mm; the hand-written Delta's Hamilton retrace: 0.19 mm), its energy
    // balance within the trapezoidal rule's 0.1 J of the cycle's 1.2 kW peaks.
    let retrace = file.result.retrace.clone().unwrap();
    assert!(retrace.max_task_error < 1e-3, "{retrace:?}");
    assert!(retrace.max_energy_balance < 0.1, "{retrace:?}");
    let errors = column(&file, "retrace.csv", "error z");
    assert_eq!(errors.len(), file.result.samples);
    assert!(errors[0].abs() < 1e-12 && errors.iter().any(|e| e.abs() > 1e-6));
}

/// Sampled positions (the exact trajectory's, every 5 ms) give efforts within the central
/// differences' error of the exact ones: 2 % of the peak at the interior samples.
#[test]
fn sampled_positions_agree_with_the_exact_trajectory() {
    let exact_study = example("stewart_gough_dynamics.toml");
    let exact = dynamics(&exact_study, &Silent).unwrap();
    let names = ["x", "y", "z", "rx", "ry", "rz"];
    let t = column(&exact, "efforts.csv", "t");
    let xs: Vec<Vec<f64>> = names
        .iter()
        .map(|n| column(&exact, "efforts.csv", n))
        .collect();
    let mut sampled = exact_study.clone();
    sampled.trajectory.task_segments.clear();
    sampled.trajectory.dt = None;
    sampled.trajectory.positions = Some(
        (0..t.len())
            .map(|k| {
                std::iter::once(t[k])
                    .chain(xs.iter().map(|x| x[k]))
                    .map(Real)
                    .collect()
            })
            .collect(),
    );
    let differenced = dynamics(&sampled, &Silent).unwrap();
    let peak = exact.result.efforts.as_ref().unwrap().actuators[5].peak;
    for leg in 0..6 {
        let name = format!("effort legs[{leg}].joints[1]");
        let (a, b) = (
            column(&exact, "efforts.csv", &name),
            column(&differenced, "efforts.csv", &name),
        );
        for k in 2..a.len() - 2 {
            assert!(
                (a[k] - b[k]).abs() < 0.02 * peak,
                "leg {leg}, sample {k}: {} vs {}",
                a[k],
                b[k]
            );
        }
    }
}

/// Every setting that cannot be used is refused at its key before computing; a sample the
/// dynamics cannot take is named with its index and time.
#[test]
fn robot_file_dynamics_refusals() {
    let base = example("stewart_gough_dynamics.toml");
    let refused = |study: &DynamicsStudy, key: &str| {
        let Err(e) = dynamics(study, &Silent) else {
            panic!("{key}: accepted")
        };
        assert_eq!(
            e.path().map(ToString::to_string).as_deref(),
            Some(key),
            "{e}"
        );
    };
    let mut masses = base.clone();
    masses.masses = from_toml_str::<DynamicsStudy>(
        r#"
[mechanism.rotary_delta]
base_radius = 0.194
plate_offset = 0.03
arm = 0.26
forearm = 0.48
[masses]
plate = 1.0
arm_inertia = 0.01
arm_mass = 1.0
arm_centre_of_mass = 0.1
elbow = 0.0
forearm = 0.0
[trajectory.pick_and_place]
cycle_time = 0.5
"#,
    )
    .unwrap()
    .masses;
    refused(&masses, "masses");
    let mut kappa = example("rotary_delta_file_dynamics.toml");
    if let Some(forward) = &mut kappa.dynamics.forward {
        forward.kappa = Real(5.0);
    }
    refused(&kappa, "dynamics.forward.kappa");
    let mut builtin = base.clone();
    builtin.trajectory.task_segments.clear();
    builtin.trajectory.pick_and_place = masses_cycle();
    refused(&builtin, "trajectory");
    let mut short = base.clone();
    short.trajectory.task_segments[0].end.pop();
    refused(&short, "trajectory.task_segments[0].end");
    let mut narrow = base.clone();
    narrow.trajectory.task_segments.clear();
    narrow.trajectory.dt = None;
    narrow.trajectory.positions = Some(
        (0..4)
            .map(|k| vec![Real(0.01 * f64::from(k)), Real(0.0), Real(0.0), Real(0.3)])
            .collect(),
    );
    refused(&narrow, "trajectory.positions[0]");
    // The Hexa's arms cannot reach 1 m below home: a sample of the first segment (60 samples
    // of 5 ms) fails, named with its index and time.
    let mut far = example("hexa_dynamics.toml");
    far.trajectory.task_segments[0].end[2] = Real(-1.5);
    far.trajectory.task_segments[1].start[2] = Real(-1.5);
    match dynamics(&far, &Silent) {
        Err(StudyError::RobotDynamics { sample, time, .. }) => {
            assert!(sample > 0 && sample <= 60 && (time - 0.005 * sample as f64).abs() < 1e-12);
        }
        Err(other) => panic!("{other}"),
        Ok(_) => panic!("reached 1 m below home"),
    }
}

fn masses_cycle() -> Option<PickAndPlaceSpec> {
    Some(PickAndPlaceSpec {
        cycle_time: Real(0.5),
        reading: ReadingSpec::RoundTrip,
    })
}

/// The Stewart–Gough example's effort map: each cell is the library's eq. D5 at its centre
/// (largest over the actuators), and a map naming a coordinate the robot lacks is refused.
#[test]
fn an_effort_map_is_the_peak_effort_at_each_cell() {
    let study = example("stewart_gough_dynamics.toml");
    let outcome = dynamics(&study, &Silent).unwrap();
    let map = &outcome.result.effort_maps[0];
    assert_eq!(map.cells, 24);
    let (x, y, peak) = (
        column(&outcome, &map.csv, "x"),
        column(&outcome, &map.csv, "y"),
        column(&outcome, &map.csv, "peak_effort"),
    );
    let MechanismSpec::RobotFile(spec) = &study.mechanism else {
        panic!("a robot file")
    };
    let model = spec.model().unwrap();
    let bounds = [5.0, 5.0, 5.0, 20.0, 20.0, 20.0];
    for k in [0, 100, 300, 575] {
        let expected = model
            .peak_efforts_at_rest(
                &[x[k], y[k], 0.3, 0.0, 0.0, 0.0],
                &bounds,
                model.home_mode(),
            )
            .unwrap()
            .amax();
        assert!((peak[k] - expected).abs() < 1e-12 * expected, "cell {k}");
    }
    assert!(map.max_peak.unwrap() > map.min_peak.unwrap());
    let mut bad = study.clone();
    bad.effort_maps[0].axes[1] = "w".into();
    let e = dynamics(&bad, &Silent).err().unwrap();
    assert_eq!(
        e.path().map(ToString::to_string).as_deref(),
        Some("effort_maps[0].axes")
    );
}

/// An effort map can be cancelled while it runs: a progress that asks to stop once the map
/// starts gets `Cancelled`, not a map computed to the end.
#[test]
fn an_effort_map_stops_when_cancelled() {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    #[derive(Default)]
    struct StopAtMap {
        stop: AtomicBool,
        rows: AtomicU64,
    }
    impl pkm_traits::Progress for StopAtMap {
        fn start(&self, label: &str, _total: u64) {
            if label.starts_with("effort map") {
                self.stop.store(true, Ordering::Relaxed);
            }
        }
        fn advance(&self, n: u64) {
            self.rows.fetch_add(n, Ordering::Relaxed);
        }
        fn is_cancelled(&self) -> bool {
            self.stop.load(Ordering::Relaxed)
        }
    }
    let progress = StopAtMap::default();
    let run = dynamics(&example("stewart_gough_dynamics.toml"), &progress);
    assert!(matches!(run, Err(StudyError::Cancelled)), "{:?}", run.err());
}
