"""Progress of a running study as tqdm bars (one per task), or nothing without tqdm."""

import contextlib
from typing import Any, Callable, Dict, Iterator, Optional

Report = Optional[Callable[[int, str, int, int], None]]
"""A progress callback ``report(task, label, done, total)``, or None."""


@contextlib.contextmanager
def progress_bar() -> Iterator[Report]:
    """Yields a callback ``report(task, label, done, total)`` that drives tqdm bars, or None
    when tqdm is not installed; closes the last bar on exit."""
    try:
        from tqdm.auto import tqdm
    except ImportError:
        yield None
        return
    state: Dict[str, Any] = {"task": None, "bar": None}

    def report(task: int, label: str, done: int, total: int) -> None:
        if state["task"] != task:
            if state["bar"] is not None:
                state["bar"].close()
            state["task"] = task
            state["bar"] = tqdm(total=total or None, desc=label, leave=False)
        bar = state["bar"]
        bar.update(done - bar.n)

    try:
        yield report
    finally:
        if state["bar"] is not None:
            state["bar"].close()
