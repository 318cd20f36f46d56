//! Progress on the terminal (indicatif) and cooperative cancellation on Ctrl-C (ctrlc).

use indicatif::{ProgressBar, ProgressStyle};
use pkm_traits::Progress;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

/// Set by the first Ctrl-C; experiments see it through [`Progress::is_cancelled`].
#[derive(Debug, Clone, Default)]
pub(crate) struct CancelFlag(Arc<AtomicBool>);

impl CancelFlag {
    /// The process-wide flag that the first Ctrl-C sets; a second Ctrl-C exits at once (status
    /// 130). The handler is installed on the first call.
    ///
    /// # Errors
    /// When the signal handler cannot be installed.
    pub(crate) fn on_ctrl_c() -> anyhow::Result<Self> {
        static FLAG: OnceLock<Result<CancelFlag, String>> = OnceLock::new();
        let installed = FLAG.get_or_init(|| {
            let flag = Self::default();
            let handler_flag = flag.clone();
            ctrlc::set_handler(move || {
                if handler_flag.0.swap(true, Ordering::SeqCst) {
                    std::process::exit(130);
                }
                eprintln!("\ncancelling: waiting for the running experiment to stop (Ctrl-C again to abort)");
            })
            .map(|()| flag)
            .map_err(|e| e.to_string())
        });
        installed.clone().map_err(anyhow::Error::msg)
    }

    /// Sets the flag, as Ctrl-C does.
    #[cfg(test)]
    pub(crate) fn set(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether Ctrl-C was pressed.
    pub(crate) fn is_set(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}

/// A spinner for one experiment (label and elapsed time) that turns into a bar while the
/// experiment reports a task with a known total.
#[derive(Debug)]
pub(crate) struct Spinner {
    bar: ProgressBar,
    cancel: CancelFlag,
}

const SPINNER: &str = "{spinner} [{elapsed_precise}] {prefix} {msg}";
const BAR: &str = "{spinner} [{elapsed_precise}] {prefix} {msg} {wide_bar} {pos}/{len} (eta {eta})";

fn style(template: &str) -> ProgressStyle {
    ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_spinner())
}

impl Spinner {
    /// Starts the spinner of experiment `id` (drawn on stderr, hidden when it is not a terminal).
    pub(crate) fn new(id: &str, cancel: CancelFlag) -> Self {
        let bar = ProgressBar::new_spinner()
            .with_style(style(SPINNER))
            .with_prefix(id.to_owned());
        bar.enable_steady_tick(Duration::from_millis(120));
        Self { bar, cancel }
    }

    /// Removes the spinner; the caller prints the outcome.
    pub(crate) fn close(&self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for Spinner {
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
