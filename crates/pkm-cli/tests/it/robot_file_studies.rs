//! `[mechanism.robot_file] file = "..."` in the `pkm` command: the robot file is read relative to
//! the study file, the study gives the numbers of the hand-written table, and errors in the
//! robot file are placed at its line and column.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{example, pkm, run_study};
use std::path::Path;

#[test]
fn the_example_robot_file_study_matches_the_tsai_table() {
    let dir = tempfile::tempdir().unwrap();
    let from_file = run_study(
        "workspace",
        &example("robot_file_workspace.toml"),
        &dir.path().join("file"),
        &[],
    );
    // The same study on the hand-written table (Stamper's maximum-GCI design).
    let text = std::fs::read_to_string(example("robot_file_workspace.toml")).unwrap();
    let text = text.replace(
        "[mechanism.robot_file]\nfile = \"../robots/tsai.toml\"",
        "[mechanism.tsai]\na = 0.44\nb = 0.56\n#",
    );
    let hand_file = dir.path().join("tsai.toml");
    std::fs::write(&hand_file, text).unwrap();
    let hand = run_study("workspace", &hand_file, &dir.path().join("hand"), &[]);
    let (a, b) = (
        &hand["result"]["estimate"],
        &from_file["result"]["estimate"],
    );
    assert!(a["n_inside"].as_u64().unwrap() > 1000);
    assert_eq!(a["n_inside"], b["n_inside"]);
    for key in ["volume", "eta", "gci"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!((x - y).abs() <= 1e-9 * x.abs(), "{key}: {x} vs {y}");
    }
    assert_eq!(from_file["result"]["mechanism"], "robot_file");
}

/// A study in `dir/studies/` naming `dir/robots/robot.toml` with `robot`; returns stderr.
fn rejected(dir: &Path, robot: Option<&str>) -> String {
    std::fs::create_dir_all(dir.join("studies")).unwrap();
    std::fs::create_dir_all(dir.join("robots")).unwrap();
    if let Some(robot) = robot {
        std::fs::write(dir.join("robots/robot.toml"), robot).unwrap();
    }
    let study = "[mechanism.robot_file]\nfile = \"../robots/robot.toml\"\n\
                 [sampling]\npoints = 64\n\
                 region = { hemisphere = { center = [0.0, 0.0, 0.0], radius = 1.0 } }\n";
    let file = dir.join("studies/study.toml");
    std::fs::write(&file, study).unwrap();
    let out = dir.join("out");
    let run = pkm(&[
        "workspace",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!run.ok);
    assert!(!out.join("results.json").exists());
    run.stderr
}

#[test]
fn a_bad_robot_file_is_reported_at_its_line_and_column() {
    let tsai = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/robots/tsai.toml"),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();

    // A zero axis on line 9: the model's check, at its key in the robot file.
    let zero_axis = tsai.replacen("axis = [0.0, -1.0, 0.0]", "axis = [0.0, 0.0, 0.0]", 1);
    let line = zero_axis
        .lines()
        .position(|l| l.contains("[0.0, 0.0, 0.0]"))
        .unwrap()
        + 1;
    let column = zero_axis
        .lines()
        .nth(line - 1)
        .unwrap()
        .find("[0.0, 0.0, 0.0]")
        .unwrap()
        + 1;
    let stderr = rejected(dir.path(), Some(&zero_axis));
    let position = format!("robot.toml:{line}:{column}:");
    assert!(
        stderr.contains(&position),
        "expected {position} in {stderr}"
    );
    assert!(
        stderr.contains("mechanism.robot_file.legs[0].joints[0].axis"),
        "{stderr}"
    );

    // A name that is not a parameter: at the number it stands for.
    let unknown = tsai.replacen("offset = 0.0", "offset = \"home_angle\"", 1);
    let line = unknown
        .lines()
        .position(|l| l.contains("home_angle"))
        .unwrap()
        + 1;
    let column = unknown
        .lines()
        .nth(line - 1)
        .unwrap()
        .find("\"home_angle\"")
        .unwrap()
        + 1;
    let stderr = rejected(dir.path(), Some(&unknown));
    let position = format!("robot.toml:{line}:{column}:");
    assert!(
        stderr.contains(&position),
        "expected {position} in {stderr}"
    );
    assert!(stderr.contains("home_angle"), "{stderr}");

    // Not TOML at all: the parser's position in the robot file.
    let stderr = rejected(dir.path(), Some("name = \"3-RUU\"\ntask = [\"x\",\n"));
    assert!(stderr.contains("robot.toml:2:13:"), "{stderr}");

    // No such file: at `file` in the study.
    std::fs::remove_file(dir.path().join("robots/robot.toml")).unwrap();
    let stderr = rejected(dir.path(), None);
    assert!(stderr.contains("study.toml:2:8:"), "{stderr}");
    assert!(stderr.contains("cannot read"), "{stderr}");
}
