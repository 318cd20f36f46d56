"""Shared fixtures: the repository root, the `pkm` command and small studies."""

import copy
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]

# A small NUWAR-like workspace study with joint limits (the mechanism and constraints of
# examples/studies/nuwar_workspace.toml, fewer points): seconds in a debug build.
NUWAR_STUDY = {
    "title": "NUWAR-like rotary Delta, small",
    "mechanism": {
        "rotary_delta": {
            "base_radius": 0.15,
            "plate_offset": 0.04,
            "arm": 0.2,
            "forearm": 0.45,
            "alpha_deg": 35.264389682754654,
            "beta_deg": 60.0,
        }
    },
    "constraints": {
        "below_z": 0.0,
        "joint_range_deg": [-40.0, 90.0],
        "passive_cone_deg": 35.0,
        "leg_clearance": 0.03,
    },
    "sampling": {
        "sampler": "sobol",
        "seed": 42,
        "points": 2048,
        "replicates": 2,
        "symmetry_folds": 3,
        "region": {"cylinder": {"radius": 0.76, "z_min": -0.65, "z_max": 0.0}},
    },
    "workspace": {"slices": [{"plane": "xy", "at": -0.4, "cells": 12}]},
}


@pytest.fixture
def nuwar_study():
    return copy.deepcopy(NUWAR_STUDY)


# A Linear Delta grid of 5 × 5 designs with both a sweep (one refinement level) and a Pareto
# section, η1 on a coarse rule (examples/studies/linear_delta_*.toml, smaller): a second.
GRID_STUDY = {
    "title": "Linear Delta, small grid",
    "mechanism": {
        "linear_delta": {"l1_over_yr": 2.0, "ya_over_yr": 0.0, "zr_over_yr": 0.0, "l2_over_l1": 0.63}
    },
    "indices": {"eta1_points": 4},
    "variables": [
        {"name": "l1_over_yr", "from": 1.6, "to": 2.4, "step": 0.2},
        {"name": "l2_over_l1", "from": 0.6, "to": 1.0, "step": 0.1},
    ],
    "sweep": {"objective": {"eta1": 1.0, "eta2": 1.0}, "refine": [{"step": 0.05, "half_width": 1}]},
    "pareto": {"objectives": ["eta1", "eta2"], "weights": [[1.0, 1.0], [1.0, 0.0]]},
}


@pytest.fixture
def grid_study():
    return copy.deepcopy(GRID_STUDY)


# The Tsai platform's largest volume under a + b + d + e <= 1 m
# (examples/studies/tsai_volume_optimize.toml with a coarse quadrature and two short starts).
OPTIMIZE_STUDY = {
    "title": "Tsai platform, small optimisation",
    "mechanism": {
        "tsai": {"a": 0.4, "b": 0.6, "d_plus_e": 0.0, "c_minus_r": 0.0, "phi2_deg": 120.0, "phi3_deg": 240.0}
    },
    "optimize": {
        "objective": "volume",
        "columns": 24,
        "check_step": 1e-2,
        "variables": {"a": [0.02, 1.0], "b": [0.02, 1.0]},
        "constraints": [{"name": "reach", "coefficients": {"a": 1.0, "b": 1.0}, "at_most": 1.0}],
        "starts": {"count": 2, "seed": 2024},
        "solver": {"fd_step": 1e-4, "tolerance": 1e-6, "feasibility": 1e-6, "max_outer": 6, "max_inner": 40},
    },
}


@pytest.fixture
def optimize_study():
    return copy.deepcopy(OPTIMIZE_STUDY)


EXAMPLES = ROOT / "examples" / "studies"


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v + '"'
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def to_toml(study):
    """A study dict as TOML text (inline tables; enough for the studies of these tests)."""
    return "".join(f"{k} = {toml_value(v)}\n" for k, v in study.items())


@pytest.fixture(scope="session")
def pkm_command():
    """The `pkm` command of this checkout (PKM_COMMAND, or target/debug/pkm, built if need be)."""
    path = os.environ.get("PKM_COMMAND")
    if path:
        return pathlib.Path(path)
    subprocess.run(["cargo", "build", "-q", "-p", "pkm-cli"], cwd=ROOT, check=True)
    return ROOT / "target" / "debug" / "pkm"
