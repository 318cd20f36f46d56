//! End-to-end runs of the `optimize` and `task` study files of `examples/studies/` through the
//! command: files written, errors at their line, thread counts, cancellation (the science of
//! both studies is checked in `pkm-study`'s tests).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use clap::Parser;
use pkm_cli::output::Results;
use pkm_cli::{Cli, run};
use pkm_study::TaskResult;
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

#[test]
fn task_writes_its_starts_its_drawing_and_its_results() {
    let (results, out) =
        run_study::<TaskResult>("task", &studies().join("three_upu_singularity.toml"));
    let files = [
        "starts.csv",
        "starts.svg",
        "robot.svg",
        "robot.csv",
        "results.json",
    ];
    for file in files {
        assert!(out.path().join(file).is_file(), "{file}");
    }
    let csv = std::fs::read_to_string(out.path().join("starts.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + results.result.starts);
    assert!(csv.starts_with("start,start_x,"), "{csv}");
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
    let (_, task): (_, pkm_study::TaskStudy) =
        pkm_cli::study::load_study(&load("three_upu_singularity.toml")).unwrap();
    let optimized = pkm_study::optimize(&optimize, &context.progress);
    assert!(
        matches!(optimized, Err(pkm_study::StudyError::Cancelled)),
        "{optimized:?}"
    );
    let tasked = pkm_study::task(&task, &context.progress);
    assert!(
        matches!(tasked, Err(pkm_study::StudyError::Cancelled)),
        "{tasked:?}"
    );
    assert!(!out.path().join("results.json").exists());
}
