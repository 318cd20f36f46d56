//! Bad study files get an error that names the file, the line and what was expected (with
//! units), and the command fails without writing results.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::pkm;

const WORKSPACE: &str = r#"title = "bad-file probe"

[mechanism.rotary_delta]
base_radius = 0.15
plate_offset = 0.04
arm = 0.2
forearm = 0.45

[constraints]
below_z = 0.0

[sampling]
points = 256
replicates = 2
"#;

const SWEEP: &str = r#"[mechanism.linear_delta]
l1_over_yr = 2.0
ya_over_yr = 0.0
zr_over_yr = 0.0
l2_over_l1 = 0.63

[[variables]]
name = "l1_over_yr"
from = 1.4
to = 2.0
step = 0.2

[sweep]
objective = { eta2 = 1.0 }
"#;

/// Runs `command` on `text`, expects failure with `file:line:` and every one of `expected` in
/// the message, and no results.json.
fn rejects(command: &str, text: &str, line: usize, expected: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("out");
    let run = pkm(&[
        command,
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!run.ok, "accepted:\n{text}");
    let position = format!("bad.toml:{line}:");
    assert!(
        run.stderr.contains(&position),
        "expected {position} in: {}",
        run.stderr
    );
    for e in expected {
        assert!(run.stderr.contains(e), "expected `{e}` in: {}", run.stderr);
    }
    assert!(!out.join("results.json").exists());
}

fn replace(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

#[test]
fn the_probe_itself_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("ok.toml");
    std::fs::write(&file, WORKSPACE).unwrap();
    let out = dir.path().join("out");
    let run = pkm(&[
        "workspace",
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.ok, "{}", run.stderr);
    assert!(out.join("results.json").exists());
}

#[test]
fn unknown_keys_are_rejected_at_their_line() {
    rejects(
        "workspace",
        &replace(WORKSPACE, "arm = 0.2", "arm = 0.2\ncolour = \"red\""),
        7,
        &["unknown field `colour`"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "[sampling]", "[sampling]\nsamples = 3"),
        13,
        &["unknown field `samples`"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "rotary_delta", "rotary_detla"),
        3,
        &["unknown variant `rotary_detla`"],
    );
}

#[test]
fn wrong_types_name_the_expected_unit() {
    rejects(
        "workspace",
        &replace(WORKSPACE, "arm = 0.2", "arm = \"long\""),
        6,
        &["length in metres"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "points = 256", "points = 2.5"),
        13,
        &["u64"],
    );
}

#[test]
fn missing_fields_are_named() {
    rejects(
        "workspace",
        &replace(WORKSPACE, "forearm = 0.45\n", ""),
        3,
        &["missing field `forearm`"],
    );
}

#[test]
fn nan_and_negative_lengths_are_rejected() {
    rejects(
        "workspace",
        &replace(WORKSPACE, "arm = 0.2", "arm = nan"),
        6,
        &["NaN", "metres", "> 0"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "arm = 0.2", "arm = -0.2"),
        6,
        &["metres", "> 0"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "below_z = 0.0", "leg_clearance = -0.01"),
        10,
        &["metres", ">= 0"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "below_z = 0.0", "joint_range_deg = [90, -40]"),
        10,
        &["degrees", "lower <= upper"],
    );
    rejects(
        "workspace",
        &replace(WORKSPACE, "below_z = 0.0", "passive_cone_deg = 200"),
        10,
        &["degrees"],
    );
}

#[test]
fn constraints_that_do_not_fit_the_mechanism_are_rejected() {
    let tsai = WORKSPACE.replace(
        "[mechanism.rotary_delta]\nbase_radius = 0.15\nplate_offset = 0.04\narm = 0.2\nforearm = 0.45",
        "[mechanism.tsai]\na = 0.44\nb = 0.56\n\n",
    );
    rejects(
        "workspace",
        &replace(&tsai, "below_z = 0.0", "passive_cone_deg = 30"),
        9,
        &["[constraints]"],
    );
    let degrees_on_rails = SWEEP.replace(
        "[[variables]]",
        "[constraints]\njoint_range_deg = [0, 1]\n\n[[variables]]",
    );
    rejects("sweep", &degrees_on_rails, 7, &["prismatic", "joint_range"]);
}

#[test]
fn grid_errors_point_at_the_variable() {
    rejects(
        "sweep",
        &replace(SWEEP, "name = \"l1_over_yr\"", "name = \"l1\""),
        8,
        &["not a design variable", "l1_over_yr"],
    );
    rejects(
        "sweep",
        &replace(SWEEP, "step = 0.2", "step = -0.2"),
        11,
        &["step"],
    );
    rejects(
        "sweep",
        &replace(SWEEP, "step = 0.2", "steps = 3\nstep = 0.2"),
        8,
        &["exactly one of step or steps"],
    );
    rejects(
        "sweep",
        &replace(SWEEP, "{ eta2 = 1.0 }", "{ gci = 1.0 }"),
        14,
        &["[sampling]"],
    );
    rejects(
        "sweep",
        &replace(SWEEP, "{ eta2 = 1.0 }", "{ eta3 = 1.0 }"),
        14,
        &["unknown variant `eta3`"],
    );
    rejects(
        "pareto",
        &format!("{SWEEP}\n[pareto]\nobjectives = [\"eta1\"]\n"),
        17,
        &["two or more"],
    );
}

#[test]
fn bad_shards_are_refused_by_the_argument_parser() {
    for shard in ["0/3", "4/3", "a/3", "3"] {
        let run = pkm(&["sweep", "x.toml", "--shard", shard]);
        assert!(
            !run.ok && run.stderr.contains("I/N"),
            "{shard}: {}",
            run.stderr
        );
    }
}

#[test]
fn hostile_check_steps_are_refused_before_any_start_runs() {
    let text = std::fs::read_to_string(common::example("tsai_volume_optimize.toml")).unwrap();
    for step in ["1e300", "0.9", "1e-300", "5e-324", "0.0", "-1e-2", "nan"] {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("bad.toml");
        let hostile = replace(&text, "check_step = 1e-2", &format!("check_step = {step}"));
        std::fs::write(&file, hostile).unwrap();
        let out = dir.path().join("out");
        let run = pkm(&[
            "optimize",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!run.ok, "check_step = {step} accepted");
        assert!(
            run.stderr.contains("check_step") && !run.stderr.contains("panicked"),
            "{step}: {}",
            run.stderr
        );
        assert!(!out.join("results.json").exists());
    }
}
