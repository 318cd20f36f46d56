#!/usr/bin/env python3
"""A robot file's dynamics in Pinocchio, against pkm's (issue 31's peer; not run in CI).

The robot file is exported by `pkm urdf` (URDF + closures.yaml) and loaded in Pinocchio as a
tree with a 6-D loop-closure constraint per closure. Along a parabolic rest-to-rest move from
home (1 m/s² and 1 rad/s² in every task coordinate, 0.3 s; the idle and constant coordinates
held at home), at rest at home (t = 0) and, with --moving, 45 % through the move (t = 0.135 s):

1. Pinocchio solves the configuration itself: Newton on its closures and on the known pose
   coordinates (positions; the rotation, or for a tilt-and-torsion file whose torsion is
   dependent the platform normal R e_z), then the joint velocities and the accelerations of
   the asked motion by least squares on its closure and platform Jacobians, with the drifts from
   its own frame accelerations. The home orientation is zero in every example file, so the
   platform turns about a fixed axis and its angular velocity and acceleration are exact.
2. Efforts: RNEA on the tree, τ_tree = Sᵀτ + J_cᵀλ projected off the range of J_cᵀ and solved
   for the efforts of least norm (as pkm's, which are least-norm under redundant actuation);
   compared with `pkm dynamics` on the same move, relative to the largest effort (at least 1).
3. Accelerations: `constraintDynamics` under pkm's efforts (armature ARMATURE, default 1e-12,
   makes the inertia of massless links invertible; proximal μ = 1e-8 for redundant closures),
   the task's accelerations (positions; angular acceleration, or the normal's, when the task
   turns the platform) against the asked ones.

With --time (robots whose closures are independent and whose passive joints the closures
determine, as the 6-UPS): the CPU time per call of Pinocchio's fastest Python route to the
efforts at the home state (computeJointJacobians, the constraints' calc, getConstraintsJacobian,
rnea, one square solve on the unactuated rows) and of constraintDynamics (exact, μ = 0), as
`../shared/peers/pin_bench.py` times them for the NUWAR.

Usage: python3 pin_robot_file.py [--moving] [--time] ROBOT.toml  (prints one JSON line).
Needs `pip install pin numpy` (Pinocchio 4.1) and the `pkm` command (PKM_COMMAND, default `pkm`).
"""

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib

import numpy as np
import pinocchio as pin

ARMATURE = float(os.environ.get("ARMATURE", "1e-12"))
ACCEL = 1.0  # m/s² or rad/s² in every task coordinate
DURATION = 0.3  # s, rest to rest
DT = 0.0015  # s, the dynamics study's sample interval
MOVING = 0.135  # s, 45 % through the move (still accelerating: ẍ = ACCEL)
LOCAL = pin.ReferenceFrame.LOCAL
ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def pkm(*args):
    run = subprocess.run([os.environ.get("PKM_COMMAND", "pkm"), "-q", *map(str, args)],
                         capture_output=True, text=True)
    if run.returncode != 0:
        raise SystemExit(f"pkm {args[0]}: {run.stderr.strip()}")


class Move:
    """The pose coordinates along the move: c(t) = home + ½ a t² on the task coordinates."""

    def __init__(self, robot):
        with open(robot, "rb") as f:
            spec = tomllib.load(f)
        self.tilt_torsion = spec.get("orientation", "rotation_vector") == "tilt_torsion"
        names = ["x", "y", "z"] + (["tilt_x", "tilt_y", "torsion"] if self.tilt_torsion
                                   else ["rx", "ry", "rz"])
        self.task = spec["task"]
        self.task_index = [names.index(n) for n in self.task]
        home = spec["home"]
        self.home = np.array(list(home["position"]) + list(home.get("orientation", [0.0] * 3)))
        if np.any(self.home[3:] != 0.0):
            raise SystemExit("the home orientation must be zero (the platform turns about a fixed axis)")
        self.mask = np.array([1.0 if n in self.task else 0.0 for n in names])
        dependent = set(spec.get("dependent", []))
        self.known_positions = [k for k in range(3) if names[k] not in dependent]
        orientation = [names[k] in dependent for k in range(3, 6)]
        if not any(orientation):
            self.orientation = "rotation"
        elif self.tilt_torsion and orientation == [False, False, True]:
            self.orientation = "normal"
        elif all(orientation):
            self.orientation = None
        else:
            raise SystemExit(f"dependent orientation coordinates {orientation} are not handled")
        turn = self.mask[3:]
        self.axis = turn / np.linalg.norm(turn) if turn.any() else np.array([0.0, 0.0, 1.0])
        self.rate = ACCEL * np.linalg.norm(turn)  # angular acceleration about the axis

    def start(self):
        return [float(self.home[k]) for k in self.task_index]

    def end(self):
        return [float(self.home[k] + ACCEL * DURATION ** 2 / 4) for k in self.task_index]

    def task_rows(self):
        """Which of the known pose rows are the task's: its positions, and the orientation rows
        when the task turns the platform."""
        rows = [self.mask[k] > 0 for k in self.known_positions]
        turns = bool(self.mask[3:].any())
        rows += {"rotation": [turns] * 3, "normal": [turns] * 3, None: []}[self.orientation]
        return np.array(rows)

    def targets(self, t):
        """Positions, rotation and their first and second time derivatives at t (first half)."""
        p = self.home[:3] + 0.5 * ACCEL * t * t * self.mask[:3]
        v, a = ACCEL * t * self.mask[:3], ACCEL * self.mask[:3]
        angle = 0.5 * self.rate * t * t
        rotation = pin.exp3(angle * self.axis)
        return p, v, a, rotation, self.rate * t * self.axis, self.rate * self.axis


class Model:
    """The exported robot in Pinocchio with its closures."""

    def __init__(self, directory):
        self.model = pin.buildModelFromUrdf(os.path.join(directory, "robot.urdf"))
        self.model.gravity.linear = np.array([0.0, 0.0, -9.81])
        self.data = self.model.createData()
        with open(os.path.join(directory, "closures.yaml")) as f:
            pairs = [line.strip()[3:-1].split(", ") for line in f if line.strip().startswith("- [")]
        self.closures = [(self.model.getFrameId(a), self.model.getFrameId(b)) for a, b in pairs]
        self.platform = self.model.getFrameId("platform")
        self.motors = [self.model.joints[j].idx_v for j, name in enumerate(self.model.names)
                       if name.endswith("_mot")]
        self.constraints = pin.StdVec_RigidConstraintModel()
        for a, b in self.closures:
            fa, fb = self.model.frames[a], self.model.frames[b]
            self.constraints.append(pin.RigidConstraintModel(
                pin.ContactType.CONTACT_6D, self.model, fa.parentJoint, fa.placement,
                fb.parentJoint, fb.placement, LOCAL))
        self.constraint_datas = pin.StdVec_RigidConstraintData()
        for c in self.constraints:
            self.constraint_datas.append(c.createData())

    def kinematics(self, q, v=None, a=None):
        m, d = self.model, self.data
        v = np.zeros(m.nv) if v is None else v
        a = np.zeros(m.nv) if a is None else a
        pin.forwardKinematics(m, d, q, v, a)
        pin.computeJointJacobians(m, d, q)
        pin.updateFramePlacements(m, d)

    def closure_jacobian(self):
        m, d = self.model, self.data
        return np.vstack([pin.getFrameJacobian(m, d, a, LOCAL) - pin.getFrameJacobian(m, d, b, LOCAL)
                          for a, b in self.closures]) if self.closures else np.zeros((0, m.nv))

    def rows(self, move, normal):
        """The known pose rows of the platform Jacobian (LOCAL_WORLD_ALIGNED)."""
        j = pin.getFrameJacobian(self.model, self.data, self.platform, ALIGNED)
        rows = [j[move.known_positions]]
        if move.orientation == "rotation":
            rows.append(j[3:])
        elif move.orientation == "normal":
            rows.append(-pin.skew(normal) @ j[3:])
        return np.vstack(rows)

    def constraint_matrix(self, move, normal):
        return np.vstack([self.closure_jacobian(), self.rows(move, normal)])

    def solve_configuration(self, move, t):
        """Newton on the closures and the known pose coordinates at time t."""
        m, d = self.model, self.data
        p, _, _, rotation, _, _ = move.targets(t)
        q = pin.neutral(m)
        for _ in range(100):
            self.kinematics(q)
            oMp = d.oMf[self.platform]
            residual = [pin.log6(d.oMf[b].actInv(d.oMf[a])).vector for a, b in self.closures]
            residual.append((oMp.translation - p)[move.known_positions])
            normal = oMp.rotation[:, 2]
            if move.orientation == "rotation":
                residual.append(pin.log3(oMp.rotation @ rotation.T))
            elif move.orientation == "normal":
                residual.append(normal - rotation[:, 2])
            residual = np.concatenate(residual)
            if np.abs(residual).max() < 1e-15:
                break
            step = np.linalg.lstsq(self.constraint_matrix(move, normal), -residual, rcond=None)[0]
            q = pin.integrate(m, q, step)
        return q, float(np.abs(residual).max())

    def motion(self, move, t, q):
        """Joint velocities and accelerations of the asked motion at configuration q."""
        m, d = self.model, self.data
        _, pv, pa, rotation, omega, alpha = move.targets(t)
        normal = rotation[:, 2]
        self.kinematics(q)
        A = self.constraint_matrix(move, normal)
        velocity = [np.zeros(6 * len(self.closures)), pv[move.known_positions]]
        if move.orientation == "rotation":
            velocity.append(omega)
        elif move.orientation == "normal":
            velocity.append(np.cross(omega, normal))
        v = np.linalg.lstsq(A, np.concatenate(velocity), rcond=None)[0]
        drift, target = self.drifts(move, q, v, normal), [np.zeros(6 * len(self.closures)),
                                                          pa[move.known_positions]]
        if move.orientation == "rotation":
            target.append(alpha)
        elif move.orientation == "normal":
            target.append(np.cross(alpha, normal) + np.cross(omega, np.cross(omega, normal)))
        target = np.concatenate(target)
        a = np.linalg.lstsq(A, target - drift, rcond=None)[0]
        return v, a, A, target

    def drifts(self, move, q, v, normal):
        """The rows' accelerations with q̈ = 0."""
        m, d = self.model, self.data
        self.kinematics(q, v)
        rows = [pin.getFrameAcceleration(m, d, a, LOCAL).vector
                - pin.getFrameAcceleration(m, d, b, LOCAL).vector for a, b in self.closures]
        classical = pin.getFrameClassicalAcceleration(m, d, self.platform, ALIGNED)
        rows.append(classical.linear[move.known_positions])
        if move.orientation == "rotation":
            rows.append(classical.angular)
        elif move.orientation == "normal":
            omega = pin.getFrameVelocity(m, d, self.platform, ALIGNED).angular
            rows.append(-pin.skew(normal) @ classical.angular
                        + np.cross(omega, np.cross(omega, normal)))
        return np.concatenate(rows)

    def least_norm_efforts(self, q, v, a):
        """τ with Sᵀτ + J_cᵀλ = RNEA, of least norm: projected off the range of J_cᵀ."""
        m, d = self.model, self.data
        tree = pin.rnea(m, d, q, v, a).copy()
        self.kinematics(q)
        jc = self.closure_jacobian()
        projector = np.eye(m.nv) - jc.T @ np.linalg.pinv(jc.T, rcond=1e-10)
        s = np.zeros((m.nv, len(self.motors)))
        for i, j in enumerate(self.motors):
            s[j, i] = 1.0
        return np.linalg.lstsq(projector @ s, projector @ tree, rcond=1e-10)[0]

    def forward(self, q, v, efforts):
        """constraintDynamics under the efforts, with the armature (RNEA runs without it)."""
        m = self.model.copy()
        m.armature = np.full(m.nv, ARMATURE)
        d = m.createData()
        tau = np.zeros(m.nv)
        tau[self.motors] = efforts
        pin.initConstraintDynamics(m, d, self.constraints, self.constraint_datas)
        settings = pin.ProximalSettings(1e-14, 1e-8, 200)
        return pin.constraintDynamics(m, d, q, v, tau, self.constraints, self.constraint_datas,
                                      settings).copy()


def pkm_efforts(robot, move, out):
    """pkm's efforts along the same move: {t: [efforts in actuator order]}."""
    study = os.path.join(out, "study.toml")
    with open(study, "w") as f:
        f.write(f'[mechanism.robot_file]\nfile = "{robot}"\n[trajectory]\ndt = {DT}\n')
        f.write(f"[[trajectory.task_segments]]\nstart = {move.start()}\nend = {move.end()}\n"
                f'law = "parabolic"\nduration = {DURATION}\n')
    pkm("dynamics", study, "--out", os.path.join(out, "dyn"))
    with open(os.path.join(out, "dyn", "results.json")) as f:
        names = [a["name"] for a in json.load(f)["result"]["efforts"]["actuators"]]
    with open(os.path.join(out, "dyn", "efforts.csv")) as f:
        header, *lines = f.read().splitlines()
    columns = header.split(",")
    rows = [dict(zip(columns, map(float, line.split(",")))) for line in lines]
    return lambda t: next([r[f"effort {n}"] for n in names] for r in rows if abs(r["t"] - t) < 1e-9)


def check(model, move, t, efforts_pkm):
    q, closure = model.solve_configuration(move, t)
    v, a, A, target = model.motion(move, t, q)
    efforts = model.least_norm_efforts(q, v, a)
    scale = max(1.0, float(np.abs(efforts_pkm).max()))
    a_forward = model.forward(q, v, efforts_pkm)
    model.kinematics(q)
    normal = model.data.oMf[model.platform].rotation[:, 2]
    rows = 6 * len(model.closures)
    reached = (A @ a_forward + model.drifts(move, q, v, normal))[rows:]
    task = move.task_rows()
    return {
        "t": t,
        "residual": closure,
        "joint_speed_max": float(np.abs(v).max()),
        "efforts_pinocchio": efforts.tolist(),
        "efforts_pkm": list(efforts_pkm),
        "efforts_relative_error": float(np.abs(efforts - efforts_pkm).max() / scale),
        "acceleration_error": float(np.abs(reached - target[rows:])[task].max()),
    }


def bench(fn, batches=201):
    """CPU microseconds per call: min and median over batches of about 2 ms."""
    for _ in range(20):
        fn()
    calls = 1
    while True:
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        elapsed = time.perf_counter() - start
        if elapsed > 2.5e-4:
            break
        calls *= 2
    calls = max(1, int(calls * 2e-3 / elapsed))
    times = []
    for _ in range(batches):
        start = time.thread_time_ns()
        for _ in range(calls):
            fn()
        times.append((time.thread_time_ns() - start) / 1e3 / calls)
    return {"cpu_min_us": min(times), "cpu_median_us": statistics.median(times),
            "calls_per_batch": calls, "batches": batches}


def timing(model):
    """Pinocchio's fastest Python route to the efforts at home at rest, and constraintDynamics."""
    m, cms, cds = model.model, model.constraints, model.constraint_datas
    d = m.createData()
    q, v, a = pin.neutral(m), np.zeros(m.nv), np.zeros(m.nv)
    motors = model.motors
    passive = [j for j in range(m.nv) if j not in motors]
    pin.initConstraintDynamics(m, d, cms, cds)

    def inverse_dynamics():
        pin.computeJointJacobians(m, d, q)
        for cm, cd in zip(cms, cds):
            cm.calc(m, d, cd)
        jc = pin.getConstraintsJacobian(m, d, cms, cds)
        tree = pin.rnea(m, d, q, v, a)
        multipliers = np.linalg.solve(jc[:, passive].T, tree[passive])
        return tree[motors] - jc[:, motors].T @ multipliers

    tau = np.zeros(m.nv)
    tau[motors] = inverse_dynamics()
    settings = pin.ProximalSettings(1e-14, 0.0, 1)  # exact for independent closures
    forward_data = m.createData()
    pin.initConstraintDynamics(m, forward_data, cms, cds)
    return {
        "inverse_dynamics": bench(inverse_dynamics),
        "constraintDynamics": bench(lambda: pin.constraintDynamics(
            m, forward_data, q, v, tau, cms, cds, settings)),
    }


def main():
    flags = {a for a in sys.argv[1:] if a.startswith("--")}
    robot = os.path.abspath(next(a for a in sys.argv[1:] if not a.startswith("--")))
    move, out = Move(robot), tempfile.mkdtemp()
    efforts_at = pkm_efforts(robot, move, out)
    pkm("urdf", robot, "--out", os.path.join(out, "urdf"))
    model = Model(os.path.join(out, "urdf"))
    states = {"rest": check(model, move, 0.0, np.array(efforts_at(0.0)))}
    if "--moving" in flags:
        states["moving"] = check(model, move, MOVING, np.array(efforts_at(MOVING)))
    result = {"robot": os.path.basename(robot), "pinocchio": pin.__version__,
              "armature": ARMATURE, "nv": model.model.nv, "states": states}
    if "--time" in flags:
        result["timing_us"] = timing(model)
    print(json.dumps(result))


if __name__ == "__main__":
    main()
