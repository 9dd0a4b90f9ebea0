"""Scenes, overrides, results, channels, sweeps and pickling."""

from __future__ import annotations

import math
import pickle
import sys
from typing import List, Tuple

import numpy as np
import pandas as pd
import pytest

import kanestop
from conftest import CASE01, ROOT, without_wall_time


def test_scene_round_trips(case01: kanestop.Scene) -> None:
    d = case01.to_dict()
    assert d["ship"]["mass"] == 500000.0 and d["meta"]["name"] == "case01"
    assert kanestop.Scene.from_dict(d) == case01
    assert kanestop.Scene.from_toml(case01.to_toml()) == case01
    assert pickle.loads(pickle.dumps(case01)) == case01
    # Hashable, equal scenes alike: a dict key, a set member.
    heavy = case01.with_overrides({"ship.mass": 6e5})
    assert hash(pickle.loads(pickle.dumps(case01))) == hash(case01)
    assert len({case01, kanestop.Scene.from_dict(d), heavy}) == 2 and {case01: 1}[kanestop.Scene.from_dict(d)] == 1
    assert case01.name == "case01"
    assert repr(case01) == 'Scene("case01": 46 bodies, ship 500 t at 3 m/s, anchor 40 t, chain 15 × 1 m)'
    heavier = case01.with_overrides({"ship.mass": 6e5, "chain.elements": 20})
    assert repr(heavier) == 'Scene("case01": 51 bodies, ship 600 t at 3 m/s, anchor 40 t, chain 20 × 1 m)'


def test_the_paper_cases_are_built_in(case01: kanestop.Scene) -> None:
    assert kanestop.Scene.paper(1) == case01
    for n in (8, 19):
        assert kanestop.Scene.paper(n) == kanestop.Scene.load(ROOT / "scenes" / "paper" / f"case{n:02}.toml")
    assert kanestop.Scene.paper(np.int64(5)).name == "case05"
    for bad in (0, 20, -1):
        with pytest.raises(ValueError, match=f"number = {bad}: in 1–19"):
            kanestop.Scene.paper(bad)
    for wrong in (True, 1.0, "1"):
        with pytest.raises(TypeError, match="must be an int in 1–19"):
            kanestop.Scene.paper(wrong)  # type: ignore[arg-type]


def test_toml_text_that_extends_a_file_is_laid_over_it(tmp_path: object) -> None:
    # Regression: Scene.from_toml refused `extends` ("unknown field") where Scene.load took it.
    text = 'extends = "case01.toml"\n[ship]\nmass = 6e5\n'
    folder = ROOT / "scenes" / "paper"
    from_text = kanestop.Scene.from_toml(text, base_dir=folder)
    (tmp := tmp_path / "heavy.toml").write_text(text.replace('"case01.toml"', '"' + str(CASE01) + '"'))  # type: ignore[operator]
    assert from_text.to_dict()["ship"]["mass"] == 6e5
    assert from_text.to_dict()["chain"] == kanestop.Scene.load(tmp).to_dict()["chain"]
    with pytest.raises(kanestop.SceneError):
        kanestop.Scene.from_toml(text, base_dir=tmp_path)  # no case01.toml there


def test_a_check_is_added_to_a_scene_without_checks(case01: kanestop.Scene) -> None:
    # Regression: "no field `checks` here" on a scene with no [checks].
    checked = case01.with_overrides({"checks.max_stopping_distance": 20.0})
    assert checked.to_dict()["checks"] == {"max_stopping_distance": 20.0}


def test_overrides_set_fields_and_are_checked(case01: kanestop.Scene) -> None:
    s = case01.with_overrides({"ship.mass": 1e6, "cable.stages[2].elements": 12})
    d = s.to_dict()
    assert d["ship"]["mass"] == 1e6 and d["cable"]["stages"][2]["elements"] == 12
    assert case01.to_dict()["ship"]["mass"] == 500000.0  # the original is unchanged
    d2 = case01.to_dict()
    d2["ship"]["mass"] = 1e6
    d2["cable"]["stages"][2]["elements"] = 12
    assert kanestop.Scene.from_dict(d2) == s
    # NumPy scalars are numbers.
    assert case01.with_overrides({"ship.mass": np.float64(1e6), "chain.elements": np.int64(15)}).to_dict()["ship"]["mass"] == 1e6
    # A dict of the wrong shape: the message names the entry's position in its array.
    d3 = case01.to_dict()
    d3["cable"]["stages"][1]["elements"] = "x"
    with pytest.raises(kanestop.SceneError, match=r"in `cable\.stages\[1\]\.elements`"):
        kanestop.Scene.from_dict(d3)


def test_a_line_laid_by_its_tension_follows_the_cable_length(case01: kanestop.Scene) -> None:
    # T_h replaces x_L (the two are alternatives), and holds where a fixed x_L does not lay.
    by_tension = case01.with_overrides({"initial.horizontal_tension": 150})
    initial = by_tension.to_dict()["initial"]
    assert initial["horizontal_tension"] == 150.0 and "horizontal_projection" not in initial
    longer = by_tension.with_overrides({"cable.stages[1].element_length": 12.0})
    result = kanestop.run(longer)
    assert result.stopping_time is not None
    with pytest.raises(kanestop.SceneError, match=r"initial\.horizontal_projection = 148: must be in \[170"):
        case01.with_overrides({"cable.stages[1].element_length": 12.0})
    with pytest.raises(kanestop.SceneError, match=r"initial\.horizontal_tension = 1000000: must be in \[0\.0000100595, 226722\] N"):
        case01.with_overrides({"initial.horizontal_tension": 1e6})
    # Both in one dict: refused, whatever the dict's order.
    with pytest.raises(kanestop.SceneError, match=r"are both set"):
        case01.with_overrides({"initial.horizontal_tension": 150.0, "initial.horizontal_projection": 149.0})


def test_a_line_laid_by_its_top_tension(case01: kanestop.Scene) -> None:
    # T_t = T_h + w_c h_L replaces T_h or x_L; the summary gives all three of the laid line.
    by_top = case01.with_overrides({"initial.horizontal_tension": 150}).with_overrides({"initial.top_tension": 2000})
    initial = by_top.to_dict()["initial"]
    assert initial["top_tension"] == 2000.0 and "horizontal_tension" not in initial
    summary = kanestop.run(by_top).summary
    assert summary["initial_top_tension"] == pytest.approx(2000.0, rel=1e-12)
    w_c = (summary["initial_top_tension"] - summary["initial_horizontal_tension"]) / 6.0
    assert w_c == pytest.approx(118.146, rel=1e-5)
    base = kanestop.run(case01).summary
    assert base["initial_top_tension"] == pytest.approx(base["initial_horizontal_tension"] + 6.0 * w_c, rel=1e-12)
    with pytest.raises(kanestop.SceneError, match=r"initial\.top_tension = 500: must be in \[708\.875, 227431\] N"):
        case01.with_overrides({"initial.top_tension": 500})


def test_overridden_runs_change_the_result(case01: kanestop.Scene) -> None:
    light = kanestop.run(case01.with_overrides({"ship.mass": 4e5}))
    heavy = kanestop.run(case01.with_overrides({"ship.mass": 6e5}))
    assert light.stopping_time is not None and heavy.stopping_time is not None
    assert light.stopping_time < heavy.stopping_time


def test_scene_error_has_field_value_and_range(case01: kanestop.Scene) -> None:
    with pytest.raises(kanestop.SceneError) as info:
        case01.with_overrides({"ship.mass": -1.0, "anchor.mass": float("nan")})
    e = info.value
    assert e.kind == "invalid"
    assert e.problems == [("anchor.mass", "nan", "finite and > 0 kg"), ("ship.mass", "-1", "finite and > 0 kg")]
    assert "ship.mass = -1: must be finite and > 0 kg" in str(e)
    assert isinstance(e, ValueError)
    with pytest.raises(kanestop.SceneError) as info:
        case01.with_overrides({"ship.nope": 1.0})
    assert info.value.kind == "override" and "no field `nope`" in str(info.value)
    with pytest.raises(kanestop.SceneError) as info:
        kanestop.Scene.load(ROOT / "no-such-scene.toml")
    assert info.value.kind == "io"


def test_channels(case01_result: kanestop.Result) -> None:
    a = case01_result.arrays
    n = case01_result.summary["bodies"]
    for name in ("t", "ship_x", "ship_vx", "ship_displacement", "anchor_x", "anchor_drag", "anchor_sliding"):
        assert name in a, name
    for name in ("tension_fairlead", "tension_anchor", "tension_max", "energy_kinetic", "work_drag", "energy_balance"):
        assert name in a, name
    assert f"body{n}_x" in a and f"tension_joint{n}" in a and "tension_joint1" not in a
    assert np.array_equal(a["ship_x"], a[f"body{n}_x"]) and np.array_equal(a["tension_fairlead"], a[f"tension_joint{n}"])
    assert np.array_equal(a["anchor_x"], a["body1_x"]) and np.array_equal(a["tension_anchor"], a["tension_joint2"])
    assert np.array_equal(a["anchor_drag"], a["anchor_x"] - a["anchor_x"][0])
    lengths = {len(v) for v in a.values()}
    assert len(lengths) == 1 and a["t"][0] == 0.0
    assert all(v.dtype == np.float64 for v in a.values())
    assert not a["t"].flags.owndata  # the Rust vector, handed to NumPy without a copy
    assert math.isclose(a["t"][-1], case01_result.summary["t_end"])
    df = case01_result.channels
    assert isinstance(df, pd.DataFrame) and list(df.columns) == list(a)
    assert case01_result.events and case01_result.events[0]["anchor"] == "free"
    assert case01_result.events[0]["t"] == case01_result.summary["anchor_start"]
    assert case01_result.diagnostic is None and not case01_result.failed


def test_channel_units_and_groups(case01_result: kanestop.Result) -> None:
    r = case01_result
    assert list(r.units) == list(r.arrays) == list(r.descriptions) == list(r.groups)
    assert r.units["t"] == "s" and r.units["ship_x"] == "m" and r.units["tension_fairlead"] == "N"
    assert r.units["body1_omega"] == "rad/s" and r.units["anchor_sliding"] == "1" and r.units["work_drag"] == "J"
    assert r.channels.attrs["units"] == r.units
    assert "rod–ship joint" in r.descriptions["tension_fairlead"]
    assert r.channels_of("tension") == ["t", "tension_fairlead", "tension_anchor", "tension_max"]
    # Channel names too, mixed with groups, in column order, as `run --channels` takes them.
    assert r.channels_of("tension_anchor", "ship_vx") == ["t", "ship_vx", "tension_anchor"]
    assert r.channels_of("tension_max", "tension") == r.channels_of("tension")
    with pytest.raises(ValueError, match="unknown channel or group \\['nope'\\]"):
        r.channels_of("nope")


def test_results_pickle(case01_result: kanestop.Result) -> None:
    r = pickle.loads(pickle.dumps(case01_result))
    assert r.summary == case01_result.summary and r.events == case01_result.events
    assert r.units == case01_result.units and r.descriptions == case01_result.descriptions
    assert all(np.array_equal(r.arrays[k], v) for k, v in case01_result.arrays.items())
    assert r.channels.shape == case01_result.channels.shape
    assert r.core_time == case01_result.core_time


def test_the_history_is_read_once_and_an_unread_result_pickles_whole(case01: kanestop.Scene) -> None:
    unread = kanestop.run(case01, end_time=0.5)
    read = kanestop.run(case01, end_time=0.5)
    arrays = read.arrays
    assert read.arrays is arrays and read.channels_of("ship")[0] == "t"
    again = pickle.loads(pickle.dumps(unread))
    assert list(again.arrays) == list(arrays) and again.units == read.units
    assert all(np.array_equal(again.arrays[k], v) for k, v in arrays.items())


def test_core_time_holds_the_run_and_lies_inside_the_call(case01: kanestop.Scene) -> None:
    """The Rust core's share of a call: at least the run's own wall time, at most the call."""
    import time

    t0 = time.perf_counter()
    r = kanestop.run(case01, end_time=1.0)
    call = time.perf_counter() - t0
    assert r.core_time is not None
    assert r.summary["wall_time"] <= r.core_time <= call


def test_sweep_equals_single_runs_in_order(case01: kanestop.Scene) -> None:
    rows = [{"ship.mass": m} for m in (6e5, 4e5, 5e5)] + [{"ship.mass": -1.0}]
    seen = []
    df = kanestop.sweep(case01, rows, jobs=2, end_time=3.0, progress=lambda done, total: seen.append((done, total)))
    assert seen == [(i, 4) for i in range(1, 5)]
    assert list(df["ship.mass"]) == [6e5, 4e5, 5e5, -1.0]
    assert list(df["index"]) == [0, 1, 2, 3] and list(df["name"]) == [f"case01-{i:03}" for i in range(4)]
    for i, row in enumerate(rows[:3]):
        one = kanestop.run(case01.with_overrides(row), end_time=3.0).summary
        got = df.iloc[i]
        assert got["status"] == one["status"] and got["t_end"] == one["t_end"] and got["steps"] == one["steps"]
        assert got["peak_tension"] == one["peak_tension"]["tension"] and got["peak_joint"] == one["peak_tension"]["joint"]
        assert got["work_drag"] == one["work"]["drag"] and got["ship_displacement"] == one["ship_displacement"]
        assert pd.isna(got["message"]), "an empty message is a missing value"
    assert df.iloc[3]["status"] == "invalid" and "ship.mass = -1" in df.iloc[3]["message"]


def test_rows_may_set_different_paths(case01: kanestop.Scene) -> None:
    df = kanestop.sweep(case01, [{"ship.mass": 4e5}, {"initial.ship_speed": 2.5}], end_time=0.2)
    assert list(df.columns[:4]) == ["index", "name", "ship.mass", "initial.ship_speed"]
    assert df.iloc[0]["ship.mass"] == 4e5 and math.isnan(df.iloc[0]["initial.ship_speed"])
    assert math.isnan(df.iloc[1]["ship.mass"]) and df.iloc[1]["initial.ship_speed"] == 2.5


def test_the_old_grid_dict_is_deprecated_and_is_a_spec(case01: kanestop.Scene) -> None:
    grid = {"ship.mass": [4e5, 5e5], "initial.ship_speed": [2.5, 3.0]}
    with pytest.warns(DeprecationWarning, match="deprecated"):
        old = kanestop.sweep({"scene": str(CASE01), "grid": grid, "solver": {"end_time": 0.5}})
    assert len(old) == 4 and set(old["status"]) == {"end time"}
    assert list(zip(old["ship.mass"], old["initial.ship_speed"])) == [(4e5, 2.5), (4e5, 3.0), (5e5, 2.5), (5e5, 3.0)]
    axes = [{"path": p, "values": v} for p, v in grid.items()]
    new = kanestop.sweep({"base": case01, "axis": axes, "solver": {"end_time": 0.5}})
    same = [c for c in new.columns if c not in ("wall_time", "cpu_time")]
    assert list(old.columns) == list(new.columns) and old[same].equals(new[same])


def test_a_progress_callback_that_raises_cancels(case01: kanestop.Scene) -> None:
    def stop(done: int, total: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        kanestop.sweep(case01, [{"ship.mass": 5e5}] * 8, jobs=1, end_time=0.2, progress=stop)


@pytest.mark.parametrize("records", [False, True])
def test_an_interrupted_sweep_keeps_the_rows_that_finished(case01: kanestop.Scene, records: bool) -> None:
    """The exception carries the finished rows as ``partial``, in the form a return has:
    here the progress callback stops the sweep once three of eight rows have finished (one
    thread: the fourth is stopped mid-run or not started, so it is not among them)."""

    def stop(done: int, total: int) -> None:
        if done == 3:
            raise KeyboardInterrupt

    masses = [4e5 + 1e4 * i for i in range(8)]
    with pytest.raises(KeyboardInterrupt) as caught:
        kanestop.sweep(case01, [{"ship.mass": m} for m in masses], jobs=1, end_time=0.2, progress=stop, records=records)
    partial = caught.value.partial  # type: ignore[attr-defined]
    whole = kanestop.sweep(case01, [{"ship.mass": m} for m in masses[:3]], jobs=1, end_time=0.2, records=records)
    if records:
        assert [r["index"] for r in partial] == [0, 1, 2]
        assert [r["summary"]["peak_tension"] for r in partial] == [r["summary"]["peak_tension"] for r in whole]
    else:
        assert list(partial["index"]) == [0, 1, 2] and list(partial.columns) == list(whole.columns)
        assert list(partial["ship.mass"]) == masses[:3]
        assert list(partial["peak_tension"]) == list(whole["peak_tension"])
    if sys.version_info >= (3, 11):
        assert any("3 of 8 rows had finished" in n for n in caught.value.__notes__)


def test_ctrl_c_stops_a_run(case01: kanestop.Scene) -> None:
    """Ctrl-C (here its Python stand-in, ``_thread.interrupt_main``) stops a long
    run at its next step and raises KeyboardInterrupt. Uninterrupted, the run
    takes about two million steps (half a minute or more); interrupted after
    0.3 s it returns within a fraction of a second, so the bound of 10 s only
    separates the two."""
    import _thread
    import threading
    import time

    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        kanestop.run(case01, dt=1e-5, output_interval=0.1)
    timer.join()
    assert time.perf_counter() - start < 10.0


def test_ctrl_c_stops_a_sweep_s_running_rows(case01: kanestop.Scene) -> None:
    """As a run: two rows of two million steps each, interrupted after 0.3 s."""
    import _thread
    import threading
    import time

    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt) as caught:
        kanestop.sweep(case01, [{"ship.mass": 5e5}] * 2, jobs=2, dt=1e-5, output_interval=0.1)
    timer.join()
    assert time.perf_counter() - start < 10.0
    # Neither row finished: the partial table is empty.
    partial = caught.value.partial  # type: ignore[attr-defined]
    assert isinstance(partial, pd.DataFrame) and len(partial) == 0


def test_ctrl_c_stops_a_sensitivity_study(case01: kanestop.Scene) -> None:
    """As a run: its base run of two million steps, interrupted after 0.3 s (the study
    waited for all of its runs; docs/python.md)."""
    import _thread
    import threading
    import time

    slow = case01.with_overrides({"solver.dt": 1e-5, "solver.output_interval": 0.1})
    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        kanestop.sensitivity(slow, jobs=2)
    timer.join()
    assert time.perf_counter() - start < 10.0


def test_runs_release_the_gil(case01: kanestop.Scene) -> None:
    """A thread that needs the GIL keeps running while a run integrates.

    With the GIL held for the run, the ticker could not record a time inside
    the run (at most one just as it starts or ends, when the interpreter hands
    the GIL over); released, it ticks every few milliseconds. The test counts
    ticks in the middle 80 % of the run: the whole case (about 0.2 s of work)
    leaves room for dozens, and three are asked for, so a busy machine does not
    decide it."""
    import threading
    import time

    ticks = []
    done = threading.Event()

    def tick() -> None:
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.002)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    kanestop.run(case01)
    end = time.perf_counter()
    done.set()
    t.join()
    margin = 0.1 * (end - start)
    inside = [x for x in ticks if start + margin < x < end - margin]
    assert len(inside) >= 3, f"{len(inside)} ticks in the middle of a run of {end - start:.3f} s"


def test_a_whole_float_sets_an_integer_field_as_a_spec_axis_does(case01: kanestop.Scene) -> None:
    whole = case01.with_overrides({"cable.stages[0].elements": 2})
    assert case01.with_overrides({"cable.stages[0].elements": 2.0}) == whole
    assert case01.with_overrides({"cable.stages[0].elements": np.float64(2)}) == whole
    with pytest.raises(kanestop.SceneError, match="elements"):
        case01.with_overrides({"cable.stages[0].elements": 2.5})
    rows = [{"cable.stages[0].elements": e} for e in np.linspace(2, 3, 2)]
    df = kanestop.sweep(case01, rows, end_time=0.05)
    assert list(df["status"]) == ["end time"] * 2


def test_empty_sweep_cells_are_none_and_numeric_columns_are_float(case01: kanestop.Scene) -> None:
    df = kanestop.sweep(case01, [{"ship.mass": 4e5}, {"ship.mass": -1.0}], end_time=0.05)
    assert pd.isna(df["message"][0]) and isinstance(df["message"][1], str) and df["message"][1]
    # No row stopped the ship: an output no row has is still a float column of NaN.
    assert df["stopping_time"].dtype == np.float64 and df["stopping_time"].isna().all()
    assert df["peak_proof_utilisation"].dtype == np.float64
    assert df["index"].dtype == np.int64 and df["status"].tolist() == ["end time", "invalid"]


def test_a_failed_check_is_on_the_result(case01: kanestop.Scene) -> None:
    """A run that stops but fails a [checks] limit is not `failed`: `checks_pass` says so."""
    s = case01.with_overrides({"checks.max_anchor_drag": 1e-3, "solver.end_time": 2.0})
    r = kanestop.run(s)
    assert not r.failed and r.checks_pass is False
    assert [c["name"] for c in r.checks] == ["max_anchor_drag"] and r.checks[0]["pass"] is False
    assert "checks FAIL" in repr(r) and "t_end=2 " not in repr(r) and "t_end=2>" in repr(r)
    plain = kanestop.run(case01, end_time=0.02)
    assert plain.checks == [] and plain.checks_pass is True and "checks pass" in repr(plain)


def test_tolerances_under_rk4_are_said_to_do_nothing(case01: kanestop.Scene) -> None:
    with pytest.warns(UserWarning, match="rk4 takes a fixed step and ignores them"):
        kanestop.run(case01, rtol=1e-3, end_time=0.01)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kanestop.run(case01, integrator="dp5", dt=0.01, rtol=1e-3, end_time=0.02)


def test_sensitivity_takes_the_solver_keywords(case01: kanestop.Scene) -> None:
    """As `run`: the keywords are set on the scene for every run (a TypeError before)."""
    by_keyword = kanestop.sensitivity(case01, end_time=0.1, jobs=1, records=True)
    by_scene = kanestop.sensitivity(case01.with_overrides({"solver.end_time": 0.1}), jobs=1, records=True)
    assert by_keyword["rows"] == by_scene["rows"] and by_keyword["base"] == by_scene["base"]
    with pytest.raises(kanestop.SceneError, match="solver.end_time = -1"):
        kanestop.sensitivity(case01, end_time=-1.0)


def test_sensitivity_reports_progress_and_stops_when_it_raises(case01: kanestop.Scene) -> None:
    """``progress(done, total)`` counts the base run and every perturbed run, as the
    command line's bar does: it ends at (runs, runs), never goes back, and an exception
    raised in it stops the study and is raised."""
    seen: List[Tuple[int, int]] = []
    study = kanestop.sensitivity(case01, end_time=0.1, jobs=1, progress=lambda d, t: seen.append((d, t)))
    runs = study.attrs["runs"]
    assert seen[-1] == (runs, runs) and all(t == runs for _, t in seen)
    assert [d for d, _ in seen] == sorted(set(d for d, _ in seen)) and seen[0][0] >= 1

    class Stop(Exception):
        pass

    def stop(done: int, total: int) -> None:
        raise Stop

    with pytest.raises(Stop):
        kanestop.sensitivity(case01, end_time=0.1, jobs=1, progress=stop)
    with pytest.raises(TypeError, match="progress must be callable"):
        kanestop.sensitivity(case01, end_time=0.1, progress="yes")  # type: ignore[arg-type]


def test_a_step_given_raises_a_shorter_output_interval(case01: kanestop.Scene) -> None:
    """As the command line's ``--dt``: ``dt=`` above the scene's output interval (0.02 s)
    raises the interval to the step, with a warning; with ``output_interval=`` beside it,
    the interval is the keyword's and is checked."""
    with pytest.warns(UserWarning, match=r"output_interval raised from the scene's 0.02 s to the step, 0.03 s"):
        r = kanestop.run(case01, dt=0.03, end_time=0.3)
    assert list(r.channels["t"]) == pytest.approx([0.03 * i for i in range(11)])
    with pytest.warns(UserWarning, match="raised"):
        df = kanestop.sweep(case01, [{"ship.mass": 5e5}], dt=0.03, end_time=0.3)
    assert list(df["status"]) == ["end time"]
    with pytest.raises(kanestop.SceneError, match="solver.output_interval = 0.02"):
        kanestop.run(case01, dt=0.03, output_interval=0.02, end_time=0.3)
