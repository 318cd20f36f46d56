//! The modules of `pkm-study` form a DAG: every `crate::` path of a module's code (comments and
//! unit tests left out; `schema/*` files count as their own modules, other folders as one; the
//! `super::` of a schema file is `crate::schema::`) is
//! an edge, names re-exported at the crate root lead to the module that defines them, and a
//! depth-first search finds no cycle.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            sources(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The node of a source file: `schema::<file>` (or `schema::<folder>`) under `schema/`, the top
/// folder or file else.
fn node_of(src: &Path, file: &Path) -> String {
    let rel: Vec<String> = file
        .strip_prefix(src)
        .unwrap()
        .with_extension("")
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    match rel.as_slice() {
        [schema, m] if schema == "schema" && m != "mod" => format!("schema::{m}"),
        // A folder of schema (`schema/kinds/`) is one module.
        [schema, m, _] if schema == "schema" => format!("schema::{m}"),
        [first, ..] => first.clone(),
        [] => unreachable!("a file has a name"),
    }
}

/// The code of a file without comment lines and without its unit tests.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifiers after each `crate::` (the first two path segments, or the names in braces).
fn crate_paths(code: &str) -> Vec<Vec<String>> {
    let mut paths = Vec::new();
    for (k, _) in code.match_indices("crate::") {
        let rest = &code[k + "crate::".len()..];
        let end = rest
            .find(|c: char| {
                !(c.is_alphanumeric()
                    || c == '_'
                    || c == ':'
                    || c == '{'
                    || c == ','
                    || c == ' '
                    || c == '\n')
            })
            .unwrap_or(rest.len());
        let path = &rest[..end];
        let (head, braces) = path.split_once('{').unwrap_or((path, ""));
        let head: Vec<String> = head
            .split("::")
            .map(|s| s.split_whitespace().next().unwrap_or(""))
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect();
        if braces.is_empty() {
            paths.push(head);
        } else {
            for name in braces.split(',') {
                let first = name.split("::").next().unwrap_or("");
                let first = first.split_whitespace().next().unwrap_or("");
                let mut p = head.clone();
                p.push(first.to_owned());
                paths.push(p);
            }
        }
    }
    paths
}

#[test]
fn the_study_modules_form_a_dag() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    // Root re-exports: `pub use module::{A, B};` / `pub use module::A;`.
    let mut reexported: BTreeMap<String, String> = BTreeMap::new();
    for line in lib.lines().filter(|l| l.starts_with("pub use ")) {
        let path = line.trim_start_matches("pub use ").trim_end_matches(';');
        let Some((module, names)) = path.split_once("::") else {
            continue;
        };
        let module = match module {
            "schema" => format!("schema::{}", names.split("::").next().unwrap_or("")),
            m => m.to_owned(),
        };
        let names = names
            .rsplit("::")
            .next()
            .unwrap_or("")
            .trim_matches(|c| c == '{' || c == '}');
        for name in names.split(',') {
            reexported.insert(name.trim().to_owned(), module.clone());
        }
    }
    let nodes: BTreeSet<String> = files.iter().map(|f| node_of(&src, f)).collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files.iter().filter(|f| !f.ends_with("lib.rs")) {
        let from = node_of(&src, file);
        let mut text = code(&std::fs::read_to_string(file).unwrap());
        if from.starts_with("schema::") {
            text = text.replace("super::", "crate::schema::");
        }
        for path in crate_paths(&text) {
            let target = match path.as_slice() {
                [schema, m, ..] if schema == "schema" => format!("schema::{m}"),
                [first, ..] if nodes.contains(first) => first.clone(),
                [first, ..] => match reexported.get(first) {
                    Some(m) => m.clone(),
                    None => continue,
                },
                [] => continue,
            };
            if target != from && nodes.contains(&target) {
                graph.entry(from.clone()).or_default().insert(target);
            }
        }
    }
    for (from, to) in &graph {
        println!(
            "{from:20} -> {}",
            to.iter().cloned().collect::<Vec<_>>().join(", ")
        );
    }
    // Depth-first search with colours: grey on the stack, black done.
    let mut colour: BTreeMap<&str, u8> = BTreeMap::new();
    fn visit<'a>(
        v: &'a str,
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        colour: &mut BTreeMap<&'a str, u8>,
        stack: &mut Vec<&'a str>,
    ) {
        colour.insert(v, 1);
        stack.push(v);
        for w in graph.get(v).into_iter().flatten() {
            match colour.get(w.as_str()) {
                Some(1) => panic!("import cycle: {} -> {w}", stack.join(" -> ")),
                Some(_) => {}
                None => visit(w, graph, colour, stack),
            }
        }
        stack.pop();
        colour.insert(v, 2);
    }
    for v in graph.keys() {
        if !colour.contains_key(v.as_str()) {
            visit(v, &graph, &mut colour, &mut Vec::new());
        }
    }
    assert!(graph.len() > 15, "the graph was read: {graph:?}");
}
