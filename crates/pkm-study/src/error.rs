//! Why a study cannot run, with the key path of the offending setting (`sweep.refine[1].step`)
//! so that every front end can point at it: the `pkm` command maps it to a file, line and
//! column, the Python package raises it with the path.

use crate::schema::index::IndexName;
use pkm_dynamics_hamilton::DynamicsError;
use pkm_optimizers::OptimizeError;
use pkm_screw_theory::ScrewError;
use pkm_traits::{IntegrationError, ObjectiveError};
use pkm_workspace_indices::IndexError;
use std::fmt;
use std::ops::Range;

/// One step of a [`KeyPath`]: a table key or an array index.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Key {
    /// A key of a table (a struct field or a map key).
    Field(String),
    /// An element of an array, from 0.
    Index(usize),
}

/// Where a setting sits in a study: the keys and indices from the top of the document.
///
/// Displays as `sweep.refine[1].step`; the empty path (the study as a whole) as `(study)`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub struct KeyPath(Vec<Key>);

impl KeyPath {
    /// The path of the study as a whole.
    pub fn root() -> Self {
        Self::default()
    }

    /// Parses a path written as it displays (`sweep.refine[1].step`); a malformed index is kept
    /// as part of its key.
    pub fn parse(text: &str) -> Self {
        let mut keys = Vec::new();
        for part in text.split('.').filter(|p| !p.is_empty()) {
            let (name, mut rest) = part.split_once('[').map_or((part, ""), |(n, r)| (n, r));
            if !name.is_empty() {
                keys.push(Key::Field(name.to_owned()));
            }
            while let Some((index, tail)) = rest.split_once(']') {
                match index.parse() {
                    Ok(i) => keys.push(Key::Index(i)),
                    Err(_) => keys.push(Key::Field(format!("[{index}]"))),
                }
                rest = tail.strip_prefix('[').unwrap_or(tail);
            }
        }
        Self(keys)
    }

    /// This path followed by the table key `name`.
    #[must_use]
    pub fn field(mut self, name: impl Into<String>) -> Self {
        self.0.push(Key::Field(name.into()));
        self
    }

    /// This path followed by the array index `index`.
    #[must_use]
    pub fn index(mut self, index: usize) -> Self {
        self.0.push(Key::Index(index));
        self
    }

    /// The steps, from the top of the document.
    pub fn keys(&self) -> &[Key] {
        &self.0
    }

    /// Whether this is the path of the study as a whole.
    pub fn is_root(&self) -> bool {
        self.0.is_empty()
    }
}

impl From<&str> for KeyPath {
    fn from(text: &str) -> Self {
        Self::parse(text)
    }
}

impl From<&serde_path_to_error::Path> for KeyPath {
    fn from(path: &serde_path_to_error::Path) -> Self {
        use serde_path_to_error::Segment;
        Self(
            path.iter()
                .filter_map(|segment| match segment {
                    Segment::Seq { index } => Some(Key::Index(*index)),
                    Segment::Map { key } | Segment::Enum { variant: key } => {
                        Some(Key::Field(key.clone()))
                    }
                    Segment::Unknown => None,
                })
                .collect(),
        )
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("(study)");
        }
        for (k, key) in self.0.iter().enumerate() {
            match key {
                Key::Field(name) if k == 0 => f.write_str(name)?,
                Key::Field(name) => write!(f, ".{name}")?,
                Key::Index(i) => write!(f, "[{i}]")?,
            }
        }
        Ok(())
    }
}

/// Why shard results do not make up one run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MergeError {
    /// Nothing to merge.
    #[error("no shard results to merge")]
    NoShards,
    /// Parts of runs split differently (shard counts or grid sizes differ).
    #[error("different shard counts or grids; merge only the shards of one run")]
    Mixed,
    /// Not every part exactly once.
    #[error("expected shards 1..={count} once each, got {got:?}")]
    Incomplete {
        /// N.
        count: usize,
        /// The parts given, in order.
        got: Vec<usize>,
    },
    /// A part that does not hold its nodes.
    #[error("shard {index}/{count} should hold nodes {expected:?}")]
    WrongNodes {
        /// I.
        index: usize,
        /// N.
        count: usize,
        /// Its nodes.
        expected: Range<usize>,
    },
    /// The parts evaluated other indices than the study asks for.
    #[error("the shards evaluated {got:?}, the study asks for {expected:?}")]
    OtherIndices {
        /// What the parts hold.
        got: Vec<IndexName>,
        /// What the study asks for.
        expected: Vec<IndexName>,
    },
    /// The parts cover another grid than the study's.
    #[error("the shards cover {got} nodes, the study's grid has {expected}")]
    OtherGrid {
        /// Nodes of the parts.
        got: usize,
        /// Nodes of the study's grid.
        expected: usize,
    },
}

/// Why a study cannot run or stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StudyError {
    /// The study does not have the schema's shape: a wrong type, an unknown or a missing key, a
    /// value out of its unit's range.
    #[error("{path}: {message}")]
    Schema {
        /// The offending setting (for an unknown key, the table that holds it).
        path: KeyPath,
        /// What is wrong and what was expected (with units).
        message: String,
        /// Byte range in the source text, when the data format knows it (TOML does).
        span: Option<Range<usize>>,
    },
    /// A setting that has the right shape but cannot be used (with the others, or by this
    /// mechanism).
    #[error("{path}: {message}")]
    Invalid {
        /// The offending setting.
        path: KeyPath,
        /// What is wrong and what was expected.
        message: String,
    },
    /// An index computation refused its input.
    #[error("{0}")]
    Index(IndexError),
    /// A search refused its settings or found no feasible design.
    #[error("{0}")]
    Optimize(OptimizeError),
    /// No node of a grid study has a value.
    #[error("no feasible design among {nodes} nodes (first reason: {reason})")]
    NoFeasibleDesign {
        /// Nodes evaluated.
        nodes: usize,
        /// Why the first infeasible node has no value.
        reason: String,
    },
    /// Shard results that are not the parts of one run of the study.
    #[error("{0}")]
    Merge(#[from] MergeError),
    /// The dynamics refused a sample (out of reach, singular, non-finite) with its time.
    #[error("{0}")]
    Dynamics(DynamicsError),
    /// A robot file's dynamics refused a sample (out of reach, singular, no gravity).
    #[error("sample {sample} (t = {time} s): {source}")]
    RobotDynamics {
        /// The sample's index, from 0.
        sample: usize,
        /// Its time (s).
        time: f64,
        /// Why.
        source: pkm_robot_file::DynamicsError,
    },
    /// The forward integration failed (tolerance not met, step budget spent, ...).
    #[error("forward integration: {0}")]
    Integration(IntegrationError),
    /// An objective could not be evaluated at a design a search returned.
    #[error("{0}")]
    Objective(ObjectiveError),
    /// A screw computation (a line set's rank, a twist) refused its input.
    #[error("{0}")]
    Screw(ScrewError),
    /// The caller's progress reporter asked to stop.
    #[error("cancelled")]
    Cancelled,
}

impl StudyError {
    /// [`StudyError::Invalid`] at `path`.
    pub fn invalid(path: impl Into<KeyPath>, message: impl Into<String>) -> Self {
        Self::Invalid {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The setting this error is about, when it is about one.
    pub fn path(&self) -> Option<&KeyPath> {
        match self {
            Self::Schema { path, .. } | Self::Invalid { path, .. } => Some(path),
            _ => None,
        }
    }

    /// The message without its key path.
    pub fn message(&self) -> String {
        match self {
            Self::Schema { message, .. } | Self::Invalid { message, .. } => message.clone(),
            e => e.to_string(),
        }
    }
}

impl From<IndexError> for StudyError {
    fn from(e: IndexError) -> Self {
        match e {
            IndexError::Cancelled => Self::Cancelled,
            e => Self::Index(e),
        }
    }
}

impl From<OptimizeError> for StudyError {
    fn from(e: OptimizeError) -> Self {
        match e {
            OptimizeError::Cancelled => Self::Cancelled,
            e => Self::Optimize(e),
        }
    }
}

impl From<DynamicsError> for StudyError {
    fn from(e: DynamicsError) -> Self {
        match e {
            DynamicsError::Integration(e) => e.into(),
            e => Self::Dynamics(e),
        }
    }
}

impl From<ObjectiveError> for StudyError {
    fn from(e: ObjectiveError) -> Self {
        match e {
            ObjectiveError::Cancelled => Self::Cancelled,
            e => Self::Objective(e),
        }
    }
}

impl From<IntegrationError> for StudyError {
    fn from(e: IntegrationError) -> Self {
        match e {
            IntegrationError::Cancelled => Self::Cancelled,
            e => Self::Integration(e),
        }
    }
}

impl From<pkm_traits::Cancelled> for StudyError {
    fn from(_: pkm_traits::Cancelled) -> Self {
        Self::Cancelled
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_display_as_written_and_parse_back() {
        let path = KeyPath::root()
            .field("sweep")
            .field("refine")
            .index(1)
            .field("step");
        assert_eq!(path.to_string(), "sweep.refine[1].step");
        assert_eq!(KeyPath::parse("sweep.refine[1].step"), path);
        assert_eq!(KeyPath::parse("a[0][2]").keys().len(), 3);
        assert_eq!(KeyPath::root().to_string(), "(study)");
    }
}
