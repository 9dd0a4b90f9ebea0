"""Python overhead against the Rust core and the command line (docs/python.md records the numbers).

    python python/bench.py [--cli target/release/kanestop] [--runs 5] [--rows 100] [--repeats 2]

1. `kanestop.run` on case 1: the call's wall time against its `core_time` (measured inside
   Rust from the call's start to the summary: the overrides, the model, the run and its
   start-up, the summary, all of which the CLI does too): the difference is the Python
   overhead (argument handling, the `Result`), as a share of the core's time; the first
   read of the channels (the history handed to NumPy) is timed beside it. The CLI's `run --json` process is shown beside it. Wall and CPU time.
2. A sweep spec of `--rows` rows (one axis: ship mass 4e5 … 6e5 kg on case 1) run by
   `kanestop.sweep(SPEC)` in this process and by `kanestop sweep SPEC --out DIR` (the CLI,
   which also writes sweep.csv, sweep.json and every row's scene), both on every core,
   alternating which goes first. Wall time and CPU time: `time.process_time()` (every
   thread of this process) for Python, `resource.getrusage(RUSAGE_CHILDREN)` for the CLI.
   The two tables are checked equal (every cell but `wall_time`). Best of `--repeats`.

The load average (1 min) is printed before and after each part: the development machine
is shared.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import resource
import statistics
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any, Callable, List, Tuple

import kanestop

ROOT = Path(__file__).resolve().parents[1]
CASE01 = ROOT / "scenes" / "paper" / "case01.toml"


def load() -> str:
    return f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores"


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed_cli(args: List[str]) -> Tuple[float, float]:
    """(wall, CPU) of one CLI process."""
    c0, t0 = children_cpu(), time.perf_counter()
    subprocess.run(args, check=True, capture_output=True)
    return time.perf_counter() - t0, children_cpu() - c0


def timed_python(f: Callable[[], Any]) -> Tuple[float, float, Any]:
    """(wall, CPU of this process, result) of one call."""
    c0, t0 = time.process_time(), time.perf_counter()
    out = f()
    return time.perf_counter() - t0, time.process_time() - c0, out


def bench_run(cli: str, runs: int) -> None:
    print(f"run: {load()}")
    scene = kanestop.Scene.load(CASE01)
    kanestop.run(scene).arrays  # warm up (page cache, allocator)
    overheads, walls, cpus, inner, core, reads = [], [], [], [], [], []
    for _ in range(runs):
        wall, cpu, r = timed_python(lambda: kanestop.run(scene))
        assert r.core_time is not None
        walls.append(wall)
        cpus.append(cpu)
        inner.append(r.summary["wall_time"])
        core.append(r.core_time)
        overheads.append(wall - r.core_time)
        reads.append(timed_python(lambda: r.arrays)[0])
    cli_runs = [timed_cli([cli, "run", str(CASE01), "--json"]) for _ in range(runs)]
    # A CLI process that does no work: what the process itself costs (start, exit).
    idle = [timed_cli([cli, "--version"]) for _ in range(runs)]
    o, w, c, i, k, a = (statistics.median(x) for x in (overheads, walls, cpus, inner, core, reads))
    cw, cc = (statistics.median(x) for x in zip(*cli_runs))
    iw, ic = (statistics.median(x) for x in zip(*idle))
    print(f"run case01 ×{runs} (median): kanestop.run {w * 1e3:.1f} ms wall, {c * 1e3:.1f} ms CPU;")
    print(f"  in the Rust core (core_time: overrides, model, run, summary) {k * 1e3:.1f} ms, of which the run's wall_time {i * 1e3:.1f} ms")
    print(f"  Python overhead per run (call less core_time) {o * 1e3:.2f} ms = {100 * o / k:.2f} % of the run (target < 2 %)")
    print(f"  the channels' first read (351 NumPy arrays) {a * 1e3:.2f} ms; call and read {100 * (o + a) / k:.2f} % of the run")
    print(f"  CLI run --json process {cw * 1e3:.1f} ms wall, {cc * 1e3:.1f} ms CPU; an idle CLI process {iw * 1e3:.1f} ms wall")
    print(f"  {load()}")


def same_tables(df: Any, path: Path) -> None:
    """The CLI's sweep.csv and the DataFrame: the same columns and cells (but wall_time)."""
    with open(path, newline="") as f:
        head, *lines = list(csv.reader(f))
    assert list(df.columns) == head and len(df) == len(lines)
    for i, line in enumerate(lines):
        for col, text in zip(head, line):
            v = df.iloc[i][col]
            if col in ("wall_time", "cpu_time"):
                continue
            if isinstance(v, str):
                assert v == text, (i, col, v, text)
            elif text == "":
                assert v is None or (isinstance(v, float) and math.isnan(v)), (i, col, v)
            else:
                assert float(v) == float(text), (i, col, v, text)


def bench_sweep(cli: str, rows: int, repeats: int) -> None:
    print(f"sweep: {load()}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "base.toml").write_text(CASE01.read_text())
        spec = folder / "bench.toml"
        spec.write_text(
            f'base = "base.toml"\n[[axis]]\npath = "ship.mass"\nrange = {{ from = 4e5, to = 6e5, steps = {rows} }}\n'
        )
        out = folder / "out"
        py: List[Tuple[float, float]] = []
        cl: List[Tuple[float, float]] = []
        frames: List[Any] = []

        def python_sweep() -> None:
            wall, cpu, df = timed_python(lambda: kanestop.sweep(spec))
            py.append((wall, cpu))
            frames.append(df)
            assert len(df) == rows and set(df["status"]) == {"stopped"}, set(df["status"])

        def cli_sweep() -> None:
            cl.append(timed_cli([cli, "sweep", str(spec), "--out", str(out)]))

        # Alternate which goes first: the machine's load drifts.
        for i in range(repeats):
            for f in (python_sweep, cli_sweep) if i % 2 == 0 else (cli_sweep, python_sweep):
                f()
        same_tables(frames[-1], out / "sweep.csv")
    (pw, pc), (cw, cc) = min(py), min(cl)
    print(f"sweep spec of {rows} rows (best of {repeats} by wall):")
    print(f"  kanestop.sweep(SPEC)  {pw:.2f} s wall, {pc:.2f} s CPU")
    print(f"  kanestop sweep SPEC   {cw:.2f} s wall, {cc:.2f} s CPU")
    print(f"  Python/CLI: wall {pw / cw:.3f}, CPU {pc / cc:.3f}; the tables are equal (every cell but wall_time)")
    (mpw, mpc), (mcw, mcc) = ((statistics.median(w), statistics.median(c)) for w, c in (zip(*py), zip(*cl)))
    print(f"  median of {repeats}: Python {mpw:.2f} s wall, {mpc:.2f} s CPU; CLI {mcw:.2f} s wall, {mcc:.2f} s CPU")
    each = ", ".join(f"{a[0]:.2f}/{b[0]:.2f} ({a[1]:.2f}/{b[1]:.2f} CPU)" for a, b in zip(py, cl))
    print(f"  each repeat, Python/CLI s: {each}")
    print(f"  {load()}")


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
