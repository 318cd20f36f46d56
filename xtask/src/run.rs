//! What a run of the experiments produced: each [`ExperimentRun`], and the [`Summary`] of their
//! verdicts (shared by the command, which prints it, and the report, which writes it).

use pkm::papers::{Comparison, Experiment, ExperimentError, Outcome, Verdict};
use std::fmt;
use std::time::Duration;

/// One experiment as it ran.
#[derive(Debug)]
pub(crate) struct ExperimentRun {
    /// The experiment.
    pub(crate) experiment: Experiment,
    /// Wall time.
    pub(crate) elapsed: Duration,
    /// What it produced, or why it produced nothing.
    pub(crate) outcome: Result<Outcome, ExperimentError>,
}

impl ExperimentRun {
    /// Its comparisons (none when it failed to run).
    pub(crate) fn comparisons(&self) -> &[Comparison] {
        self.outcome.as_ref().map_or(&[], |o| &o.comparisons)
    }
}

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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use pkm::papers::{Context, Paper, Source};

    fn passing(_: &Context<'_>) -> Result<Outcome, ExperimentError> {
        Ok(Outcome::default())
    }

    /// A run of a synthetic experiment `id` with `outcome`.
    pub(crate) fn synthetic_run(
        id: &'static str,
        outcome: Result<Outcome, ExperimentError>,
    ) -> ExperimentRun {
        ExperimentRun {
            experiment: Experiment {
                id,
                paper: Paper::WolfShoham,
                title: "synthetic experiment",
                run: passing,
            },
            elapsed: Duration::from_millis(1250),
            outcome,
        }
    }

    #[test]
    fn summary_counts_verdicts_and_errors() {
        let source = Source::new("a", Paper::Stamper1997, "Table 1");
        let outcome = Outcome {
            comparisons: vec![
                source.check("V", "m^3", 2.0, 2.05, 0.1),
                source.check("GCI", "", 0.5, 0.9, 0.1),
                source.info("n", "", 1000.0),
            ],
            ..Outcome::default()
        };
        let runs = [
            synthetic_run("a", Ok(outcome)),
            synthetic_run("b", Err(ExperimentError::Cancelled)),
        ];
        assert_eq!(runs[1].comparisons().len(), 0);
        assert_eq!(
            Summary::of(&runs).to_string(),
            "2 experiments, 1 errored; 1 pass, 1 fail, 0 erratum, 1 info"
        );
    }
}
