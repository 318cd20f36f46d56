"""Type stubs of the extension module ``pkm._native`` (Rust, PyO3): the kernels, the study
functions without their progress bars, and the exception hierarchy. The package ``pkm`` wraps
it; use that."""

import os
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Tuple, Union

from typing_extensions import final

import numpy as np
import numpy.typing as npt

__all__ = [
    "MAX_POINTS",
    "Cancelled",
    "Error",
    "Infeasible",
    "InvalidInput",
    "Mechanism",
    "NotConverged",
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

__version__: str
MAX_POINTS: int
"""Largest number of rows a kernel takes in one call (larger inputs raise InvalidInput)."""

_Study = Union[Dict[str, Any], str, "os.PathLike[str]"]
"""A study: the dict of a study file, or the path of a TOML (or JSON) study file."""

_Report = Optional[Callable[[int, str, int, int], None]]
"""A progress callback ``report(task, label, done, total)``, or None."""

_RawOutcome = Dict[str, Any]
"""``{"result", "summary", "tables", "figures"}`` with each figure as SVG text."""

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

@final
class Mechanism:
    """A parallel kinematic machine from a preset name or a ``[mechanism]`` dict (a robot file
    as ``{"robot_file": {"file": "robots/tsai.toml"}}``, read from the working directory, or
    its keys inline), under a ``[constraints]`` dict."""

    def __new__(
        cls, design: Union[str, Dict[str, Any]], constraints: Optional[Dict[str, Any]] = None
    ) -> "Mechanism": ...
    @property
    def kind(self) -> str:
        """The mechanism kind (``"rotary_delta"``, ``"tsai"``, ...)."""
    @property
    def joints(self) -> int:
        """The number of actuated joints (3, or 6 for the Stewart–Gough platform)."""
    @property
    def actuators(self) -> Optional[List[str]]:
        """The name of each actuator of a robot file, the columns of every joint array: the key
        path of its joint (``"legs[0].joints[1]"``; a leg may carry several); ``None`` for a
        built-in mechanism."""
    @property
    def variables(self) -> List[str]:
        """The design variables a sweep may vary."""
    @property
    def task(self) -> List[str]:
        """The task coordinates, the columns of every ``points`` array: ``["x", "y", "z"]`` (m), or
        a robot file's own (``["z", "tilt_x", "tilt_y"]``: m and rad)."""
    def design(self) -> Dict[str, Any]:
        """The ``[mechanism]`` and ``[constraints]`` tables as a dict."""
    def inverse_kinematics(
        self, points: npt.ArrayLike
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """Joints (N × joints) and the inside mask; outside rows are NaN."""
    def velocity_jacobian(
        self, points: npt.ArrayLike
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """J = -J_q⁻¹ J_x (N × joints × n, n = len(task)) and the mask of rows where it is defined."""
    def local_indices(self, points: npt.ArrayLike) -> Dict[str, npt.NDArray[Any]]:
        """``{"inverse_condition": (N,), "inside": (N,) bool}``; a robot file in its own task
        coordinates adds ``"inverse_margin"``, ``"direct_margin"``, ``"constraint_margin"``."""
    def contains(self, points: npt.ArrayLike) -> npt.NDArray[np.bool_]:
        """Whether each point belongs to the workspace."""
    def forward_kinematics(
        self, joints: npt.ArrayLike, guess: npt.ArrayLike
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
        """Task coordinates (N × n) closing the loops from ``guess`` and the converged mask (NaN
        rows where Newton does not converge)."""

def presets() -> Dict[str, Dict[str, Any]]:
    """The preset designs by name: ``{"description": str, "mechanism": dict}``."""

def workspace(study: _Study, progress: _Report = None) -> _RawOutcome: ...
def sweep(study: _Study, shard: Optional[Tuple[int, int]] = None, progress: _Report = None) -> _RawOutcome: ...
def pareto(study: _Study, shard: Optional[Tuple[int, int]] = None, progress: _Report = None) -> _RawOutcome: ...
def merge(parts: Iterable[Mapping[str, object]], progress: _Report = None) -> _RawOutcome: ...
def optimize(study: _Study, progress: _Report = None) -> _RawOutcome: ...
def task(study: _Study, progress: _Report = None) -> _RawOutcome: ...
def assembly(study: _Study, progress: _Report = None) -> _RawOutcome: ...
def dynamics(
    study: _Study,
    trajectory: Union[None, npt.ArrayLike, str, "os.PathLike[str]"] = None,
    progress: _Report = None,
) -> _RawOutcome: ...
