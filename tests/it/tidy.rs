//! Tidy checks on the repository itself: documentation stays true to the registry.

use pkm::papers;
use std::path::Path;

fn read_doc(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn every_experiment_id_is_listed_in_reproduce_md() {
    let doc = read_doc("reproduce.md");
    for experiment in papers::all() {
        assert!(
            doc.contains(experiment.id),
            "docs/reproduce.md does not list {}",
            experiment.id
        );
    }
}

#[test]
fn experiment_ids_are_unique() {
    let mut ids: Vec<_> = papers::all().iter().map(|e| e.id).collect();
    let n = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), n, "duplicate experiment ids");
}

/// Each package of the dependency graph `cargo tree` prints for `args`, with its features.
fn features_of(args: &[&str]) -> std::collections::BTreeMap<String, String> {
    let output = std::process::Command::new(env!("CARGO"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "tree",
            "--offline",
            "--locked",
            "--prefix",
            "none",
            "--no-dedupe",
        ])
        .args(["--format", "{p}|{f}"])
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cargo tree: {e}"));
    assert!(
        output.status.success(),
        "cargo tree {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| line.split_once('|'))
        .map(|(package, features)| {
            let package = package.trim_end_matches(" (*)").to_owned();
            (package, features.to_owned())
        })
        .collect()
}

/// `pip install ./crates/pkm-py` builds pkm-py alone (maturin), `.ci/run` after
/// `cargo test --workspace`: every dependency the two share must have the same features, or
/// the wheel rebuilds the whole dependency graph (10 minutes of CI). pkm-py's Cargo.toml names
/// the features the workspace turns on; this fails when a new dependency or feature breaks it.
#[test]
fn the_python_package_builds_with_the_test_builds_features() {
    let workspace = features_of(&["--workspace", "--edges", "normal,build,dev"]);
    let python = features_of(&["--package", "pkm-py", "--edges", "normal,build"]);
    let differing: Vec<String> = python
        .iter()
        .filter_map(|(package, features)| {
            let theirs = workspace.get(package)?;
            (theirs != features).then(|| format!("{package}: [{features}] vs [{theirs}]"))
        })
        .collect();
    assert!(
        python.len() > 50 && differing.is_empty(),
        "features of pkm-py alone vs the workspace's test build (add them to \
         crates/pkm-py/Cargo.toml):\n{}",
        differing.join("\n")
    );
}
