//! Why a design has no value in a sweep, a Pareto study or an optimisation: a typed cause kept
//! through the study layer, so a caller tells an invalid design from an empty workspace or a
//! violated inequality without reading text. Tables and results write its message.

use crate::{KeyPath, StudyError};
use pkm_traits::{DesignError, ObjectiveError};
use pkm_workspace_indices::IndexError;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Why a design has no value: recorded with its node (in the result and the landscape), never
/// an abort of the study.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Infeasible {
    /// The library refuses the design's parameters.
    #[error(transparent)]
    Design(#[from] DesignError),
    /// The robot file at this design gives no model or no working mode.
    #[error("{}", located(.path.as_ref(), .message))]
    RobotFile {
        /// The offending key of the robot file, when the error names one.
        path: Option<KeyPath>,
        /// What is wrong.
        message: String,
    },
    /// An index of the design has no value for the library's reason (a cross-section without
    /// area, a quadrature that cannot resolve it).
    #[error(transparent)]
    Index(IndexError),
    /// No sampled point lies in the workspace, so `index` (the GCI η/W, an objective weighting
    /// it) has no value.
    #[error("empty workspace: no {index}")]
    EmptyWorkspace {
        /// The index without value.
        index: &'static str,
    },
    /// An index came out NaN or infinite.
    #[error("non-finite index value {values:?}")]
    NonFinite {
        /// The values at the design, in the study's order.
        values: Vec<f64>,
    },
    /// A linear inequality $g(x) = c^\top x - u \le 0$ of the design is violated.
    #[error("constraint `{name}` violated: g = {g:.3e} > 0")]
    Inequality {
        /// The inequality's name in the study.
        name: String,
        /// Its value $g(x) > 0$.
        g: f64,
    },
    /// A cross-section index asked of a mechanism without an exact cross-section.
    #[error(
        "{index} is an index of a mechanism with an exact cross-section (linear_delta), not of \
         {kind}"
    )]
    NoCrossSection {
        /// The index's key.
        index: &'static str,
        /// The mechanism's kind.
        kind: &'static str,
    },
    /// A name that is not a design variable of the mechanism (studies check their variables
    /// before any node runs).
    #[error("{0}")]
    Variable(String),
    /// The reason a shard of a split study wrote, read back by [`merge`](crate::merge()): its
    /// message alone.
    #[error("{0}")]
    Recorded(String),
}

fn located(path: Option<&KeyPath>, message: &str) -> String {
    match path {
        Some(path) => format!("{path}: {message}"),
        None => message.to_owned(),
    }
}

impl Infeasible {
    /// A robot file's refusal of a design (its key path kept).
    pub fn robot_file(error: StudyError) -> Self {
        match error {
            StudyError::Invalid { path, message } | StudyError::Schema { path, message, .. } => {
                Self::RobotFile {
                    path: Some(path),
                    message,
                }
            }
            e => Self::RobotFile {
                path: None,
                message: e.to_string(),
            },
        }
    }
}

/// An index failure: an invalid design keeps its library cause.
impl From<IndexError> for Infeasible {
    fn from(e: IndexError) -> Self {
        match e {
            IndexError::Design(design) => Self::Design(design),
            e => Self::Index(e),
        }
    }
}

/// The search's infeasible design, with the library's typed cause for an invalid design.
impl From<Infeasible> for ObjectiveError {
    fn from(infeasible: Infeasible) -> Self {
        match infeasible {
            Infeasible::Design(design) => design.into(),
            e => Self::infeasible(e.to_string()),
        }
    }
}

/// Written as its message (a shard's file, a result).
impl Serialize for Infeasible {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// Read back as [`Infeasible::Recorded`]: the message a shard wrote.
impl<'de> Deserialize<'de> for Infeasible {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        String::deserialize(deserializer).map(Self::Recorded)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_recorded_reason_reads_back_with_the_same_message() {
        let design = DesignError {
            parameter: "a",
            value: -1.0,
            requirement: "must be > 0",
        };
        for reason in [
            Infeasible::Design(design.clone()),
            Infeasible::EmptyWorkspace { index: "GCI" },
            Infeasible::Inequality {
                name: "sum".into(),
                g: 0.25,
            },
            Infeasible::robot_file(StudyError::invalid("legs[0].joints[1].axis", "zero length")),
        ] {
            let text = serde_json::to_string(&reason).unwrap();
            let back: Infeasible = serde_json::from_str(&text).unwrap();
            assert_eq!(back, Infeasible::Recorded(reason.to_string()), "{text}");
        }
        let e = ObjectiveError::from(Infeasible::Design(design.clone()));
        assert_eq!(e.cause(), Some(&design.into()));
        let path = Infeasible::robot_file(StudyError::invalid("legs[0].name", "empty"));
        assert_eq!(path.to_string(), "legs[0].name: empty");
    }
}
