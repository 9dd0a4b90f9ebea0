"""The documented Dask example on a LocalCluster of 2 workers."""

from __future__ import annotations

import importlib.util
import sys

import pytest

import kanestop
from conftest import ROOT

distributed = pytest.importorskip("dask.distributed")


def load_example() -> object:
    path = ROOT / "python" / "examples" / "dask_sweep.py"
    spec = importlib.util.spec_from_file_location("dask_sweep", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["dask_sweep"] = module
    spec.loader.exec_module(module)
    return module


def test_dask_sweep_equals_the_rust_sweep(case01: kanestop.Scene) -> None:
    example = load_example()
    rows = [{"ship.mass": m} for m in (4e5, 5e5, 6e5, 7e5)]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            # The example is not an installed module: ship it to the workers.
            client.upload_file(str(ROOT / "python" / "examples" / "dask_sweep.py"))
            df = example.sweep_on_dask(client, case01, rows, end_time=1.5, timeout=300)  # type: ignore[attr-defined]
            assert len(client.scheduler_info()["workers"]) == 2
    local = kanestop.sweep(case01, rows, end_time=1.5)
    assert list(df["ship.mass"]) == [r["ship.mass"] for r in rows]
    # The example's flattened summaries against sweep's table (sweep.csv's columns).
    for col, table in (
        ("status", "status"),
        ("t_end", "t_end"),
        ("steps", "steps"),
        ("ship_displacement", "ship_displacement"),
        ("peak_tension.tension", "peak_tension"),
        ("anchor_drag_distance", "anchor_drag_distance"),
    ):
        assert list(df[col]) == list(local[table]), col
