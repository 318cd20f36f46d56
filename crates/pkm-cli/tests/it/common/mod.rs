//! Running the `pkm` binary in tests.
#![allow(
    dead_code,
    unreachable_pub,
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic
)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// A study file of `tests/studies/`.
pub fn study(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/studies")
        .join(name)
}

/// An example study of `examples/studies/` at the workspace root.
pub fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/studies")
        .join(name)
}

/// Output of one run of the binary.
#[derive(Debug)]
pub struct Run {
    pub ok: bool,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `pkm ARGS… -q`.
pub fn pkm(args: &[&str]) -> Run {
    let output = Command::new(env!("CARGO_BIN_EXE_pkm"))
        .args(args)
        .arg("-q")
        .output()
        .expect("the pkm binary runs");
    Run {
        ok: output.status.success(),
        stdout: String::from_utf8_lossy(&output.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
    }
}

/// Runs `pkm COMMAND FILE --out DIR EXTRA…`, asserts success and returns `results.json`.
pub fn run_study(command: &str, file: &Path, out: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        command,
        file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let run = pkm(&args);
    assert!(run.ok, "pkm {args:?} failed: {}", run.stderr);
    let text = std::fs::read_to_string(out.join("results.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Rows of a CSV file written by pkm (no quoted commas in numeric columns).
pub fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (header, rows)
}

/// `a` and `b` agree to `rel` relative (and 1e-300 absolute).
pub fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + 1e-300
}
