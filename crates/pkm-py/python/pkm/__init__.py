"""pkm: optimal design and dynamic modelling of parallel kinematic machines.

Mechanisms vectorised over NumPy arrays (:class:`Mechanism`) and the design studies of the
``pkm`` command as functions taking a dict or a TOML path (:func:`workspace`, :func:`sweep`,
:func:`pareto`, :func:`optimize`, :func:`task`, :func:`dynamics`, :func:`assembly`; :func:`merge` joins the shards of a split
sweep or Pareto study). Every
error is a :class:`pkm.Error`; study errors carry ``.key_path``.
"""

import os
from typing import Any, Callable, Dict, Iterable, List, Optional, Tuple, TypedDict, Union, cast

import numpy.typing as npt

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
from ._figure import Figure
from ._progress import Report
from ._progress import progress_bar as _progress_bar

Study = Union[Dict[str, Any], str, "os.PathLike[str]"]
"""A study: the dict of a study file, or the path of a TOML (or JSON) study file."""

Shard = Tuple[int, int]
"""``(i, n)``: the i-th (from 1) of n nearly equal blocks of grid nodes."""


class Outcome(TypedDict):
    """What a study returns: ``result`` is exactly the ``result`` of the command's
    ``results.json``; ``summary`` the lines it prints; ``tables`` each CSV file it writes as
    ``{column: array}``; ``figures`` each SVG file it writes."""

    result: Dict[str, Any]
    summary: List[str]
    tables: Dict[str, Dict[str, Any]]
    figures: Dict[str, Figure]


class Part(Outcome):
    """A shard of a split sweep or Pareto study (``shard=(i, n)``, n > 1), for :func:`merge`."""

    kind: str
    study: Dict[str, Any]

__all__ = [
    "MAX_POINTS",
    "Cancelled",
    "Error",
    "Figure",
    "Infeasible",
    "InvalidInput",
    "Mechanism",
    "NotConverged",
    "Outcome",
    "Part",
    "Shard",
    "Study",
    "__version__",
    "assembly",
    "dynamics",
    "merge",
    "optimize",
    "pareto",
    "presets",
    "sweep",
    "task",
    "workspace",
]


def _study(run: Callable[[Report], Dict[str, Any]], progress: bool) -> Outcome:
    """Calls ``run(report)`` with a tqdm callback when ``progress`` is true and tqdm is
    installed, else ``run(None)``, and wraps each figure's SVG text in a :class:`Figure`."""
    if not progress:
        raw = run(None)
    else:
        with _progress_bar() as report:
            raw = run(report)
    raw["figures"] = {name: Figure(name, svg) for name, svg in raw["figures"].items()}
    return cast(Outcome, raw)


def workspace(study: Study, *, progress: bool = True) -> Outcome:
    """The workspace study (``pkm workspace``) of ``study``, a dict or a TOML path.

    Returns an :class:`Outcome`: ``{"result": ..., "summary": [...], "tables": {name: {column:
    array}}, "figures": {name: Figure}}``; ``result`` is the ``result`` of the command's
    ``results.json``.
    Shows a tqdm bar when tqdm is installed and ``progress`` is true; Ctrl-C cancels the study
    within a fraction of a second and raises ``KeyboardInterrupt``.
    """
    return _study(lambda report: _native.workspace(study, report), progress)


def sweep(study: Study, shard: Optional[Shard] = None, *, progress: bool = True) -> Outcome:
    """The sweep study (``pkm sweep``) of ``study``, a dict or a TOML path: an exhaustive grid
    over design variables, a weighted utility Σ wᵢ ηᵢ, refinement around the grid optimum.

    Returns the outcome dict of :func:`workspace` (``result`` as in ``results.json``; the table
    ``"landscape.csv"`` has one array per column, the heat maps their tables).

    ``shard=(i, n)`` with 1 ≤ i ≤ n evaluates only the i-th of n nearly equal blocks of grid
    nodes (``pkm sweep --shard i/n``); for n > 1 it returns the part: ``result`` holds the nodes'
    values, ``kind`` is ``"sweep"`` and ``study`` the study as a plain dict, so that
    :func:`merge` of the n parts (on any machines, in any order) returns exactly what
    ``sweep(study)`` returns. Raises :class:`pkm.Error` subclasses with ``.key_path``;
    Ctrl-C cancels within a second.
    """
    return _study(lambda report: _native.sweep(study, shard, report), progress)


def pareto(study: Study, shard: Optional[Shard] = None, *, progress: bool = True) -> Outcome:
    """The Pareto study (``pkm pareto``) of ``study``, a dict or a TOML path: the
    non-dominated designs of two or more indices and, for two, the weights that select each.

    Returns the outcome dict of :func:`workspace`; ``result["front"]`` lists the front, and the
    table ``"front.csv"`` holds it as arrays. ``shard=(i, n)`` splits the grid as in
    :func:`sweep`; :func:`merge` joins the parts.
    """
    return _study(lambda report: _native.pareto(study, shard, report), progress)


def merge(parts: Iterable[Outcome], *, progress: bool = True) -> Outcome:
    """Joins the parts of a split study: the return values of ``sweep(study, shard=(i, n))``
    (or :func:`pareto`) for i = 1…n, in any order. Returns exactly what the study returns run
    whole, bit for bit. Raises :class:`pkm.InvalidInput` for parts that are not the n parts of
    one run of one study.
    """
    return _study(lambda report: _native.merge(parts, report), progress)


def optimize(study: Study, *, progress: bool = True) -> Outcome:
    """The optimisation study (``pkm optimize``) of ``study``, a dict or a TOML path:
    multistart constrained optimisation of a design with the first- and second-order checks at
    the optimum. Returns the outcome dict of :func:`workspace` (the starts as the table
    ``"starts.csv"``).
    """
    return _study(lambda report: _native.optimize(study, report), progress)


def task(study: Study, *, progress: bool = True) -> Outcome:
    """The task study (``pkm task``) of ``study``, a dict or a TOML path: Wolf & Shoham's
    task-based objective for a Stewart–Gough platform or a 3-UPU (``[mechanism.<kind>]``), the
    multistart over the chosen pose and design variables with the first- and second-order checks
    at the best start. Returns the outcome dict of :func:`workspace` (the starts as the table
    ``"starts.csv"``).
    """
    return _study(lambda report: _native.task(study, report), progress)


def assembly(study: Study, *, progress: bool = True) -> Outcome:
    """The assembly-mode study (``pkm assembly``) of ``study``, a dict or a TOML path: every
    assembly mode (forward-kinematics solution) of a ``[mechanism.robot_file]`` at the
    actuator coordinates or task poses of ``[assembly]`` (default: home), by parameter homotopy
    where the robot has a polynomial form, with the multistart added when the homotopy's report
    is not complete or the robot has no form. ``result["queries"][k]`` holds the modes (task and
    pose coordinates, home label, singularity margins), the homotopy's report (paths, real,
    complex, singular, at infinity, exceptional, refused, failed) and ``complete``: true when
    the modes are every real assembly mode. Returns the outcome dict of :func:`workspace` (the
    modes as the table ``"modes.csv"``).
    """
    return _study(lambda report: _native.assembly(study, report), progress)


def dynamics(
    study: Study,
    trajectory: Union[None, npt.ArrayLike, str, "os.PathLike[str]"] = None,
    *,
    progress: bool = True,
) -> Outcome:
    """The dynamics study (``pkm dynamics``) of ``study``, a dict or a TOML path: the motor
    torques of a rotary Delta by Hamilton and by Lagrange along a trajectory, and the forward
    retrace when ``[dynamics.forward]`` asks for it; or, for a ``[mechanism.robot_file]`` whose
    file has masses and gravity, the actuator efforts of any robot along a trajectory in its
    task coordinates (``result["efforts"]``: peaks, RMS and power per actuator).

    ``trajectory``, when given, is the motion: an N × 4 array of ``t, x, y, z`` rows (s, m;
    equally spaced times; for a robot file N × (1 + n) rows of ``t`` and its n task
    coordinates) or the path of a CSV file of such rows after a header line (relative to the
    working directory); it replaces the study's ``trajectory.csv`` or
    ``trajectory.positions``, and the study may then leave out its ``trajectory`` table. A
    study's own ``trajectory.csv`` is read relative to the study file (for a dict: the working
    directory), as the ``pkm`` command reads it.

    Returns the outcome dict of :func:`workspace`; the table ``"torques.csv"`` holds the torque
    histories (``t``, ``tau_hamilton_1`` … ``tau_lagrange_3``) as arrays, and for a robot file
    ``"efforts.csv"`` the efforts (``effort legs[0].joints[1]`` …), powers and energies.
    """
    return _study(lambda report: _native.dynamics(study, trajectory, report), progress)
