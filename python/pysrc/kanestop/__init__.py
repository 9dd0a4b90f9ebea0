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

>>> kanestop.sweep("scenes/sweeps/mass_speed.toml")                    # doctest: +SKIP
   index           name  ship.mass  initial.ship_speed  status checks  stopping_time ...
"""

from __future__ import annotations

import json
import os
import warnings
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._kanestop import MAX_JOBS, EvalError, ModelError, Scene, SceneError, Spec, SpecError, __version__
from ._kanestop import _History, _run, _sensitivity, _sensitivity_units, _sweep, _toml_keys
from ._kanestop import eval as _eval

__all__ = [
    "Scene",
    "SceneError",
    "Spec",
    "SpecError",
    "ModelError",
    "EvalError",
    "Result",
    "run",
    "sweep",
    "sensitivity",
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
      pandas); ``arrays`` is always the dict, its arrays owned by NumPy without a copy. The
      names are the CSV history's (``kanestop run --out``; docs/conventions.md): ``t``,
      ``ship_x``, ``anchor_drag``, ``tension_fairlead``, ``energy_balance``, ``body3_x``,
      ``tension_joint5``, …; ``units`` and ``descriptions`` map each name to its SI unit
      and meaning (the DataFrame carries ``attrs["units"]`` too);
    - ``events``: the anchor's located switches, ``[{"t": 3.1, "anchor": "free"}, …]``;
    - ``diagnostic``: the numerical failure in words (None when the run did not fail);
      ``failure`` is its data (``t``, ``body``, ``kind``). A failure is a result, not an
      exception;
    - ``core_time``: the wall time, s, the call spent in the Rust core (the solver overrides,
      the model, the run with its start-up, the summary); ``summary["wall_time"]`` is the
      run's part of it. None for a result not made by ``kanestop.run``.

    The channels stay in Rust until first used: ``arrays``, ``channels``, ``units``,
    ``descriptions`` and ``groups`` hand the whole history to NumPy on the first access
    (about 2 ms for case 1's 351 channels of 992 samples), so a run whose history is never
    read does not pay for it.

    Results pickle (summary, arrays and events), so Dask and multiprocessing can ship them.
    """

    __slots__ = (
        "summary",
        "events",
        "failure",
        "core_time",
        "_history",
        "_arrays",
        "_units",
        "_descriptions",
        "_groups",
        "_frame",
    )

    def __init__(
        self,
        summary: Dict[str, Any],
        arrays: Optional[Dict[str, "np.ndarray[Any, np.dtype[np.float64]]"]],
        events: List[Dict[str, Any]],
        failure: Optional[Dict[str, Any]] = None,
        channel_info: Sequence[Tuple[str, str, str, str]] = (),
        core_time: Optional[float] = None,
        *,
        history: Optional[_History] = None,
    ) -> None:
        """A result from its parts: the channels as ``arrays`` with their ``channel_info``
        (name, unit, group, description), or, for ``kanestop.run``, a ``history`` still in
        Rust (``arrays`` None)."""
        self.summary = summary
        self.events = events
        self.failure = failure
        self.core_time = core_time
        self._history = history
        self._arrays: Optional[Dict[str, "np.ndarray[Any, np.dtype[np.float64]]"]] = None
        self._units: Dict[str, str] = {}
        self._descriptions: Dict[str, str] = {}
        self._groups: Dict[str, str] = {}
        if history is None:
            self._set_channels(arrays if arrays is not None else {}, channel_info)
        self._frame: Any = None

    def _set_channels(
        self,
        arrays: Dict[str, "np.ndarray[Any, np.dtype[np.float64]]"],
        channel_info: Sequence[Tuple[str, str, str, str]],
    ) -> None:
        self._arrays = arrays
        self._units = {name: unit for name, unit, _, _ in channel_info}
        self._descriptions = {name: what for name, _, _, what in channel_info}
        self._groups = {name: group for name, _, group, _ in channel_info}
        self._history = None

    def _load(self) -> Dict[str, "np.ndarray[Any, np.dtype[np.float64]]"]:
        if self._arrays is None:
            if self._history is None:
                self._set_channels({}, ())
            else:
                arrays, info = self._history.columns()
                self._set_channels(arrays, info)
        assert self._arrays is not None
        return self._arrays

    @property
    def arrays(self) -> Dict[str, "np.ndarray[Any, np.dtype[np.float64]]"]:
        """The time history as a dict of NumPy arrays (owned by NumPy, no copy), by channel
        name in column order."""
        return self._load()

    @property
    def units(self) -> Dict[str, str]:
        """Each channel's SI unit (``"m"``, ``"N"``, ``"rad/s"``; ``"1"`` for a flag)."""
        self._load()
        return self._units

    @property
    def descriptions(self) -> Dict[str, str]:
        """Each channel's meaning in words, as the CLI's ``<history>.units.csv`` has it."""
        self._load()
        return self._descriptions

    @property
    def groups(self) -> Dict[str, str]:
        """Each channel's group (``ship``, ``anchor``, ``tension``, ``energy``, ``bodies``,
        ``joints``; ``time`` for ``t``), as ``kanestop run --channels`` selects them."""
        self._load()
        return self._groups

    @property
    def channels(self) -> Any:
        """The time history: a DataFrame with one column per channel if pandas is
        installed, else the dict of NumPy arrays (``arrays``)."""
        if self._frame is None:
            pd = _pandas()
            if pd is None:
                self._frame = self.arrays
            else:
                self._frame = pd.DataFrame(self.arrays, copy=False)
                self._frame.attrs["units"] = dict(self.units)
        return self._frame

    def channels_of(self, *names: str) -> List[str]:
        """The channels these names select, in column order (``t`` first), as
        ``kanestop run --channels ship,tension_fairlead`` selects them: each name a group
        (``ship``, ``tension``, …) or a channel (``tension_fairlead``, ``anchor_drag``, …)."""
        valid_groups = set(self.groups.values())
        unknown = [n for n in names if n not in valid_groups and n not in self.groups]
        if unknown:
            raise ValueError(
                f"unknown channel or group {unknown}: give channel names (ship_x, anchor_drag, "
                f"tension_fairlead, …; see docs/conventions.md) or groups {sorted(valid_groups)}"
            )
        return [n for n, g in self.groups.items() if g == "time" or g in names or n in names]

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

    @property
    def checks_pass(self) -> Optional[bool]:
        """Whether every design check passed (the break loads, and the scene's ``[checks]``):
        ``summary["checks_pass"]``, None where no check was made (a run that failed, or was
        refused, with no break load exceeded). ``False`` is the command line's exit code 4;
        a run that did not fail can still fail its checks (``failed`` is False)."""
        v = self.summary.get("checks_pass")
        return None if v is None else bool(v)

    @property
    def checks(self) -> List[Dict[str, Any]]:
        """The records of the scene's ``[checks]`` (``{name, value, limit, joint, pass}``), an
        empty list for a scene without ``[checks]`` (``summary["checks"]`` is then absent)."""
        return list(self.summary.get("checks", []))

    def __getstate__(self) -> Dict[str, Any]:
        return {
            "summary": self.summary,
            "arrays": self.arrays,
            "events": self.events,
            "failure": self.failure,
            "units": self.units,
            "descriptions": self.descriptions,
            "groups": self.groups,
            "core_time": self.core_time,
        }

    def __setstate__(self, state: Dict[str, Any]) -> None:
        self.summary = state["summary"]
        self.events = state["events"]
        self.failure = state["failure"]
        self.core_time = state.get("core_time")
        self._arrays = state["arrays"]
        self._units = state.get("units", {})
        self._descriptions = state.get("descriptions", {})
        self._groups = state.get("groups", {})
        self._history = None
        self._frame = None

    def __repr__(self) -> str:
        s = self.summary

        def short(v: Any) -> str:
            return "None" if v is None else f"{v:.6g}"

        checks = {True: " checks pass", False: " checks FAIL", None: ""}[self.checks_pass]
        # The kind's name only ("energy runaway", "step"): `r.diagnostic` has the words.
        kind = f" ({str(self.failure['kind']).split(':')[0]})" if self.failure else ""
        return (
            f"<kanestop.Result {s.get('scene')!r} {s.get('status')}{kind}{checks} "
            f"stopping_time={short(s.get('stopping_time'))} t_end={short(s.get('t_end'))}>"
        )


def _no_bools(**solver: Any) -> None:
    """A bool is an int to Python, and would pass as 1.0 s: refused for the solver's reals."""
    for name, value in solver.items():
        if isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{name} = {value}: a number of seconds (or a tolerance), not a bool")


def _solver(
    integrator: Optional[str],
    dt: Optional[float],
    rtol: Optional[float],
    atol: Optional[float],
    end_time: Optional[float],
    output_interval: Optional[float],
) -> Dict[str, Any]:
    """The solver keywords of ``run``, ``sweep`` and ``sensitivity`` as the Rust functions
    take them, a bool refused for the reals."""
    _no_bools(dt=dt, rtol=rtol, atol=atol, end_time=end_time, output_interval=output_interval)
    return {
        "integrator": integrator,
        "dt": dt,
        "rtol": rtol,
        "atol": atol,
        "end_time": end_time,
        "output_interval": output_interval,
    }


def _jobs(jobs: Any) -> Optional[int]:
    """``jobs`` as the pool takes it: None (every core) or a whole number in [1, MAX_JOBS],
    a NumPy integer included; a bool or a float is a TypeError, a number out of range a
    ValueError naming it."""
    if jobs is None:
        return None
    if isinstance(jobs, (bool, np.bool_)) or not isinstance(jobs, (int, np.integer)):
        raise TypeError(f"jobs must be a whole number in [1, {MAX_JOBS}] or None, not {type(jobs).__name__}")
    if not 1 <= jobs <= MAX_JOBS:
        raise ValueError(f"jobs = {jobs}: must be in [1, {MAX_JOBS}] (or None for every core)")
    return int(jobs)


def _scene(scene: Union[Scene, PathLike, Mapping[str, Any]]) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, (str, os.PathLike)):
        return Scene.load(scene)
    if isinstance(scene, Mapping):
        return Scene.from_dict(dict(scene))
    raise TypeError(f"a scene is a kanestop.Scene, a path or a dict, not {type(scene).__name__}")


def run(
    scene: Union[Scene, PathLike, Mapping[str, Any]],
    *,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    end_time: Optional[float] = None,
    output_interval: Optional[float] = None,
    kernel: str = "generated",
) -> Result:
    """Runs a scene (a ``Scene``, a path or a dict of its tables) until the ship stops, the end time or a
    numerical failure, with the GIL released; Ctrl-C stops it at its next step (or
    within the start-up stability analysis) and raises KeyboardInterrupt.

    The keywords override the scene's ``[solver]`` like ``kanestop run --integrator --dt
    --rtol --atol`` (and ``solver.end_time``, ``solver.output_interval``); the result is
    checked as a scene file would be (``SceneError``). ``kernel`` is ``"generated"`` (the
    default) or ``"reference"``.
    """
    solver = _solver(integrator, dt, rtol, atol, end_time, output_interval)
    summary, history, events, failure, core_time = _run(_scene(scene), kernel=kernel, **solver)
    record: Dict[str, Any] = json.loads(summary)
    if (rtol is not None or atol is not None) and record.get("method") == "rk4":
        # As the command line notes it: the keywords were not wrong, but did nothing.
        warnings.warn(
            "rtol and atol are the adaptive methods' tolerances; rk4 takes a fixed step and ignores them",
            stacklevel=2,
        )
    return Result(record, None, events, failure, (), core_time, history=history)


def eval(
    scene: Union[Scene, PathLike, Mapping[str, Any]],
    q: Optional[Union[Sequence[float], "npt.NDArray[np.floating[Any]]"]] = None,
    u: Optional[Union[Sequence[float], "npt.NDArray[np.floating[Any]]"]] = None,
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


def sensitivity(
    scene: Union[Scene, PathLike, Mapping[str, Any]],
    *,
    step: float = 0.05,
    jobs: Optional[int] = None,
    progress: Optional[Callable[[int, int], Any]] = None,
    records: bool = False,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    end_time: Optional[float] = None,
    output_interval: Optional[float] = None,
) -> Any:
    """The sensitivity study of ``kanestop report sensitivity SCENE --step STEP``
    (docs/sweeps.md): the effect of each continuous parameter p on the stopping time (s),
    the stopping distance (m) and the peak tension (N) as d(output)/d(ln p), by central
    differences at p·(1 ± step) (one-sided, or at a smaller step, where a perturbed scene
    is refused), ranked by the stopping time's.

    Returns ``sensitivity.csv``'s table: a DataFrame (pandas installed) with the columns
    ``rank, parameter, value, d_stopping_time, d_stopping_distance, d_peak_tension,
    message, difference, step`` and ``df.attrs`` holding ``scene``, the base run's
    ``base`` outputs, the ``runs`` made, ``ranked_by`` (``stopping_time``, or
    ``peak_tension`` when the base run has no stop to move, as the command line's note
    says) and each column's ``units`` (as
    ``sensitivity.units.csv``; ``value`` is in its parameter's own unit); else a list of
    dicts. The solver keywords (``integrator``, ``dt``, ``rtol``, ``atol``, ``end_time``,
    ``output_interval``) are set on the scene for every run, as ``run``'s are
    (``SceneError`` when out of range). With ``records=True``:
    ``sensitivity.json``'s record as a dict. The runs release the GIL, ``jobs`` at a time
    (every core when None); ``progress(done, total)`` is called on this thread as runs
    finish (``total``: the base run and each parameter's perturbed runs, as the command line's bar
    counts them); Ctrl-C, or an exception raised in ``progress``, stops them at their next
    step and is raised. A step outside
    [1e-6, 0.5), ``jobs`` outside [1, MAX_JOBS], or a base scene that fails raises
    ``ValueError`` (the last with the command line's diagnosis); a ``jobs`` that is no whole
    number (a bool, a float) or a bool ``step``, ``TypeError``.
    """
    if isinstance(step, (bool, np.bool_)):
        raise TypeError(f"step = {step}: a relative step (e.g. 0.05), not a bool")
    solver = _solver(integrator, dt, rtol, atol, end_time, output_interval)
    text = _sensitivity(_scene(scene), step, _jobs(jobs), progress=progress, **solver)
    study: Dict[str, Any] = json.loads(text)
    if records:
        return study
    rows = [
        {
            "rank": i + 1,
            "parameter": r["parameter"],
            "value": r["value"],
            "d_stopping_time": r["stopping_time"],
            "d_stopping_distance": r["stopping_distance"],
            "d_peak_tension": r["peak_tension"],
            "message": r["message"] or None,
            "difference": (r["difference"] or "").lower() or None,
            "step": r["step"],
        }
        for i, r in enumerate(study["rows"])
    ]
    pd = _pandas()
    if pd is None:
        return rows
    df = _with_words(pd, pd.DataFrame(rows, columns=list(rows[0]) if rows else None), {"parameter", "message", "difference"})
    base = dict(zip(("stopping_time", "stopping_distance", "peak_tension"), study["base"]))
    df.attrs.update(
        {"scene": study["scene"], "step": study["step"], "base": base, "runs": study["runs"], "ranked_by": study["ranked_by"]}
    )
    df.attrs["units"] = dict(_sensitivity_units())
    return df


def _with_words(pd: Any, frame: Any, words: "set[str]") -> Any:
    """A table's DataFrame with one rule for empty cells: the columns of ``words`` hold
    text, None where empty (object dtype, whatever pandas would infer); every other column
    is numeric, float64 with NaN where empty, even where every row is (an output no row
    has), unless it holds words (an input such as solver.integrator)."""
    for c in frame.columns:
        if c in words:
            column = frame[c].astype(object)
            frame[c] = column.where(column.notna(), None)
            continue
        try:
            frame[c] = pd.to_numeric(frame[c])
        except (TypeError, ValueError):
            pass  # an input of words
    return frame


Rows = Iterable[Mapping[str, Any]]
SweepSpec = Union[Spec, Scene, PathLike, Mapping[str, Any]]


def _legacy_spec(spec: Mapping[str, Any], rows: Optional[Rows]) -> "Tuple[Spec, Optional[Rows]]":
    """The deprecated ``{"scene": …, "grid"/"rows": …, "solver": …}`` dict as a spec: its
    grid is the spec's ``[[axis]]`` list, its solver the spec's ``[solver]``."""
    warnings.warn(
        'kanestop.sweep({"scene": …, "grid"/"rows": …}) is deprecated: give a sweep spec '
        '({"base": scene, "axis": [{"path": …, "values": […]}], "solver": {…}}, a spec file or '
        "a kanestop.Spec), or sweep(scene, rows) (docs/python.md)",
        DeprecationWarning,
        stacklevel=4,
    )
    extra = set(spec) - {"scene", "rows", "grid", "solver"}
    if extra:
        raise ValueError(f"sweep spec: unknown key(s) {sorted(extra)} (valid: scene, rows, grid, solver)")
    if "rows" in spec and "grid" in spec:
        raise ValueError("sweep spec: give rows or grid, not both")
    fields: Dict[str, Any] = {"base": _scene(spec["scene"])}
    if spec.get("solver"):
        fields["solver"] = dict(spec["solver"])
    if "grid" in spec:
        grid = spec["grid"]
        if not isinstance(grid, Mapping):
            raise TypeError("sweep spec: grid is a dict of dotted path -> list of values")
        fields["axis"] = [{"path": path, "values": list(values)} for path, values in grid.items()]
        return Spec.from_dict(fields), rows
    return Spec.from_dict(fields), rows if rows is not None else spec.get("rows")


def _is_spec_file(path: PathLike) -> bool:
    """Whether the file has a sweep spec's keys (``base``, ``axis``), valid or not."""
    keys = _toml_keys(path)
    return keys is not None and bool({"base", "axis"} & set(keys))


# The fields a sweep spec has and a scene does not (both have `checks` and `solver`).
_SPEC_ONLY_FIELDS = {"axis", "sampling", "uncertain", "set"}


def _spec(spec: SweepSpec, rows: Optional[Rows], base_dir: Optional[PathLike]) -> "Tuple[Spec, Optional[Rows]]":
    """The spec, and the rows when a scene needs them (``ValueError`` when none are given)."""
    if base_dir is not None and not (isinstance(spec, Mapping) and "base" in spec):
        what = "this dict has no base" if isinstance(spec, Mapping) else f"a {type(spec).__name__} has none to resolve"
        raise ValueError(
            "sweep: base_dir is the folder of a spec dict's base path (a spec file's base is "
            f"relative to the file); {what}"
        )
    if isinstance(spec, Spec):
        return spec, rows
    if isinstance(spec, (str, os.PathLike)) and rows is None:
        return Spec.load(spec), None  # a path alone is a sweep spec file
    if isinstance(spec, Mapping) and "scene" in spec:
        the_spec, rows = _legacy_spec(spec, rows)
        if rows is None and len(the_spec) == 1 and "grid" not in spec:
            raise ValueError("sweep spec: no rows (give rows=[{...}, …] or grid)")
        return the_spec, rows
    # A dict with a spec's own fields is a spec, whose missing base Spec.from_dict names (it
    # was taken for a scene's tables, and told to give rows).
    if isinstance(spec, Mapping) and ("base" in spec or _SPEC_ONLY_FIELDS & set(spec)):
        return Spec.from_dict(dict(spec), base_dir=base_dir), rows
    if isinstance(spec, (Scene, str, os.PathLike, Mapping)):
        if rows is None:
            raise ValueError("sweep: a scene needs rows=[{...}, …] (one dict of overrides per row), or give a sweep spec")
        if isinstance(spec, (str, os.PathLike)):
            try:
                scene = Scene.load(spec)
            except SceneError:
                if _is_spec_file(spec):
                    raise ValueError(
                        f"sweep: {os.fspath(spec)} is a sweep spec, whose rows come from its axes and "
                        "sampling; rows=[...] go with a scene (a Scene, a scene file or a dict of its tables)"
                    ) from None
                raise
            return Spec.from_scene(scene), rows
        return Spec.from_scene(_scene(spec)), rows
    raise TypeError(
        f"sweep takes a kanestop.Spec, a spec file, a spec dict (with base) or a scene with rows, not {type(spec).__name__}"
    )


def sweep(
    spec: SweepSpec,
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
    records: bool = False,
    base_dir: Optional[PathLike] = None,
) -> Any:
    """Runs a sweep as ``kanestop sweep SPEC.toml`` does (docs/sweeps.md), on the Rust
    thread pool (``jobs`` threads, every core when None) with the GIL released;
    ``progress(done, total)`` is called on this thread as rows finish (raise in it, or
    Ctrl-C, to cancel the rows not started and stop those running).

    ``spec`` is a sweep spec: a ``kanestop.Spec``, a spec file's path, or a dict of the spec
    file's fields (``{"base": "case01.toml" or a Scene, "axis": [{"path": "ship.mass",
    "values": [...]}], "sampling": {...}, "uncertain": [...], "checks": {...}}``; a ``base``
    path is relative to ``base_dir``, default the current directory). Or, with ``rows``, a
    scene (``Scene``, path or dict of its tables) and one dict of overrides per row
    (``[{"ship.mass": 1e6}, …]``; the rows may set different paths), or a pandas DataFrame
    whose columns are the paths (an empty cell leaves its path at the base's value).

    The solver keywords are set on the base scene for every row, as the spec's ``[solver]``
    would (``SceneError`` when out of range; ``SpecError`` on a path the spec sweeps, whose
    values would override it, unless the base needs the value to be valid). A bad spec
    raises ``SpecError`` naming the field (or ``SceneError`` for its base scene), before
    any run.

    Returns the table of ``sweep.csv`` as a DataFrame (a list of dicts without pandas), one
    row per run in spec order: ``index``, ``name``, one column per input (its dotted path),
    ``status`` (``invalid``: the inputs give no valid scene; the reason is in ``message``),
    ``checks``, then the outputs (``stopping_time``, ``peak_tension``, ``work_drag``,
    ``dissipated_drag``, ``check_<name>_pass``, …, ``message``), the same numbers as the
    command line's; the DataFrame's ``attrs["units"]`` maps each column to its unit, as
    ``sweep.units.csv`` has it ("" for a number without one, a count or text). With ``records=True``, the rows of ``sweep.json`` instead: a list of
    dicts ``{index, name, label, inputs, status, checks_pass, energy_split, summary,
    message}`` whose ``summary`` is the row's ``run --json`` record.

    Interrupted (Ctrl-C, or an exception raised in ``progress``), it raises that exception
    with the rows that had finished as its ``partial`` attribute, in the form a return
    would have had (in spec order; a row stopped mid-run is not among them)::

        try:
            table = kanestop.sweep(spec)
        except KeyboardInterrupt as e:
            table = e.partial
    """
    jobs = _jobs(jobs)
    the_spec, the_rows = _spec(spec, rows, base_dir)
    plan: Optional[List[Dict[str, Any]]] = None
    if the_rows is not None and hasattr(the_rows, "to_dict") and hasattr(the_rows, "columns"):
        # A pandas design table: a row per DataFrame row, a path per column; an empty cell
        # (NaN, None, pd.NA, NaT) leaves its path at the base scene's value.
        pd = _pandas()
        assert pd is not None, "a DataFrame without pandas"

        def empty(v: Any) -> bool:
            return v is None or (np.ndim(v) == 0 and bool(pd.isna(v)))

        the_rows = [{k: v for k, v in r.items() if not empty(v)} for r in the_rows.to_dict("records")]
    if the_rows is not None:
        plan = []
        for i, r in enumerate(the_rows):
            if not isinstance(r, Mapping):
                raise TypeError(f"row {i}: a row is a dict of dotted path -> value, not {type(r).__name__}")
            plan.append(dict(r))
    solver = _solver(integrator, dt, rtol, atol, end_time, output_interval)
    try:
        out = _sweep(the_spec, plan, jobs=jobs, progress=progress, kernel=kernel, records=records, **solver)
    except BaseException as e:
        raw = getattr(e, "_kanestop_partial", None)
        if raw is not None:
            done, total = getattr(e, "_kanestop_counts")
            setattr(e, "partial", _sweep_table(raw, records))
            if hasattr(e, "add_note"):
                e.add_note(
                    f"kanestop.sweep: {done} of {total} rows had finished; the exception's .partial "
                    "holds their table (in Jupyter: sys.last_value.partial)"
                )
        raise
    return _sweep_table(out, records)


def _sweep_table(out: Any, records: bool) -> Any:
    """``_sweep``'s output as ``sweep`` returns it: the records' list, else a DataFrame
    (a list of dicts without pandas)."""
    if records:
        assert isinstance(out, str)
        rows_json: List[Dict[str, Any]] = json.loads(out)
        return rows_json
    assert isinstance(out, tuple)
    columns, table, units = out
    pd = _pandas()
    if pd is not None:
        frame = pd.DataFrame.from_records(table, columns=columns)
        words = {"name", "status", "checks", "message"}
        words.update(c for c in columns if c.startswith("check_") and c.endswith("_pass"))
        frame = _with_words(pd, frame, words)
        frame.attrs["units"] = dict(zip(columns, units))
        return frame
    return [dict(zip(columns, row)) for row in table]
