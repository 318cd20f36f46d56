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
