//! `pkm assembly` as a command: the files it writes, and an error placed at its line. The
//! science is checked in `crates/pkm-study/tests/it/assembly.rs`.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use clap::Parser;
use pkm_cli::output::Results;
use pkm_cli::{Cli, CliError, run};
use pkm_study::AssemblyResult;
use std::path::Path;

/// `pkm assembly STUDY --out OUT --quiet` as `main` runs it.
fn pkm_assembly(study: &Path, out: &Path) -> Result<(), CliError> {
    let cli = Cli::parse_from([
        "pkm",
        "assembly",
        study.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    run(&cli).map(|_| ())
}

fn robots() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/robots")
        .display()
        .to_string()
}

#[test]
fn the_command_writes_the_modes_and_the_robot() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("modes.toml");
    let text = format!(
        "[mechanism.robot_file]\nfile = \"{}/agile_eye.toml\"\n[assembly]\nactuators = [[0.1, \
         0.2, 0.3]]\n",
        robots()
    );
    std::fs::write(&study, text).unwrap();
    let out = dir.path().join("out");
    pkm_assembly(&study, &out).unwrap();
    let results: Results<AssemblyResult> =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert_eq!(results.command, "assembly");
    assert_eq!(
        results.files,
        ["modes.csv", "modes.svg", "robot.svg", "robot.csv"]
    );
    for file in &results.files {
        assert!(out.join(file).is_file(), "{file} listed but missing");
    }
    let query = &results.result.queries[0];
    let csv = std::fs::read_to_string(out.join("modes.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + query.modes.len());
    assert_eq!(query.homotopy.as_ref().unwrap().generic_solutions, 8);
}

#[test]
fn a_refused_query_is_placed_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("modes.toml");
    let text = format!(
        "[mechanism.robot_file]\nfile = \"{}/agile_eye.toml\"\n\n[assembly]\nactuators = [\n  \
         [0.1, 0.2, 0.3],\n  [0.1, 0.2],\n]\n",
        robots()
    );
    std::fs::write(&study, text).unwrap();
    let error = pkm_assembly(&study, &dir.path().join("out"))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("modes.toml:7:") && error.contains("assembly.actuators[1]: 2 values for 3"),
        "{error}"
    );
}
