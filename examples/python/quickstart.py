"""pkm from Python, notebook style: run it cell by cell or as a script.

    pip install ./crates/pkm-py      # once
    python examples/python/quickstart.py

1. The workspace of a NUWAR with joint limits, as the `pkm workspace` study (a dict).
2. The same machine's kinematics on a million points, as NumPy arrays.
3. The Pareto front of a Linear Delta's two indices, split into shards and merged.
4. Motor torques of the NUWAR prototype along a trajectory given as an array.
Figures are drawn with Matplotlib when it is installed (into target/python-quickstart).
"""

# %% 1. The workspace study of a NUWAR with joint limits
import pathlib
import time

import numpy as np

import pkm

print(f"pkm {pkm.__version__}")
OUT = pathlib.Path("target/python-quickstart")
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
    print("matplotlib not installed: no figures")


def save(fig, name):
    OUT.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT / name, dpi=120)
    print(f"wrote {OUT / name}")


study = {
    "title": "NUWAR with joint limits",
    "mechanism": pkm.presets()["nuwar"]["mechanism"],
    "constraints": {"below_z": 0.0, "joint_range_deg": [-40.0, 90.0], "passive_cone_deg": 35.0},
    "sampling": {
        "sampler": "sobol",
        "seed": 42,
        "points": 16384,
        "replicates": 4,
        "symmetry_folds": 3,
        "region": {"cylinder": {"radius": 0.8, "z_min": -1.1, "z_max": 0.0}},
    },
    "workspace": {"slices": [{"plane": "xz", "at": 0.0, "cells": 60}]},
}
outcome = pkm.workspace(study)
for line in outcome["summary"]:
    print(line)
estimate = outcome["result"]["estimate"]
print(f"W = {estimate['volume']:.6f} ± {estimate['volume_se']:.6f} m³, GCI = {estimate['gci']:.4f}")

table = outcome["tables"]["slice-1-xz.csv"]
if plt:
    n = int(round(np.sqrt(len(table["x"]))))
    fig, ax = plt.subplots(figsize=(5, 4))
    image = ax.pcolormesh(table["x"][:n], table["z"][::n], table["inverse_condition"].reshape(n, n), shading="nearest")
    fig.colorbar(image, label="1/κ")
    ax.set(xlabel="x (m)", ylabel="z (m)", title="NUWAR with joint limits: 1/κ on y = 0")
    save(fig, "nuwar-slice.png")

# %% 2. Kinematics on a million points
nuwar = pkm.Mechanism("nuwar", study["constraints"])
x = np.random.default_rng(1).uniform([-0.6, -0.6, -1.1], [0.6, 0.6, 0.0], (1_000_000, 3))
start = time.perf_counter()
local = nuwar.local_indices(x)
elapsed = time.perf_counter() - start
inside = local["inside"]
print(f"1/κ at {len(x):,} points in {elapsed * 1e3:.0f} ms: {inside.mean():.1%} inside, "
      f"mean 1/κ inside {np.mean(local['inverse_condition'][inside]):.4f}")
some = x[inside][:5]
q, ok = nuwar.inverse_kinematics(some)
print("joints at five points inside (deg):", np.round(np.rad2deg(q), 2).tolist())
back, converged = nuwar.forward_kinematics(q, some + 1e-3)
print("IK → FK round trip, largest error (m):", float(np.max(np.abs(back - some))))

# %% 3. A Linear Delta's Pareto front of η1 (manipulability) and η2 (space utilisation)
# examples/studies/linear_delta_pareto.toml on two of its four variables. The grid is split into
# four shards, as a Dask or Ray cluster would run them (docs/python.md), and merged: the same
# result as one run, bit for bit.
grid = {
    "title": "Linear Delta: eta1 vs eta2",
    "mechanism": {"linear_delta": {"l1_over_yr": 2.0, "ya_over_yr": 0.0, "zr_over_yr": 0.0, "l2_over_l1": 0.63}},
    "indices": {"eta1_points": 8},
    "variables": [
        {"name": "l1_over_yr", "from": 1.4, "to": 2.7, "step": 0.1},
        {"name": "l2_over_l1", "from": 0.6, "to": 1.8, "step": 0.1},
    ],
    "pareto": {"objectives": ["eta1", "eta2"], "weights": [[1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]},
}
parts = [pkm.pareto(grid, shard=(i, 4), progress=False) for i in range(1, 5)]
front = pkm.merge(parts)
result = front["result"]
print(f"{result['nodes']} designs, {result['infeasible']} infeasible, {len(result['front'])} on the front")
for optimum in result["weighted_optima"]:
    print(f"  weights {optimum['weights']}: node {optimum['node']}, "
          f"η1 = {optimum['values'][0]:.4f}, η2 = {optimum['values'][1]:.4f}")
landscape = front["tables"]["landscape.csv"]
if plt:
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.scatter(landscape["eta1"], landscape["eta2"], s=6, c="0.7", label="grid")
    f = front["tables"]["front.csv"]
    order = np.argsort(f["eta1"])  # the front is listed by node
    ax.plot(f["eta1"][order], f["eta2"][order], "o-", ms=4, label="Pareto front")
    ax.set(xlabel="η1", ylabel="η2", title="Linear Delta: η1 vs η2")
    ax.legend()
    save(fig, "linear-delta-front.png")

# %% 4. Torques along a trajectory: a rest-to-rest cycloidal line, sampled every 2 ms
dynamics = {
    "title": "NUWAR prototype, a cycloidal line",
    "mechanism": {
        "rotary_delta": {
            "base_radius": 0.194, "plate_offset": 0.03, "arm": 0.26, "forearm": 0.48,
            "alpha_deg": 35.26, "beta_deg": 60.0, "motor_plane_z": -0.2928, "azimuth_motor_1_deg": 300.0,
        }
    },
    "masses": {  # Miller 2004 §3.5
        "plate": 0.2807, "arm_inertia": 0.01822, "arm_mass": 0.977, "arm_centre_of_mass": 0.13,
        "elbow": 0.0099, "forearm": 0.0296,
    },
}
t = np.arange(0.0, 0.4 + 1e-12, 0.002)
s = t / 0.4 - np.sin(2 * np.pi * t / 0.4) / (2 * np.pi)          # cycloidal law, 0 → 1
start, end = np.array([0.0, -0.2, -0.9]), np.array([0.0, 0.2, -0.9])
rows = np.column_stack([t, start + s[:, None] * (end - start)])   # N × 4: t, x, y, z
outcome = pkm.dynamics(dynamics, trajectory=rows)
for line in outcome["summary"]:
    print(line)
torques = outcome["tables"]["torques.csv"]
if plt:
    fig, ax = plt.subplots(figsize=(6, 4))
    for i in (1, 2, 3):
        ax.plot(torques["t"], torques[f"tau_hamilton_{i}"], label=f"motor {i}, Hamilton")
        ax.plot(torques["t"], torques[f"tau_lagrange_{i}"], "k:", lw=1)
    ax.set(xlabel="t (s)", ylabel="τ (N m)", title="NUWAR: motor torques (dotted: Lagrange)")
    ax.legend()
    save(fig, "nuwar-torques.png")
