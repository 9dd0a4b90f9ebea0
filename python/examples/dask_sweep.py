"""A sweep spread over a Dask cluster: one task per row, results gathered into a DataFrame.

    python python/examples/dask_sweep.py scenes/paper/case01.toml

Scenes and results pickle, so the scene travels to the workers with each task and each
`kanestop.Result` comes back whole (its summary, channels and events).
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any, Dict, List, Mapping

import pandas as pd
from dask.distributed import Client, LocalCluster, wait

import kanestop


def run_row(scene: kanestop.Scene, overrides: Mapping[str, Any], end_time: float | None = None) -> kanestop.Result:
    """One row of the sweep, on a worker."""
    return kanestop.run(scene.with_overrides(dict(overrides)), end_time=end_time)


def sweep_on_dask(
    client: Client,
    scene: kanestop.Scene,
    rows: List[Dict[str, Any]],
    end_time: float | None = None,
    timeout: float | None = None,
) -> pd.DataFrame:
    """Runs every row on the cluster of `client`: the override columns, then the flattened
    summary, one row per input row in order."""
    futures = client.map(run_row, [scene] * len(rows), rows, [end_time] * len(rows), pure=False)
    wait(futures, timeout=timeout)
    results: List[kanestop.Result] = client.gather(futures)
    return pd.DataFrame([{**row, **kanestop.flatten(r.summary)} for row, r in zip(rows, results)])


def main(path: str) -> None:
    scene = kanestop.Scene.load(path)
    rows = [{"ship.mass": m, "initial.ship_speed": v} for m in (4e5, 5e5, 6e5) for v in (2.5, 3.0)]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
        df = sweep_on_dask(client, scene, rows)
    print(df[["ship.mass", "initial.ship_speed", "status", "stopping_time", "peak_tension.tension"]])


if __name__ == "__main__":
    # Case 1 of the checkout this file is in, from whatever folder it is run.
    case01 = Path(__file__).resolve().parents[2] / "scenes" / "paper" / "case01.toml"
    main(sys.argv[1] if len(sys.argv) > 1 else str(case01))
