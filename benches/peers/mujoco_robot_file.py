"""A robot file exported by `pkm mjcf` in MuJoCo, held by pkm's efforts (issue 31's peer; not
run in CI).

At the home configuration (qpos0, where the closures were taken) with zero velocity:
- the equality constraints' violation (`efc_pos` of the equality rows) is zero;
- hard-constrained dynamics of MuJoCo's own model: with its mass matrix M (`mj_mulM`), bias
  forces c and equality Jacobian J, the least-squares solution of the KKT system
  [M, -Jᵀ; J, 0] [q̈; λ] = [τ - c; 0] under the efforts pkm's inverse dynamics gives for the
  robot at rest at home (gravity held) as the motors' controls, against the same without them
  (unactuated): |q̈| should be near zero when held;
- MuJoCo's own soft-constraint solver (closures stiffened, Newton, 1e-4 s steps): its `qacc`
  held and unactuated, and the platform's drift (m) and turn (rad) over 0.1 s under those
  controls.
Prints one JSON line. Usage: python3 mujoco_robot_file.py ROBOT.toml (PKM_COMMAND names the
`pkm` command). Needs `pip install mujoco numpy` (MuJoCo 3 or later).
"""

import json
import os
import re
import subprocess
import sys
import tempfile

import mujoco
import numpy as np


def pkm(*args):
    run = subprocess.run([os.environ.get("PKM_COMMAND", "pkm"), "-q", *args], capture_output=True, text=True)
    if run.returncode != 0:
        raise SystemExit(f"pkm {args[0]}: {run.stderr.strip()}")


def holding_efforts(robot, out):
    """pkm's efforts at rest at home (a zero-length segment is refused, so a 1 µm one whose
    first sample is at rest and accelerates negligibly)."""
    text = open(robot).read()
    names = re.findall(r'"(\w+)"', re.search(r"^task = \[([^\]]*)\]", text, re.M).group(1))
    position = [float(v) for v in re.search(r"position = \[([^\]]*)\]", text).group(1).split(",")]
    home6 = dict(zip(["x", "y", "z"], position))
    home = [home6.get(n, 0.0) for n in names]
    end = [h + 1e-9 for h in home]
    study = os.path.join(out, "study.toml")
    with open(study, "w") as f:
        f.write(f'[mechanism.robot_file]\nfile = "{robot}"\n[trajectory]\ndt = 0.01\n')
        f.write(f"[[trajectory.task_segments]]\nstart = {home}\nend = {end}\nlaw = \"parabolic\"\nduration = 1.0\n")
    pkm("dynamics", study, "--out", os.path.join(out, "dyn"))
    result = json.load(open(os.path.join(out, "dyn", "results.json")))
    actuators = [a["name"] for a in result["result"]["efforts"]["actuators"]]
    header, first = open(os.path.join(out, "dyn", "efforts.csv")).read().splitlines()[:2]
    row = dict(zip(header.split(","), map(float, first.split(","))))
    return [row[f"effort {n}"] for n in actuators]


def hard_qacc(model, data, controls):
    """|q̈| of the hard-constrained dynamics under the controls, by least squares on the KKT
    system of MuJoCo's mass matrix, bias forces and equality Jacobian at the current state."""
    data.ctrl[:] = controls
    mujoco.mj_forward(model, data)
    mass = np.zeros((model.nv, model.nv))
    for k in range(model.nv):
        unit, column = np.zeros(model.nv), np.zeros(model.nv)
        unit[k] = 1.0
        mujoco.mj_mulM(model, data, column, unit)
        mass[:, k] = column
    rows = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    jacobian = data.efc_J.reshape(-1, model.nv)[rows] if data.efc_J.size else np.zeros((0, model.nv))
    m = jacobian.shape[0]
    kkt = np.block([[mass, -jacobian.T], [jacobian, np.zeros((m, m))]])
    force = np.concatenate([data.qfrc_actuator - data.qfrc_bias, np.zeros(m)])
    qacc = np.linalg.lstsq(kkt, force, rcond=None)[0][:model.nv]
    return float(np.linalg.norm(qacc)), float(np.linalg.cond(mass))


def main():
    robot = os.path.abspath(sys.argv[1])
    out = tempfile.mkdtemp()
    pkm("mjcf", robot, "--out", out)
    model = mujoco.MjModel.from_xml_path(os.path.join(out, "robot.xml"))
    model.opt.timestep = 1e-4
    model.opt.solver = mujoco.mjtSolver.mjSOL_NEWTON
    model.opt.tolerance = 1e-12
    model.opt.iterations = 200
    # Nearly hard closures: MuJoCo's constraints are soft (a constraint force leaves an
    # acceleration of its impedance), which would blur a check of efforts.
    model.eq_solimp[:] = [0.99999, 0.99999, 0.001, 0.5, 2.0]
    model.eq_solref[:] = [2e-4, 1.0]
    model.dof_armature[:] = float(os.environ.get("ARMATURE", "0"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    equality_rows = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    violation_home = float(np.abs(data.efc_pos[equality_rows]).max(initial=0.0))
    free_qacc = float(np.linalg.norm(data.qacc))
    tau = holding_efforts(robot, out)
    hard_unactuated, mass_condition = hard_qacc(model, data, np.zeros(model.nu))
    hard_held, _ = hard_qacc(model, data, tau)
    data.ctrl[:] = tau
    mujoco.mj_forward(model, data)
    held_qacc = float(np.linalg.norm(data.qacc))
    platform = model.body("platform").id
    start, start_rotation = data.xpos[platform].copy(), data.xmat[platform].reshape(3, 3).copy()
    for _ in range(1000):
        mujoco.mj_step(model, data)
    drift = float(np.linalg.norm(data.xpos[platform] - start))
    turn = start_rotation.T @ data.xmat[platform].reshape(3, 3)
    turn = float(np.arccos(np.clip((np.trace(turn) - 1.0) / 2.0, -1.0, 1.0)))
    mujoco.mj_forward(model, data)
    equality_rows = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    print(json.dumps({"robot": os.path.basename(robot), "mujoco": mujoco.__version__, "nq": model.nq,
                      "nv": model.nv, "equality_violation_home": violation_home,
                      "hard_qacc_unactuated": hard_unactuated, "hard_qacc_held": hard_held,
                      "mass_matrix_condition": mass_condition,
                      "qacc_unactuated": free_qacc, "qacc_held": held_qacc,
                      "held_over_unactuated": held_qacc / max(free_qacc, 1e-300),
                      "platform_drift_0_1s": drift, "platform_turn_0_1s": turn,
                      "equality_violation_0_1s": float(np.abs(data.efc_pos[equality_rows]).max(initial=0.0)),
                      "efforts_pkm": tau}))


if __name__ == "__main__":
    main()
