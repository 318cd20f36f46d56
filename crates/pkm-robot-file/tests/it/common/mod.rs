//! Shared helpers of the integration tests: the example robot files.

#![allow(dead_code)]

use pkm_robot_file::RobotModel;

/// The text of `examples/robots/<name>`.
pub(crate) fn robot_text(name: &str) -> String {
    let path = format!(
        "{}/../../examples/robots/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// `text` without its legs' `links = [ ... ]` arrays (the edits of a test that changes a
/// leg's joints would leave them mismatched).
pub(crate) fn without_links(text: &str) -> String {
    let mut out = String::new();
    let mut skipping = false;
    for line in text.lines() {
        if line.starts_with("links = [") {
            skipping = true;
        } else if skipping && line == "]" {
            skipping = false;
        } else if !skipping {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

/// The model of `examples/robots/<name>`.
pub(crate) fn robot(name: &str) -> RobotModel {
    RobotModel::from_toml(&robot_text(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Every example robot file.
pub(crate) fn all_files() -> Vec<String> {
    let dir = format!("{}/../../examples/robots", env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    names
}

/// Asserts that `text` is refused as a robot file at `key` with a requirement that contains
/// `words`.
pub(crate) fn refused_at(text: &str, key: &str, words: &str) {
    match RobotModel::from_toml(text) {
        Err(pkm_robot_file::RobotFileError::Invalid {
            key: at,
            requirement,
            ..
        }) => assert!(
            at == key && requirement.contains(words),
            "{at}: {requirement}"
        ),
        other => panic!("{key}: {other:?}"),
    }
}
