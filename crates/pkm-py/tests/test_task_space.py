"""Workspace studies in a robot's own task space: the example study files, their robot files
named by path, give from Python the same result as the `pkm` command, to the last bit."""

import json
import subprocess

import pytest

import pkm
from conftest import ROOT

EXAMPLES = [
    "three_prs_reachable.toml",
    "exechon_reachable.toml",
    "five_bar_reachable.toml",
    "stewart_gough_constant_orientation.toml",
    "stewart_gough_dexterous.toml",
    "three_rpr_constant_orientation.toml",
    "hexa_orientation.toml",
    "agile_eye_orientation.toml",
]


@pytest.mark.parametrize("name", EXAMPLES)
def test_every_kind_gives_the_commands_result(pkm_command, name, tmp_path):
    study = ROOT / "examples" / "studies" / name
    subprocess.run([str(pkm_command), "workspace", str(study), "--out", str(tmp_path), "--quiet"], check=True)
    command = json.loads((tmp_path / "results.json").read_text())
    outcome = pkm.workspace(str(study), progress=False)
    assert json.dumps(outcome["result"], sort_keys=True) == json.dumps(command["result"], sort_keys=True)
    assert outcome["result"]["task_space"]["unit"]
    assert outcome["result"]["estimate"]["n_inside"] > 0


def test_a_misfit_setting_raises_with_its_key_path():
    study = ROOT / "examples" / "studies" / "five_bar_reachable.toml"
    text = study.read_text().replace('kind = "reachable"', 'kind = "orientation"')
    import tomllib

    document = tomllib.loads(text)
    document["mechanism"]["robot_file"]["file"] = str(ROOT / "examples" / "robots" / "five_bar.toml")
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.workspace(document, progress=False)
    assert caught.value.key_path == "task_space.kind"


def test_a_robot_file_optimisation_gives_the_commands_result(pkm_command, tmp_path):
    study = ROOT / "examples" / "studies" / "symmetric_three_rpr_optimize.toml"
    subprocess.run([str(pkm_command), "optimize", str(study), "--out", str(tmp_path), "--quiet"], check=True)
    command = json.loads((tmp_path / "results.json").read_text())
    outcome = pkm.optimize(str(study), progress=False)
    assert json.dumps(outcome["result"], sort_keys=True) == json.dumps(command["result"], sort_keys=True)
    assert outcome["result"]["unit"] == "m²"
    assert outcome["result"]["search"]["method"] == "compass"


def test_a_robot_file_task_study_gives_the_commands_result(pkm_command, tmp_path):
    study = ROOT / "examples" / "studies" / "three_prs_task_synthesis.toml"
    subprocess.run([str(pkm_command), "task", str(study), "--out", str(tmp_path), "--quiet"], check=True)
    command = json.loads((tmp_path / "results.json").read_text())
    outcome = pkm.task(str(study), progress=False)
    assert json.dumps(outcome["result"], sort_keys=True) == json.dumps(command["result"], sort_keys=True)
    assert outcome["result"]["mechanism"] == "robot_file"
    assert outcome["result"]["wrench_matrix"]["rank"] == 6


def robot(name):
    return pkm.Mechanism({"robot_file": {"file": str(ROOT / "examples" / "robots" / name)}})


@pytest.mark.parametrize(
    "name, task, lower, upper",
    [
        ("three_prs.toml", ["z", "tilt_x", "tilt_y"], [0.4, -0.3, -0.3], [0.6, 0.3, 0.3]),
        (
            "stewart_gough.toml",
            ["x", "y", "z", "rx", "ry", "rz"],
            [-0.02, -0.02, 0.28, -0.05, -0.05, -0.05],
            [0.02, 0.02, 0.32, 0.05, 0.05, 0.05],
        ),
        ("five_bar.toml", ["x", "y"], [-0.1, 0.2], [0.1, 0.3]),
        ("agile_eye.toml", None, [-0.3, -0.3, -0.3], [0.3, 0.3, 0.3]),
    ],
)
def test_a_robot_file_takes_arrays_of_its_own_task_coordinates(name, task, lower, upper):
    import numpy as np

    m = robot(name)
    n = len(m.task)
    if task is not None:
        assert m.task == task
    x = np.random.default_rng(4).uniform(lower, upper, (64, n))
    q, inside = m.inverse_kinematics(x)
    assert q.shape == (64, m.joints) and inside.sum() > 8
    np.testing.assert_array_equal(inside, m.contains(x))
    k = m.local_indices(x)
    assert ((k["inverse_condition"][inside] >= 0) & (k["inverse_condition"][inside] <= 1)).all()
    assert np.isfinite(k["direct_margin"][inside]).all() and np.isnan(k["direct_margin"][~inside]).all()
    # Forward kinematics from a nearby guess returns the points (a round trip).
    back, ok = m.forward_kinematics(q[inside], x[inside] + 1e-4)
    assert ok.all()
    np.testing.assert_allclose(back, x[inside], atol=1e-9)
    # The velocity Jacobian against central differences of the inverse kinematics.
    some = x[inside][:8]
    j, defined = m.velocity_jacobian(some)
    assert j.shape == (8, m.joints, n) and defined.all()
    h = 1e-6
    for c in range(n):
        step = np.zeros(n)
        step[c] = h
        qp, _ = m.inverse_kinematics(some + step)
        qm, _ = m.inverse_kinematics(some - step)
        np.testing.assert_allclose(j[:, :, c], (qp - qm) / (2 * h), atol=1e-6)


def test_arrays_of_the_wrong_width_raise():
    m = robot("stewart_gough.toml")
    with pytest.raises(pkm.InvalidInput):
        m.inverse_kinematics([[0.0, 0.0, 0.3]])
    with pytest.raises(pkm.InvalidInput):
        m.forward_kinematics([[0.3] * 6], [[0.0, 0.0, 0.3]])


def test_a_task_space_sweep_gives_the_commands_result(pkm_command, tmp_path):
    text = (ROOT / "examples" / "studies" / "three_prs_sweep.toml").read_text()
    study = tmp_path / "sweep.toml"
    study.write_text(text.replace("points = 2048", "points = 128"))
    out = tmp_path / "out"
    subprocess.run([str(pkm_command), "sweep", str(study), "--out", str(out), "--quiet"], check=True)
    command = json.loads((out / "results.json").read_text())
    outcome = pkm.sweep(str(study), progress=False)
    assert json.dumps(outcome["result"], sort_keys=True) == json.dumps(command["result"], sort_keys=True)
    assert outcome["result"]["nodes"] == 5
