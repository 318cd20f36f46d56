//! Running a study off the main thread: the study runs on a worker thread (its parallel
//! loops on rayon) with the GIL released, while the main thread polls
//! [`Python::check_signals`] every [`POLL`] and forwards progress to a Python callback. On
//! Ctrl-C the [`Bridge`] asks the study to stop (cooperative cancellation through
//! [`Progress`]), the worker is joined and `KeyboardInterrupt` is raised.

use pkm_traits::Progress;
use pyo3::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

/// How often the main thread looks for signals and reports progress.
const POLL: Duration = Duration::from_millis(50);

/// The [`Progress`] a study reports to: counters read by the main thread, and the cancel flag.
#[derive(Debug, Default)]
pub(crate) struct Bridge {
    cancelled: AtomicBool,
    done: AtomicU64,
    total: AtomicU64,
    /// The current task's label and a counter of tasks started (so a new task with the same
    /// label still opens a new bar).
    task: Mutex<(String, u64)>,
}

impl Progress for Bridge {
    fn phase(&self, message: &str) {
        self.begin(message, 0);
    }
    fn start(&self, label: &str, total: u64) {
        self.begin(label, total);
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }
    fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }
}

impl Bridge {
    fn begin(&self, label: &str, total: u64) {
        if let Ok(mut task) = self.task.lock() {
            self.done.store(0, Ordering::Relaxed);
            self.total.store(total, Ordering::Relaxed);
            task.0 = label.to_owned();
            task.1 += 1;
        }
    }

    /// (task number, label, done, total) as they stand.
    fn snapshot(&self) -> (u64, String, u64, u64) {
        let (label, number) = self
            .task
            .lock()
            .map(|t| (t.0.clone(), t.1))
            .unwrap_or_default();
        let done = self.done.load(Ordering::Relaxed);
        (number, label, done, self.total.load(Ordering::Relaxed))
    }
}

/// Runs `work` on a worker thread with the GIL released, reporting to `callback(task, label,
/// done, total)` (when given) and cancelling on a pending signal, which is then raised.
///
/// # Errors
/// The signal's exception (`KeyboardInterrupt`) after the worker stopped, or the callback's.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&Bridge) -> T + Send,
) -> PyResult<T> {
    let bridge = Bridge::default();
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| work(&bridge));
        let mut reported = None;
        loop {
            let finished = py.detach(|| {
                let deadline = std::time::Instant::now() + POLL;
                while !worker.is_finished() && std::time::Instant::now() < deadline {
                    std::thread::sleep(Duration::from_millis(5));
                }
                worker.is_finished()
            });
            let step = report(callback, &bridge, &mut reported);
            let signal = py.check_signals();
            if let Err(e) = step.and(signal) {
                bridge.cancelled.store(true, Ordering::Relaxed);
                let _ = py.detach(|| worker.join());
                return Err(e);
            }
            if finished {
                return worker.join().map_err(|_| {
                    crate::errors::raise(
                        py,
                        crate::errors::Kind::Other,
                        "the study stopped unexpectedly".into(),
                        None,
                    )
                });
            }
        }
    })
}

/// Calls `callback` when the progress changed since `reported`.
fn report(
    callback: Option<&Bound<'_, PyAny>>,
    bridge: &Bridge,
    reported: &mut Option<(u64, String, u64, u64)>,
) -> PyResult<()> {
    let Some(callback) = callback else {
        return Ok(());
    };
    let now = bridge.snapshot();
    if reported.as_ref() != Some(&now) && now.0 > 0 {
        callback.call1(now.clone())?;
        *reported = Some(now);
    }
    Ok(())
}
