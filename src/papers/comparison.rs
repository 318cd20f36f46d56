//! One reported quantity compared with the paper.

use serde::Serialize;

/// How a computed value relates to the paper's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// Within tolerance of the paper's value.
    Pass,
    /// Outside tolerance, with no documented reason: the reproduction fails.
    Fail,
    /// Outside tolerance because the paper's value is wrong; `docs/conventions.md` documents the
    /// evidence under the anchor named in the note.
    Erratum,
    /// A quantity the paper does not print (or cannot be compared), reported for information.
    Info,
}

/// A computed quantity, the paper's value and the verdict; one row of `results.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// Experiment id, as in `../shared/spec/README.md` (`miller2004.linear_delta.table2.row4`).
    pub id: String,
    /// File name of the paper.
    pub paper: &'static str,
    /// Where in the paper (`"Table 2 row 4"`, `"§4.1"`).
    #[serde(rename = "where")]
    pub location: String,
    /// Quantity name, as in `../shared/spec/README.md` (`"L1/YR"`).
    pub quantity: String,
    /// Unit (`""` when dimensionless).
    pub unit: String,
    /// The paper's value; `None` when the paper does not print it.
    pub paper_value: Option<f64>,
    /// The computed value.
    pub value: f64,
    /// Admissible absolute deviation from the paper's value; `None` for `info` rows.
    pub tolerance: Option<f64>,
    /// The verdict.
    pub verdict: Verdict,
    /// Why the tolerance is what it is, how the value was computed, or the erratum's evidence.
    pub note: String,
}

/// Where a group of comparisons comes from: experiment id, paper and location in the paper.
///
/// ```
/// use pkm::papers::{Paper, Source, Verdict};
/// let source = Source::new("wolf2006.s4_1.lambda1", Paper::WolfShoham, "§4.1");
/// let row = source.check("F", "", 400.3, 404.9, 8.0);
/// assert_eq!(row.verdict, Verdict::Pass);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Source {
    id: String,
    paper: super::Paper,
    location: String,
}

impl Source {
    /// Comparisons of experiment `id` with `paper` at `location` (`"Table 2 row 4"`).
    pub fn new(id: &str, paper: super::Paper, location: &str) -> Self {
        Self {
            id: id.to_owned(),
            paper,
            location: location.to_owned(),
        }
    }

    /// The same paper and location under another experiment id.
    pub fn with_id(&self, id: &str) -> Self {
        Self {
            id: id.to_owned(),
            ..self.clone()
        }
    }

    /// A comparison against a printed value: `pass` when `|value − paper_value| ≤ tolerance`,
    /// `fail` otherwise (also when `value` is not finite).
    pub fn check(
        &self,
        quantity: &str,
        unit: &str,
        paper_value: f64,
        value: f64,
        tolerance: f64,
    ) -> Comparison {
        let within = (value - paper_value).abs() <= tolerance;
        Comparison {
            paper_value: Some(paper_value),
            tolerance: Some(tolerance),
            verdict: if within { Verdict::Pass } else { Verdict::Fail },
            ..self.info(quantity, unit, value)
        }
    }

    /// A quantity the paper does not print, reported for information.
    pub fn info(&self, quantity: &str, unit: &str, value: f64) -> Comparison {
        Comparison {
            id: self.id.clone(),
            paper: self.paper.file(),
            location: self.location.clone(),
            quantity: quantity.to_owned(),
            unit: unit.to_owned(),
            paper_value: None,
            value,
            tolerance: None,
            verdict: Verdict::Info,
            note: String::new(),
        }
    }
}

impl Comparison {
    /// Marks a failed comparison as a documented erratum of the paper.
    ///
    /// `anchor` is the heading id in `docs/conventions.md` that holds the evidence (a tidy test
    /// checks it exists). A comparison that passes stays `pass`: an erratum is never claimed for
    /// a value that reproduces.
    pub fn erratum(mut self, anchor: &str) -> Self {
        if self.verdict == Verdict::Fail {
            self.verdict = Verdict::Erratum;
            let evidence = format!("erratum, evidence in docs/conventions.md#{anchor}");
            self.note = if self.note.is_empty() {
                evidence
            } else {
                format!("{evidence}; {}", self.note)
            };
        }
        self
    }

    /// [`Comparison::erratum`] while `evidence` holds: the paper's error, shown by a quantity
    /// computed in the same run. Without the evidence the comparison stays as it is, so a value
    /// that leaves its tolerance fails.
    pub fn erratum_if(self, evidence: bool, anchor: &str) -> Self {
        if evidence { self.erratum(anchor) } else { self }
    }

    /// Attaches a note.
    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        let note = note.into();
        self.note = if self.note.is_empty() {
            note
        } else {
            format!("{}; {note}", self.note)
        };
        self
    }

    /// `value − paper_value`, when the paper prints a value.
    pub fn deviation(&self) -> Option<f64> {
        self.paper_value.map(|p| self.value - p)
    }
}
