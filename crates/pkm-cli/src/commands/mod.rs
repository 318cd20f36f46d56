//! The subcommands. Adding one is a module here with an `Args` type (clap `Args`) that
//! implements [`Run`], plus one line in the `subcommands!` invocation below.

use crate::CliError;
pub use crate::output::Report;
use crate::output::{Output, StudyEcho};
use crate::progress::Spinner;
use crate::study;
use pkm_study::{Outcome, StudyError};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// What every command receives: where to write and how to report progress.
#[derive(Debug)]
pub struct Context {
    /// The output directory (`--out`).
    pub out: PathBuf,
    /// Progress bar and Ctrl-C flag.
    pub progress: Spinner,
}

/// A subcommand's arguments know how to run it.
pub trait Run {
    /// Runs the command.
    ///
    /// # Errors
    /// Whatever stops the command; [`CliError::Cancelled`] on Ctrl-C.
    fn run(&self, context: &Context) -> Result<Report, CliError>;
}

pub mod assembly;
pub mod dynamics;
pub mod merge;
pub mod mjcf;
pub mod optimize;
pub mod pareto;
pub mod sweep;
pub mod task;
pub mod urdf;
pub mod workspace;

/// Declares the [`Command`] enum with one variant per subcommand module (its `Args`), and the
/// dispatch. The modules are declared outside the macro, so that rustfmt formats them.
macro_rules! subcommands {
    ($($(#[$doc:meta])* $variant:ident => $module:ident,)*) => {
        /// The subcommands of `pkm`.
        #[derive(Debug, clap::Subcommand)]
        pub enum Command {
            $($(#[$doc])* $variant($module::Args),)*
        }

        impl Command {
            /// The subcommand's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Self::$variant(_) => stringify!($module),)*
                }
            }

            /// Runs the subcommand.
            ///
            /// # Errors
            /// As the subcommand's [`Run::run`].
            pub fn run(&self, context: &Context) -> Result<Report, CliError> {
                match self {
                    $(Self::$variant(args) => Run::run(args, context),)*
                }
            }
        }
    };
}

subcommands! {
    /// Workspace volume ± standard error, η and GCI, slices and cross-sections of one design.
    Workspace => workspace,
    /// Exhaustive grid over design variables, weighted utility, refinement, landscape.
    Sweep => sweep,
    /// Non-dominated designs of two or more indices and the weights that select each.
    Pareto => pareto,
    /// Joins the outputs of `--shard 1/N … N/N` into the result of a single run.
    Merge => merge,
    /// Multistart constrained optimisation of a design, with first- and second-order checks.
    Optimize => optimize,
    /// Task-based synthesis (Wolf & Shoham): pose and geometry for weighted task twists, and
    /// the 3-UPU singularity search.
    Task => task,
    /// Inverse dynamics (Hamilton and Lagrange) of a rotary Delta along a trajectory, and the
    /// forward retrace with its constraint drift; or the actuator efforts of a robot file.
    Dynamics => dynamics,
    /// Every assembly mode of a robot file at given actuator coordinates or poses, by
    /// parameter homotopy where it has a polynomial form, with what the search guarantees.
    Assembly => assembly,
    /// A robot file with its masses as URDF plus its loop closures (closures.yaml), for
    /// tree-and-constraint tools such as Pinocchio.
    Urdf => urdf,
    /// A robot file with its masses as MuJoCo's MJCF (robot.xml): nested bodies, loops closed
    /// by connect and weld constraints, a motor per actuator.
    Mjcf => mjcf,
}

/// Runs a study of the study layer: reads the file at `path` with its schema (errors at their
/// line), runs `study` with the progress bar, writes its artifacts and `results.json`, and
/// reports its summary.
///
/// # Errors
/// The study's errors at the offending key's line, I/O errors, [`CliError::Cancelled`].
pub fn run_library_study<S: DeserializeOwned, R: Serialize>(
    command: &str,
    path: &Path,
    context: &Context,
    study: impl FnOnce(&S, &dyn pkm_traits::Progress) -> Result<Outcome<R>, StudyError>,
) -> Result<Report, CliError> {
    let (source, parsed) = study::load_study_source::<S>(path)?;
    let outcome = study(&parsed, &context.progress).map_err(|e| source.error(e))?;
    let mut report = Report {
        lines: outcome.summary,
    };
    let mut out = Output::create(&context.out)?;
    out.write_artifacts(&outcome.artifacts, &mut report)?;
    let echo = StudyEcho {
        file: path.display().to_string(),
        robot_file: source.robot_echo(),
        text: source.text().to_owned(),
    };
    let written = out.finish(command, echo, outcome.result)?;
    report.line(format!("wrote {}", written.display()));
    Ok(report)
}

/// Reads the robot file at `path` and converts it with `export` (`pkm urdf`, `pkm mjcf`): a
/// refused value is reported at its line and column in the file with the line's text, text
/// that does not parse with its own line and column.
///
/// # Errors
/// [`CliError::Study`] at the refused value, [`CliError::Invalid`] for text that does not
/// parse, I/O errors.
pub fn export_robot_file<T>(
    path: &Path,
    export: impl FnOnce(&str) -> Result<T, StudyError>,
) -> Result<T, CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::io(path, e))?;
    export(&text).map_err(|e| match e.path().filter(|key| !key.is_root()) {
        Some(key) => {
            let offset = pkm_study::files::locate(&text, key).start;
            let place = pkm_study::files::Place::at(&path.display().to_string(), &text, offset);
            CliError::Study {
                file: place.file,
                line: place.line,
                column: place.column,
                message: format!("{key}: {}\n    | {}", e.message(), place.source_line),
            }
        }
        None => CliError::Invalid(format!("{}: {}", path.display(), e.message())),
    })
}
