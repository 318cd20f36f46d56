//! Progress on the terminal (indicatif) and cooperative cancellation on Ctrl-C (ctrlc): the
//! first Ctrl-C asks the running computation to stop at its next check, a second one exits at
//! once (status 130).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pkm_traits::Progress;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

/// Set by the first Ctrl-C; computations see it through [`Progress::is_cancelled`].
#[derive(Debug, Clone, Default)]
pub struct CancelFlag(Arc<AtomicBool>);

impl CancelFlag {
    /// The process-wide flag that Ctrl-C sets (the handler is installed on the first call;
    /// later calls return the same flag).
    ///
    /// # Errors
    /// ctrlc's message when the signal handler cannot be installed (another handler is
    /// already installed, or the platform refuses).
    pub fn on_ctrl_c() -> Result<Self, String> {
        static FLAG: OnceLock<Result<CancelFlag, String>> = OnceLock::new();
        FLAG.get_or_init(|| {
            let flag = Self::default();
            let handler_flag = flag.clone();
            ctrlc::set_handler(move || {
                if handler_flag.0.swap(true, Ordering::SeqCst) {
                    std::process::exit(130);
                }
                eprintln!("\ncancelling: waiting for the running computation to stop (Ctrl-C again to abort)");
            })
            .map(|()| flag)
            .map_err(|e| e.to_string())
        })
        .clone()
    }

    /// Sets the flag, as Ctrl-C does.
    pub fn set(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether cancellation was asked for.
    pub fn is_set(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}

/// A spinner (label and elapsed time) that turns into a bar while a task with a known total
/// runs; drawn on stderr, hidden when stderr is not a terminal or when `quiet`.
#[derive(Debug)]
pub struct Spinner {
    bar: ProgressBar,
    cancel: CancelFlag,
}

const SPINNER: &str = "{spinner} [{elapsed_precise}] {prefix} {msg}";
const BAR: &str = "{spinner} [{elapsed_precise}] {prefix} {msg} {wide_bar} {pos}/{len} (eta {eta})";

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_spinner())
}

impl Spinner {
    /// Starts the spinner of command `name`.
    pub fn new(name: &str, cancel: CancelFlag, quiet: bool) -> Self {
        let bar = ProgressBar::new_spinner()
            .with_style(style(SPINNER))
            .with_prefix(name.to_owned());
        if quiet {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        } else {
            bar.enable_steady_tick(Duration::from_millis(120));
        }
        Self { bar, cancel }
    }

    /// A spinner that draws nothing and is cancelled by `cancel` only (for tests).
    pub fn hidden(cancel: CancelFlag) -> Self {
        Self::new("", cancel, true)
    }

    /// Removes the spinner.
    pub fn close(&self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for Spinner {
    /// Shows `message` after the prefix (a phase of the command).
    fn phase(&self, message: &str) {
        self.bar.set_style(style(SPINNER));
        self.bar.set_message(message.to_owned());
    }

    fn start(&self, label: &str, total: u64) {
        self.bar.set_style(style(BAR));
        self.bar.set_length(total);
        self.bar.set_position(0);
        self.bar.set_message(label.to_owned());
    }

    fn advance(&self, n: u64) {
        self.bar.inc(n);
    }

    fn finish(&self) {
        self.bar.set_style(style(SPINNER));
        self.bar.set_message("");
    }

    fn is_cancelled(&self) -> bool {
        self.cancel.is_set()
    }
}
