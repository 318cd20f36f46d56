"""The optimisation and dynamics studies through Python give the `pkm` command's results to the
last bit; a dynamics trajectory comes from the study's CSV file, a CSV path or an N × 4 array."""

import json
import shutil

import numpy as np
import pytest

import pkm
from conftest import EXAMPLES
from test_studies import run_command
from test_sweep_pareto_merge import serialised

DYNAMICS_TOML = EXAMPLES / "nuwar_dynamics_csv.toml"
CSV = EXAMPLES / "nuwar_pick_and_place.csv"

# examples/studies/nuwar_dynamics_csv.toml as a dict, without its trajectory.
DYNAMICS_STUDY = {
    "title": "NUWAR pick-and-place from a CSV trajectory",
    "mechanism": {
        "rotary_delta": {
            "base_radius": 0.194,
            "plate_offset": 0.03,
            "arm": 0.26,
            "forearm": 0.48,
            "alpha_deg": 35.26,
            "beta_deg": 60.0,
            "motor_plane_z": -0.2928,
            "azimuth_motor_1_deg": 300.0,
        }
    },
    "masses": {
        "plate": 0.2807,
        "arm_inertia": 0.01822,
        "arm_mass": 0.977,
        "arm_centre_of_mass": 0.13,
        "elbow": 0.0099,
        "forearm": 0.0296,
        "gravity": 9.81,
        "forearm_model": "rod",
    },
    "dynamics": {
        "differencing": "central",
        "lagrange_accelerations": "trajectory",
        "forward": {"kappa": 20.0, "rtol": 1e-8, "atol": 1e-11},
    },
}


def csv_rows():
    """The CSV's rows parsed by Python (correctly rounded, as Rust parses them)."""
    lines = CSV.read_text().splitlines()[1:]
    return np.array([[float(v) for v in line.split(",")] for line in lines if line.strip()])


def test_optimize_result_is_the_commands_to_the_last_bit(pkm_command, optimize_study, tmp_path):
    path, command = run_command(pkm_command, "optimize", optimize_study, tmp_path)
    outcome = pkm.optimize(optimize_study, progress=False)
    assert serialised(outcome["result"]) == serialised(command["result"])
    assert serialised(pkm.optimize(path, progress=False)["result"]) == serialised(command["result"])
    starts = outcome["tables"]["starts.csv"]
    assert all(isinstance(v, (np.ndarray, list)) and len(v) == 2 for v in starts.values())


@pytest.fixture(scope="module")
def dynamics_command(pkm_command, tmp_path_factory):
    out = tmp_path_factory.mktemp("dynamics") / "out"
    import subprocess

    subprocess.run(
        [str(pkm_command), "dynamics", str(DYNAMICS_TOML), "--out", str(out), "--quiet"],
        check=True,
        capture_output=True,
    )
    return json.loads((out / "results.json").read_text())["result"]


def test_dynamics_from_the_study_file_is_the_commands(dynamics_command):
    outcome = pkm.dynamics(DYNAMICS_TOML, progress=False)
    assert serialised(outcome["result"]) == serialised(dynamics_command)
    torques = outcome["tables"]["torques.csv"]
    assert torques["tau_hamilton_1"].shape == (outcome["result"]["samples"],)
    peak = np.max(np.abs(np.column_stack([torques[f"tau_hamilton_{i}"] for i in (1, 2, 3)])))
    assert peak == outcome["result"]["hamilton"]["max"]


def test_dynamics_trajectory_as_csv_path_or_array_is_the_commands(dynamics_command, tmp_path, monkeypatch):
    from_array = pkm.dynamics(DYNAMICS_STUDY, trajectory=csv_rows(), progress=False)
    assert serialised(from_array["result"]) == serialised(dynamics_command)
    from_path = pkm.dynamics(DYNAMICS_STUDY, trajectory=CSV, progress=False)
    assert serialised(from_path["result"]) == serialised(dynamics_command)
    # A dict's own trajectory.csv is read relative to the working directory.
    shutil.copy(CSV, tmp_path / "cycle.csv")
    monkeypatch.chdir(tmp_path)
    own = dict(DYNAMICS_STUDY, trajectory={"csv": "cycle.csv"})
    assert serialised(pkm.dynamics(own, progress=False)["result"]) == serialised(dynamics_command)
    # Positions inline in the dict: the same numbers.
    inline = dict(DYNAMICS_STUDY, trajectory={"positions": csv_rows().tolist()})
    assert serialised(pkm.dynamics(inline, progress=False)["result"]) == serialised(dynamics_command)


def test_bad_trajectories_are_refused_with_their_key(tmp_path):
    rows = csv_rows()
    cases = [
        (rows[:, :3], "trajectory.positions[0]", "3 values; expected 4"),
        (rows[:2], "trajectory.positions", "at least 3"),
        (np.zeros((0, 4)), "trajectory.positions", "at least 3"),
        (rows.astype(str), None, "real numbers"),
        ("/no/such/trajectory.csv", "trajectory.csv", "no/such"),
    ]
    nan = rows.copy()
    nan[7, 2] = np.nan
    cases.append((nan, "trajectory.positions[7]", "finite"))
    bad_csv = tmp_path / "bad.csv"
    bad_csv.write_text("t,x,y,z\n0,0,0,-0.9\n0.1,0,0\n")
    cases.append((bad_csv, "trajectory.csv", "line 3: 3 values"))
    for trajectory, key_path, message in cases:
        with pytest.raises(pkm.InvalidInput, match=message) as caught:
            pkm.dynamics(DYNAMICS_STUDY, trajectory=trajectory, progress=False)
        assert caught.value.key_path == key_path, trajectory
    # The CSV's line is named when the library refuses one of its rows.
    uneven = tmp_path / "uneven.csv"
    uneven.write_text("t,x,y,z\n0,0,0,-0.9\n0.1,0,0,-0.9\n0.3,0,0,-0.9\n0.4,0,0,-0.9\n")
    with pytest.raises(pkm.InvalidInput, match="uneven.csv: line") as caught:
        pkm.dynamics(DYNAMICS_STUDY, trajectory=uneven, progress=False)
    assert caught.value.key_path == "trajectory.csv"
    both = dict(DYNAMICS_STUDY, trajectory={"pick_and_place": {"cycle_time": 0.5}})
    with pytest.raises(pkm.InvalidInput, match="exactly one") as caught:
        pkm.dynamics(both, trajectory=rows, progress=False)
    assert caught.value.key_path == "trajectory"
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.dynamics(DYNAMICS_STUDY, progress=False)
    assert caught.value.key_path in ("(study)", "trajectory")


TASK_TOML = EXAMPLES / "three_upu_singularity.toml"


def test_task_result_is_the_commands_to_the_last_bit(pkm_command, tmp_path):
    import subprocess

    out = tmp_path / "out"
    subprocess.run(
        [str(pkm_command), "task", str(TASK_TOML), "--out", str(out), "--quiet"],
        check=True,
        capture_output=True,
    )
    command = json.loads((out / "results.json").read_text())["result"]
    outcome = pkm.task(TASK_TOML, progress=False)
    assert serialised(outcome["result"]) == serialised(command)
    assert len(outcome["tables"]["starts.csv"]["objective"]) == 16


def test_task_refuses_a_bad_setting_at_its_key_path(tmp_path):
    text = TASK_TOML.read_text().replace("count = 16", "count = 0")
    study = tmp_path / "bad.toml"
    study.write_text(text)
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.task(study, progress=False)
    assert caught.value.key_path == "task.starts.count"
