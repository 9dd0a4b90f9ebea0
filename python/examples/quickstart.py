"""The package in one page: a scene, an override, a run, its channels, eval and a sweep.

    python python/examples/quickstart.py [scenes/paper/case01.toml]
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import numpy as np

import kanestop


def main(path: str) -> None:
    scene = kanestop.Scene.load(path)
    result = kanestop.run(scene)
    t: Optional[float] = result.stopping_time
    print(f"{scene.name}: {result.status}, stopping time {t} s (paper {result.summary['paper_stopping_time']} s)")

    heavy = scene.with_overrides({"ship.mass": 6e5})
    r = kanestop.run(heavy, integrator="dp5", dt=0.02, rtol=1e-4, atol=1e-6)
    ship_vx: np.ndarray = r.arrays["ship_vx"]
    print(f"6e5 kg with dp5: stops at {r.stopping_time} s; max ship speed {float(ship_vx.max()):.3f} m/s")

    try:
        scene.with_overrides({"ship.mass": -1.0})
    except kanestop.SceneError as e:
        for field, value, expected in e.problems:
            print(f"refused: {field} = {value}, must be {expected}")

    e0 = kanestop.eval(scene)
    m: np.ndarray = e0["M"]
    print(f"eval: {m.shape[0]} active speeds, cond(M) = {e0['cond']:.3e}")
    # At another state: q and u as NumPy arrays (or lists), here the first link turned 0.01 rad.
    e1 = kanestop.eval(scene, q=e0["q"] + np.eye(len(e0["q"]))[0] * 0.01, u=e0["u"])
    print(f"eval: first link +0.01 rad changes its acceleration by {float(e1['qdd'][0] - e0['qdd'][0]):.3e} rad/s²")

    frame = kanestop.sweep(
        {"base": scene, "axis": [{"path": "ship.mass", "values": [4e5, 5e5, 6e5]}]},
        progress=lambda done, total: print(f"  {done}/{total}", end="\r"),
    )
    print(frame[["name", "ship.mass", "status", "stopping_time", "peak_tension"]])


if __name__ == "__main__":
    # Case 1 of the checkout this file is in, from whatever folder it is run.
    case01 = Path(__file__).resolve().parents[2] / "scenes" / "paper" / "case01.toml"
    main(sys.argv[1] if len(sys.argv) > 1 else str(case01))
