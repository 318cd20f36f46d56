//! The direction of an optimisation: every solver of this crate takes a [`Sense`], so a
//! maximisation is never written as the minimisation of a negated objective (which a sum of
//! squares $\lVert r \rVert^2$ cannot express as residuals).

use serde::Serialize;

/// Whether the objective is minimised or maximised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
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
}
