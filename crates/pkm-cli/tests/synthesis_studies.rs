//! End-to-end runs of the `optimize` and `task` study files (the optimize study's science is
//! checked in `pkm-study`'s tests) in `examples/studies/`,
//! each checked against the same computation done directly through the library, plus checks
//! that do not share the command's code path (closed forms, the analytic trajectory, the
//! library's own objectives at the reported optimum).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use clap::Parser;
use nalgebra::{Isometry3, Rotation3, Unit, Vector3, Vector6};
use pkm_cli::commands::task::TaskResult;
use pkm_cli::output::Results;
use pkm_cli::{Cli, run};
use pkm_mechanisms::{
    StewartDesign, StewartGough, StewartTaskProblem, ThreeUpu, ThreeUpuDesign, UJointAxes,
    WrenchSystem, pose_from_task, presets,
};
use pkm_optimizers::{LmSettings, Multistart, Sense, multistart_levenberg_marquardt};
use pkm_screw_theory::Twist;
use pkm_traits::{Bounds, Objective, ObjectiveError, Residuals, Silent, Task};
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

fn studies() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/studies")
}

/// Runs `pkm COMMAND STUDY --out TEMP --quiet` as `main` does and reads `results.json`.
fn run_study<R: DeserializeOwned>(command: &str, study: &Path) -> (Results<R>, tempfile::TempDir) {
    let out = tempfile::tempdir().unwrap();
    let cli = Cli::parse_from([
        "pkm",
        command,
        study.to_str().unwrap(),
        "--out",
        out.path().to_str().unwrap(),
        "--quiet",
    ]);
    run(&cli).unwrap_or_else(|e| panic!("pkm {command} {}: {e}", study.display()));
    let text = std::fs::read_to_string(out.path().join("results.json")).unwrap();
    let results: Results<R> = serde_json::from_str(&text).unwrap();
    assert_eq!(results.command, command);
    assert_eq!(
        results.study.text,
        std::fs::read_to_string(study).unwrap(),
        "results.json echoes the study"
    );
    for file in &results.files {
        assert!(out.path().join(file).is_file(), "{file} listed but missing");
    }
    (results, out)
}

fn close(a: f64, b: f64, relative: f64) -> bool {
    (a - b).abs() <= relative * a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

fn section_4_1_twist() -> Twist {
    Twist::from_screw(
        &Vector3::new(2.0, 2.0, 1.0),
        &Vector3::new(0.02, 0.03, 0.06),
        0.01,
        1.0,
    )
    .unwrap()
}

fn stewart_problem(twist: Twist) -> StewartTaskProblem {
    StewartTaskProblem::new(
        StewartDesign::from_deg(0.12, 0.08, 30.0, 8.0),
        Vector3::new(0.0, 0.0, 0.35),
        Vector3::zeros(),
        twist,
    )
    .unwrap()
    .free_position(0, Bounds::new(-0.1, 0.1).unwrap())
    .unwrap()
    .free_position(1, Bounds::new(-0.1, 0.1).unwrap())
    .unwrap()
    .free_position(2, Bounds::new(0.2, 0.5).unwrap())
    .unwrap()
    .free_rotation(30f64.to_radians())
    .unwrap()
}

fn pose_of(r: &TaskResult) -> Isometry3<f64> {
    let [x, y, z] = r.pose.position;
    let [a, b, c] = r.pose.rotation_deg.map(f64::to_radians);
    pose_from_task(&Task::<6>::new(x, y, z, a, b, c)).unwrap()
}

#[test]
fn stewart_task_synthesis_matches_the_library_multistart() {
    let study = studies().join("stewart_task_synthesis.toml");
    let (results, _out) = run_study::<TaskResult>("task", &study);
    let r = results.result;
    let problem = stewart_problem(section_4_1_twist());
    let best = multistart_levenberg_marquardt(
        &problem,
        Sense::Maximise,
        &Multistart::new(20, 2006),
        &LmSettings::default(),
        &Silent,
    )
    .unwrap()
    .best;
    assert!(
        close(r.objective, best.value, 1e-12),
        "{} vs {}",
        r.objective,
        best.value
    );
    let names = ["x", "y", "z", "u_x", "u_y", "u_z"];
    for (name, v) in names.iter().zip(&best.design) {
        assert!((r.optimum[*name] - v).abs() < 1e-12, "{name}");
    }
    // Independent of the problem's own evaluation: F of the library's platform at the
    // reported pose, and the leg lengths there.
    let sg = StewartGough::new(StewartDesign::from_deg(0.12, 0.08, 30.0, 8.0)).unwrap();
    let pose = pose_of(&r);
    let f = sg.task_objective(&pose, &section_4_1_twist()).unwrap();
    assert!(close(f, r.objective, 1e-9), "{f} vs {}", r.objective);
    assert!(close(r.twists[0].f, r.objective, 1e-9));
    let lengths = sg.leg_lengths(&pose);
    for (l, reported) in lengths.iter().zip(r.leg_lengths.unwrap()) {
        assert!(close(*l, reported, 1e-9));
    }
    assert!(r.pose.angle_deg <= 30.0 + 1e-9);
    assert!(r.optimality.termination.starts_with("converged"));
}

#[test]
fn weighted_copies_of_one_twist_are_that_twist() {
    let text = std::fs::read_to_string(studies().join("stewart_task_synthesis.toml")).unwrap();
    let split = text.replace(
        "weight = 1.0\n",
        "weight = 0.25\n\n[[task.twists]]\naxis = [2.0, 2.0, 1.0]\npoint = [0.02, 0.03, 0.06]\n\
         pitch = 0.01\nweight = 0.75\n",
    );
    assert_ne!(split, text);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("split.toml");
    std::fs::write(&path, split).unwrap();
    let (results, _out) = run_study::<TaskResult>("task", &path);
    let r = results.result;
    let best = multistart_levenberg_marquardt(
        &stewart_problem(section_4_1_twist()),
        Sense::Maximise,
        &Multistart::new(20, 2006),
        &LmSettings::default(),
        &Silent,
    )
    .unwrap()
    .best;
    // 0.25 F + 0.75 F = F: the same maximum, and each part's F is the total.
    assert!(
        close(r.objective, best.value, 1e-9),
        "{} vs {}",
        r.objective,
        best.value
    );
    assert_eq!(r.twists.len(), 2);
    for t in &r.twists {
        assert!(close(t.f, r.objective, 1e-9));
    }
}

/// σ_min of the 3-UPU's eq. 18 matrix over (x, y, z, rx, ry, rz) (m, degrees), written
/// directly.
struct UpuSigmaMin([Bounds; 6]);

/// Park's 3-UPU at base radius 0.2 m and platform radius 0.1 m, joints tilted by 30°.
fn upu_design() -> ThreeUpuDesign {
    ThreeUpuDesign {
        base_radius: 0.2,
        platform_radius: 0.1,
        azimuths: presets::PARK_AZIMUTHS_DEG.map(f64::to_radians),
        upper: tilted_axes(30.0),
    }
}

fn tilted_axes(gamma_deg: f64) -> [UJointAxes; 3] {
    presets::PARK_AZIMUTHS_DEG.map(|t| {
        let UJointAxes { u1, u2 } = UJointAxes::park(t.to_radians());
        let tilt = Rotation3::from_axis_angle(&Unit::new_normalize(u2), 0.0)
            * Rotation3::from_axis_angle(&Unit::new_normalize(u1), gamma_deg.to_radians());
        UJointAxes {
            u1: tilt * u1,
            u2: tilt * u2,
        }
    })
}

impl Objective for UpuSigmaMin {
    fn dimension(&self) -> usize {
        6
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn value(&self, v: &[f64]) -> Result<f64, ObjectiveError> {
        let mut r = [0.0];
        self.residuals(v, &mut r)?;
        Ok(r[0] * r[0])
    }
}

impl Residuals for UpuSigmaMin {
    fn n_residuals(&self) -> usize {
        1
    }
    fn residuals(&self, v: &[f64], r: &mut [f64]) -> Result<(), ObjectiveError> {
        let upu = ThreeUpu::new(upu_design())?;
        let [a, b, c] = [v[3], v[4], v[5]].map(f64::to_radians);
        let pose = pose_from_task(&Task::<6>::new(v[0], v[1], v[2], a, b, c)).unwrap();
        let rows = upu.wrench_rows(&pose).map_err(ObjectiveError::from)?;
        r[0] = rows
            .singular_values()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        Ok(())
    }
}

#[test]
fn three_upu_singularity_search_matches_the_library_multistart() {
    let (results, _out) =
        run_study::<TaskResult>("task", &studies().join("three_upu_singularity.toml"));
    let r = results.result;
    let b = |lo, hi| Bounds::new(lo, hi).unwrap();
    let angle = b(-20.0, 20.0);
    let problem = UpuSigmaMin([
        b(-0.05, 0.05),
        b(-0.05, 0.05),
        b(0.0, 0.3),
        angle,
        angle,
        angle,
    ]);
    let best = multistart_levenberg_marquardt(
        &problem,
        Sense::Minimise,
        &Multistart::new(16, 44),
        &LmSettings::default(),
        &Silent,
    )
    .unwrap()
    .best;
    let names = ["x", "y", "z", "rx_deg", "ry_deg", "rz_deg"];
    for (name, v) in names.iter().zip(&best.design) {
        assert!(
            (r.optimum[*name] - v).abs() < 1e-12,
            "{name}: {} vs {v}",
            r.optimum[*name]
        );
    }
    assert!((r.objective - best.value).abs() < 1e-15);
    // A singular pose: the twist most nearly reciprocal to the rows has F = σ_min² by the
    // library's task objective, the rows lose rank and the determinant vanishes.
    let w = &r.wrench_matrix;
    assert!(w.sigma_min < 1e-6, "sigma_min = {}", w.sigma_min);
    assert!((w.most_reciprocal_f - w.sigma_min * w.sigma_min).abs() < 1e-12);
    let chi = Twist::from_vector(Vector6::from(w.most_reciprocal_twist));
    let upu = ThreeUpu::new(upu_design()).unwrap();
    assert!(upu.task_objective(&pose_of(&r), &chi).unwrap() < 1e-12);
    assert!(w.rank < 6 && w.det.abs() < 1e-6);
}

/// The error of `pkm COMMAND` on the study `text` (written to a temporary file).
fn study_error(command: &str, text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let cli = Cli::parse_from([
        "pkm",
        command,
        path.to_str().unwrap(),
        "--out",
        dir.path().join("out").to_str().unwrap(),
        "--quiet",
    ]);
    let e = run(&cli).expect_err("the study is invalid").to_string();
    assert!(!dir.path().join("out/results.json").exists(), "{e}");
    e
}

/// `text` with the first `from` replaced by `to` (which must occur).
fn edited(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(studies().join(name)).unwrap();
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

/// The 1-based line of the first line of `text` that starts with `prefix`.
fn line_of(text: &str, prefix: &str) -> usize {
    text.lines().position(|l| l.starts_with(prefix)).unwrap() + 1
}

#[test]
fn bad_study_files_are_refused_at_their_line_with_the_expected_unit() {
    // An unknown key, at its line.
    let text = edited("tsai_volume_optimize.toml", "columns = 128", "colums = 128");
    let e = study_error("optimize", &text);
    assert!(
        e.contains(&format!(":{}:", line_of(&text, "colums"))) && e.contains("colums"),
        "{e}"
    );
    // A variable the mechanism does not have.
    let text = edited(
        "tsai_volume_optimize.toml",
        "c_minus_r = [0.0, 0.3]",
        "c = [0.0, 0.3]",
    );
    let e = study_error("optimize", &text);
    assert!(
        e.contains("unknown design variable `c`") && e.contains("phi2_deg"),
        "{e}"
    );
    // A twist point that is not a length.
    let text = edited(
        "stewart_task_synthesis.toml",
        "point = [0.02, 0.03, 0.06]",
        "point = [0.02, \"a\", 0.06]",
    );
    let e = study_error("task", &text);
    assert!(
        e.contains(&format!(":{}:", line_of(&text, "point"))) && e.contains("metres"),
        "{e}"
    );
    // A twist with neither form.
    let text = edited(
        "stewart_task_synthesis.toml",
        "point = [0.02, 0.03, 0.06]",
        "",
    );
    let e = study_error("task", &text);
    assert!(e.contains("expected either `vector`"), "{e}");
}

/// `results.json` of `pkm COMMAND STUDY --threads N`.
fn results_with_threads(command: &str, study: &str, threads: usize) -> String {
    let out = tempfile::tempdir().unwrap();
    let path = studies().join(study);
    let threads = threads.to_string();
    let cli = Cli::parse_from([
        "pkm",
        command,
        path.to_str().unwrap(),
        "--out",
        out.path().to_str().unwrap(),
        "--threads",
        &threads,
        "--quiet",
    ]);
    run(&cli).unwrap();
    std::fs::read_to_string(out.path().join("results.json")).unwrap()
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    for (command, study) in [
        ("task", "stewart_task_synthesis.toml"),
        ("task", "three_upu_singularity.toml"),
        ("optimize", "tsai_volume_optimize.toml"),
    ] {
        let one = results_with_threads(command, study, 1);
        assert_eq!(one, results_with_threads(command, study, 3), "{study}");
    }
}

#[test]
fn a_cancelled_run_stops_without_results() {
    use pkm_cli::Context;
    use pkm_cli::progress::{CancelFlag, Spinner};
    let flag = CancelFlag::default();
    flag.set();
    let out = tempfile::tempdir().unwrap();
    let context = Context {
        out: out.path().to_path_buf(),
        progress: Spinner::hidden(flag),
    };
    let load = |name: &str| studies().join(name);
    let (_, optimize): (_, pkm_study::OptimizeStudy) =
        pkm_cli::study::load_study(&load("tsai_volume_optimize.toml")).unwrap();
    let task = pkm_cli::study::load(&load("three_upu_singularity.toml")).unwrap();
    let optimized = pkm_study::optimize(&optimize, &context.progress);
    assert!(
        matches!(optimized, Err(pkm_study::StudyError::Cancelled)),
        "{optimized:?}"
    );
    let outcomes = [pkm_cli::commands::task::compute(&task, &context).map(|_| ())];
    for outcome in outcomes {
        assert!(
            matches!(outcome, Err(pkm_cli::CliError::Cancelled)),
            "{outcome:?}"
        );
    }
    assert!(!out.path().join("results.json").exists());
}

/// Runs `pkm COMMAND` on `text` written to a temporary study file.
fn run_text<R: DeserializeOwned>(command: &str, text: &str) -> Results<R> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("study.toml");
    std::fs::write(&path, text).unwrap();
    run_study::<R>(command, &path).0
}

#[test]
fn the_largest_three_upu_f_for_a_unit_rotation_is_three() {
    // The constraint couples [0; u_i] contribute (u_i·ω)² ≤ 1 each and the legs of a zero-pitch
    // twist through the apex nothing, so F ≤ 3|ω|² = 3, reached with every couple along ω.
    let text = "[mechanism.three_upu]\nbase_radius = 0.2\nplatform_radius = 0.1\n\
        [task]\ngoal = \"maximise\"\npose = { position = [0.0, 0.0, 0.1] }\n\
        [task.variables]\nbeta1_deg = [-90, 90]\ngamma1_deg = [-90, 90]\nbeta2_deg = [-90, 90]\n\
        gamma2_deg = [-90, 90]\nbeta3_deg = [-90, 90]\ngamma3_deg = [-90, 90]\n\
        [[task.twists]]\naxis = [-0.94, 0.35, 0.0]\npoint = [0.0, 0.0, 0.2]\n\
        [task.starts]\ncount = 8\nseed = 18\n";
    let r = run_text::<TaskResult>("task", text).result;
    assert!((r.objective - 3.0).abs() < 1e-9, "{}", r.objective);
    assert!(r.optimality.free_gradient_max < 1e-6);
}
