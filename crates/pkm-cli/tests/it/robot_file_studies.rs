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

/// The path of `examples/robots/<name>`.
fn robot_path(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/robots")
        .join(name)
}

#[test]
fn a_robot_file_study_draws_the_robot_and_needs_no_region() {
    let dir = tempfile::tempdir().unwrap();
    // The Linear Delta's carriages have no limits: the study gives its region.
    let delta = format!(
        "[mechanism.robot_file]\nfile = {:?}\n[sampling]\npoints = 2048\n\
         region = {{ box = {{ lower = [-0.3, -0.25, -0.35], upper = [0.3, 0.25, 0.0] }} }}\n",
        robot_path("linear_delta.toml").to_str().unwrap()
    );
    // The Tsai platform's reach region is the robot file's own bound.
    let tsai = format!(
        "[mechanism.robot_file]\nfile = {:?}\n[sampling]\npoints = 2048\n",
        robot_path("tsai.toml").to_str().unwrap()
    );
    for (name, study) in [("delta", delta), ("tsai", tsai)] {
        let file = dir.path().join(format!("{name}.toml"));
        std::fs::write(&file, study).unwrap();
        let out = dir.path().join(name);
        let run = pkm(&[
            "workspace",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(run.ok, "{name}: {}", run.stderr);
        let report = format!("{}{}", run.stdout, run.stderr);
        assert!(!report.contains("no drawing"), "{name}: {report}");
        let svg = std::fs::read_to_string(out.join("robot.svg")).unwrap();
        assert!(svg.contains("<svg"), "{name}");
        let results: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap())
                .unwrap();
        assert!(
            results["files"]
                .as_array()
                .unwrap()
                .iter()
                .any(|f| f == "robot.svg")
        );
        assert!(
            results["result"]["estimate"]["n_inside"].as_u64().unwrap() > 0,
            "{name}"
        );
    }
}

#[test]
fn working_modes_go_beside_a_named_robot_file() {
    let dir = tempfile::tempdir().unwrap();
    let study = |modes: &str| {
        format!(
            "[mechanism.robot_file]\nfile = {:?}\nmodes = {modes}\n[sampling]\npoints = 1024\n",
            robot_path("tsai.toml").to_str().unwrap()
        )
    };
    let run = |name: &str, modes: &str| {
        let file = dir.path().join(format!("{name}.toml"));
        std::fs::write(&file, study(modes)).unwrap();
        let out = dir.path().join(name);
        pkm(&[
            "workspace",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let all = run("all", r#"["home", "all"]"#);
    assert!(all.ok, "{}", all.stderr);
    // A bad label: at its place in the study file (line 3), not in the robot file.
    let bad = run("bad", r#"["home", "+-"]"#);
    assert!(!bad.ok);
    assert!(bad.stderr.contains("bad.toml:3:"), "{}", bad.stderr);
    assert!(
        bad.stderr.contains("mechanism.robot_file.modes[1]"),
        "{}",
        bad.stderr
    );
}

#[test]
fn results_json_echoes_the_robot_file_and_shards_merge_without_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("studies")).unwrap();
    std::fs::create_dir_all(dir.path().join("robots")).unwrap();
    // The Tsai platform with its arms' zero angle a design variable (the actuator offset).
    let robot = std::fs::read_to_string(robot_path("tsai.toml"))
        .unwrap()
        .replace("offset = 0.0", "offset = \"arm_zero_deg\"")
        .replace("[home]", "[parameters]\narm_zero_deg = 0.0\n\n[home]");
    std::fs::write(dir.path().join("robots/robot.toml"), &robot).unwrap();
    let study = "[mechanism.robot_file]\nfile = \"../robots/robot.toml\"\n\
                 [constraints]\njoint_range_deg = [-20.0, 80.0]\n\
                 [sampling]\nseed = 3\npoints = 1024\n\
                 region = { hemisphere = { center = [0.0, 0.0, 0.0], radius = 1.0 } }\n\
                 [[variables]]\nname = \"arm_zero_deg\"\nfrom = 0.0\nto = 20.0\nsteps = 3\n\
                 [sweep]\nobjective = { gci = 1.0 }\n";
    let file = dir.path().join("studies/sweep.toml");
    std::fs::write(&file, study).unwrap();
    let out = |name: &str| dir.path().join(name);
    let whole = run_study("sweep", &file, &out("whole"), &[]);
    let echo = &whole["study"]["robot_file"];
    assert_eq!(echo["text"].as_str().unwrap(), robot);
    assert!(
        echo["file"].as_str().unwrap().ends_with("robot.toml"),
        "{echo}"
    );
    for shard in ["1/2", "2/2"] {
        let name = format!("shard{}", &shard[..1]);
        run_study("sweep", &file, &out(&name), &["--shard", shard]);
    }
    // The merge reads the robot file from the shards' results.json, not from the disk.
    std::fs::remove_file(dir.path().join("robots/robot.toml")).unwrap();
    let merge = pkm(&[
        "merge",
        out("shard1").to_str().unwrap(),
        out("shard2").to_str().unwrap(),
        "--out",
        out("merged").to_str().unwrap(),
    ]);
    assert!(merge.ok, "{}", merge.stderr);
    let merged: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out("merged").join("results.json")).unwrap())
            .unwrap();
    assert_eq!(merged["result"], whole["result"]);
    assert_eq!(merged["study"]["robot_file"], whole["study"]["robot_file"]);
    // A study without a named robot file echoes none.
    let plain = run_study(
        "workspace",
        &example("robot_file_workspace.toml"),
        &out("plain"),
        &[],
    );
    assert!(
        plain["study"]["robot_file"]["text"]
            .as_str()
            .unwrap()
            .contains("3-RUU")
    );
    let tsai = run_study(
        "workspace",
        &common::study("three_upu_workspace_quick.toml"),
        &out("upu"),
        &[],
    );
    assert!(tsai["study"].get("robot_file").is_none());
}

#[test]
fn a_json_study_file_runs_as_its_toml_and_reads_its_robot_file_relative_to_it() {
    let dir = tempfile::tempdir().unwrap();
    let toml_study = example("robot_file_workspace.toml");
    let document: toml::Table =
        toml::from_str(&std::fs::read_to_string(&toml_study).unwrap()).unwrap();
    // The same layout as examples/: `../robots/tsai.toml` relative to the study.
    std::fs::create_dir_all(dir.path().join("robots")).unwrap();
    std::fs::create_dir_all(dir.path().join("studies")).unwrap();
    let robot = toml_study.with_file_name("../robots/tsai.toml");
    std::fs::copy(&robot, dir.path().join("robots/tsai.toml")).unwrap();
    let json_study = dir.path().join("studies/study.json");
    std::fs::write(&json_study, serde_json::to_string(&document).unwrap()).unwrap();
    let from_json = run_study("workspace", &json_study, &dir.path().join("json"), &[]);
    let from_toml = run_study("workspace", &toml_study, &dir.path().join("toml"), &[]);
    assert_eq!(from_json["result"], from_toml["result"]);
    assert_eq!(
        from_json["study"]["robot_file"]["text"],
        from_toml["study"]["robot_file"]["text"]
    );
    // A JSON error names the file; a schema error its key path.
    let bad = dir.path().join("bad.json");
    std::fs::write(&bad, "{\"mechanism\": {\"tsai\": {\"a\": \"x\"}}}").unwrap();
    let run = pkm(&[
        "workspace",
        bad.to_str().unwrap(),
        "--out",
        dir.path().join("bad").to_str().unwrap(),
    ]);
    assert!(!run.ok);
    assert!(run.stderr.contains("mechanism.tsai.a"), "{}", run.stderr);
}

/// `pkm urdf`: the Stewart–Gough file as URDF (one actuated `_mot` joint per leg, a link of
/// its own per body) and its five 6-D closures; a file that does not parse is refused with its
/// line and column. (The export's geometry is checked in `pkm-robot-file`: the tree closes its
/// loops at random poses.)
#[test]
fn a_robot_file_exports_to_urdf_with_its_closures() {
    let out = tempfile::tempdir().unwrap();
    let robot =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/robots/stewart_gough.toml");
    let dir = out.path().join("urdf");
    let run = pkm(&[
        "urdf",
        robot.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    let urdf = std::fs::read_to_string(dir.join("robot.urdf")).unwrap();
    assert_eq!(urdf.matches("_mot\" type=\"prismatic\"").count(), 6);
    assert_eq!(urdf.matches("<inertial>").count(), 13);
    let closures = std::fs::read_to_string(dir.join("closures.yaml")).unwrap();
    assert!(
        closures.contains("type: [6D, 6D, 6D, 6D, 6D]"),
        "{closures}"
    );
    let bad = out.path().join("bad.toml");
    std::fs::write(&bad, "name = \"6-UPS\"\ntask = [\"x\"\n").unwrap();
    let run = pkm(&[
        "urdf",
        bad.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!run.ok && run.stderr.contains("line"), "{}", run.stderr);
}

/// `pkm mjcf`: the Stewart–Gough file as MJCF (a slide motor per leg, five legs closed on the
/// platform by `connect` at their ball centres, the leg carrying the platform keeping its
/// ball); a file that does not parse is refused with its line and column. (The export's
/// geometry is checked in `pkm-robot-file`: the loops close at random poses.)
#[test]
fn a_robot_file_exports_to_mjcf() {
    let out = tempfile::tempdir().unwrap();
    let robot =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/robots/stewart_gough.toml");
    let dir = out.path().join("mjcf");
    let run = pkm(&[
        "mjcf",
        robot.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    let mjcf = std::fs::read_to_string(dir.join("robot.xml")).unwrap();
    assert_eq!(mjcf.matches("<motor ").count(), 6, "{mjcf}");
    assert_eq!(mjcf.matches("type=\"slide\"").count(), 6);
    assert_eq!(mjcf.matches("<connect ").count(), 5);
    assert_eq!(mjcf.matches("type=\"ball\"").count(), 1);
    let bad = out.path().join("bad.toml");
    std::fs::write(&bad, "name = \"6-UPS\"\ntask = [\"x\"\n").unwrap();
    let run = pkm(&[
        "mjcf",
        bad.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!run.ok && run.stderr.contains("line"), "{}", run.stderr);
    // A refused value at its line and column, for both exports.
    let five_bar = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/robots/five_bar.toml"),
    )
    .unwrap();
    let line = five_bar
        .lines()
        .position(|l| l.contains("{ mass = 0.3,"))
        .unwrap()
        + 1;
    std::fs::write(
        &bad,
        five_bar.replacen("{ mass = 0.3,", "{ mass = -0.3,", 1),
    )
    .unwrap();
    for command in ["mjcf", "urdf"] {
        let run = pkm(&[
            command,
            bad.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ]);
        let at = format!("bad.toml:{line}:12: legs[0].links[0].mass: -0.3");
        assert!(
            !run.ok && run.stderr.contains(&at),
            "{command}: {}",
            run.stderr
        );
    }
}
