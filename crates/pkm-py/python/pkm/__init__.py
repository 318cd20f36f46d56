"""pkm: optimal design and dynamic modelling of parallel kinematic machines.

Mechanisms vectorised over NumPy arrays (:class:`Mechanism`) and the design studies of the
``pkm`` command as functions taking a dict or a TOML path (:func:`workspace`, ...). Every
error is a :class:`pkm.Error`; study errors carry ``.key_path``.
"""

from . import _native
from ._native import (
    MAX_POINTS,
    Cancelled,
    Error,
    Infeasible,
    InvalidInput,
    Mechanism,
    NotConverged,
    __version__,
    presets,
)
from ._progress import progress_bar as _progress_bar

__all__ = [
    "MAX_POINTS",
    "Cancelled",
    "Error",
    "Infeasible",
    "InvalidInput",
    "Mechanism",
    "NotConverged",
    "__version__",
    "presets",
    "workspace",
]


def _study(run, study, progress):
    """Runs a native study with a tqdm bar when ``progress`` is true and tqdm is installed."""
    if not progress:
        return run(study)
    with _progress_bar() as report:
        return run(study, report)


def workspace(study, *, progress=True):
    """The workspace study (``pkm workspace``) of ``study``, a dict or a TOML path.

    Returns ``{"result": ..., "summary": [...], "tables": {name: {column: array}},
    "figures": [...]}``; ``result`` is the ``result`` of the command's ``results.json``.
    Shows a tqdm bar when tqdm is installed and ``progress`` is true; Ctrl-C cancels the study
    within a fraction of a second and raises ``KeyboardInterrupt``.
    """
    return _study(_native.workspace, study, progress)
