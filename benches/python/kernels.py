#!/usr/bin/env python3
"""Times 1/κ on 10⁶ points of the Miller Delta three ways in one run:

  python : pkm.Mechanism("delta").local_indices(x) from Python (array checks, GIL released,
           rayon threads, NumPy outputs);
  rust   : the same Rust kernel on the same points held in Rust (Mechanism._time_rust_kernel:
           no Python objects inside the timed region);
  numpy  : ../shared/peers/numpy_delta_gci.py's vectorised NumPy (np.linalg.svd on the stack).

The Delta is the peer's design in the peer's frame (R = 0.194, r = 0.03, La = 0.26,
Lb = 0.48 m), the points the peer's box and seed; the values are compared too (an independent
check of the kernel). Prints one JSON line; docs/performance.md records the numbers.

Usage: python benches/python/kernels.py [--quick] [--peer PATH]
"""
import json
import os
import pathlib
import statistics
import sys
import time

import numpy as np

import pkm

QUICK = "--quick" in sys.argv
N = 200_000 if QUICK else 1_000_000
REPEATS = 3 if QUICK else 5
ROOT = pathlib.Path(__file__).resolve().parents[2]


def peer_path():
    if "--peer" in sys.argv:
        return pathlib.Path(sys.argv[sys.argv.index("--peer") + 1])
    # shared/ lies beside the checkout (CI) or beside the folder of worktrees.
    for base in [ROOT.parent, ROOT.parent.parent]:
        path = base / "shared" / "peers" / "numpy_delta_gci.py"
        if path.exists():
            return path
    sys.exit("numpy_delta_gci.py not found: pass --peer PATH")


def median_time(f):
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    path = peer_path()
    sys.path.insert(0, str(path.parent))
    import numpy_delta_gci as peer  # noqa: E402

    # The peer's Delta in the peer's frame: motor plane z = 0, motor 1 at azimuth 0.
    delta = pkm.Mechanism({"rotary_delta": {
        "base_radius": peer.R_BASE, "plate_offset": peer.R_PLATE, "arm": peer.LA, "forearm": peer.LB,
        "motor_plane_z": 0.0, "azimuth_motor_1_deg": 0.0}})
    x = np.random.default_rng(peer.SEED).uniform(peer.BOX_LO, peer.BOX_HI, size=(N, 3))
    delta.local_indices(x[:1000])  # warm the thread pool
    python = median_time(lambda: delta.local_indices(x))
    rust = statistics.median(delta._time_rust_kernel(x) for _ in range(REPEATS))
    numpy_s = median_time(lambda: peer.run_vectorised(x, peer.index_svd))
    ours = delta.local_indices(x)
    theirs = peer.run_vectorised(x, peer.index_svd)
    both = ours["inside"] & ~np.isnan(theirs)
    print(json.dumps({
        "points": N,
        "threads": int(os.environ.get("RAYON_NUM_THREADS", os.cpu_count() or 1)),
        "python_s": round(python, 4),
        "rust_s": round(rust, 4),
        "numpy_s": round(numpy_s, 4),
        "python_over_rust": round(python / rust, 3),
        "numpy_over_python": round(numpy_s / python, 2),
        "same_inside": bool((ours["inside"] == ~np.isnan(theirs)).all()),
        "inside": int(both.sum()),
        "max_abs_diff_vs_numpy": float(np.max(np.abs(ours["inverse_condition"][both] - theirs[both]))),
    }))


if __name__ == "__main__":
    main()
