//! The direction of an optimisation: every solver of this crate takes a [`Sense`], so a
//! maximisation is never written as the minimisation of a negated objective (which a sum of
//! squares $\lVert r \rVert^2$ cannot express as residuals).

use serde::{Deserialize, Serialize};

/// Whether the objective is minimised or maximised (`"minimise"` or `"maximise"` in a study
/// file).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sense {
    /// Find the smallest value.
    #[default]
    Minimise,
    /// Find the largest value.
    Maximise,
}

impl Sense {
    /// $\sigma = -1$ to minimise, $+1$ to maximise: a change $\Delta f$ improves when
    /// $\sigma\,\Delta f > 0$.
    pub(crate) fn sign(self) -> f64 {
        match self {
            Self::Minimise => -1.0,
            Self::Maximise => 1.0,
        }
    }

    /// `value` oriented so that smaller is better: itself to minimise, $-$`value` to maximise
    /// (a negation, exact in floating point).
    pub(crate) fn minimised(self, value: f64) -> f64 {
        match self {
            Self::Minimise => value,
            Self::Maximise => -value,
        }
    }

    /// `value` oriented so that larger is better: itself to maximise, $-$`value` to minimise
    /// (a negation, exact in floating point).
    pub(crate) fn goodness(self, value: f64) -> f64 {
        match self {
            Self::Minimise => -value,
            Self::Maximise => value,
        }
    }

    /// Whether `candidate` is strictly better than `incumbent` in this sense (a tie is not).
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::Sense;
    /// assert!(Sense::Minimise.improves(1.0, 2.0) && Sense::Maximise.improves(2.0, 1.0));
    /// assert!(!Sense::Minimise.improves(1.0, 1.0));
    /// ```
    pub fn improves(self, candidate: f64, incumbent: f64) -> bool {
        match self {
            Self::Minimise => candidate < incumbent,
            Self::Maximise => candidate > incumbent,
        }
    }

    /// Whether `candidate` is at least as good as `incumbent` in this sense.
    pub fn at_least_as_good(self, candidate: f64, incumbent: f64) -> bool {
        match self {
            Self::Minimise => candidate <= incumbent,
            Self::Maximise => candidate >= incumbent,
        }
    }

    /// The one rule by which every search of this crate picks its best among values in order
    /// (the starts of a [`crate::multistart`], the nodes of a grid, the weightings of a front):
    /// the position and value of the best value in this sense, where `None` (a failed start, an
    /// infeasible node) and NaN are never best and a tie goes to the lowest position, so the
    /// choice depends on the order of the values only, never on scheduling. `None` when no
    /// value qualifies.
    ///
    /// # Example
    /// ```
    /// use pkm_optimizers::Sense;
    /// let values = [Some(3.0), None, Some(f64::NAN), Some(1.0), Some(1.0), Some(7.0)];
    /// assert_eq!(Sense::Minimise.best(values), Some((3, 1.0)));
    /// assert_eq!(Sense::Maximise.best(values), Some((5, 7.0)));
    /// assert_eq!(Sense::Minimise.best([None, Some(f64::NAN)]), None);
    /// ```
    pub fn best(self, values: impl IntoIterator<Item = Option<f64>>) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (k, value) in values.into_iter().enumerate() {
            if let Some(v) = value
                && !v.is_nan()
                && best.is_none_or(|(_, b)| self.improves(v, b))
            {
                best = Some((k, v));
            }
        }
        best
    }
}
