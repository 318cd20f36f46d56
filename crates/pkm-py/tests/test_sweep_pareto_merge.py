"""Grid studies through Python give the `pkm` command's results to the last bit, whole and
split into shards joined by pkm.merge."""

import json
import pickle

import numpy as np
import pytest

import pkm
from test_studies import run_command


def serialised(result):
    """The result as the command serialises it (tuples and lists alike, keys sorted)."""
    return json.dumps(result, sort_keys=True)


@pytest.mark.parametrize("kind", ["sweep", "pareto"])
def test_grid_study_result_is_the_commands_to_the_last_bit(pkm_command, grid_study, tmp_path, kind):
    path, command = run_command(pkm_command, kind, grid_study, tmp_path)
    study = getattr(pkm, kind)
    from_dict = study(grid_study, progress=False)
    from_file = study(path, progress=False)
    assert serialised(from_dict["result"]) == serialised(command["result"])
    assert serialised(from_file["result"]) == serialised(command["result"])
    assert from_dict["result"]["nodes"] == 25


def test_landscape_is_arrays_matching_the_commands_csv(pkm_command, grid_study, tmp_path):
    run_command(pkm_command, "sweep", grid_study, tmp_path)
    outcome = pkm.sweep(grid_study, progress=False)
    table = outcome["tables"]["landscape.csv"]
    csv = np.genfromtxt(tmp_path / "out" / "landscape.csv", delimiter=",", names=True)
    for column in ["l1_over_yr", "l2_over_l1", "eta1", "eta2", "utility"]:
        assert table[column].dtype == np.float64 and table[column].shape == (25,)
        np.testing.assert_array_equal(table[column], csv[column])
    # Node numbers are integers; the reasons are strings (None where the node is feasible).
    assert table["node"].dtype == np.int64
    np.testing.assert_array_equal(table["node"], np.arange(25))
    assert isinstance(table["infeasible"], list) and len(table["infeasible"]) == 25
    assert all(r is None or (isinstance(r, str) and not r.startswith('"')) for r in table["infeasible"])
    assert "heatmap-l1_over_yr-l2_over_l1.svg" in outcome["figures"]


def test_pareto_front_is_a_table_of_arrays(grid_study):
    outcome = pkm.pareto(grid_study, progress=False)
    front = outcome["tables"]["front.csv"]
    assert len(front["eta1"]) == len(outcome["result"]["front"]) > 0
    values = np.array([p["values"] for p in outcome["result"]["front"]])
    np.testing.assert_array_equal(np.column_stack([front["eta1"], front["eta2"]]), values)


@pytest.mark.parametrize("kind", ["sweep", "pareto"])
@pytest.mark.parametrize("count", [2, 3, 30])
def test_merged_shards_return_the_whole_run_bit_for_bit(grid_study, kind, count):
    study = getattr(pkm, kind)
    whole = study(grid_study, progress=False)
    parts = [study(grid_study, shard=(i, count), progress=False) for i in range(1, count + 1)]
    assert all(p["kind"] == kind for p in parts)
    # Parts travel between processes: through pickle, in any order.
    parts = [pickle.loads(pickle.dumps(p)) for p in reversed(parts)]
    merged = pkm.merge(parts, progress=False)
    assert serialised(merged["result"]) == serialised(whole["result"])
    assert merged["summary"] == whole["summary"]
    assert merged["figures"] == whole["figures"]
    assert merged["tables"].keys() == whole["tables"].keys()
    for name, table in whole["tables"].items():
        for column, values in table.items():
            np.testing.assert_array_equal(merged["tables"][name][column], values)


def test_shards_of_a_file_study_merge_without_the_file(pkm_command, grid_study, tmp_path):
    path, command = run_command(pkm_command, "sweep", grid_study, tmp_path)
    parts = [pkm.sweep(path, shard=(i, 2), progress=False) for i in (1, 2)]
    path.unlink()
    merged = pkm.merge(parts, progress=False)
    assert serialised(merged["result"]) == serialised(command["result"])


def test_the_single_shard_is_the_whole_run(grid_study):
    whole = pkm.sweep(grid_study, progress=False)
    single = pkm.sweep(grid_study, shard=(1, 1), progress=False)
    assert serialised(single["result"]) == serialised(whole["result"])
    assert "kind" not in single


@pytest.mark.parametrize("shard", [(0, 2), (3, 2), (1, 0), (-1, 2), (1, 2, 3), "1/2", (1.5, 2), (1, 10**40)])
def test_bad_shards_are_refused(grid_study, shard):
    with pytest.raises(pkm.InvalidInput, match="shard"):
        pkm.sweep(grid_study, shard=shard, progress=False)


def test_merge_refuses_what_is_not_one_run(grid_study):
    parts = [pkm.sweep(grid_study, shard=(i, 3), progress=False) for i in (1, 2, 3)]
    with pytest.raises(pkm.InvalidInput, match="no shard results"):
        pkm.merge([], progress=False)
    with pytest.raises(pkm.InvalidInput, match=r"expected shards 1..=3"):
        pkm.merge(parts[:2], progress=False)
    with pytest.raises(pkm.InvalidInput, match=r"expected shards 1..=3"):
        pkm.merge(parts + parts[:1], progress=False)
    other = dict(grid_study, title="another study")
    with pytest.raises(pkm.InvalidInput, match=r"parts\[2\]: a shard of another study"):
        pkm.merge(parts[:2] + [pkm.sweep(other, shard=(3, 3), progress=False)], progress=False)
    pareto_part = pkm.pareto(grid_study, shard=(3, 3), progress=False)
    with pytest.raises(pkm.InvalidInput, match=r"parts\[2\]"):
        pkm.merge(parts[:2] + [pareto_part], progress=False)
    whole = pkm.sweep(grid_study, progress=False)
    for bad in [whole, {"kind": "sweep"}, 3, None, dict(parts[0], kind="task")]:
        with pytest.raises(pkm.InvalidInput, match=r"parts\[0\]"):
            pkm.merge([bad], progress=False)
    tampered = pickle.loads(pickle.dumps(parts[0]))
    tampered["result"]["outcomes"] = tampered["result"]["outcomes"][:-1]
    with pytest.raises(pkm.InvalidInput, match="should hold nodes"):
        pkm.merge([tampered] + parts[1:], progress=False)
    with pytest.raises(pkm.InvalidInput):
        pkm.merge(None, progress=False)


def test_infeasibility_reasons_are_plain_strings(grid_study):
    # A grid that reaches designs the library refuses (L1/YR < 1): their reasons as text.
    grid_study["variables"][0] = {"name": "l1_over_yr", "from": 0.6, "to": 1.4, "step": 0.4}
    outcome = pkm.sweep(grid_study, progress=False)
    reasons = outcome["tables"]["landscape.csv"]["infeasible"]
    given = [r for r in reasons if r is not None]
    assert given and all(isinstance(r, str) and r and not r.startswith('"') for r in given)
    assert len(given) < len(reasons)
