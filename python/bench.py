"""Python overhead against the Rust core and the command line (docs/python.md records the numbers).

    python python/bench.py [--cli target/release/kanestop] [--runs 5] [--rows 100] [--repeats 2]

1. `kanestop.run` on case 1: the call's wall time against the run's own `wall_time` (the
   summary's, measured inside Rust around the integration): the difference is the Python
   overhead (argument handling, the model, the summary, the channels as NumPy arrays).
   The CLI's `run --json` process time is shown beside it.
2. A sweep of `--rows` rows (ship mass 4e5 … 6e5 kg) with `kanestop.sweep` against the CLI's
   `batch` on a folder of the same scenes (each `extends` case 1 with its mass), both on
   every core. Best of `--repeats`.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path
from typing import List

import kanestop

ROOT = Path(__file__).resolve().parents[1]
CASE01 = ROOT / "scenes" / "paper" / "case01.toml"


def masses(rows: int) -> List[float]:
    return [4e5 + 2e5 * i / max(rows - 1, 1) for i in range(rows)]


def bench_run(cli: str, runs: int) -> None:
    scene = kanestop.Scene.load(CASE01)
    kanestop.run(scene)  # warm up (page cache, allocator)
    overheads, walls, inner = [], [], []
    for _ in range(runs):
        t0 = time.perf_counter()
        r = kanestop.run(scene)
        wall = time.perf_counter() - t0
        walls.append(wall)
        inner.append(r.summary["wall_time"])
        overheads.append(wall - r.summary["wall_time"])
    cli_walls = []
    for _ in range(runs):
        t0 = time.perf_counter()
        subprocess.run([cli, "run", str(CASE01), "--json"], check=True, capture_output=True)
        cli_walls.append(time.perf_counter() - t0)
    o, w, i = statistics.median(overheads), statistics.median(walls), statistics.median(inner)
    print(f"run case01 ×{runs} (median): kanestop.run {w * 1e3:.1f} ms, of which the run's wall_time {i * 1e3:.1f} ms;")
    print(f"  Python overhead {o * 1e3:.2f} ms = {100 * o / i:.2f} % of the run; CLI run --json process {statistics.median(cli_walls) * 1e3:.1f} ms")


def bench_sweep(cli: str, rows: int, repeats: int) -> None:
    scene = kanestop.Scene.load(CASE01)
    plan = [{"ship.mass": m} for m in masses(rows)]
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp) / "base.toml"
        base.write_text(CASE01.read_text())
        folder = Path(tmp) / "rows"
        folder.mkdir()
        for k, m in enumerate(masses(rows)):
            (folder / f"row{k:03}.toml").write_text(f'extends = "../base.toml"\n[meta]\nname = "row{k:03}"\n[ship]\nmass = {m!r}\n')
        py, cl = [], []
        def python_sweep() -> None:
            t0 = time.perf_counter()
            df = kanestop.sweep(scene, plan)
            py.append(time.perf_counter() - t0)
            assert len(df) == rows and set(df["status"]) == {"stopped"}, set(df["status"])

        def cli_batch() -> None:
            t0 = time.perf_counter()
            subprocess.run([cli, "batch", str(folder), "--out", str(Path(tmp) / "out")], check=True, capture_output=True)
            cl.append(time.perf_counter() - t0)

        # Alternate which goes first: the machine's load drifts.
        for i in range(repeats):
            for f in (python_sweep, cli_batch) if i % 2 == 0 else (cli_batch, python_sweep):
                f()
        rows_json = json.loads((Path(tmp) / "out" / "batch.json").read_text())
        assert len(rows_json) == rows
    p, c = min(py), min(cl)
    each = ", ".join(f"{a:.2f}/{b:.2f}" for a, b in zip(py, cl))
    print(f"sweep of {rows} rows (best of {repeats}): kanestop.sweep {p:.2f} s, CLI batch {c:.2f} s: Python/CLI = {p / c:.3f}")
    print(f"  each repeat, Python/CLI s: {each}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default=str(ROOT / "target" / "release" / "kanestop"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--rows", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=2)
    a = ap.parse_args()
    bench_run(a.cli, a.runs)
    bench_sweep(a.cli, a.rows, a.repeats)


if __name__ == "__main__":
    main()
