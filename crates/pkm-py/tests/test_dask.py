"""A sweep as a map over shards on a dask.distributed LocalCluster of two worker processes,
joined by pkm.merge: the single-process result bit for bit (docs/python.md's recipe)."""

import os

import pytest

import pkm
from test_sweep_pareto_merge import serialised

distributed = pytest.importorskip("dask.distributed")


def test_sweep_shards_on_two_worker_processes_merge_to_the_single_process_result(grid_study):
    whole = pkm.sweep(grid_study, progress=False)
    count = 4

    def shard(i):
        return os.getpid(), pkm.sweep(grid_study, shard=(i, count), progress=False)

    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        workers = set(client.run(os.getpid).values())
        done = client.gather(client.map(shard, range(1, count + 1)))
    assert len(workers) == 2 and os.getpid() not in workers
    assert {pid for pid, _ in done} <= workers
    merged = pkm.merge([part for _, part in done], progress=False)
    assert serialised(merged["result"]) == serialised(whole["result"])
    assert merged["summary"] == whole["summary"]
