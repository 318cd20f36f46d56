#!/usr/bin/env python3
"""Martyushev's fkSGP (2025, MIT licence, https://github.com/martyushev/fkSGP): the forward
kinematics of Dietmaier's Stewart–Gough design (40 real postures) by its elimination-template
solver in Python/NumPy, timed per call; issue 32's peer of pkm's homotopy (`pkm assembly`,
`RobotModel::forward_kinematics_all`; not run in CI).

Dietmaier's design and leg lengths are fkSGP's own (`genSGP(100)`), the ones of
`examples/robots/dietmaier_40.toml`. Timed: `solver66(X, x, L, realOnly)` with real postures
only, the process's CPU time (every thread NumPy's BLAS uses) and the wall time per call over
batches of three (min and median), and the number of real postures with an error below 1e-6.

Usage: FKSGP_DIR=<a checkout of fkSGP (the folder that holds python/)> python3
fksgp_dietmaier.py (prints one JSON line). Needs `pip install numpy scipy`.
"""

import importlib
import json
import os
import statistics
import sys
import time
import types


def main():
    folder = os.environ.get("FKSGP_DIR")
    if not folder or not os.path.isdir(os.path.join(folder, "python")):
        raise SystemExit("set FKSGP_DIR to a checkout of https://github.com/martyushev/fkSGP")
    # fkSGP's package is `python/`; its __init__ imports a test module that needs Python 3.12, so
    # the package is declared here without running it.
    package = types.ModuleType("fksgp")
    package.__path__ = [os.path.join(folder, "python")]
    sys.modules["fksgp"] = package
    genSGP = importlib.import_module("fksgp.genSGP").genSGP
    solver66 = importlib.import_module("fksgp.solver66").solver66

    sgp = genSGP(100, 1)
    X, x, L = sgp["X"], sgp["x"], sgp["L"]
    Rt, err = solver66(X, x, L, 1)
    real = int(sum(1 for e in err if e < 1e-6))
    cpu, wall = [], []
    for _ in range(int(os.environ.get("BATCHES", "41"))):
        start, clock = time.process_time_ns(), time.perf_counter_ns()
        for _ in range(3):
            solver66(X, x, L, 1)
        cpu.append((time.process_time_ns() - start) / 3e3)
        wall.append((time.perf_counter_ns() - clock) / 3e3)
    timing = {"cpu_min_us": min(cpu), "cpu_median_us": statistics.median(cpu),
              "wall_min_us": min(wall), "wall_median_us": statistics.median(wall),
              "calls_per_batch": 3, "batches": len(cpu)}
    print(json.dumps({
        "solver": "fkSGP solver66 (Python/NumPy)",
        "real_postures": real,
        "postures": int(Rt.shape[0]),
        "timing_us": {"solver66": timing},
    }))


if __name__ == "__main__":
    main()
