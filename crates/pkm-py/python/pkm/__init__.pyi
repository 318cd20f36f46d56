"""Type stubs of pkm (the extension module pkm._native and its Python wrappers)."""

import os
from typing import Any, Callable, Dict, Iterable, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
MAX_POINTS: int
"""Largest number of rows a kernel takes in one call (larger inputs raise InvalidInput)."""

Study = Union[Dict[str, Any], str, "os.PathLike[str]"]
"""A study: the dict of a study file, or the path of a TOML (or JSON) study file."""

Points = npt.ArrayLike
"""An N × 3 array of real numbers (float64 read in place, any strides; other real dtypes converted)."""

class Error(Exception):
    """Every error of pkm."""

    key_path: Optional[str]
    """The study setting the error is about (``"sweep.refine[1].step"``), or None."""

class InvalidInput(Error):
    """An argument, a design or a study setting that violates its requirement."""

class Infeasible(Error):
    """No feasible design or pose."""

class NotConverged(Error):
    """An iterative solver stopped before its tolerance."""

class Cancelled(Error):
    """The computation was cancelled."""

class Mechanism:
    """A parallel kinematic machine from a preset name or a ``[mechanism]`` dict (a robot file
    as ``{"robot_file": {"file": "robots/tsai.toml"}}``, read from the working directory, or
    its keys inline), under a ``[constraints]`` dict."""

    def __init__(self, design: Union[str, Dict[str, Any]], constraints: Optional[Dict[str, Any]] = None) -> None: ...
    @property
    def kind(self) -> str:
        """The mechanism kind (``"rotary_delta"``, ``"tsai"``, ...)."""
    @property
    def joints(self) -> int:
        """The number of actuated joints (3, or 6 for the Stewart–Gough platform)."""
    @property
    def variables(self) -> List[str]:
        """The design variables a sweep may vary."""
    @property
    def task(self) -> List[str]:
        """The task coordinates, the columns of every ``points`` array: ``["x", "y", "z"]`` (m), or
        a robot file's own (``["z", "tilt_x", "tilt_y"]``: m and rad)."""
    def design(self) -> Dict[str, Any]:
        """The ``[mechanism]`` and ``[constraints]`` tables as a dict."""
    def inverse_kinematics(self, points: Points) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """Joints (N × joints) and the inside mask; outside rows are NaN."""
    def velocity_jacobian(self, points: Points) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """J = -J_q⁻¹ J_x (N × joints × n, n = len(task)) and the mask of rows where it is defined."""
    def local_indices(self, points: Points) -> Dict[str, npt.NDArray[Any]]:
        """``{"inverse_condition": (N,), "inside": (N,) bool}``; a robot file in its own task
        coordinates adds ``"inverse_margin"``, ``"direct_margin"``, ``"constraint_margin"``."""
    def contains(self, points: Points) -> npt.NDArray[np.bool_]:
        """Whether each point belongs to the workspace."""
    def forward_kinematics(self, joints: Points, guess: Points) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """Task coordinates (N × n) closing the loops from ``guess`` and the converged mask (NaN rows
        where Newton does not converge). For a robot file (``{"robot_file": {"file": ...}}``),
        damped Newton on the closure of every leg from the assembly at ``guess``."""

def presets() -> Dict[str, Dict[str, Any]]:
    """The preset designs by name: ``{"description": str, "mechanism": dict}``."""

class Figure:
    """An SVG figure of a study (a chart or the robot drawing): the text the ``pkm`` command
    writes under ``name``; Jupyter shows it inline."""
    name: str
    svg: str
    def __init__(self, name: str, svg: str) -> None: ...
    def _repr_svg_(self) -> str: ...
    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the SVG text to ``path`` (UTF-8)."""

Outcome = Dict[str, Any]
"""``{"result": dict, "summary": list[str], "tables": {name: {column: ndarray}}, "figures": {name: Figure}}``."""

def workspace(study: Study, *, progress: bool = True) -> Outcome:
    """The workspace study (``pkm workspace``)."""

Shard = Tuple[int, int]
"""``(i, n)``: the i-th (from 1) of n nearly equal blocks of grid nodes."""

def sweep(study: Study, shard: Optional[Shard] = None, *, progress: bool = True) -> Outcome:
    """The sweep study (``pkm sweep``); for ``shard=(i, n)``, n > 1, the part for :func:`merge`
    (the outcome dict plus ``"kind"`` and ``"study"``)."""

def pareto(study: Study, shard: Optional[Shard] = None, *, progress: bool = True) -> Outcome:
    """The Pareto study (``pkm pareto``); shards as :func:`sweep`."""

def merge(parts: Iterable[Outcome], *, progress: bool = True) -> Outcome:
    """The parts of a split sweep or Pareto study joined: what the whole run returns."""

def optimize(study: Study, *, progress: bool = True) -> Outcome:
    """The optimisation study (``pkm optimize``)."""

def task(study: Study, *, progress: bool = True) -> Outcome:
    """The task study (``pkm task``): Wolf & Shoham's task-based objective, multistart."""

def dynamics(
    study: Study,
    trajectory: Union[None, npt.ArrayLike, str, "os.PathLike[str]"] = None,
    *,
    progress: bool = True,
) -> Outcome:
    """The dynamics study (``pkm dynamics``); ``trajectory`` is an N × 4 array of t, x, y, z
    rows or a CSV path, replacing the study's ``trajectory.csv`` / ``positions``."""
