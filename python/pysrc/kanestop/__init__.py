"""kanestop: a Kane's-method simulator of a ship-restraining system, for Python studies.

A powerless ship is stopped by an overhead net; its cable pulls an anchor chain that drags
a gravity anchor. The Rust core (scenes and their checks, the generated Kane kernels, the
integrators, the run with event location and health checks) is the engine; this package
gives it NumPy, pandas and Dask.

>>> import kanestop
>>> scene = kanestop.Scene.load("scenes/paper/case01.toml")            # doctest: +SKIP
>>> kanestop.run(scene).summary["stopping_time"]                       # doctest: +SKIP
19.808...

See docs/python.md for the API, the channel names and the Dask example.
"""

from __future__ import annotations

import itertools
import json
import os
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from ._kanestop import EvalError, ModelError, Scene, SceneError, __version__
from ._kanestop import _run, _sweep
from ._kanestop import eval as _eval

__all__ = [
    "Scene",
    "SceneError",
    "ModelError",
    "EvalError",
    "Result",
    "run",
    "sweep",
    "eval",
    "flatten",
    "to_frame",
    "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]


def _pandas() -> Any:
    try:
        import pandas  # noqa: PLC0415 (optional dependency)
    except ImportError:
        return None
    return pandas


def flatten(summary: Mapping[str, Any], prefix: str = "") -> Dict[str, Any]:
    """A summary with its nested records as dotted columns: ``peak_tension.tension``,
    ``work.drag``, ``failure.message`` (None records stay None under their own name)."""
    out: Dict[str, Any] = {}
    for key, value in summary.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(flatten(value, prefix=f"{name}."))
        else:
            out[name] = value
    return out


def to_frame(records: Sequence[Mapping[str, Any]]) -> Any:
    """Rows of flat records as a pandas DataFrame (a list of dicts without pandas)."""
    pd = _pandas()
    rows = [dict(r) for r in records]
    return pd.DataFrame.from_records(rows) if pd is not None else rows


class Result:
    """What one run produced.

    - ``summary``: a dict with the same content as ``kanestop run --json`` (docs/conventions.md);
    - ``channels``: the time history, a pandas DataFrame (a dict of NumPy arrays without
      pandas); ``arrays`` is always the dict, its arrays owned by NumPy without a copy;
    - ``events``: the anchor's located switches, ``[{"t": 3.1, "anchor": "free"}, …]``;
    - ``diagnostic``: the numerical failure in words (None when the run did not fail);
      ``failure`` is its data (``t``, ``body``, ``kind``). A failure is a result, not an
      exception.

    Results pickle (summary, arrays and events), so Dask and multiprocessing can ship them.
    """

    __slots__ = ("summary", "arrays", "events", "failure", "_frame")

    def __init__(
        self,
        summary: Dict[str, Any],
        arrays: Dict[str, "np.ndarray[Any, np.dtype[np.float64]]"],
        events: List[Dict[str, Any]],
        failure: Optional[Dict[str, Any]] = None,
    ) -> None:
        self.summary = summary
        self.arrays = arrays
        self.events = events
        self.failure = failure
        self._frame: Any = None

    @property
    def channels(self) -> Any:
        """The time history: a DataFrame with one column per channel if pandas is
        installed, else the dict of NumPy arrays (``arrays``)."""
        if self._frame is None:
            pd = _pandas()
            self._frame = pd.DataFrame(self.arrays, copy=False) if pd is not None else self.arrays
        return self._frame

    @property
    def diagnostic(self) -> Optional[str]:
        """The failure's diagnostic as the command line prints it, or None."""
        f = self.summary.get("failure")
        return None if f is None else str(f["message"])

    @property
    def status(self) -> str:
        """``stopped``, ``end time`` or ``failed``."""
        return str(self.summary["status"])

    @property
    def failed(self) -> bool:
        """Whether the run ended in a numerical failure."""
        return self.summary.get("failure") is not None

    @property
    def stopping_time(self) -> Optional[float]:
        """First zero of the ship's surge speed, s (None if it did not stop)."""
        t = self.summary.get("stopping_time")
        return None if t is None else float(t)

    def __getstate__(self) -> Dict[str, Any]:
        return {"summary": self.summary, "arrays": self.arrays, "events": self.events, "failure": self.failure}

    def __setstate__(self, state: Dict[str, Any]) -> None:
        self.summary = state["summary"]
        self.arrays = state["arrays"]
        self.events = state["events"]
        self.failure = state["failure"]
        self._frame = None

    def __repr__(self) -> str:
        s = self.summary
        return (
            f"<kanestop.Result {s.get('scene')!r} {s.get('status')} "
            f"stopping_time={s.get('stopping_time')} t_end={s.get('t_end')}>"
        )


def _scene(scene: Union[Scene, PathLike, Mapping[str, Any]]) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    if isinstance(scene, Mapping):
        return Scene.from_dict(dict(scene))
    raise TypeError(f"a scene is a kanestop.Scene, a path or a dict, not {type(scene).__name__}")


def run(
    scene: Union[Scene, PathLike],
    *,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    end_time: Optional[float] = None,
    output_interval: Optional[float] = None,
    kernel: str = "generated",
) -> Result:
    """Runs a scene (a ``Scene`` or a path) until the ship stops, the end time or a
    numerical failure, with the GIL released.

    The keywords override the scene's ``[solver]`` like ``kanestop run --integrator --dt
    --rtol --atol`` (and ``solver.end_time``, ``solver.output_interval``); the result is
    checked as a scene file would be (``SceneError``). ``kernel`` is ``"generated"`` (the
    default) or ``"reference"``.
    """
    summary, arrays, events, failure = _run(
        _scene(scene),
        integrator=integrator,
        dt=dt,
        rtol=rtol,
        atol=atol,
        end_time=end_time,
        output_interval=output_interval,
        kernel=kernel,
    )
    return Result(json.loads(summary), arrays, events, failure)


def eval(
    scene: Union[Scene, PathLike],
    q: Optional[Sequence[float]] = None,
    u: Optional[Sequence[float]] = None,
    *,
    anchor: Optional[str] = None,
    kernel: str = "generated",
) -> Dict[str, Any]:
    """The equations of motion at the scene's initial state, or at (q, u): the
    ``kanestop eval`` JSON as a dict with ``M`` (n × n), ``f``, ``qdd``, ``q`` and ``u`` as
    NumPy arrays (n active speeds: N with the anchor free, N − 1 stuck).

    q = (β_2 … β_N, s_1) in rad and m, u their rates; ``anchor`` is ``"stuck"`` or
    ``"free"`` (default: the scene's initial state). Raises ``EvalError`` for a state of
    the wrong length or with a non-finite entry.
    """
    return _eval(_scene(scene), q, u, anchor=anchor, kernel=kernel)


Rows = Iterable[Mapping[str, Any]]
Spec = Union[Scene, PathLike, Mapping[str, Any]]


def _rows(spec: Spec, rows: Optional[Rows]) -> "tuple[Scene, List[Dict[str, Any]], Dict[str, Any]]":
    solver: Dict[str, Any] = {}
    if isinstance(spec, Mapping) and "scene" in spec:
        extra = set(spec) - {"scene", "rows", "grid", "solver"}
        if extra:
            raise ValueError(f"sweep spec: unknown key(s) {sorted(extra)} (valid: scene, rows, grid, solver)")
        scene = _scene(spec["scene"])
        solver = dict(spec.get("solver") or {})
        if rows is None:
            if "rows" in spec and "grid" in spec:
                raise ValueError("sweep spec: give rows or grid, not both")
            if "grid" in spec:
                grid = spec["grid"]
                if not isinstance(grid, Mapping):
                    raise TypeError("sweep spec: grid is a dict of dotted path -> list of values")
                keys = list(grid)
                rows = [dict(zip(keys, combo)) for combo in itertools.product(*(list(grid[k]) for k in keys))]
            else:
                rows = spec.get("rows")
    else:
        scene = _scene(spec)
    if rows is None:
        raise ValueError("sweep: no rows (pass rows=[{...}, …], or a spec with rows or grid)")
    out = []
    for i, r in enumerate(rows):
        if not isinstance(r, Mapping):
            raise TypeError(f"row {i}: a row is a dict of dotted path -> value, not {type(r).__name__}")
        out.append(dict(r))
    return scene, out, solver


def sweep(
    spec: Spec,
    rows: Optional[Rows] = None,
    *,
    jobs: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    end_time: Optional[float] = None,
    output_interval: Optional[float] = None,
    kernel: str = "generated",
) -> Any:
    """Runs a scene once per row of overrides on the Rust thread pool (``jobs`` threads,
    every core when None), with the GIL released; ``progress(done, total)`` is called on
    this thread as rows finish (raise in it to cancel the rows not started).

    ``spec`` is a scene (``Scene``, path or dict) with ``rows=[{"ship.mass": 1e6}, …]``, or
    a dict ``{"scene": …, "rows": [...]}`` or ``{"scene": …, "grid": {"ship.mass": [...],
    "initial.ship_speed": [...]}}`` (every combination), optionally with ``"solver":
    {"dt": …}``. Returns a DataFrame (a list of dicts without pandas), one row per input
    row in order: the override columns, then the flattened summary (``kanestop.flatten``),
    then ``error`` (why a row could not run; its ``status`` is ``invalid``).
    """
    scene, plan, solver = _rows(spec, rows)
    keywords: Dict[str, Any] = dict(
        integrator=integrator, dt=dt, rtol=rtol, atol=atol, end_time=end_time, output_interval=output_interval
    )
    for key, value in solver.items():
        if key not in keywords:
            raise ValueError(f"sweep spec: solver.{key} is not a sweep keyword (valid: {', '.join(keywords)})")
        if keywords[key] is None:
            keywords[key] = value
    outcomes = _sweep(scene, plan, jobs=jobs, progress=progress, kernel=kernel, **keywords)
    records = []
    for overrides, (summary, error) in zip(plan, outcomes):
        record: Dict[str, Any] = dict(overrides)
        if summary is not None:
            record.update(flatten(json.loads(summary)))
            record["error"] = None
        else:
            record.update(status="invalid", error=error)
        records.append(record)
    return to_frame(records)
