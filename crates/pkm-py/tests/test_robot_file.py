"""pkm.Mechanism from a robot file (issue 18): the vectorised inverse kinematics and forward
kinematics of examples/robots/*.toml, an IK → FK round trip to 1e-9 m, NaN rows and a mask
where Newton does not converge."""

import numpy as np
import pytest

import pkm

from conftest import ROOT

ROBOTS = ROOT / "examples" / "robots"

# A box around each robot's home position, inside its reach (m).
BOXES = {
    "tsai.toml": ([-0.3, -0.3, 0.3], [0.3, 0.3, 0.8]),
    "linear_delta.toml": ([-0.1, -0.08, -0.3], [0.1, 0.08, -0.12]),
}


def robot(name):
    return pkm.Mechanism({"robot_file": {"file": str(ROBOTS / name)}})


@pytest.mark.parametrize("name", sorted(BOXES))
def test_inverse_then_forward_kinematics_round_trip(name):
    m = robot(name)
    assert m.kind == "robot_file" and m.joints == 3
    lower, upper = (np.array(b) for b in BOXES[name])
    x = lower + (upper - lower) * np.random.default_rng(7).random((400, 3))
    q, inside = m.inverse_kinematics(x)
    assert inside.sum() > 100, inside.sum()
    assert np.isnan(q[~inside]).all() and np.isfinite(q[inside]).all()
    # Newton from a guess 1 cm off along each axis, in the assembly mode of the guess.
    back, ok = m.forward_kinematics(q[inside], x[inside] + 0.01)
    assert back.shape == (int(inside.sum()), 3)
    assert ok.all(), f"{(~ok).sum()} rows did not converge"
    error = np.abs(back - x[inside]).max()
    assert error < 1e-9, error


def test_forward_kinematics_flags_the_rows_that_do_not_close():
    m = robot("linear_delta.toml")
    x = np.array([[0.02, -0.01, -0.21], [0.0, 0.0, -0.2]])
    q, inside = m.inverse_kinematics(x)
    assert inside.all()
    # Carriages 2 m apart along their rails: arms of 0.3 m cannot meet.
    joints = np.vstack([q, [[-1.0, 1.0, 0.0]]])
    back, ok = m.forward_kinematics(joints, np.vstack([x, [[0.0, 0.0, -0.2]]]))
    assert list(ok) == [True, True, False]
    np.testing.assert_allclose(back[:2], x, rtol=0, atol=1e-9)
    assert np.isnan(back[2]).all()


def test_a_missing_robot_file_is_reported_at_its_key():
    with pytest.raises(pkm.InvalidInput) as e:
        pkm.Mechanism({"robot_file": {"file": str(ROBOTS / "no_such_robot.toml")}})
    assert e.value.key_path == "mechanism.robot_file.file"


def test_a_redundant_robot_has_four_actuators_and_a_least_squares_forward_kinematics():
    """The planar 4-RRR (issue 33): four actuator columns, a 4 x 3 J, the poses back from
    consistent actuator values to 1e-9, and a masked row where one actuator is 5 mrad off."""
    m = robot("four_rrr.toml")
    assert m.joints == 4 and m.task == ["x", "y", "rz"]
    rng = np.random.default_rng(3)
    x = np.column_stack([rng.uniform(-0.05, 0.05, 50), rng.uniform(-0.05, 0.05, 50), rng.uniform(-0.2, 0.2, 50)])
    q, inside = m.inverse_kinematics(x)
    assert q.shape == (50, 4) and inside.all()
    j, defined = m.velocity_jacobian(x)
    assert j.shape == (50, 4, 3) and defined.all()
    back, ok = m.forward_kinematics(q, x + 0.01)
    assert ok.all() and np.abs(back - x).max() < 1e-9
    q[0, 2] += 5e-3
    back, ok = m.forward_kinematics(q, x + 0.01)
    assert not ok[0] and np.isnan(back[0]).all() and ok[1:].all()


def test_two_actuators_per_leg_are_named_columns_and_round_trip():
    """The 3-PPSR on XY stages (issue 33): six actuators in three legs, named by their joints,
    six joint columns, and the poses back from the actuator values to 1e-9."""
    m = robot("three_ppsr.toml")
    assert m.joints == 6 and len(m.task) == 6
    assert m.actuators == [f"legs[{i}].joints[{j}]" for i in range(3) for j in range(2)]
    assert robot("tsai.toml").actuators == [f"legs[{i}].joints[0]" for i in range(3)]
    assert pkm.Mechanism("tsai").actuators is None
    rng = np.random.default_rng(5)
    x = np.column_stack(
        [rng.uniform(-0.03, 0.03, (20, 2)), 0.4 + rng.uniform(-0.03, 0.03, 20), rng.uniform(-0.05, 0.05, (20, 3))]
    )
    q, inside = m.inverse_kinematics(x)
    assert q.shape == (20, 6) and inside.all()
    back, ok = m.forward_kinematics(q, x + 0.005)
    assert ok.all() and np.abs(back - x).max() < 1e-9


def test_the_dynamics_of_a_robot_file_from_python_equals_the_command(tmp_path):
    """Issue 31: ``pkm.dynamics`` on a robot-file study (the Stewart–Gough's example) gives the
    command's result; an N × 7 array of sampled task coordinates is taken as the trajectory,
    and a row of the wrong width is refused at its key."""
    import json
    import os
    import subprocess

    study = ROOT / "examples" / "studies" / "stewart_gough_dynamics.toml"
    outcome = pkm.dynamics(study, progress=False)
    efforts = outcome["result"]["efforts"]
    assert [a["name"] for a in efforts["actuators"]] == [f"legs[{i}].joints[1]" for i in range(6)]
    assert efforts["formulation_difference"] < 1e-9
    out = tmp_path / "out"
    subprocess.run([os.environ.get("PKM_COMMAND", "pkm"), "-q", "dynamics", str(study), "--out", str(out)], check=True)
    command = json.loads((out / "results.json").read_text())["result"]
    assert json.dumps(command, sort_keys=True) == json.dumps(outcome["result"], sort_keys=True)
    table = outcome["tables"]["efforts.csv"]
    rows = np.column_stack([table[k] for k in ["t", "x", "y", "z", "rx", "ry", "rz"]])
    bare = {"mechanism": {"robot_file": {"file": str(ROBOTS / "stewart_gough.toml")}}}
    sampled = pkm.dynamics(bare, rows, progress=False)["result"]["efforts"]
    peak = efforts["actuators"][5]["peak"]
    assert abs(sampled["actuators"][5]["peak"] - peak) < 0.02 * peak
    with pytest.raises(pkm.InvalidInput) as e:
        pkm.dynamics(bare, rows[:, :4], progress=False)
    assert e.value.key_path == "trajectory.positions[0]"


def test_every_assembly_mode_of_a_pose_includes_it_and_says_it_is_complete():
    """pkm.assembly (issue 32): the modes at the actuators of a commanded 3-RPR pose, by
    homotopy: the report is complete, the pose is one of the modes, and every mode's inverse
    kinematics gives the actuators back; the table has a row per mode."""
    pose = [0.02, -0.03, 0.1]
    study = {
        "mechanism": {"robot_file": {"file": str(ROBOTS / "three_rpr.toml")}},
        "assembly": {"poses": [pose], "label": False},
    }
    outcome = pkm.assembly(study, progress=False)
    query = outcome["result"]["queries"][0]
    assert query["complete"] and query["homotopy"]["generic_solutions"] == 6
    tasks = np.array([m["task"] for m in query["modes"]])
    assert np.abs(tasks - pose).max(axis=1).min() < 1e-9
    m = robot("three_rpr.toml")
    q, inside = m.inverse_kinematics(np.array([pose]))
    assert np.abs(q[0] - query["actuators"]).max() < 1e-12
    assert len(outcome["tables"]["modes.csv"]["mode"]) == len(query["modes"])


def test_a_refused_assembly_query_names_its_key():
    study = {
        "mechanism": {"robot_file": {"file": str(ROBOTS / "three_rpr.toml")}},
        "assembly": {"actuators": [[0.3, 0.3]]},
    }
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.assembly(study, progress=False)
    assert caught.value.key_path == "assembly.actuators[0]", str(caught.value)
