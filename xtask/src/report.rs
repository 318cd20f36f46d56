//! The files of a run: `results.json`, `report.md`, one CSV per table, one SVG per figure and
//! the CSV of its data;
//! and the reproduction table of `README.md`.

use crate::reproduce::ExperimentRun;
use crate::{figure_data, plot, table};
use anyhow::{Context as _, bail};
use pkm::papers::{Comparison, Figure, Mode, Outcome, Table, Verdict};
use serde::Serialize;
use std::fmt;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// Counts of verdicts, experiments that errored, and experiments that ran.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Summary {
    pass: usize,
    fail: usize,
    erratum: usize,
    info: usize,
    errors: usize,
    experiments: usize,
}

impl Summary {
    /// Counts over `runs`.
    pub(crate) fn of(runs: &[ExperimentRun]) -> Self {
        let mut summary = Self {
            experiments: runs.len(),
            errors: runs.iter().filter(|r| r.outcome.is_err()).count(),
            ..Self::default()
        };
        for row in runs.iter().flat_map(ExperimentRun::comparisons) {
            *match row.verdict {
                Verdict::Pass => &mut summary.pass,
                Verdict::Fail => &mut summary.fail,
                Verdict::Erratum => &mut summary.erratum,
                Verdict::Info => &mut summary.info,
            } += 1;
        }
        summary
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} experiments, {} errored; {} pass, {} fail, {} erratum, {} info",
            self.experiments, self.errors, self.pass, self.fail, self.erratum, self.info
        )
    }
}

/// `git rev-parse HEAD` in `root`, with `-dirty` when `git status --porcelain` lists changes;
/// `unknown` without git.
pub(crate) fn git_commit(root: &Path) -> String {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(root)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_owned())
    };
    match (git(&["rev-parse", "HEAD"]), git(&["status", "--porcelain"])) {
        (Some(head), Some(status)) if !status.is_empty() => format!("{head}-dirty"),
        (Some(head), _) => head,
        (None, _) => "unknown".to_owned(),
    }
}

/// Creates `dir` if needed and checks that a report can be written there, before anything
/// runs: `--out` must name a directory (not a file) that can be created and written.
///
/// # Errors
/// When `dir` is a file, lies below a file, or cannot be created or written.
pub(crate) fn prepare_output_dir(dir: &Path) -> anyhow::Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("--out {} is not a directory", dir.display());
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("--out {}: cannot create the directory", dir.display()))?;
    let probe = dir.join(format!(".write-check-{}", std::process::id()));
    std::fs::write(&probe, b"")
        .with_context(|| format!("--out {}: the directory is not writable", dir.display()))?;
    std::fs::remove_file(&probe)
        .with_context(|| format!("--out {}: cannot remove {}", dir.display(), probe.display()))
}

/// Writes `contents` to `path` atomically: into a temporary file of the same directory, then
/// renamed over `path`, so a reader (or a crash, or Ctrl-C) never sees a half-written file.
fn write_atomically(path: &Path, contents: &[u8]) -> anyhow::Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&temporary, contents).with_context(|| temporary.display().to_string())?;
    std::fs::rename(&temporary, path).with_context(|| {
        let _ = std::fs::remove_file(&temporary);
        format!("renaming {} to {}", temporary.display(), path.display())
    })
}

/// Everything a run writes.
#[derive(Debug)]
pub(crate) struct Report<'a> {
    mode: Mode,
    git_commit: String,
    runs: &'a [ExperimentRun],
    cancelled: bool,
}

impl<'a> Report<'a> {
    /// The report of `runs` in `mode` at `git_commit`.
    pub(crate) fn new(mode: Mode, git_commit: String, runs: &'a [ExperimentRun]) -> Self {
        Self {
            mode,
            git_commit,
            runs,
            cancelled: false,
        }
    }

    /// Marks the report as that of a run cancelled by Ctrl-C.
    pub(crate) fn cancelled(self, cancelled: bool) -> Self {
        Self { cancelled, ..self }
    }

    fn rows(&self) -> Vec<Comparison> {
        self.runs
            .iter()
            .flat_map(|r| r.comparisons().to_vec())
            .collect()
    }

    /// Writes `results.json`, `report.md`, the CSVs and the SVGs into `dir` (created if needed)
    /// and returns the path of the report.
    ///
    /// `results.json` and `report.md` are written atomically (temporary file, then rename). A
    /// cancelled run writes only `results.cancelled.json` and `report.cancelled.md`, both with
    /// `cancelled: true`, and leaves every file of the previous complete report as it was.
    ///
    /// # Errors
    /// When a file cannot be written or a figure cannot be rendered.
    pub(crate) fn write(&self, dir: &Path) -> anyhow::Result<std::path::PathBuf> {
        std::fs::create_dir_all(dir)?;
        if self.cancelled {
            write_atomically(&dir.join("results.cancelled.json"), self.json()?.as_bytes())?;
            let report = dir.join("report.cancelled.md");
            write_atomically(&report, self.markdown().as_bytes())?;
            return Ok(report);
        }
        for run in self.runs {
            let Ok(outcome) = &run.outcome else { continue };
            let id = run.experiment.id;
            for t in &outcome.tables {
                let path = dir.join(format!("{id}.{}.csv", t.name));
                std::fs::write(&path, csv(t)).with_context(|| path.display().to_string())?;
            }
            for figure in &outcome.figures {
                let path = dir.join(format!("{id}.{}.svg", figure.name));
                plot::render(figure, &path).with_context(|| path.display().to_string())?;
                if let Some(name) = figure_csv_name(outcome, figure) {
                    let path = dir.join(format!("{id}.{name}.csv"));
                    std::fs::write(&path, figure_data::csv(figure))
                        .with_context(|| path.display().to_string())?;
                }
            }
        }
        write_atomically(&dir.join("results.json"), self.json()?.as_bytes())?;
        let report = dir.join("report.md");
        write_atomically(&report, self.markdown().as_bytes())?;
        Ok(report)
    }

    /// `results.json`: `{"mode", "git_commit", "cancelled", "results": [Comparison…]}`.
    fn json(&self) -> serde_json::Result<String> {
        /// The schema of `results.json`, fields in this order.
        #[derive(Serialize)]
        struct Results<'a> {
            mode: Mode,
            git_commit: &'a str,
            cancelled: bool,
            results: Vec<Comparison>,
        }
        serde_json::to_string_pretty(&Results {
            mode: self.mode,
            git_commit: &self.git_commit,
            cancelled: self.cancelled,
            results: self.rows(),
        })
    }

    /// `report.md`: summary, table, and a section per experiment.
    fn markdown(&self) -> String {
        let mode = serde_json::to_value(self.mode)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default();
        let cancelled = if self.cancelled {
            " **Cancelled** (Ctrl-C): only the experiments below ran."
        } else {
            ""
        };
        let mut md = format!(
            "# Reproduction report\n\nMode `{mode}`, commit `{}`.{cancelled}\n\n{}\n\n## Results\n\n{}",
            self.git_commit,
            Summary::of(self.runs),
            table::markdown(&self.rows())
        );
        md.push_str("\n## Experiments\n");
        for run in self.runs {
            experiment_section(&mut md, run);
        }
        md
    }
}

fn experiment_section(md: &mut String, run: &ExperimentRun) {
    let e = &run.experiment;
    let seconds = run.elapsed.as_secs_f64();
    // Writing to a String cannot fail.
    let _ = write!(
        md,
        "\n### `{}`: {}\n\nPaper `{}`, {seconds:.1} s",
        e.id,
        e.title,
        e.paper.file()
    );
    let outcome = match &run.outcome {
        Ok(outcome) => outcome,
        Err(error) => {
            let _ = writeln!(md, ", **error**: {error}");
            return;
        }
    };
    let _ = writeln!(md, ", {} comparisons.", outcome.comparisons.len());
    for figure in &outcome.figures {
        let _ = write!(md, "\n![{}]({}.{}.svg)\n", figure.title, e.id, figure.name);
    }
    let figure_data = outcome
        .figures
        .iter()
        .filter_map(|f| figure_csv_name(outcome, f));
    let names: Vec<&str> = outcome
        .tables
        .iter()
        .map(|t| t.name.as_str())
        .chain(figure_data)
        .collect();
    if !names.is_empty() {
        md.push_str("\nData:");
        for name in names {
            let _ = write!(md, " [{name}]({}.{name}.csv)", e.id);
        }
        md.push('\n');
    }
}

/// The CSV stem of `figure`'s data: its own name, unless a table of the outcome already has
/// that name (the experiment wrote the data behind the figure itself).
fn figure_csv_name<'a>(outcome: &Outcome, figure: &'a Figure) -> Option<&'a str> {
    let taken = outcome.tables.iter().any(|t| t.name == figure.name);
    (!taken).then_some(figure.name.as_str())
}

/// A table as CSV: quoted headers when needed, values in shortest round-trip form.
fn csv(t: &Table) -> String {
    let field = figure_data::field;
    let mut out: Vec<String> = vec![
        t.columns
            .iter()
            .map(|c| field(c))
            .collect::<Vec<_>>()
            .join(","),
    ];
    out.extend(
        t.rows
            .iter()
            .map(|row| row.iter().map(f64::to_string).collect::<Vec<_>>().join(",")),
    );
    out.join("\n") + "\n"
}

const BEGIN: &str = "<!-- reproduce:begin -->";
const END: &str = "<!-- reproduce:end -->";

/// Replaces what lies between the reproduce markers of `readme` with the markdown table of the
/// run and its summary.
///
/// # Errors
/// When the file cannot be read or written, or lacks the markers.
pub(crate) fn update_readme(readme: &Path, report: &Report<'_>) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(readme).with_context(|| readme.display().to_string())?;
    let block = format!(
        "{}\nCommit `{}`: {}.\n",
        table::markdown(&report.rows()),
        report.git_commit,
        Summary::of(report.runs)
    );
    let updated = replace_between_markers(&text, &block)?;
    std::fs::write(readme, updated).with_context(|| readme.display().to_string())
}

fn replace_between_markers(text: &str, table: &str) -> anyhow::Result<String> {
    let (Some(begin), Some(end)) = (text.find(BEGIN), text.find(END)) else {
        bail!("README.md lacks the markers {BEGIN} … {END}");
    };
    if end < begin {
        bail!("README.md has {END} before {BEGIN}");
    }
    let head = &text[..begin + BEGIN.len()];
    Ok(format!("{head}\n{table}{}", &text[end..]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reproduce::tests::synthetic_run;
    use pkm::draw::{Link, LinkKind, PointKind, Scene, Skeleton, SkeletonPoint};
    use pkm::papers::{
        ExperimentError, Figure, FigureKind, Heatmap, LinePlot, LineSeries, Outcome, Paper,
        RobotDrawing, SeriesStyle, Source,
    };
    use serde_json::Value;

    fn outcome() -> Outcome {
        let source = Source::new("test.synthetic", Paper::Stamper1997, "Table 1");
        Outcome {
            comparisons: vec![
                source.check("V", "m^3", 2.0, 2.05, 0.1),
                source.check("GCI", "", 0.5, 0.9, 0.1),
                source.info("n", "", 1000.0).with_note("samples"),
            ],
            tables: vec![Table {
                name: "volume".into(),
                columns: vec!["samples".into(), "volume, m^3".into()],
                rows: vec![vec![100.0, 1.5], vec![1000.0, 0.1]],
            }],
            figures: vec![
                Figure {
                    name: "convergence".into(),
                    title: "Figure 3: volume convergence".into(),
                    kind: FigureKind::Lines(LinePlot {
                        x_label: "samples".into(),
                        y_label: "volume (m^3)".into(),
                        series: vec![
                            LineSeries {
                                label: "pkm".into(),
                                style: SeriesStyle::Line,
                                points: vec![(1.0, 2.0), (2.0, 1.5), (3.0, f64::NAN), (4.0, 1.7)],
                            },
                            LineSeries {
                                label: "paper".into(),
                                style: SeriesStyle::Points,
                                points: vec![(1.0, 2.1), (4.0, 1.6)],
                            },
                        ],
                    }),
                },
                Figure {
                    name: "gci".into(),
                    title: "Figure 5: GCI landscape".into(),
                    kind: FigureKind::Heatmap(Heatmap {
                        x_label: "a (m)".into(),
                        y_label: "b (m)".into(),
                        z_label: "GCI".into(),
                        x: vec![0.0, 1.0, 2.0],
                        y: vec![0.0, 0.5],
                        values: vec![Some(0.1), None, Some(0.3), Some(0.4), Some(0.5), None],
                    }),
                },
                Figure {
                    name: "robot".into(),
                    title: "a two-link robot".into(),
                    kind: FigureKind::Robot(RobotDrawing {
                        scene: Scene::new(Skeleton {
                            points: ["A", "B"]
                                .into_iter()
                                .zip([0.0, 1.0])
                                .map(|(label, z)| SkeletonPoint {
                                    label: label.into(),
                                    kind: PointKind::Passive,
                                    position: [0.0, 0.0, z].into(),
                                })
                                .collect(),
                            links: vec![Link {
                                from: 0,
                                to: 1,
                                kind: LinkKind::Actuated,
                            }],
                        }),
                        unit: "m".into(),
                    }),
                },
            ],
        }
    }

    #[test]
    fn a_run_writes_json_markdown_csv_and_svg() {
        let runs = [
            synthetic_run("test.synthetic", Ok(outcome())),
            synthetic_run("test.broken", Err(ExperimentError::Cancelled)),
        ];
        let dir = tempfile::tempdir().unwrap();
        Report::new(Mode::Quick, "abc123-dirty".into(), &runs)
            .write(dir.path())
            .unwrap();
        let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap();

        let json: Value = serde_json::from_str(&read("results.json")).unwrap();
        assert_eq!(json["mode"], "quick");
        assert_eq!(json["git_commit"], "abc123-dirty");
        let results = json["results"].as_array().unwrap();
        assert_eq!(results.len(), 3);
        let keys = [
            "id",
            "paper",
            "where",
            "quantity",
            "unit",
            "paper_value",
            "value",
            "tolerance",
            "verdict",
            "note",
        ];
        for row in results {
            let mut found: Vec<&str> = row
                .as_object()
                .unwrap()
                .keys()
                .map(String::as_str)
                .collect();
            found.sort_unstable();
            let mut expected = keys.to_vec();
            expected.sort_unstable();
            assert_eq!(found, expected);
        }
        assert_eq!(results[0]["where"], "Table 1");
        assert_eq!(results[0]["paper"], Paper::Stamper1997.file());
        assert_eq!(results[0]["verdict"], "pass");
        assert_eq!(results[1]["verdict"], "fail");
        assert!(results[2]["paper_value"].is_null());
        assert!(results[2]["tolerance"].is_null());
        assert_eq!(results[2]["verdict"], "info");
        assert_eq!(results[2]["value"], 1000.0);

        let md = read("report.md");
        assert!(md.contains("1 pass, 1 fail, 0 erratum, 1 info"), "{md}");
        assert!(
            md.contains("| test.synthetic | GCI | 0.5 | 0.9 | +0.4 (+80 %) | fail |"),
            "{md}"
        );
        assert!(md.contains("![Figure 3: volume convergence](test.synthetic.convergence.svg)"));
        assert!(md.contains("[volume](test.synthetic.volume.csv)"));
        assert!(md.contains("### `test.broken`: synthetic experiment"));
        assert!(md.contains("**error**: cancelled"));

        assert_eq!(
            read("test.synthetic.volume.csv"),
            "samples,\"volume, m^3\"\n100,1.5\n1000,0.1\n"
        );
        let line = read("test.synthetic.convergence.svg");
        for text in [
            "Figure 3: volume convergence",
            "samples",
            "volume (m^3)",
            "pkm",
            "paper",
        ] {
            assert!(line.contains(text), "line plot lacks {text}");
        }
        assert!(line.contains("<polyline") || line.contains("<path"));
        assert!(line.contains("<circle"));
        // The data behind every figure beside it, and linked from the report.
        assert!(read("test.synthetic.convergence.csv").starts_with("series,x,y\npkm,1,2\n"));
        assert!(read("test.synthetic.gci.csv").starts_with("x,y,z\n0,0,0.1\n1,0,\n"));
        assert!(md.contains("[convergence](test.synthetic.convergence.csv)"));
        let robot = read("test.synthetic.robot.svg");
        assert!(robot.contains("a two-link robot") && robot.contains("3-D"));
        assert_eq!(
            read("test.synthetic.robot.csv").lines().nth(2),
            Some("point,1,B,passive,0,0,1")
        );
        let heat = read("test.synthetic.gci.svg");
        for text in ["Figure 5: GCI landscape", "a (m)", "b (m)", "GCI"] {
            assert!(heat.contains(text), "heatmap lacks {text}");
        }
    }

    #[test]
    fn a_cancelled_run_keeps_the_previous_complete_report() {
        let dir = tempfile::tempdir().unwrap();
        let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap();
        let complete = [synthetic_run("test.synthetic", Ok(outcome()))];
        let written = Report::new(Mode::Full, "abc".into(), &complete)
            .write(dir.path())
            .unwrap();
        assert_eq!(written, dir.path().join("report.md"));
        let (json, md, csv) = (
            read("results.json"),
            read("report.md"),
            read("test.synthetic.volume.csv"),
        );
        assert_eq!(
            serde_json::from_str::<Value>(&json).unwrap()["cancelled"],
            false
        );
        let partial = [synthetic_run("test.other", Ok(Outcome::default()))];
        let written = Report::new(Mode::Quick, "def".into(), &partial)
            .cancelled(true)
            .write(dir.path())
            .unwrap();
        assert_eq!(written, dir.path().join("report.cancelled.md"));
        assert_eq!(read("results.json"), json);
        assert_eq!(read("report.md"), md);
        assert_eq!(read("test.synthetic.volume.csv"), csv);
        let cancelled: Value = serde_json::from_str(&read("results.cancelled.json")).unwrap();
        assert_eq!(cancelled["cancelled"], true);
        assert_eq!(cancelled["git_commit"], "def");
        assert!(read("report.cancelled.md").contains("**Cancelled**"));
        let leftovers: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .filter_map(Result::ok)
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    }

    #[test]
    fn summary_counts_verdicts_and_errors() {
        let runs = [
            synthetic_run("a", Ok(outcome())),
            synthetic_run("b", Err(ExperimentError::Cancelled)),
        ];
        assert_eq!(
            Summary::of(&runs).to_string(),
            "2 experiments, 1 errored; 1 pass, 1 fail, 0 erratum, 1 info"
        );
    }

    #[test]
    fn readme_table_replaces_only_the_text_between_markers() {
        let text = format!("# pkm\n\n{BEGIN}\nold table\n{END}\n\n## After\n");
        let rows = outcome().comparisons;
        let updated = replace_between_markers(&text, &table::markdown(&rows)).unwrap();
        assert!(updated.starts_with(&format!("# pkm\n\n{BEGIN}\n| id |")));
        assert!(updated.ends_with(&format!("| info |\n{END}\n\n## After\n")));
        assert!(!updated.contains("old table"));
        let again = replace_between_markers(&updated, &table::markdown(&rows)).unwrap();
        assert_eq!(again, updated);
        assert!(replace_between_markers("no markers", "").is_err());
    }

    #[test]
    fn git_commit_is_a_hash_or_unknown() {
        let commit = git_commit(&crate::reproduce::workspace_root());
        let hash = commit.trim_end_matches("-dirty");
        assert!(
            commit == "unknown"
                || (hash.len() == 40 && hash.chars().all(|c| c.is_ascii_hexdigit())),
            "{commit}"
        );
        assert_eq!(git_commit(Path::new("/")), "unknown");
    }
}
