"""Every study of `examples/studies/` gives the same `result` through Python as through the
`pkm` command, to the last bit: both front ends read a study with the study layer's loader, so
a robot file or a trajectory CSV named relative to the study is read the same way.

The studies run in quick versions (fewer points, grids of a few nodes, one refinement level) so
the whole set takes seconds; everything else, the files they name included, is as written."""

import json
import subprocess
import tomllib

import pytest

import pkm
from conftest import EXAMPLES, to_toml

# The command of a study, by the section that names it.
COMMANDS = ["optimize", "task", "pareto", "sweep", "dynamics", "assembly"]


def command_of(study):
    if "trajectory" in study:
        return "dynamics"
    return next((c for c in COMMANDS if c in study), "workspace")


def quick(study, base):
    """A smaller study of the same kind, its file names made absolute."""
    sampling = study.get("sampling", {})
    for key, most in [("points", 1024), ("replicates", 2)]:
        if key in sampling:
            sampling[key] = min(sampling[key], most)
    for variable in study.get("variables", []):
        if "step" in variable:
            variable["to"] = min(variable["to"], variable["from"] + 2 * variable["step"])
    if "refine" in study.get("sweep", {}):
        study["sweep"]["refine"] = study["sweep"]["refine"][:1]
    for table in [study.get("indices", {})] + study.get("sweep", {}).get("refine", []):
        if "eta1_points" in table:
            table["eta1_points"] = min(table["eta1_points"], 4)
    task_space = study.get("task_space", {})
    charts = task_space.get("maps", []) + study.get("sweep", {}).get("heatmaps", []) + study.get("effort_maps", [])
    for chart in charts + [task_space.get("singularity_free", {})]:
        if "cells" in chart:
            chart["cells"] = min(chart["cells"], 8)
    robot = study.get("mechanism", {}).get("robot_file", {})
    if "file" in robot:
        robot["file"] = str((base / robot["file"]).resolve())
    trajectory = study.get("trajectory", {})
    if "csv" in trajectory:
        trajectory["csv"] = str((base / trajectory["csv"]).resolve())
    return study


@pytest.mark.parametrize("example", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_example_study_gives_the_commands_result(pkm_command, example, tmp_path):
    study = quick(tomllib.loads(example.read_text()), example.parent)
    command = command_of(study)
    path = tmp_path / example.name
    path.write_text(to_toml(study))
    out = tmp_path / "out"
    run = subprocess.run([str(pkm_command), command, str(path), "--out", str(out), "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    from_command = json.loads((out / "results.json").read_text())["result"]
    from_python = getattr(pkm, command)(str(path), progress=False)["result"]
    assert json.dumps(from_python, sort_keys=True) == json.dumps(from_command, sort_keys=True)


def test_a_robot_file_named_relative_to_the_study_is_read_as_the_command_reads_it(pkm_command, tmp_path):
    example = EXAMPLES / "robot_file_workspace.toml"
    out = tmp_path / "out"
    subprocess.run([str(pkm_command), "workspace", str(example), "--out", str(out), "--quiet"],
                   check=True, capture_output=True)
    results = json.loads((out / "results.json").read_text())
    robot = example.parent / _robot_file_of(example.read_text())
    assert results["study"]["robot_file"]["text"] == robot.read_text()
    assert pkm.workspace(str(example), progress=False)["result"] == results["result"]


def test_an_error_in_a_named_robot_file_is_placed_at_its_line_in_both_front_ends(pkm_command, tmp_path):
    (tmp_path / "robot.toml").write_text("name = \"bad\"\nlegs = [1,\n")
    study = tmp_path / "study.toml"
    text = (EXAMPLES / "robot_file_workspace.toml").read_text()
    study.write_text(text.replace(_robot_file_of(text), "robot.toml"))
    run = subprocess.run([str(pkm_command), "workspace", str(study), "--out", str(tmp_path / "o"), "--quiet"],
                         capture_output=True, text=True)
    assert run.returncode != 0
    assert "robot.toml:" in run.stderr, run.stderr
    with pytest.raises(pkm.InvalidInput) as raised:
        pkm.workspace(str(study), progress=False)
    message = str(raised.value)
    assert "robot.toml:" in message and "mechanism.robot_file.file" in message, message


def _robot_file_of(text):
    return tomllib.loads(text)["mechanism"]["robot_file"]["file"]
