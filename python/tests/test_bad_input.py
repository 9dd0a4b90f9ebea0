"""Bad types and values raise TypeError, ValueError or SceneError; nothing crashes."""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
import pytest

import kanestop
from conftest import CASE01

NAN = float("nan")


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.parametrize(
    "call, error",
    [
        (lambda s: kanestop.Scene.load(None), TypeError),
        (lambda s: kanestop.Scene.load(3.5), TypeError),
        (lambda s: kanestop.Scene.from_dict(None), TypeError),
        (lambda s: kanestop.Scene.from_dict("ship"), TypeError),
        (lambda s: kanestop.Scene.from_dict({}), kanestop.SceneError),
        (lambda s: kanestop.Scene.from_toml(None), TypeError),
        (lambda s: kanestop.Scene.from_toml("not [toml"), kanestop.SceneError),
        (lambda s: s.with_overrides(None), TypeError),
        (lambda s: s.with_overrides("ship.mass=1"), TypeError),
        (lambda s: s.with_overrides({"ship.mass": None}), TypeError),
        (lambda s: s.with_overrides({"ship.mass": "heavy"}), kanestop.SceneError),
        (lambda s: s.with_overrides({"ship.mass": NAN}), kanestop.SceneError),
        (lambda s: s.with_overrides({"ship.mass": math.inf}), kanestop.SceneError),
        (lambda s: s.with_overrides({"ship.mass": object()}), TypeError),
        (lambda s: s.with_overrides({"ship.mass": 10**30}), kanestop.SceneError),
        (lambda s: s.with_overrides({"chain.elements": 2.5}), kanestop.SceneError),
        (lambda s: s.with_overrides({"cable.stages[9].elements": 2}), kanestop.SceneError),
        (lambda s: s.with_overrides({"ship": None}), TypeError),
        (lambda s: s.with_overrides({None: 1.0}), TypeError),
        (lambda s: kanestop.run(None), TypeError),
        (lambda s: kanestop.run(42), TypeError),
        (lambda s: kanestop.run(s, dt="0.002"), TypeError),
        (lambda s: kanestop.run(s, dt=NAN), kanestop.SceneError),
        (lambda s: kanestop.run(s, dt=-1.0), kanestop.SceneError),
        (lambda s: kanestop.run(s, integrator="rk5"), kanestop.SceneError),
        (lambda s: kanestop.run(s, integrator=4), TypeError),
        (lambda s: kanestop.run(s, kernel="fast"), ValueError),
        (lambda s: kanestop.run(s, kernel=None), TypeError),
        (lambda s: kanestop.eval(s, None, [0.0] * 46), ValueError),
        (lambda s: kanestop.eval(s, "abc", "def"), TypeError),
        (lambda s: kanestop.eval(s, [0.0] * 3, [0.0] * 3), kanestop.EvalError),
        (lambda s: kanestop.eval(s, [NAN] * 46, [0.0] * 46), kanestop.EvalError),
        (lambda s: kanestop.eval(s, [None] * 46, [0.0] * 46), TypeError),
        (lambda s: kanestop.eval(s, anchor="loose"), ValueError),
        (lambda s: kanestop.sweep(s, None), ValueError),
        (lambda s: kanestop.sweep(s, [None]), TypeError),
        (lambda s: kanestop.sweep(s, [{"ship.mass": None}]), TypeError),
        (lambda s: kanestop.sweep(s, [{}], jobs=0), ValueError),
        (lambda s: kanestop.sweep(s, [{}], jobs="2"), TypeError),
        (lambda s: kanestop.sweep(s, [{}], jobs=-1), ValueError),
        (lambda s: kanestop.sweep(s, [{}], jobs=2**70), ValueError),
        (lambda s: kanestop.sweep(s, [{}], jobs=kanestop.MAX_JOBS + 1), ValueError),
        (lambda s: kanestop.sweep(s, [{}], jobs=True), TypeError),
        (lambda s: kanestop.sweep(s, [{}], progress="yes"), TypeError),
        (lambda s: kanestop.sweep({"scene": s, "grid": 3}), TypeError),
        (lambda s: kanestop.sweep({"scene": s, "rows": [], "bogus": 1}), ValueError),
        (lambda s: kanestop.sweep(s), ValueError),
        (lambda s: kanestop.sweep(42), TypeError),
        (lambda s: kanestop.sweep(s, [{}], end_time=-1.0), kanestop.SceneError),
        (lambda s: kanestop.sweep({"base": s, "axis": [{"path": "ship.mass", "values": [None]}]}), TypeError),
        (lambda s: kanestop.sweep({"base": s, "axis": [{"path": "ship.mass", "values": [1e5]}]}, [{}]), ValueError),
        (lambda s: kanestop.Spec.from_dict(None), TypeError),
        (lambda s: kanestop.Spec.from_toml(None), TypeError),
        (lambda s: kanestop.Spec.load(None), TypeError),
    ],
)
def test_bad_input_raises(case01: kanestop.Scene, call: Callable[[kanestop.Scene], Any], error: Any) -> None:
    with pytest.raises(error):
        call(case01)


def test_jobs_errors_name_the_argument_and_its_range(case01: kanestop.Scene) -> None:
    for study in (lambda jobs: kanestop.sweep(case01, [{}], jobs=jobs), lambda jobs: kanestop.sensitivity(case01, jobs=jobs)):
        for jobs in (0, -1, 2**70):
            with pytest.raises(ValueError, match=rf"jobs = {jobs}: must be in \[1, {kanestop.MAX_JOBS}\]"):
                study(jobs)
        for bad in (True, 2.0, "2"):
            with pytest.raises(TypeError, match="jobs must be a whole number"):
                study(bad)
    with pytest.raises(TypeError, match="step = True: a relative step"):
        kanestop.sensitivity(case01, step=True)


def test_a_numpy_integer_is_a_number_of_jobs(case01: kanestop.Scene) -> None:
    rows = kanestop.sweep(case01, [{}], jobs=np.int64(1), end_time=0.02, records=True)
    assert len(rows) == 1 and rows[0]["status"] != "invalid", rows


def test_a_huge_integer_is_refused_by_its_range_and_a_path_is_text(case01: kanestop.Scene) -> None:
    with pytest.raises(kanestop.SceneError, match="ship.mass"):
        case01.with_overrides({"ship.mass": 10**30})
    with pytest.raises(ValueError, match=r"Scene.paper: number = 1180591620717411303424: in 1–19"):
        kanestop.Scene.paper(2**70)
    spec = kanestop.Spec.from_dict({"base": CASE01, "axis": [{"path": "ship.mass", "values": [4e5]}]})
    assert spec == kanestop.Spec.from_dict({"base": str(CASE01), "axis": [{"path": "ship.mass", "values": [4e5]}]})


def test_empty_text_cells_are_none_and_empty_numbers_nan(case01: kanestop.Scene) -> None:
    pd = pytest.importorskip("pandas")
    df = kanestop.sweep(case01, [{"ship.mass": 4e5}, {"ship.mass": -1}], end_time=0.1)
    assert df["message"].iloc[0] is None and isinstance(df["message"].iloc[1], str)
    assert df["checks"].iloc[1] is None and df["checks"].iloc[0] == "pass"
    assert df["stopping_time"].dtype == np.float64 and pd.isna(df["stopping_time"]).all()
    sens = kanestop.sensitivity(case01.with_overrides({"solver.end_time": 0.1}), jobs=1)
    assert sens["d_stopping_time"].dtype == np.float64
    assert all(m is None or (isinstance(m, str) and m) for m in sens["message"])


def test_a_bad_sweep_row_is_a_row_not_an_exception(case01: kanestop.Scene) -> None:
    df = kanestop.sweep(case01, [{"ship.mass": NAN}, {"ship.mass": "x"}], end_time=0.1)
    assert list(df["status"]) == ["invalid"] * 2
    assert all(isinstance(e, str) and e for e in df["message"])


def test_a_row_path_that_names_no_field_is_refused_before_any_run(case01: kanestop.Scene) -> None:
    calls = []
    with pytest.raises(ValueError, match=r"row 1: ship.mas: no field `mas` here \(valid: .*mass"):
        kanestop.sweep(case01, [{"ship.mass": 4e5}, {"ship.mas": 4e5}], end_time=0.1, progress=lambda d, t: calls.append(d))
    assert calls == []


def test_the_columns_do_not_depend_on_which_rows_ran(case01: kanestop.Scene) -> None:
    pytest.importorskip("pandas")
    ran = kanestop.sweep(case01, [{"ship.mass": 5e5}], end_time=0.02)
    invalid = kanestop.sweep(case01, [{"ship.mass": -1.0}], end_time=0.02)
    assert list(invalid.columns) == list(ran.columns) and "work_drag" in ran.columns


def test_the_state_of_eval_takes_numpy(case01: kanestop.Scene) -> None:
    e0 = kanestop.eval(case01)
    e1 = kanestop.eval(case01, e0["q"], e0["u"], anchor=e0["anchor"])
    assert (e1["qdd"] == e0["qdd"]).all()


def test_path_objects_and_strings_load(case01: kanestop.Scene) -> None:
    assert kanestop.Scene.load(str(CASE01)) == case01


def test_a_bool_is_no_solver_number(case01: kanestop.Scene) -> None:
    # Regression: run(s, end_time=True) ran for 1 s (a bool is an int to Python).
    with pytest.raises(TypeError, match="end_time = True: a number of seconds"):
        kanestop.run(case01, end_time=True)
    with pytest.raises(TypeError, match="dt = False"):
        kanestop.sweep(case01, [{}], dt=False)


def test_a_type_is_named_with_its_article(case01: kanestop.Scene) -> None:
    with pytest.raises(TypeError, match="ship.mass: an ellipsis is not a scene value"):
        case01.with_overrides({"ship.mass": ...})
