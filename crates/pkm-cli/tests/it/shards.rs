//! `--shard I/N` and `pkm merge` reproduce the single run bit for bit (N = 3), whatever the
//! thread counts; Ctrl-C stops a run without writing results.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use crate::common;

use common::{pkm, run_study, study};
use pkm_cli::progress::{CancelFlag, Spinner};
use pkm_cli::{Context, Run};
use std::path::Path;

/// The names and bytes of every file in `dir`, sorted.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut all: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect();
    all.sort();
    all
}

fn split_and_merge_equals_single_run(command: &str, name: &str) {
    let root = tempfile::tempdir().unwrap();
    let file = study(name);
    let single = root.path().join("single");
    run_study(command, &file, &single, &["--threads", "2"]);
    let mut dirs = Vec::new();
    for (i, threads) in [(1, "1"), (2, "3"), (3, "1")] {
        let dir = root.path().join(format!("shard{i}"));
        let shard = format!("{i}/3");
        let results = run_study(
            command,
            &file,
            &dir,
            &["--shard", &shard, "--threads", threads],
        );
        assert_eq!(results["result"]["shard"]["index"], i);
        dirs.push(dir);
    }
    let merged = root.path().join("merged");
    // Any order of the shard directories.
    let (a, b, c) = (
        dirs[2].to_str().unwrap(),
        dirs[0].to_str().unwrap(),
        dirs[1].to_str().unwrap(),
    );
    let run = pkm(&["merge", a, b, c, "--out", merged.to_str().unwrap()]);
    assert!(run.ok, "{}", run.stderr);
    let (single, merged) = (files(&single), files(&merged));
    assert_eq!(
        single.iter().map(|f| &f.0).collect::<Vec<_>>(),
        merged.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((name, s), (_, m)) in single.iter().zip(&merged) {
        assert!(
            s == m,
            "{name} differs between the single run and the merge"
        );
    }
    assert!(single.iter().any(|f| f.0 == "landscape.csv"));
}

#[test]
fn a_sweep_split_in_three_merges_into_the_single_run() {
    split_and_merge_equals_single_run("sweep", "tsai_quick.toml");
}

#[test]
fn a_pareto_study_split_in_three_merges_into_the_single_run() {
    split_and_merge_equals_single_run("pareto", "linear_delta_pareto_quick.toml");
}

#[test]
fn merge_refuses_an_incomplete_or_mixed_set() {
    let root = tempfile::tempdir().unwrap();
    let file = study("linear_delta_pareto_quick.toml");
    let one = root.path().join("one");
    let two = root.path().join("two");
    run_study("pareto", &file, &one, &["--shard", "1/3"]);
    run_study("pareto", &file, &two, &["--shard", "2/3"]);
    let out = root.path().join("out");
    let run = pkm(&[
        "merge",
        one.to_str().unwrap(),
        two.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        !run.ok && run.stderr.contains("expected shards 1..=3"),
        "{}",
        run.stderr
    );
    let run = pkm(&[
        "merge",
        one.to_str().unwrap(),
        one.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!run.ok, "the same shard twice");
    assert!(!out.join("results.json").exists());
}

#[test]
fn a_cancelled_run_writes_nothing() {
    let root = tempfile::tempdir().unwrap();
    let cancel = CancelFlag::default();
    cancel.set();
    let context = Context {
        out: root.path().join("out"),
        progress: Spinner::hidden(cancel),
    };
    let args = pkm_cli::commands::sweep::Args {
        file: study("tsai_quick.toml"),
        shard: None,
    };
    assert!(matches!(
        args.run(&context),
        Err(pkm_cli::CliError::Cancelled)
    ));
    let args = pkm_cli::commands::workspace::Args {
        file: study("nuwar_workspace_quick.toml"),
    };
    assert!(matches!(
        args.run(&context),
        Err(pkm_cli::CliError::Cancelled)
    ));
    assert!(!root.path().join("out/results.json").exists());
}
