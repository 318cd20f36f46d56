//! `pkm dynamics` as a command: the CSV trajectory read relative to the study file and handed
//! to the study layer, the files written, errors placed at their line, Ctrl-C. The science is
//! checked in `crates/pkm-study/tests/dynamics.rs`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use clap::Parser;
use pkm_cli::commands::dynamics::Args;
use pkm_cli::output::Results;
use pkm_cli::progress::{CancelFlag, Spinner};
use pkm_cli::{Cli, CliError, Context, Run, run};
use pkm_study::schema::units::Real;
use pkm_study::{DynamicsResult, DynamicsStudy};
use pkm_traits::Silent;
use std::path::{Path, PathBuf};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies")
        .join(name)
}

/// `pkm dynamics STUDY --out OUT --quiet` as `main` runs it.
fn pkm_dynamics(study: &Path, out: &Path) -> Result<(), CliError> {
    let cli = Cli::parse_from([
        "pkm",
        "dynamics",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    run(&cli).map(|_| ())
}

#[test]
fn the_csv_example_is_the_study_layers_run_on_its_rows() {
    let out = tempfile::tempdir().unwrap();
    let study = example("nuwar_dynamics_csv.toml");
    pkm_dynamics(&study, out.path()).unwrap();
    let text = std::fs::read_to_string(out.path().join("results.json")).unwrap();
    let results: Results<DynamicsResult> = serde_json::from_str(&text).unwrap();
    assert_eq!(results.command, "dynamics");
    assert_eq!(
        results.files,
        [
            "torques.csv",
            "torques.svg",
            "retrace.csv",
            "retrace.svg",
            "robot.svg",
            "robot.csv"
        ]
    );
    for file in &results.files {
        assert!(out.path().join(file).is_file(), "{file} listed but missing");
    }
    // The same study with the CSV's rows handed in directly.
    let mut direct: DynamicsStudy =
        pkm_study::from_toml_str(&std::fs::read_to_string(&study).unwrap()).unwrap();
    let csv = std::fs::read_to_string(example("nuwar_pick_and_place.csv")).unwrap();
    let rows = csv.lines().skip(1).map(|line| {
        let v: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        v.into_iter().map(Real).collect::<Vec<_>>()
    });
    direct.trajectory.csv = None;
    direct.trajectory.positions = Some(rows.collect());
    let expected = pkm_study::dynamics(&direct, &Silent).unwrap().result;
    assert_eq!(results.result, expected);
    let torques = std::fs::read_to_string(out.path().join("torques.csv")).unwrap();
    assert_eq!(torques.lines().count(), expected.samples + 1);
}

/// The error of `pkm dynamics` on the example study edited from `from` to `to`, with the
/// 1-based line of `to` in the edited text; no results are written.
fn refusal(from: &str, to: &str, dir: &Path) -> (String, usize) {
    let text = std::fs::read_to_string(example("nuwar_dynamics_csv.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    // The study is written elsewhere: its CSV, when not edited, is the example's.
    let csv = format!(
        "{:?}",
        example("nuwar_pick_and_place.csv").display().to_string()
    );
    let text = text
        .replacen(from, to, 1)
        .replacen("\"nuwar_pick_and_place.csv\"", &csv, 1);
    let path = dir.join("bad.toml");
    std::fs::write(&path, &text).unwrap();
    let out = dir.join("out");
    let e = pkm_dynamics(&path, &out).expect_err("the study is invalid");
    assert!(!out.join("results.json").exists(), "{e}");
    let first = to.lines().next().unwrap_or(to);
    let line = text.lines().position(|l| l.starts_with(first)).unwrap() + 1;
    (e.to_string(), line)
}

#[test]
fn bad_masses_and_csv_rows_are_refused_at_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let (e, line) = refusal("plate = 0.2807", "plate = -0.2807", dir.path());
    assert!(
        e.contains(&format!(":{line}:")) && e.contains("masses.plate"),
        "{e}"
    );
    assert!(e.contains("m_p"), "{e}");
    // A row that is not four numbers: at the `csv` key, naming the CSV line.
    let csv = dir.path().join("t.csv");
    std::fs::write(&csv, "t,x,y,z\n0,0,-0.2,-0.9\n0.002,0,-0.2\n").unwrap();
    let to = format!("csv = {:?}", csv.display().to_string());
    let (e, line) = refusal("csv = \"nuwar_pick_and_place.csv\"", &to, dir.path());
    assert!(
        e.contains(&format!(":{line}:")) && e.contains("line 3: 3 values"),
        "{e}"
    );
    // Unequal steps, found by the study layer, still name the CSV line.
    std::fs::write(
        &csv,
        "t,x,y,z\n0,0,-0.2,-0.9\n0.002,0,-0.2,-0.9\n\n0.005,0,-0.2,-0.9\n",
    )
    .unwrap();
    let (e, line) = refusal("csv = \"nuwar_pick_and_place.csv\"", &to, dir.path());
    assert!(
        e.contains(&format!(":{line}:")) && e.contains("t.csv: line 5: t = 0.005 s"),
        "{e}"
    );
    // A file that does not exist, relative to the study file.
    let (e, line) = refusal(
        "csv = \"nuwar_pick_and_place.csv\"",
        "csv = \"missing.csv\"",
        dir.path(),
    );
    assert!(
        e.contains(&format!(":{line}:")) && e.contains("missing.csv"),
        "{e}"
    );
    // A retrace setting, before the inverse dynamics run.
    let (e, line) = refusal("rtol = 1e-8", "rtol = 0.0", dir.path());
    assert!(
        e.contains(&format!(":{line}:")) && e.contains("dynamics.forward.rtol"),
        "{e}"
    );
}

#[test]
fn a_cancelled_run_writes_no_results() {
    let flag = CancelFlag::default();
    flag.set();
    let out = tempfile::tempdir().unwrap();
    let context = Context {
        out: out.path().to_path_buf(),
        progress: Spinner::hidden(flag),
    };
    let args = Args {
        file: example("nuwar_dynamics_csv.toml"),
    };
    let outcome = args.run(&context);
    assert!(matches!(outcome, Err(CliError::Cancelled)), "{outcome:?}");
    assert!(!out.path().join("results.json").exists());
}
