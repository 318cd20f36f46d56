//! `cargo xtask reproduce`: runs the experiments, prints the table, writes the report.

use crate::run::{ExperimentRun, Summary};
use crate::{report, table};
use anyhow::{Context as _, bail};
use pkm::papers::{self, Comparison, Context, Experiment, Mode, Verdict};
use pkm_term::{CancelFlag, OutputDir, Spinner};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Options of `cargo xtask reproduce`.
#[derive(Debug, Default, clap::Args)]
pub(crate) struct ReproduceArgs {
    /// Run the reduced sizes that `cargo test` runs.
    #[arg(long)]
    quick: bool,
    /// Run only the experiments whose id starts with (or is a prefix of) ID_PREFIX; repeatable.
    #[arg(long = "only", value_name = "ID_PREFIX")]
    only: Vec<String>,
    /// List the experiments (id, paper, title) and exit.
    #[arg(long)]
    list: bool,
    /// Where to write the report [default: target/reproduce in the workspace].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Also write the table into README.md between `<!-- reproduce:begin -->` and
    /// `<!-- reproduce:end -->` (full run of every experiment only).
    #[arg(long)]
    update_readme: bool,
}

/// The workspace root: the parent of this crate's manifest directory.
pub(crate) fn workspace_root() -> PathBuf {
    let xtask = Path::new(env!("CARGO_MANIFEST_DIR"));
    xtask.parent().unwrap_or(xtask).to_path_buf()
}

/// Runs the command; the exit code is non-zero when a comparison fails, an experiment errors or
/// the run is cancelled.
///
/// # Errors
/// When `--only` is empty or selects nothing, the options contradict each other, `--out` is
/// not a creatable, writable directory (checked before anything runs), or a report file cannot
/// be written.
pub(crate) fn run(args: &ReproduceArgs) -> anyhow::Result<ExitCode> {
    run_registry(args, papers::all())
}

/// [`run`] over the experiments `registry`.
fn run_registry(args: &ReproduceArgs, registry: Vec<Experiment>) -> anyhow::Result<ExitCode> {
    let experiments = select(registry, &args.only)?;
    if args.list {
        for e in &experiments {
            println!("{}\t{}\t{}", e.id, e.paper.file(), e.title);
        }
        if experiments.is_empty() {
            println!("no experiments registered");
        }
        return Ok(ExitCode::SUCCESS);
    }
    let mode = if args.quick { Mode::Quick } else { Mode::Full };
    if args.update_readme && (mode == Mode::Quick || !args.only.is_empty()) {
        bail!("--update-readme records a full run of every experiment: drop --quick and --only");
    }
    if experiments.is_empty() {
        println!("no experiments registered: nothing to reproduce");
        return Ok(ExitCode::SUCCESS);
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| workspace_root().join("target/reproduce"));
    // Checked before anything runs: a directory that can be created and written.
    OutputDir::create(&out).with_context(|| format!("--out {}", out.display()))?;
    let cancel = CancelFlag::on_ctrl_c().map_err(anyhow::Error::msg)?;
    let runs = run_all(&experiments, mode, &cancel);
    let cancelled = cancel.is_set();
    let rows: Vec<Comparison> = runs.iter().flat_map(|r| r.comparisons().to_vec()).collect();
    println!();
    if rows.is_empty() {
        println!("no comparisons");
    } else {
        print!("{}", table::plain(&rows, console::colors_enabled()));
    }
    let report = report::Report::new(mode, report::git_commit(&workspace_root()), &runs)
        .cancelled(cancelled);
    let written = report
        .write(&out)
        .with_context(|| format!("writing {}", out.display()))?;
    if args.update_readme && !cancelled {
        let readme = workspace_root().join("README.md");
        report::update_readme(&readme, &report)?;
        println!("updated {}", readme.display());
    }
    let summary = Summary::of(&runs);
    println!("\n{summary}");
    println!("report: {}", written.display());
    if cancelled {
        println!(
            "cancelled: {} of {} experiments completed",
            runs.iter().filter(|r| r.outcome.is_ok()).count(),
            experiments.len()
        );
    }
    Ok(if succeeded(&runs, cancelled) {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// The experiments `--only` selects (all without `--only`).
///
/// # Errors
/// When a prefix is empty (it would select everything), or prefixes are given and none
/// matches.
fn select(all: Vec<Experiment>, only: &[String]) -> anyhow::Result<Vec<Experiment>> {
    if only.is_empty() {
        return Ok(all);
    }
    if only.iter().any(|p| p.trim().is_empty()) {
        bail!("--only needs a non-empty experiment id prefix (run without --only to run all)");
    }
    let selected: Vec<Experiment> = all
        .into_iter()
        .filter(|e| only.iter().any(|p| e.matches(p)))
        .collect();
    if selected.is_empty() {
        bail!("no experiment matches --only {}", only.join(" --only "));
    }
    Ok(selected)
}

/// Runs the experiments in order, each under a spinner, until done or cancelled.
fn run_all(experiments: &[Experiment], mode: Mode, cancel: &CancelFlag) -> Vec<ExperimentRun> {
    let mut runs = Vec::with_capacity(experiments.len());
    for &experiment in experiments {
        if cancel.is_set() {
            break;
        }
        let spinner = Spinner::new(experiment.id, cancel.clone(), false);
        let start = Instant::now();
        let outcome = (experiment.run)(&Context {
            mode,
            progress: &spinner,
        });
        let elapsed = start.elapsed();
        spinner.close();
        let status = match &outcome {
            Ok(o) => format!("{} rows", o.comparisons.len()),
            Err(e) => format!("error: {e}"),
        };
        eprintln!(
            "{:>8.1} s  {}  {status}",
            elapsed.as_secs_f64(),
            experiment.id
        );
        runs.push(ExperimentRun {
            experiment,
            elapsed,
            outcome,
        });
    }
    runs
}

/// Whether the run succeeded: not cancelled, every experiment ran and no comparison failed.
pub(crate) fn succeeded(runs: &[ExperimentRun], cancelled: bool) -> bool {
    !cancelled
        && runs.iter().all(|r| {
            r.outcome
                .as_ref()
                .is_ok_and(|o| o.comparisons.iter().all(|c| c.verdict != Verdict::Fail))
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::tests::synthetic_run;
    use pkm::papers::{ExperimentError, Outcome, Paper, Source};

    fn passing(_: &Context<'_>) -> Result<Outcome, ExperimentError> {
        Ok(Outcome::default())
    }

    fn must_not_run(_: &Context<'_>) -> Result<Outcome, ExperimentError> {
        panic!("an experiment ran before --out was checked");
    }

    fn failing(context: &Context<'_>) -> Result<Outcome, ExperimentError> {
        let source = Source::new("test.failing", Paper::Miller2004, "Table 2");
        let value = context.mode.pick(2.0, 3.0);
        Ok(Outcome {
            comparisons: vec![source.check("x", "", 1.0, value, 0.1)],
            ..Outcome::default()
        })
    }

    fn experiment(
        id: &'static str,
        run: fn(&Context<'_>) -> Result<Outcome, ExperimentError>,
    ) -> Experiment {
        Experiment {
            id,
            paper: Paper::Miller2004,
            title: "synthetic",
            run,
        }
    }

    fn with_rows(rows: Vec<Comparison>) -> ExperimentRun {
        synthetic_run(
            "test.rows",
            Ok(Outcome {
                comparisons: rows,
                ..Outcome::default()
            }),
        )
    }

    #[test]
    fn a_failed_comparison_an_error_or_a_cancellation_fails_the_run() {
        let source = Source::new("test.rows", Paper::Miller2004, "Table 2");
        let pass = source.check("x", "", 1.0, 1.05, 0.1);
        let fail = source.check("y", "", 1.0, 2.0, 0.1);
        let erratum = fail.clone().erratum("anchor");
        let info = source.info("z", "", 3.0);
        assert!(succeeded(
            &[with_rows(vec![pass.clone(), erratum, info])],
            false
        ));
        assert!(succeeded(&[], false));
        assert!(!succeeded(&[with_rows(vec![pass.clone(), fail])], false));
        assert!(!succeeded(&[with_rows(vec![pass.clone()])], true));
        let errored = synthetic_run("test.error", Err(ExperimentError::Cancelled));
        assert!(!succeeded(&[with_rows(vec![pass]), errored], false));
    }

    #[test]
    fn only_selects_by_prefix_and_refuses_an_empty_selection() {
        let make = |id| synthetic_run(id, Ok(Outcome::default())).experiment;
        let all = vec![
            make("wolf2006.a"),
            make("wolf2006.b"),
            make("stamper1997.c"),
        ];
        let ids = |v: Vec<Experiment>| v.iter().map(|e| e.id).collect::<Vec<_>>();
        assert_eq!(ids(select(all.clone(), &[]).unwrap()).len(), 3);
        assert_eq!(
            ids(select(all.clone(), &["wolf2006".into()]).unwrap()),
            ["wolf2006.a", "wolf2006.b"]
        );
        assert_eq!(
            ids(select(all.clone(), &["wolf2006.b.row1".into(), "stamper".into()]).unwrap()),
            ["wolf2006.b", "stamper1997.c"]
        );
        let error = select(all.clone(), &["miller".into()]).unwrap_err();
        assert!(
            error
                .to_string()
                .contains("no experiment matches --only miller")
        );
        for empty in ["", "  "] {
            let error = select(all.clone(), &["wolf2006".into(), empty.into()]).unwrap_err();
            assert!(error.to_string().contains("non-empty"), "{error}");
        }
    }

    #[test]
    fn out_must_be_a_creatable_directory_before_anything_runs() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a-file");
        std::fs::write(&file, "not a directory").unwrap();
        let registry = vec![experiment("test.must_not_run", must_not_run)];
        for out in [file.clone(), file.join("below")] {
            let args = ReproduceArgs {
                quick: true,
                out: Some(out.clone()),
                ..ReproduceArgs::default()
            };
            let error = run_registry(&args, registry.clone()).unwrap_err();
            assert!(format!("{error:#}").contains("--out"), "{error:#}");
        }
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a directory");
        let fresh = dir.path().join("new/nested");
        let args = ReproduceArgs {
            quick: true,
            out: Some(fresh.clone()),
            ..ReproduceArgs::default()
        };
        let registry = vec![experiment("test.passing", passing)];
        assert_eq!(run_registry(&args, registry).unwrap(), ExitCode::SUCCESS);
        assert!(fresh.join("results.json").is_file());
    }

    #[test]
    fn the_command_writes_the_report_and_fails_on_a_failed_comparison() {
        let dir = tempfile::tempdir().unwrap();
        let args = |only: &[&str]| ReproduceArgs {
            quick: true,
            only: only.iter().map(|s| (*s).to_owned()).collect(),
            out: Some(dir.path().to_path_buf()),
            ..ReproduceArgs::default()
        };
        let registry = || {
            vec![
                experiment("test.passing", passing),
                experiment("test.failing", failing),
            ]
        };
        let read_json = || -> serde_json::Value {
            serde_json::from_str(&std::fs::read_to_string(dir.path().join("results.json")).unwrap())
                .unwrap()
        };
        assert_eq!(
            run_registry(&args(&[]), registry()).unwrap(),
            ExitCode::FAILURE
        );
        let json = read_json();
        assert_eq!(json["mode"], "quick");
        assert_eq!(json["results"][0]["value"], 2.0);
        assert_eq!(
            run_registry(&args(&["test.passing"]), registry()).unwrap(),
            ExitCode::SUCCESS
        );
        assert_eq!(read_json()["results"].as_array().unwrap().len(), 0);
        assert!(run_registry(&args(&["nothing"]), registry()).is_err());
        assert_eq!(
            run_registry(&args(&[]), Vec::new()).unwrap(),
            ExitCode::SUCCESS
        );
    }

    #[test]
    fn a_cancelled_run_stops_before_the_next_experiment() {
        let experiments = [
            experiment("test.passing", passing),
            experiment("test.failing", failing),
        ];
        let cancel = CancelFlag::default();
        assert_eq!(run_all(&experiments, Mode::Quick, &cancel).len(), 2);
        cancel.set();
        assert!(run_all(&experiments, Mode::Quick, &cancel).is_empty());
    }
}
