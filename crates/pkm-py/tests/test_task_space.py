"""Workspace studies in a robot's own task space: the example study files, their robot files
named by path, give from Python the same result as the `pkm` command, to the last bit."""

import json
import subprocess

import pytest

import pkm
from conftest import ROOT

EXAMPLES = [
    "three_prs_reachable.toml",
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
