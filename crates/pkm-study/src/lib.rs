//! Design studies of parallel kinematic machines as a library.
//!
//! A study is plain serde data (read it from TOML with [`from_toml_str`], from JSON with
//! [`from_json_str`], or from any serde data model with [`from_deserializer`]: a Python dict
//! is a study too). One function per study kind takes the study and a
//! [`Progress`](pkm_traits::Progress) reporter (which also carries cancellation) and returns an
//! [`Outcome`]: the typed result, the tables and figures that belong with it, and a short
//! summary. Nothing here prints or writes files; the `pkm` command and the Python package are
//! front ends that do.
//!
//! Every error names the key path of the offending setting ([`KeyPath`], e.g.
//! `sweep.refine[1].step`), so a front end can point at it: the `pkm` command maps it to a
//! file, line and column.
//!
//! ```
//! use pkm_study::{from_json_str, workspace, WorkspaceStudy};
//! use pkm_traits::Silent;
//!
//! let study: WorkspaceStudy = from_json_str(r#"{
//!     "mechanism": { "tsai": { "a": 0.2, "b": 0.3 } },
//!     "sampling": { "points": 4096, "replicates": 2 }
//! }"#)?;
//! let outcome = workspace(&study, &Silent)?;
//! assert!(outcome.result.estimate.volume > 0.0);
//! # Ok::<(), pkm_study::StudyError>(())
//! ```

mod error;
pub mod optimize;
pub mod outcome;
mod parse;
pub mod scene;
pub mod schema;
pub mod tsai;
pub mod workspace;

pub use error::{Key, KeyPath, StudyError};
pub use optimize::{OptimizeResult, OptimizeStudy, optimize};
pub use outcome::{Artifact, Cell, Outcome, Table, short};
pub use parse::{from_deserializer, from_json_str, from_toml_str};
pub use workspace::{WorkspaceResult, WorkspaceStudy, workspace};
