"""Sweep specs from Python: the same rows as `kanestop sweep SPEC --out DIR` (sweep.csv and
sweep.json, every number), the spec as a file, a dict or TOML text, and bad specs."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any, Dict, List

import pytest

import kanestop
from conftest import CASE01, run_cli

# A grid (with one row whose mass is refused: invalid), sampled uncertain inputs and checks,
# each run cut short.
BODY = """
name = "parity"

[solver]
end_time = 1.0

[[axis]]
path = "ship.mass"
values = [4e5, -1.0]

[[axis]]
path = "initial.ship_speed"
range = { from = 2.5, to = 3.0, steps = 2 }

[sampling]
method = "latin-hypercube"
samples = 2
seed = 7

[[uncertain]]
path = "environment.seabed_friction"
distribution = "lognormal"
median = 0.3
sigma = 0.2

[checks]
max_stopping_distance = 40.0
safety_factor = 1.5
"""


def write_spec(folder: Path, body: str = BODY) -> Path:
    (folder / "base.toml").write_text(CASE01.read_text())
    spec = folder / "spec.toml"
    spec.write_text('base = "base.toml"\n' + body)
    return spec


@pytest.fixture(scope="module")
def cli_sweep(tmp_path_factory: pytest.TempPathFactory) -> Dict[str, Any]:
    folder = tmp_path_factory.mktemp("spec")
    spec = write_spec(folder)
    out = folder / "out"
    p = run_cli("sweep", str(spec), "--out", str(out))
    assert p.returncode == 3, p.stderr  # some row invalid
    with open(out / "sweep.csv", newline="") as f:
        table = list(csv.reader(f))
    with open(out / "sweep.units.csv", newline="") as f:
        units = {row[0]: row[1] for row in list(csv.reader(f))[1:]}
    return {"spec": spec, "csv": table, "units": units, "json": json.loads((out / "sweep.json").read_text())}


def same_cell(text: str, value: Any) -> bool:
    """A sweep.csv field against the DataFrame's value: empty is None/NaN, numbers equal
    exactly (the CSV writes the shortest round-trip form), words equal."""
    if isinstance(value, str):
        return text == value
    if text == "":
        return value is None or (isinstance(value, float) and math.isnan(value))
    return float(text) == float(value)


# Measured times differ between any two runs of the same row.
TIMINGS = ("wall_time", "cpu_time")


def without_wall_time(rows: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    out = []
    for r in rows:
        r = dict(r)
        if r.get("summary"):
            r["summary"] = {k: v for k, v in r["summary"].items() if k not in TIMINGS}
        out.append(r)
    return out


def test_a_spec_file_gives_the_rows_of_sweep_csv(cli_sweep: Dict[str, Any]) -> None:
    df = kanestop.sweep(cli_sweep["spec"])
    head, *lines = cli_sweep["csv"]
    assert list(df.columns) == head
    assert len(df) == len(lines) == 8
    for i, line in enumerate(lines):
        for column, text in zip(head, line):
            if column not in TIMINGS:
                assert same_cell(text, df.iloc[i][column]), (i, column, text, df.iloc[i][column])
    assert list(df["status"]).count("invalid") == 4 and set(df["checks"].dropna()) == {"fail"}
    assert "ship.mass = -1" in df[df["status"] == "invalid"]["message"].iloc[0]
    assert list(df["name"]) == [f"parity-{i:03}" for i in range(8)]
    # Each column's unit, as sweep.units.csv beside the CLI's sweep.csv has it.
    assert df.attrs["units"] == cli_sweep["units"]
    assert (df.attrs["units"]["ship.mass"], df.attrs["units"]["peak_tension"]) == ("kg", "N")


def test_records_are_the_rows_of_sweep_json(cli_sweep: Dict[str, Any]) -> None:
    rows = kanestop.sweep(cli_sweep["spec"], records=True)
    assert without_wall_time(rows) == without_wall_time(cli_sweep["json"])
    # Every number prints the same digits.
    assert json.dumps(without_wall_time(rows)) == json.dumps(without_wall_time(cli_sweep["json"]))


def test_a_spec_as_dict_or_toml_text_is_the_same_spec(cli_sweep: Dict[str, Any]) -> None:
    spec = kanestop.Spec.load(cli_sweep["spec"])
    assert spec.name == "parity" and len(spec) == 8 and spec.base.to_dict()["solver"]["end_time"] == 1.0
    assert spec.inputs()[1] == {"ship.mass": 4e5, "initial.ship_speed": 2.5, "environment.seabed_friction": spec.inputs()[1]["environment.seabed_friction"]}
    text = cli_sweep["spec"].read_text()
    folder = cli_sweep["spec"].parent
    from_text = kanestop.Spec.from_toml(text, base_dir=folder)
    base = kanestop.Scene.load(folder / "base.toml")
    from_scene = kanestop.Spec.from_toml(text.replace('base = "base.toml"\n', ""), base=base)
    fields = {
        "base": base,
        "name": "parity",
        "solver": {"end_time": 1.0},
        "axis": [
            {"path": "ship.mass", "values": [4e5, -1.0]},
            {"path": "initial.ship_speed", "range": {"from": 2.5, "to": 3.0, "steps": 2}},
        ],
        "sampling": {"method": "latin-hypercube", "samples": 2, "seed": 7},
        "uncertain": [{"path": "environment.seabed_friction", "distribution": "lognormal", "median": 0.3, "sigma": 0.2}],
        "checks": {"max_stopping_distance": 40.0, "safety_factor": 1.5},
    }
    from_dict = kanestop.Spec.from_dict(fields)
    by_path = dict(fields, base="base.toml")
    expected = without_wall_time(cli_sweep["json"])
    for s in (spec, from_text, from_scene, from_dict):
        assert s.inputs() == spec.inputs()
        assert without_wall_time(kanestop.sweep(s, records=True)) == expected
    assert without_wall_time(kanestop.sweep(by_path, base_dir=folder, records=True)) == expected


def test_numpy_arrays_ranges_and_numpy_bools_are_scene_values(case01: kanestop.Scene) -> None:
    import numpy as np

    # Regression: an axis of np.linspace(…) or range(…) was "not a scene value", and a NumPy
    # bool was read as the number 1.0.
    by_list = kanestop.Spec.from_dict({"base": case01, "axis": [{"path": "ship.mass", "values": [4e5, 5e5, 6e5]}]})
    by_array = kanestop.Spec.from_dict({"base": case01, "axis": [{"path": "ship.mass", "values": np.linspace(4e5, 6e5, 3)}]})
    assert by_array.inputs() == by_list.inputs()
    by_range = kanestop.Spec.from_dict({"base": case01, "axis": [{"path": "chain.elements", "values": range(14, 16)}]})
    assert [r["chain.elements"] for r in by_range.inputs()] == [14, 15]
    dry = case01.with_overrides({"environment.water": np.bool_(False)})
    assert dry.to_dict()["environment"]["water"] is False
    # A 0-d array is its number; bytes are no list of values.
    assert case01.with_overrides({"ship.mass": np.array(6e5)}).to_dict()["ship"]["mass"] == 6e5
    with pytest.raises(TypeError, match="not a scene value"):
        kanestop.Spec.from_dict({"base": case01, "axis": [{"path": "ship.mass", "values": b"ab"}]})


def test_solver_keywords_are_the_specs_solver(cli_sweep: Dict[str, Any]) -> None:
    df = kanestop.sweep(cli_sweep["spec"], end_time=0.5, jobs=1)
    ran = df[df["status"] != "invalid"]
    assert set(ran["t_end"]) == {0.5} and set(ran["status"]) == {"end time"}


@pytest.mark.parametrize(
    "body, field, words",
    [
        ('[[axis]]\npath = "ship.mass"\nrange = { from = 1e5, to = 2e5, steps = 0 }\n', "axis[0].range.steps", "in [1, 100000]"),
        ('[[axis]]\npath = "ship.mas"\nvalues = [1.0]\n', "axis[0].path", "a field of the scene"),
        ('[[axis]]\npath = "chain.elements"\nvalues = [2.5]\n', "axis[0].values", "whole numbers"),
        ("[checks]\nsafety_factor = 0.5\n", "checks.safety_factor", "≥ 1"),
        (
            '[sampling]\nmethod = "random"\nsamples = 3\nseed = 1\n[[uncertain]]\npath = "ship.mass"\n'
            'distribution = "normal"\nmean = 5e5\nsd = -1.0\n',
            "uncertain[0].sd",
            "finite and > 0",
        ),
        ('[sampling]\nmethod = "random"\nsamples = 3\nseed = 1\n', "sampling", "needs at least one [[uncertain]]"),
        ("bogus = 1\n", "(file)", "unknown field `bogus`"),
    ],
)
def test_a_bad_spec_names_the_field_as_the_cli_does(tmp_path: Path, body: str, field: str, words: str) -> None:
    spec = write_spec(tmp_path, body)
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.sweep(spec)
    e = info.value
    assert e.field == field and words in str(e) and e.file == str(spec)
    assert isinstance(e, ValueError)
    p = run_cli("sweep", str(spec), "--out", str(tmp_path / "out"))
    assert p.returncode == 2 and str(e).splitlines()[0] in p.stderr, (str(e), p.stderr)


def test_bad_spec_dicts_name_the_field(case01: kanestop.Scene) -> None:
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.sweep({"base": case01, "axis": [{"path": "ship.mass", "values": []}]})
    assert info.value.field == "axis[0].values" and info.value.file == "<dict>"
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.Spec.from_dict({"axis": []})
    assert info.value.field == "base" and "(missing)" in str(info.value)
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.Spec.from_dict({"base": case01, "axes": []})
    assert info.value.field == "axes" and "unknown field `axes`" in str(info.value)
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.Spec.from_dict({"base": case01, "sampling": {"method": "random", "samples": "many", "seed": 1}})
    assert info.value.field == "sampling.samples" and 'invalid type: string "many", expected a whole number ≥ 0' in str(info.value)
    assert info.value.value == '"many"'  # the value as given, as for a range error
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.Spec.from_dict({"base": case01, "axis": [{"path": "ship.mass", "valuez": [1.0]}]})
    assert info.value.field == "axis[0].valuez" and "unknown field `valuez`" in str(info.value)
    with pytest.raises(kanestop.SpecError) as info:
        axes = [{"path": "ship.mass", "values": [5e5]}, {"path": "anchor.mass", "range": {"from": 1.0, "to": 2.0, "steps": "x"}}]
        kanestop.Spec.from_dict({"base": case01, "axis": axes})
    assert info.value.field == "axis[1].range.steps" and "expected a whole number ≥ 0" in str(info.value)
    assert info.value.value == '"x"'
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.Spec.from_toml("base = 'x.toml'\n", base=case01)
    assert info.value.field == "base" and "given twice" in str(info.value)
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.Spec.load("no-such-spec.toml")
    assert info.value.field == "(file)"
    with pytest.raises(kanestop.SceneError) as scene_info:
        kanestop.Spec.from_dict({"base": str(CASE01), "set": {"ship.mass": -1.0}})
    assert scene_info.value.problems == [("ship.mass", "-1", "finite and > 0 kg")]
    with pytest.raises(kanestop.SceneError) as scene_info:
        kanestop.Spec.from_dict({"base": "no-such-scene.toml"})
    # The scene's file as given, and the message the command line prints, the spec named.
    assert scene_info.value.file == "no-such-scene.toml" and scene_info.value.kind == "io"
    assert str(scene_info.value).endswith("(the base scene of sweep spec <dict>)"), str(scene_info.value)


def test_a_spec_file_with_rows_or_a_stray_base_dir_is_refused_in_words(tmp_path: Path, case01: kanestop.Scene) -> None:
    spec = write_spec(tmp_path)
    with pytest.raises(ValueError, match="is a sweep spec, whose rows come from its axes"):
        kanestop.sweep(spec, [{"ship.mass": 5e5}])
    # Told apart by its keys, a spec that is itself invalid too.
    bad = tmp_path / "bad.toml"
    bad.write_text('base = "base.toml"\n[[axis]]\npath = "ship.mass"\nvalues = []\n')
    with pytest.raises(ValueError, match="is a sweep spec, whose rows come from its axes"):
        kanestop.sweep(bad, [{"ship.mass": 5e5}])
    # A scene file with rows is what it always was.
    assert len(kanestop.sweep(CASE01, [{"ship.mass": 5e5}], end_time=0.1)) == 1
    for not_a_dict in (spec, case01, kanestop.Spec.load(spec)):
        with pytest.raises(ValueError, match="base_dir is the folder of a spec dict's base path"):
            kanestop.sweep(not_a_dict, base_dir=tmp_path)


def test_a_spec_pickles_and_compares(tmp_path: Path) -> None:
    """A spec travels to worker processes as a scene does: its fields and base scene."""
    import pickle

    spec = kanestop.Spec.load(write_spec(tmp_path))
    back = pickle.loads(pickle.dumps(spec))
    assert back == spec and back is not spec and back.file == spec.file
    assert back.inputs() == spec.inputs() and len(back) == len(spec) and back.base == spec.base
    other = kanestop.Spec.from_dict({"base": spec.base, "axis": [{"path": "ship.mass", "values": [5e5]}]})
    assert other != spec and pickle.loads(pickle.dumps(other)) == other
    assert len({spec, back, other}) == 2
    # A scene's own name, which a spec file's name could not be, comes back as it was.
    named = kanestop.Spec.from_scene(spec.base, "case 1 (paper)")
    assert pickle.loads(pickle.dumps(named)).name == "case 1 (paper)"


def test_a_solver_keyword_on_a_path_the_spec_sweeps_is_refused(case01: kanestop.Scene) -> None:
    spec = {"base": case01, "axis": [{"path": "solver.end_time", "values": [0.1, 0.2]}]}
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.sweep(spec, end_time=0.3)
    assert info.value.field == "solver.end_time" and "whose values would override it" in str(info.value)
    # Explicit rows on a path a keyword sets: refused too (the row used to win silently).
    with pytest.raises(ValueError, match=r"row 1: solver.end_time = 0.2: the keyword end_time= sets it"):
        kanestop.sweep(case01, [{"ship.mass": 5e5}, {"solver.end_time": 0.2}], end_time=0.1)


def test_a_design_table_is_rows(case01: kanestop.Scene) -> None:
    pd = pytest.importorskip("pandas")
    design = pd.DataFrame(
        {
            "ship.mass": [4e5, 6e5],
            "anchor.mass": [float("nan"), 5e4],
            "solver.integrator": [None, "rk4"],
            "chain.elements": pd.array([pd.NA, 15], dtype="Int64"),
        }
    )
    df = kanestop.sweep(case01, design, end_time=0.05)
    second = {"ship.mass": 6e5, "anchor.mass": 5e4, "solver.integrator": "rk4", "chain.elements": 15}
    rows = kanestop.sweep(case01, [{"ship.mass": 4e5}, second], end_time=0.05)
    keep = ["ship.mass", "anchor.mass", "status", "peak_tension"]
    assert df[keep].equals(rows[keep]) and list(df["status"]) == ["end time"] * 2


def test_a_spec_dict_without_base_is_told_so() -> None:
    with pytest.raises(kanestop.SpecError) as info:
        kanestop.sweep({"axis": [{"path": "ship.mass", "values": [1e5]}]})
    assert info.value.field == "base" and "(missing)" in str(info.value)


def test_a_spec_s_repr_counts_its_rows(case01: kanestop.Scene) -> None:
    assert repr(kanestop.Spec.from_scene(case01)) == 'Spec("case01", 1 row, base "case01")'


def test_a_spec_s_base_may_be_a_dict_of_the_scene_s_tables(case01: kanestop.Scene) -> None:
    spec = kanestop.Spec.from_dict({"base": case01.to_dict(), "axis": [{"path": "ship.mass", "values": [5e5, 6e5]}]})
    assert spec.base == case01 and len(spec) == 2
    bad = case01.to_dict()
    bad["ship"]["mass"] = -1.0
    with pytest.raises(kanestop.SceneError, match="ship.mass = -1"):
        kanestop.Spec.from_dict({"base": bad, "axis": [{"path": "anchor.mass", "values": [5e4]}]})
