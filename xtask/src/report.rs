//! The files of a run: `results.json`, `report.md`, one CSV per table, one SVG per figure and
//! the CSV of its data;
//! and the reproduction table of `README.md`.

use crate::run::{ExperimentRun, Summary};
use crate::{figure, table};
use anyhow::{Context as _, bail};
use pkm::papers::{Comparison, Figure, Mode, Outcome, Table};
use pkm_term::OutputDir;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

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
    /// Every file is written atomically (temporary file, then rename), `results.json` and
    /// `report.md` last. A cancelled run writes only `results.cancelled.json` and
    /// `report.cancelled.md`, both with `cancelled: true`, and leaves every file of the previous
    /// complete report as it was.
    ///
    /// # Errors
    /// When a file cannot be written or a figure cannot be rendered.
    pub(crate) fn write(&self, dir: &Path) -> anyhow::Result<std::path::PathBuf> {
        let mut out = OutputDir::create(dir)?;
        if self.cancelled {
            out.write("results.cancelled.json", self.json()?.as_bytes())?;
            return Ok(out.write("report.cancelled.md", self.markdown().as_bytes())?);
        }
        for run in self.runs {
            let Ok(outcome) = &run.outcome else { continue };
            let id = run.experiment.id;
            for t in &outcome.tables {
                out.write(&format!("{id}.{}.csv", t.name), csv(t).as_bytes())?;
            }
            for f in &outcome.figures {
                let name = format!("{id}.{}.svg", f.name);
                let svg = figure::svg(f).with_context(|| name.clone())?;
                out.write(&name, svg.as_bytes())?;
                if let Some(stem) = figure_csv_name(outcome, f) {
                    out.write(&format!("{id}.{stem}.csv"), figure::csv(f).as_bytes())?;
                }
            }
        }
        out.write("results.json", self.json()?.as_bytes())?;
        Ok(out.write("report.md", self.markdown().as_bytes())?)
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
        let _ = write!(
            md,
            "\n![{}]({}.{}.svg)\n",
            figure.title(),
            e.id,
            figure.name
        );
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
    let field = figure::field;
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
    let updated = replace_between_markers(&text, &block, BEGIN, END)?;
    std::fs::write(readme, updated).with_context(|| readme.display().to_string())
}

/// `text` with what lies between the markers `begin` and `end` replaced by `table`.
///
/// # Errors
/// When a marker is missing or `end` comes before `begin`.
pub(crate) fn replace_between_markers(
    text: &str,
    table: &str,
    begin_marker: &str,
    end_marker: &str,
) -> anyhow::Result<String> {
    let (Some(begin), Some(end)) = (text.find(begin_marker), text.find(end_marker)) else {
        bail!("the file lacks the markers {begin_marker} … {end_marker}");
    };
    if end < begin {
        bail!("the file has {end_marker} before {begin_marker}");
    }
    let head = &text[..begin + begin_marker.len()];
    Ok(format!("{head}\n{table}{}", &text[end..]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::tests::synthetic_run;
    use pkm::draw::chart::{Chart, Heatmap, Quantity, Series};
    use pkm::draw::{Link, LinkKind, PointKind, Scene, Skeleton, SkeletonPoint};
    use pkm::papers::{ExperimentError, Figure, Outcome, Paper, Source};
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
                Figure::chart(
                    "convergence",
                    Chart::series(
                        "Figure 3: volume convergence",
                        "samples",
                        Quantity::new("volume", "m^3"),
                        vec![
                            Series::line("pkm", vec![(1.0, 2.0), (2.0, 1.5), (4.0, 1.7)]),
                            Series::points("paper", vec![(1.0, 2.1), (4.0, 1.6)]),
                        ],
                    ),
                ),
                Figure::chart(
                    "gci",
                    Chart::heatmap(
                        "Figure 5: GCI landscape",
                        Quantity::new("a", "m"),
                        Quantity::new("b", "m"),
                        Heatmap {
                            colour_axis: "GCI".into(),
                            x: vec![0.0, 1.0, 2.0],
                            y: vec![0.0, 0.5],
                            values: vec![Some(0.1), None, Some(0.3), Some(0.4), Some(0.5), None],
                        },
                    ),
                ),
                Figure::robot(
                    "robot",
                    "a two-link robot",
                    Scene::new(Skeleton {
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
                    "m",
                ),
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
            .filter(|e| e.file_name().to_string_lossy().contains(".partial"))
            .collect();
        assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    }

    #[test]
    fn readme_table_replaces_only_the_text_between_markers() {
        let text = format!("# pkm\n\n{BEGIN}\nold table\n{END}\n\n## After\n");
        let rows = outcome().comparisons;
        let updated = replace_between_markers(&text, &table::markdown(&rows), BEGIN, END).unwrap();
        assert!(updated.starts_with(&format!("# pkm\n\n{BEGIN}\n| id |")));
        assert!(updated.ends_with(&format!("| info |\n{END}\n\n## After\n")));
        assert!(!updated.contains("old table"));
        let again = replace_between_markers(&updated, &table::markdown(&rows), BEGIN, END).unwrap();
        assert_eq!(again, updated);
        assert!(replace_between_markers("no markers", "", BEGIN, END).is_err());
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
