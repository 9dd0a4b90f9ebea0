"""Python results equal the command line's, to the last digit of the JSON."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import kanestop
from conftest import CASE01, ROOT, cli_json, run_cli, without_wall_time


def test_case01_summary_equals_run_json(case01_result: kanestop.Result) -> None:
    cli = cli_json("run", str(CASE01), "--json")
    assert without_wall_time(case01_result.summary) == without_wall_time(cli)
    # Same keys in the same order, and every number prints the same digits.
    assert list(case01_result.summary) == list(cli)
    assert json.dumps(without_wall_time(case01_result.summary)) == json.dumps(without_wall_time(cli))
    assert case01_result.summary["status"] == "stopped"
    assert round(case01_result.summary["stopping_time"], 3) == 19.808


def test_solver_keywords_equal_the_cli_flags(case01: kanestop.Scene) -> None:
    args = ("run", str(CASE01), "--json", "--integrator", "dp5", "--dt", "0.02", "--rtol", "1e-4", "--atol", "1e-6")
    cli = cli_json(*args)
    py = kanestop.run(case01, integrator="dp5", dt=0.02, rtol=1e-4, atol=1e-6).summary
    assert without_wall_time(py) == without_wall_time(cli)


def test_a_failure_is_a_result_with_the_cli_diagnostic() -> None:
    path = ROOT / "scenes" / "stress" / "dt_too_large.toml"
    p = run_cli("run", str(path), "--json")
    # A step refused before the run is bad input for the CLI (exit 2); Python returns it as a result.
    assert p.returncode == 2
    r = kanestop.run(path)
    assert r.failed and r.status == "failed"
    assert r.diagnostic == json.loads(p.stdout)["failure"]["message"]
    assert r.diagnostic is not None and "stability limit" in r.diagnostic
    assert r.failure is not None and r.failure["kind"] == "RK4 step above the stability limit"
    assert without_wall_time(r.summary) == without_wall_time(json.loads(p.stdout))
    # No sample before the refusal: every channel is there, empty, with its unit.
    assert r.channels.shape == (0, len(r.units)) and list(r.channels.columns)[:2] == ["t", "ship_x"]
    assert r.units["ship_x"] == "m"


def test_a_failure_in_the_run_has_the_cli_diagnosis_too() -> None:
    # Regression: a run failing early was diagnosed without the starting state's check (the
    # step's stability was blamed where the CLI names the initial geometry).
    path = ROOT / "scenes" / "stress" / "taut_cable.toml"
    p = run_cli("run", str(path), "--json")
    assert p.returncode == 3
    r = kanestop.run(path)
    assert r.failed and r.diagnostic == json.loads(p.stdout)["failure"]["message"]
    assert r.diagnostic is not None and "initial geometry" in r.diagnostic
    # A sweep row over the same scene carries the same diagnosis.
    rows = kanestop.sweep({"base": str(path), "axis": [{"path": "ship.mass", "values": [500000.0]}]})
    assert "initial geometry" in str(rows["message"][0])


def test_sensitivity_equals_the_cli_report(tmp_path: object) -> None:
    import csv

    path = ROOT / "scenes" / "paper" / "case03.toml"
    p = run_cli("report", "sensitivity", str(path), "--out", str(tmp_path))
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "sensitivity.csv", newline="") as f:  # type: ignore[operator]
        cli = list(csv.DictReader(f))
    df = kanestop.sensitivity(path)
    assert len(df) == len(cli) > 20 and list(df.columns) == list(cli[0])
    number = lambda v: float(v) if v != "" else None  # noqa: E731
    for (_, row), c in zip(df.iterrows(), cli):
        assert row["parameter"] == c["parameter"] and row["rank"] == int(c["rank"])
        for k in ("value", "d_stopping_time", "d_stopping_distance", "d_peak_tension", "step"):
            v = row[k]
            assert (None if v is None or (isinstance(v, float) and math.isnan(v)) else v) == number(c[k]), (k, row, c)
        assert (row["difference"] or "") == c["difference"]
        assert (row["message"] or "") == c["message"]  # None where empty
    assert df.attrs["scene"] == "case03" and df.attrs["runs"] > len(df)
    assert df.attrs["ranked_by"] == "stopping_time"
    with open(tmp_path / "sensitivity.units.csv", newline="") as f:  # type: ignore[operator]
        assert df.attrs["units"] == {r["column"]: r["unit"] for r in csv.DictReader(f)}
    assert df.attrs["units"]["d_peak_tension"] == "N"
    study = kanestop.sensitivity(path, records=True)
    assert study["base"][0] == df.attrs["base"]["stopping_time"]
    with pytest.raises(ValueError, match="step = 0.7"):
        kanestop.sensitivity(path, step=0.7)


def test_eval_equals_the_cli_eval(case01: kanestop.Scene) -> None:
    cli = cli_json("eval", "--scene", str(CASE01))
    py = kanestop.eval(case01)
    assert np.array_equal(py["M"], np.array(cli["M"]))
    for key in ("f", "qdd", "q", "u"):
        assert np.array_equal(py[key], np.array(cli[key])), key
    for key in ("scene", "kernel", "physics", "bodies_count", "anchor", "coordinates", "active", "residual", "cond", "bodies"):
        assert py[key] == cli[key], key
    n = py["active"]
    assert py["M"].shape == (n, n) and py["f"].shape == (n,)
    assert np.allclose(py["M"] @ py["qdd"], py["f"], rtol=1e-9, atol=1e-9 * np.abs(py["f"]).max())
    assert math.isfinite(py["cond"])


def test_scene_error_names_what_the_cli_names(tmp_path: object) -> None:
    from pathlib import Path

    bad = Path(str(tmp_path)) / "bad.toml"
    bad.write_text(CASE01.read_text().replace("[anchor]\nmass =", "[anchor]\nmass = -1.0 #"))
    p = run_cli("run", str(bad), "--json")
    assert p.returncode == 2
    try:
        kanestop.Scene.load(bad)
    except kanestop.SceneError as e:
        assert e.kind == "invalid"
        assert e.problems == [("anchor.mass", "-1", "finite and > 0 kg")]
        for line in str(e).splitlines():
            assert line.strip() in p.stderr, (line, p.stderr)
    else:
        raise AssertionError("no SceneError")


def test_channels_are_the_cli_history_by_name_unit_and_value(case01_result: kanestop.Result, tmp_path: object) -> None:
    import csv
    from pathlib import Path

    history = Path(str(tmp_path)) / "history.csv"
    p = run_cli("run", str(CASE01), "--out", str(history))
    assert p.returncode == 0, p.stderr
    with open(history, newline="") as f:
        head, *lines = list(csv.reader(f))
    a = case01_result.arrays
    assert list(a) == head
    assert all(len(v) == len(lines) for v in a.values())
    for j, name in enumerate(head):
        column = np.array([float(line[j]) for line in lines])
        assert np.array_equal(a[name], column), name  # the CSV writes the shortest round-trip form
    with open(history.with_name("history.units.csv"), newline="") as f:
        units = list(csv.DictReader(f))
    assert [u["channel"] for u in units] == head
    assert {u["channel"]: u["unit"] for u in units} == case01_result.units
    assert {u["channel"]: u["description"] for u in units} == case01_result.descriptions
    # A selection by group is the same columns as --channels.
    picked = Path(str(tmp_path)) / "picked.csv"
    assert run_cli("run", str(CASE01), "--out", str(picked), "--channels", "ship,tension").returncode == 0
    with open(picked, newline="") as f:
        assert next(csv.reader(f)) == case01_result.channels_of("ship", "tension")
