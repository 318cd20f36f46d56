"""Hostile study dicts (unknown keys, NaN, huge counts, wrong types) end in a pkm.Error naming
the offending setting's key path (exactly the `pkm` command's), before any computation."""

import copy
import math

import pytest

import pkm
from conftest import GRID_STUDY, OPTIMIZE_STUDY
from test_optimize_dynamics import DYNAMICS_STUDY

PICK_AND_PLACE = dict(DYNAMICS_STUDY, trajectory={"pick_and_place": {"cycle_time": 0.5}})


def edited(study, path, value):
    """A deep copy of `study` with the setting at `path` (keys and list indices) set."""
    out = copy.deepcopy(study)
    node = out
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return out


GRID_CASES = [
    (("variables", 0, "from"), math.nan, "variables[0].from"),
    (("variables", 1, "to"), math.inf, "variables[1].to"),
    (("variables", 0), {"name": "l1_over_yr", "from": 1.6, "to": 2.4, "steps": 10**9}, "variables[0].steps"),
    (("variables", 0), {"name": "l1_over_yr", "from": 1.6, "to": 2.4, "steps": 10**30}, "variables[0].steps"),
    (("variables", 0), {"name": "l1_over_yr", "from": 1.6, "to": 2.4, "step": 0.1, "steps": 9}, "variables[0].name"),
    (("variables", 0, "step"), 1e-300, "variables[0].step"),
    (("variables", 0, "name"), "l9_over_yr", "variables[0].name"),
    (("indices", "eta1_points"), "many", "indices.eta1_points"),
    (("indices", "eta1_points"), 10**6, "indices.eta1_points"),
    (("indices", "eta1_points"), -1, "indices.eta1_points"),
    (("mechanism", "linear_delta", "l2_over_l1"), [1.0], "mechanism.linear_delta.l2_over_l1"),
]
SWEEP_CASES = [
    (("sweep", "objectiv"), {"eta1": 1.0}, "sweep.objectiv"),
    (("sweep", "refine", 0, "step"), 0.0, "sweep.refine[0].step"),
    (("sweep", "refine", 0, "half_width"), -1, "sweep.refine[0].half_width"),
    # (serde names the map, not the entry, for a value of an enum-keyed map)
    (("sweep", "objective"), {"eta1": math.nan}, "sweep.objective"),
]
PARETO_CASES = [
    (("pareto", "objectives"), ["eta1"], "pareto.objectives"),
    (("pareto", "weights"), [[1.0, math.nan]], "pareto.weights[0][1]"),
]


GRID_PARAMETERS = (
    [("sweep",) + c for c in GRID_CASES + SWEEP_CASES]
    + [("pareto",) + c for c in GRID_CASES + PARETO_CASES]
)


@pytest.mark.parametrize("kind, path, value, key_path", GRID_PARAMETERS, ids=lambda c: str(c))
def test_hostile_grid_studies_name_their_key(kind, path, value, key_path):
    study = edited(GRID_STUDY, path, value)
    with pytest.raises(pkm.Error) as caught:
        getattr(pkm, kind)(study, progress=False)
    assert caught.value.key_path == key_path, str(caught.value)


@pytest.mark.parametrize(
    "path, value, key_path",
    [
        (("optimize", "objectve"), "volume", "optimize.objectve"),
        (("optimize", "columns"), 10**12, "optimize.columns"),
        (("optimize", "columns"), "many", "optimize.columns"),
        (("optimize", "starts", "count"), 10**15, "optimize.starts.count"),
        (("optimize", "variables", "a"), [math.nan, 1.0], "optimize.variables.a"),
        (("optimize", "solver", "max_outer"), -3, "optimize.solver.max_outer"),
        (("mechanism", "tsai", "a"), math.nan, "mechanism.tsai.a"),
    ],
    ids=lambda c: str(c),
)
def test_hostile_optimize_studies_name_their_key(path, value, key_path):
    with pytest.raises(pkm.Error) as caught:
        pkm.optimize(edited(OPTIMIZE_STUDY, path, value), progress=False)
    assert caught.value.key_path == key_path, str(caught.value)


@pytest.mark.parametrize(
    "path, value, key_path",
    [
        (("masses", "plate"), math.nan, "masses.plate"),
        (("masses", "plate"), "heavy", "masses.plate"),
        (("masses", "plates"), 1.0, "masses.plates"),
        (("trajectory", "dt"), 1e-12, "trajectory.dt"),
        (("trajectory", "pick_and_place", "cycle_time"), -1.0, "trajectory.pick_and_place.cycle_time"),
        (("dynamics", "forward", "max_steps"), "x", "dynamics.forward.max_steps"),
        (("dynamics", "forward", "max_steps"), 10**30, "dynamics.forward.max_steps"),
        (("mechanism", "rotary_delta", "arm"), -0.2, "mechanism.rotary_delta.arm"),
    ],
    ids=lambda c: str(c),
)
def test_hostile_dynamics_studies_name_their_key(path, value, key_path):
    with pytest.raises(pkm.Error) as caught:
        pkm.dynamics(edited(PICK_AND_PLACE, path, value), progress=False)
    assert caught.value.key_path == key_path, str(caught.value)


@pytest.mark.parametrize("study", [None, 3.5, "/no/such/study.toml", ["mechanism"], {"mechanism": None}])
@pytest.mark.parametrize("kind", ["sweep", "pareto", "optimize", "dynamics"])
def test_unreadable_studies_raise_pkm_errors(kind, study):
    with pytest.raises(pkm.Error):
        getattr(pkm, kind)(study, progress=False)
