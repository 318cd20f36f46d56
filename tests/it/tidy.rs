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
    let mut all = vec![
        "tree",
        "--offline",
        "--locked",
        "--prefix",
        "none",
        "--no-dedupe",
    ];
    all.extend(["--format", "{p}|{f}"]);
    all.extend(args);
    String::from_utf8_lossy(&cargo(&all))
        .lines()
        .filter_map(|line| line.split_once('|'))
        .map(|(package, features)| {
            let package = package.trim_end_matches(" (*)").to_owned();
            (package, features.to_owned())
        })
        .collect()
}

/// The standard output of `cargo ARGS` in the workspace root (a failure fails the test).
fn cargo(args: &[&str]) -> Vec<u8> {
    let output = std::process::Command::new(env!("CARGO"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cargo {args:?}: {e}"));
    assert!(
        output.status.success(),
        "cargo {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output.stdout
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

/// Every workspace package, from `cargo metadata`: its name, manifest directory and
/// dependencies (name, kind, rename), and its `[package.metadata.pkm] feature-unification`.
fn workspace_packages() -> Vec<serde_json::Value> {
    let stdout = cargo(&[
        "metadata",
        "--format-version",
        "1",
        "--no-deps",
        "--offline",
    ]);
    let metadata: serde_json::Value =
        serde_json::from_slice(&stdout).unwrap_or_else(|e| panic!("cargo metadata: {e}"));
    metadata["packages"].as_array().cloned().unwrap_or_default()
}

/// The text of every `.rs` file under `dir` (none when it does not exist).
fn rust_sources(dir: &Path) -> String {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return String::new();
    };
    let mut text = String::new();
    for path in entries.filter_map(|e| e.ok().map(|e| e.path())) {
        if path.is_dir() {
            text += &rust_sources(&path);
        } else if path.extension().is_some_and(|e| e == "rs") {
            text += &std::fs::read_to_string(&path).unwrap_or_default();
        }
    }
    text
}

/// Whether the code names the crate `name` (a path, a `use`, a macro or a derive).
fn names_crate(code: &str, name: &str) -> bool {
    code.match_indices(name).any(|(k, _)| {
        let before = code[..k].chars().next_back();
        let after = code[k + name.len()..].chars().next();
        !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
            && matches!(after, Some(':' | '!' | ';' | ' ' | ',' | '}'))
    })
}

/// No package carries a dependency that its code never names (pkm-cli carried five): a normal
/// dependency is named in `src/` (or `build.rs`), a dev-dependency anywhere in the package. A
/// dependency kept only for its features is listed in `[package.metadata.pkm]
/// feature-unification`.
#[test]
fn no_package_has_an_unused_dependency() {
    let mut unused = Vec::new();
    for package in workspace_packages() {
        let manifest = Path::new(package["manifest_path"].as_str().unwrap_or_default());
        let dir = manifest.parent().unwrap_or(Path::new("."));
        let name = package["name"].as_str().unwrap_or_default();
        let src = rust_sources(&dir.join("src"))
            + &std::fs::read_to_string(dir.join("build.rs")).unwrap_or_default();
        let all = ["tests", "benches", "examples"]
            .iter()
            .fold(src.clone(), |text, d| text + &rust_sources(&dir.join(d)));
        let kept = &package["metadata"]["pkm"]["feature-unification"];
        for dependency in package["dependencies"].as_array().into_iter().flatten() {
            let crate_name = dependency["rename"]
                .as_str()
                .or(dependency["name"].as_str())
                .unwrap_or_default();
            let in_code = crate_name.replace('-', "_");
            let code = match dependency["kind"].as_str() {
                None => &src,
                Some("dev") => &all,
                Some(_) => continue,
            };
            let listed = kept
                .as_array()
                .is_some_and(|k| k.iter().any(|n| n == crate_name));
            if !listed && !names_crate(code, &in_code) {
                unused.push(format!("{name}: {crate_name}"));
            }
        }
    }
    assert!(
        unused.is_empty(),
        "unused dependencies:\n{}",
        unused.join("\n")
    );
}

/// The crate table of `docs/ARCHITECTURE.md` has a row for every workspace package, and each
/// row names exactly the package's pkm dependencies (normal in the second column, dev in the
/// third).
#[test]
fn the_architecture_crate_table_lists_every_package_and_its_pkm_dependencies() {
    let doc = read_doc("ARCHITECTURE.md");
    let rows: Vec<Vec<&str>> = doc
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| l.split('|').map(str::trim).collect())
        .collect();
    let mut wrong = Vec::new();
    for package in workspace_packages() {
        let name = package["name"].as_str().unwrap_or_default();
        let cell = format!("`{name}`");
        let Some(row) = rows.iter().find(|r| r.get(1).is_some_and(|c| *c == cell)) else {
            wrong.push(format!("{name}: no row"));
            continue;
        };
        for (column, kind) in [(2, None), (3, Some("dev"))] {
            let text = row.get(column).copied().unwrap_or_default();
            let listed: std::collections::BTreeSet<&str> = text
                .split('`')
                .skip(1)
                .step_by(2)
                .filter(|s| s.starts_with("pkm"))
                .map(|s| s.split('/').next().unwrap_or(s))
                .collect();
            let actual: std::collections::BTreeSet<&str> = package["dependencies"]
                .as_array()
                .into_iter()
                .flatten()
                .filter(|d| d["kind"].as_str() == kind)
                .filter_map(|d| d["name"].as_str())
                .filter(|d| d.starts_with("pkm"))
                .collect();
            if listed != actual {
                wrong.push(format!(
                    "{name}: column {column} lists {listed:?}, Cargo.toml {actual:?}"
                ));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "docs/ARCHITECTURE.md crate table:\n{}",
        wrong.join("\n")
    );
}

/// No module is declared inside a macro (rustfmt never sees such a file: `cargo fmt --check`
/// passed while six command files were unformatted).
#[test]
fn no_module_is_declared_inside_a_macro() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut text = rust_sources(&root.join("src")) + &rust_sources(&root.join("xtask"));
    for entry in std::fs::read_dir(root.join("crates"))
        .into_iter()
        .flatten()
        .flatten()
    {
        text += &rust_sources(&entry.path().join("src"));
    }
    let hidden = ["mod $", "mod $module"];
    assert!(
        !hidden.iter().any(|h| text.contains(h)),
        "a `mod` declared by a macro: declare it outside, so rustfmt formats the file"
    );
}

/// The top-level modules of the crate whose sources are in `src` and the `crate::module` edges
/// between them (comment lines and unit tests left out). `pkm-study` has a finer test of its own
/// (`crates/pkm-study/tests/it/module_graph.rs`).
fn module_graph(
    src: &Path,
) -> std::collections::BTreeMap<String, std::collections::BTreeSet<String>> {
    let mut files = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for path in std::fs::read_dir(&dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.path())
        {
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    let node = |file: &Path| {
        let rel = file.strip_prefix(src).unwrap_or(file).with_extension("");
        rel.iter()
            .next()
            .map(|c| c.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let nodes: std::collections::BTreeSet<String> = files
        .iter()
        .map(|f| node(f))
        .filter(|n| n != "lib" && n != "main")
        .collect();
    let mut graph = std::collections::BTreeMap::new();
    for file in &files {
        let from = node(file);
        if !nodes.contains(&from) {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap_or_default();
        let code: String = text
            .split("#[cfg(test)]")
            .next()
            .unwrap_or("")
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        for (k, _) in code.match_indices("crate::") {
            let rest = &code[k + "crate::".len()..];
            let names: Vec<&str> = match rest.strip_prefix('{') {
                Some(inner) => inner
                    .split('}')
                    .next()
                    .unwrap_or("")
                    .split(',')
                    .map(|n| n.trim().split("::").next().unwrap_or(""))
                    .collect(),
                None => vec![
                    rest.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                        .next()
                        .unwrap_or(""),
                ],
            };
            for name in names {
                if nodes.contains(name) && name != from {
                    graph
                        .entry(from.clone())
                        .or_insert_with(std::collections::BTreeSet::new)
                        .insert(name.to_owned());
                }
            }
        }
    }
    graph
}

/// The modules of `graph` that lie on a cycle, grouped by strongly connected component.
fn cycles(
    graph: &std::collections::BTreeMap<String, std::collections::BTreeSet<String>>,
) -> std::collections::BTreeSet<std::collections::BTreeSet<String>> {
    let reach = |start: &str| {
        let mut seen = std::collections::BTreeSet::new();
        let mut stack = vec![start.to_owned()];
        while let Some(v) = stack.pop() {
            for w in graph.get(&v).into_iter().flatten() {
                if seen.insert(w.clone()) {
                    stack.push(w.clone());
                }
            }
        }
        seen
    };
    let reachable: std::collections::BTreeMap<&String, _> =
        graph.keys().map(|v| (v, reach(v))).collect();
    reachable
        .iter()
        .filter(|(v, r)| r.contains(**v))
        .map(|(v, r)| {
            r.iter()
                .filter(|w| reachable.get(w).is_some_and(|back| back.contains(*v)))
                .cloned()
                .collect()
        })
        .collect()
}

/// The modules of every crate form a DAG (pkm-study has its own, finer test). Review 4 found
/// five cycles; all are fixed: the command's (commands ↔ output), the optimisers' (grid_axis ↔
/// grid_search), the Stewart–Gough's (stewart_gough ↔ stewart_layout), the Linear Delta's
/// (linear_delta ↔ linear_delta_cross_section) and the robot file's (model, mobility,
/// jacobian, closure, name: `MAX_LEGS` in `file`, `CoordinateRole` in `pose`, the bounded SVD
/// in `svd`).
#[test]
fn the_modules_of_every_crate_form_a_dag() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut sources = vec!["src".to_owned(), "xtask/src".to_owned()];
    for entry in std::fs::read_dir(root.join("crates"))
        .into_iter()
        .flatten()
        .flatten()
    {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name != "pkm-study" {
            sources.push(format!("crates/{name}/src"));
        }
    }
    let mut wrong = Vec::new();
    for src in &sources {
        let found = cycles(&module_graph(&root.join(src)));
        if !found.is_empty() {
            wrong.push(format!("{src}: cycles {found:?}"));
        }
    }
    assert!(wrong.is_empty(), "module cycles:\n{}", wrong.join("\n"));
}
