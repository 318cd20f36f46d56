//! Workspace studies of robot files in their own task space (`[task_space]`): every example
//! runs through the command, and every setting that does not fit the robot is refused at its
//! key path before any computation.

use crate::common::{csv, example, pkm, run_study};
use serde_json::Value;

fn number(v: &Value, path: &[&str]) -> f64 {
    let mut v = v;
    for key in path {
        v = &v[*key];
    }
    v.as_f64()
        .unwrap_or_else(|| panic!("{path:?} is a number: {v}"))
}

/// Runs an example study and checks what every task-space result holds.
fn run_example(name: &str, kind: &str, unit: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let json = run_study("workspace", &example(name), dir.path(), &[]);
    let r = &json["result"];
    let t = &r["task_space"];
    assert_eq!(t["kind"], kind, "{name}");
    assert_eq!(t["unit"], unit, "{name}");
    let (w, se) = (
        number(r, &["estimate", "volume"]),
        number(r, &["estimate", "volume_se"]),
    );
    let inside = number(r, &["estimate", "n_inside"]);
    let all = number(r, &["estimate", "n_points"]);
    assert!(
        0.0 < inside && inside < all,
        "{name}: {inside} of {all} inside"
    );
    assert!(
        w > 0.0 && w < number(r, &["domain_volume"]) && se < 0.02 * w,
        "{name}: {w} ± {se}"
    );
    let gci = number(r, &["estimate", "gci"]);
    assert!(0.0 < gci && gci <= 1.0, "{name}: GCI {gci}");
    if let Some(sf) = t.get("singularity_free") {
        let connected = number(sf, &["volume_connected"]);
        let above = number(sf, &["volume_above_margin"]);
        assert!(
            0.0 < connected && connected <= above + 1e-12,
            "{name}: {connected} of {above}"
        );
        // The grid's measure of the workspace with the margin is close to the Monte Carlo one.
        assert!(above <= 1.1 * w, "{name}: {above} against W = {w}");
        if let Some(svg) = sf["svg"].as_str() {
            assert!(dir.path().join(svg).is_file(), "{name}: {svg}");
        }
    }
    json
}

#[test]
fn every_workspace_kind_runs_on_the_example_robots() {
    run_example("three_prs_reachable.toml", "reachable", "m·rad²");
    run_example("exechon_reachable.toml", "reachable", "m·rad²");
    run_example("five_bar_reachable.toml", "reachable", "m²");
    run_example(
        "stewart_gough_constant_orientation.toml",
        "constant_orientation",
        "m³",
    );
    run_example(
        "three_rpr_constant_orientation.toml",
        "constant_orientation",
        "m²",
    );
    run_example("hexa_orientation.toml", "orientation", "rad³");
    run_example("agile_eye_orientation.toml", "orientation", "rad³");
    let dexterous = run_example("stewart_gough_dexterous.toml", "dexterous", "m³");
    let levels = dexterous["result"]["task_space"]["orientation_levels"]
        .as_array()
        .unwrap();
    assert_eq!(levels.len(), 3);
    let volumes: Vec<f64> = levels.iter().map(|l| number(l, &["volume"])).collect();
    // Finer grids hold more orientations: the sets are nested on the same points.
    assert!(volumes.windows(2).all(|w| w[1] <= w[0]), "{volumes:?}");
    let finest = number(&dexterous["result"], &["estimate", "volume"]);
    assert_eq!(finest.to_bits(), volumes[2].to_bits());
    // Every orientation of the set includes rz = 10°, tilt 0 ... and the home orientation: the
    // dexterous workspace lies inside the constant-orientation one at home orientation.
    let dir = tempfile::tempdir().unwrap();
    let home = study_with(
        "stewart_gough_dexterous.toml",
        &[
            ("kind = \"dexterous\"", "kind = \"constant_orientation\""),
            (
                "orientations = { max_tilt_deg = 5.0, torsion_deg = [-5.0, 5.0], levels = 3 }",
                "",
            ),
        ],
        dir.path(),
    );
    let json = run_study("workspace", &home, &dir.path().join("out"), &[]);
    assert!(finest < number(&json["result"], &["estimate", "volume"]));
}

#[test]
fn a_sweep_rates_robot_file_designs_in_their_task_space() {
    let dir = tempfile::tempdir().unwrap();
    let quick = study_with(
        "three_prs_sweep.toml",
        &[("points = 2048", "points = 256")],
        dir.path(),
    );
    let json = run_study("sweep", &quick, &dir.path().join("out"), &[]);
    assert_eq!(json["result"]["nodes"], 5);
    assert_eq!(json["result"]["infeasible"], 0);
    let (header, rows) = csv(&dir.path().join("out/landscape.csv"));
    let column = |name: &str| header.iter().position(|h| h == name).unwrap();
    let node = rows
        .iter()
        .find(|r| r[column("r")] == "0.1")
        .expect("the node r = 0.1");
    // The design of the robot file (r = 0.1 m) has the reachable set of the workspace study
    // on the same points.
    let workspace = study_with(
        "three_prs_reachable.toml",
        &[
            ("points = 4096", "points = 256"),
            (
                "box = { z = [0.3, 0.75], tilt_x_deg = [-45.0, 45.0], tilt_y_deg = [-45.0, 45.0] }",
                "box = { z = [0.2, 0.9], tilt_x_deg = [-60.0, 60.0], tilt_y_deg = [-60.0, 60.0] }",
            ),
            (
                "singularity_free = { min_direct_margin = 0.02, cells = 24 }",
                "",
            ),
        ],
        dir.path(),
    );
    let single = run_study("workspace", &workspace, &dir.path().join("single"), &[]);
    let w = number(&single["result"], &["estimate", "volume"]);
    let swept: f64 = node[column("volume")].parse().unwrap();
    assert_eq!(
        swept.to_bits(),
        w.to_bits(),
        "the node r = 0.1: {swept} against W = {w}"
    );
}

/// The example `name` with each `(from, to)` replaced, written in `dir`, its robot file named
/// by an absolute path.
fn study_with(name: &str, edits: &[(&str, &str)], dir: &std::path::Path) -> std::path::PathBuf {
    let mut text = std::fs::read_to_string(example(name)).unwrap();
    let robots = example("../robots/");
    text = text.replace("\"../robots/", &format!("\"{}/", robots.display()));
    for (from, to) in edits {
        assert!(text.contains(from), "{name} holds {from}");
        text = text.replace(from, to);
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Replacements `(from, to)` in a study's text.
type Edits<'a> = Vec<(&'a str, &'a str)>;

/// Runs `pkm workspace` on the edited example and returns its error message.
fn refused(name: &str, edits: &[(&str, &str)]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = study_with(name, edits, dir.path());
    let run = pkm(&[
        "workspace",
        path.to_str().unwrap(),
        "--out",
        dir.path().join("out").to_str().unwrap(),
    ]);
    assert!(!run.ok, "{name} with {edits:?} is refused");
    assert!(
        !dir.path().join("out/results.json").exists(),
        "no result for a refused study"
    );
    run.stderr
}

#[test]
fn settings_that_do_not_fit_the_robot_are_refused_at_their_key_path() {
    let five_bar = "five_bar_reachable.toml";
    let prs = "three_prs_reachable.toml";
    let sg = "stewart_gough_dexterous.toml";
    let cases: Vec<(&str, Edits<'_>, &str)> = vec![
        // An orientation workspace of a robot whose task has no orientation.
        (
            five_bar,
            vec![("kind = \"reachable\"", "kind = \"orientation\"")],
            "task_space.kind",
        ),
        // A coordinate that is not in the task, an angle in metres, a length in degrees.
        (five_bar, vec![("y = [", "z = [")], "task_space.box.z"),
        (
            prs,
            vec![("tilt_x_deg = [", "tilt_x = [")],
            "task_space.box.tilt_x",
        ),
        (
            prs,
            vec![("z = [0.3, 0.75]", "z_deg = [0.3, 0.75]")],
            "task_space.box.z_deg",
        ),
        // A missing side, an empty side, angles beyond 180°.
        (prs, vec![("z = [0.3, 0.75], ", "")], "task_space.box"),
        (
            prs,
            vec![("z = [0.3, 0.75]", "z = [0.5, 0.5]")],
            "task_space.box.z",
        ),
        (
            prs,
            vec![("tilt_y_deg = [-45.0, 45.0]", "tilt_y_deg = [-45.0, 200.0]")],
            "task_space.box.tilt_y_deg",
        ),
        // A held coordinate that is sampled; a NaN or negative threshold.
        (
            prs,
            vec![("singularity_free", "fixed = { z = 0.4 }\nsingularity_free")],
            "task_space.fixed.z",
        ),
        (
            prs,
            vec![("min_direct_margin = 0.02", "min_direct_margin = nan")],
            "task_space.singularity_free.min_direct_margin",
        ),
        (
            prs,
            vec![("[task_space]", "[task_space]\nmin_direct_margin = -1.0")],
            "task_space.min_direct_margin",
        ),
        // An orientation set that is empty in torsion order or beyond the coordinate range.
        (
            sg,
            vec![("torsion_deg = [-5.0, 5.0]", "torsion_deg = [5.0, -5.0]")],
            "task_space.orientations.torsion_deg",
        ),
        (
            sg,
            vec![("max_tilt_deg = 5.0", "max_tilt_deg = 270.0")],
            "task_space.orientations.max_tilt_deg",
        ),
        (
            sg,
            vec![("levels = 3", "levels = 0")],
            "task_space.orientations.levels",
        ),
        // A dexterous workspace without its set.
        (
            sg,
            vec![(
                "orientations = { max_tilt_deg = 5.0, torsion_deg = [-5.0, 5.0], levels = 3 }",
                "",
            )],
            "task_space.orientations",
        ),
        // Maps: an axis that is not sampled, the same axis twice, a value off its side, a
        // value on the plane, too few cells, an unknown index.
        (
            prs,
            vec![(
                "axes = [\"tilt_x_deg\", \"tilt_y_deg\"]",
                "axes = [\"x\", \"tilt_y_deg\"]",
            )],
            "task_space.maps[0].axes.x",
        ),
        (
            prs,
            vec![(
                "axes = [\"tilt_x_deg\", \"tilt_y_deg\"]",
                "axes = [\"tilt_y_deg\", \"tilt_y_deg\"]",
            )],
            "task_space.maps[0].axes",
        ),
        (
            prs,
            vec![("at = { z = 0.55 }", "at = { z = 0.95 }")],
            "task_space.maps[0].at.z",
        ),
        (
            prs,
            vec![("at = { tilt_y_deg = 0.0 }", "at = { tilt_x_deg = 0.0 }")],
            "task_space.maps[1].at.tilt_x_deg",
        ),
        (
            prs,
            vec![("cells = 48\nindex", "cells = 1\nindex")],
            "task_space.maps[1].cells",
        ),
        (
            prs,
            vec![("index = \"direct_margin\"", "index = \"volume\"")],
            "task_space.maps",
        ),
        // A box whose corners turn beyond 180° (rotation vectors of norm > π).
        (
            "agile_eye_orientation.toml",
            vec![("rx_deg = [-90.0, 90.0]", "rx_deg = [-170.0, 170.0]")],
            "task_space.box",
        ),
        // A region of [sampling] beside the box.
        (
            prs,
            vec![(
                "[sampling]",
                "[sampling]\nregion = { ball = { center = [0.0, 0.0, 0.5], radius = 0.2 } }",
            )],
            "sampling",
        ),
    ];
    for (name, edits, key) in cases {
        let message = refused(name, &edits);
        assert!(
            message.contains(key),
            "{name} {edits:?}: expected {key} in {message}"
        );
    }
    // A robot whose task is not the platform position needs the section.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bare.toml");
    let robot = example("../robots/three_prs.toml");
    std::fs::write(
        &path,
        format!(
            "[mechanism.robot_file]\nfile = {:?}\n",
            robot.display().to_string()
        ),
    )
    .unwrap();
    let run = pkm(&[
        "workspace",
        path.to_str().unwrap(),
        "--out",
        dir.path().join("out").to_str().unwrap(),
    ]);
    assert!(
        !run.ok && run.stderr.contains("task_space"),
        "{}",
        run.stderr
    );
}

/// A task-space sweep split in two shards and merged gives the whole run's result, and a
/// Pareto study of the same designs in their task space finds its front.
#[test]
fn task_space_sweeps_merge_their_shards_and_pareto_fronts_run() {
    let dir = tempfile::tempdir().unwrap();
    let quick = study_with(
        "three_prs_sweep.toml",
        &[
            ("points = 2048", "points = 128"),
            (
                "report = [\"volume\", \"eta\"]",
                "report = [\"volume\", \"eta\"]\n\n[pareto]\nobjectives = [\"volume\", \"gci\"]\nweights = [[1.0, 0.0], [0.0, 1.0]]",
            ),
        ],
        dir.path(),
    );
    let whole = run_study("sweep", &quick, &dir.path().join("whole"), &[]);
    let shards: Vec<std::path::PathBuf> = (1..=2)
        .map(|i| {
            let out = dir.path().join(format!("shard{i}"));
            run_study("sweep", &quick, &out, &["--shard", &format!("{i}/2")]);
            out
        })
        .collect();
    let merged = dir.path().join("merged");
    let run = pkm(&[
        "merge",
        shards[0].to_str().unwrap(),
        shards[1].to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    let text = std::fs::read_to_string(merged.join("results.json")).unwrap();
    let merged: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(merged["result"], whole["result"]);
    let pareto = run_study("pareto", &quick, &dir.path().join("pareto"), &[]);
    assert_eq!(pareto["result"]["nodes"], 5);
    let front = pareto["result"]["front"].as_array().unwrap();
    assert!(!front.is_empty() && front.len() <= 5, "{front:?}");
    assert_eq!(
        pareto["result"]["weighted_optima"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
}
