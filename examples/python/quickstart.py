"""pkm from Python, notebook style: run it cell by cell or as a script.

    pip install ./crates/pkm-py      # once
    python examples/python/quickstart.py

1. The workspace of a NUWAR with joint limits, as the `pkm workspace` study (a dict).
2. The same machine's kinematics on a million points, as NumPy arrays.
3. A slice of 1/κ plotted with Matplotlib, when it is installed.
"""

# %% 1. The workspace study of a NUWAR with joint limits
import pathlib
import time

import numpy as np

import pkm

print(f"pkm {pkm.__version__}")
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

# %% 3. The slice of 1/κ on the plane y = 0
table = outcome["tables"]["slice-1-xz.csv"]
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib not installed: no figure")
else:
    n = int(round(np.sqrt(len(table["x"]))))
    values = table["inverse_condition"].reshape(n, n)
    fig, ax = plt.subplots(figsize=(5, 4))
    image = ax.pcolormesh(table["x"][:n], table["z"][::n], values, shading="nearest")
    fig.colorbar(image, label="1/κ")
    ax.set(xlabel="x (m)", ylabel="z (m)", title="NUWAR with joint limits: 1/κ on y = 0")
    out = pathlib.Path("target/python-quickstart")
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "nuwar-slice.png", dpi=120)
    print(f"wrote {out / 'nuwar-slice.png'}")
