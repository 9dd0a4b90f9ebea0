"""Type stubs of the Rust extension module (python/src/lib.rs)."""

import os
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
MAX_JOBS: int
"""The most threads `sweep(jobs=…)` takes (the command line's `--jobs` limit)."""

class SceneError(ValueError):
    """A scene that could not be read or is not valid."""

    problems: List[Tuple[str, str, str]]
    """(field, value, expected) for every out-of-range value; empty for io/parse/override."""
    file: str
    kind: str
    """``io``, ``parse``, ``invalid`` or ``override``."""

class SpecError(ValueError):
    """A sweep spec that could not be read or is not valid."""

    field: str
    """The spec's field, e.g. ``axis[0].range.steps`` (an unknown key of a dict: the key,
    ``axis[0].valuez``); ``(file)`` for a file's TOML that does not parse or has an unknown key."""
    value: str
    expected: str
    file: str

class ModelError(ValueError):
    """A valid scene whose model cannot be built."""

class EvalError(ValueError):
    """A state that ``eval`` cannot evaluate."""

@final
class Scene:
    """A checked scene: every field present, finite and in range. Immutable."""

    @staticmethod
    def load(path: Union[str, "os.PathLike[str]"]) -> "Scene":
        """Reads and checks a scene file (``extends`` resolved). Raises SceneError."""
    @staticmethod
    def paper(number: int) -> "Scene":
        """Case ``number`` of the paper's Table 2 (1–19), built in: equal to
        ``scenes/paper/caseNN.toml``, no file needed. Raises ValueError outside 1–19."""
    @staticmethod
    def from_dict(d: Mapping[str, Any], name: str = "<dict>") -> "Scene":
        """A scene from a dict of its tables (as ``to_dict`` gives). Raises SceneError.
        ``name`` names the source in errors, not the scene: ``meta.name`` does (set it with
        ``with_overrides({"meta.name": …})``)."""
    @staticmethod
    def from_toml(
        text: str, name: str = "<string>", base_dir: Optional[Union[str, "os.PathLike[str]"]] = None
    ) -> "Scene":
        """A scene from TOML text; an ``extends`` is resolved from ``base_dir`` (default the
        current directory), as ``load`` resolves it from the file's folder. Raises SceneError.
        ``name`` names the source in errors, not the scene: ``meta.name`` does."""
    def with_overrides(self, overrides: Mapping[str, Any]) -> "Scene":
        """The same scene with each dotted path set (``{"ship.mass": 1e6}``), checked."""
    def to_dict(self) -> Dict[str, Any]:
        """The scene's tables as a dict, every field present."""
    def to_toml(self) -> str:
        """The scene as TOML text."""
    @property
    def name(self) -> str:
        """``meta.name``."""
    def __reduce__(self) -> Tuple[Callable[[str, str], "Scene"], Tuple[str, str]]: ...
    def __eq__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...

@final
class Spec:
    """A checked sweep spec (docs/sweeps.md). Immutable."""

    @staticmethod
    def load(path: Union[str, "os.PathLike[str]"]) -> "Spec":
        """Reads and checks a spec file. Raises SpecError or SceneError."""
    @staticmethod
    def from_toml(
        text: str, *, base_dir: Optional[Union[str, "os.PathLike[str]"]] = None, base: Optional[Scene] = None
    ) -> "Spec":
        """A spec from TOML text; ``base`` relative to ``base_dir``, or the given scene."""
    @staticmethod
    def from_dict(d: Mapping[str, Any], *, base_dir: Optional[Union[str, "os.PathLike[str]"]] = None) -> "Spec":
        """A spec from a dict of the spec file's fields; ``base`` a path, a Scene or a dict of its tables."""
    @staticmethod
    def from_scene(scene: Scene, name: Optional[str] = None) -> "Spec":
        """The spec of one scene, no axes: rows are given to ``sweep``."""
    @property
    def name(self) -> str: ...
    @property
    def base(self) -> Scene:
        """The base scene with ``[solver]`` and ``[set]`` applied."""
    @property
    def file(self) -> str: ...
    def inputs(self) -> List[Dict[str, Any]]:
        """Every row's inputs in spec order."""
    def __len__(self) -> int: ...
    def __reduce__(self) -> Tuple[Callable[[str, str, str, str], "Spec"], Tuple[str, str, str, str]]: ...
    def __eq__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...

def _scene_from_toml(text: str, name: str) -> Scene: ...
def _spec_from_parts(fields: str, base: str, base_name: str, file: str) -> Spec: ...
def _toml_keys(path: Union[str, "os.PathLike[str]"]) -> Optional[List[str]]: ...
@final
class _History:
    """A run's time history, still in Rust (``kanestop.Result`` converts it on first use)."""

    def columns(self) -> Tuple[Dict[str, npt.NDArray[np.float64]], List[Tuple[str, str, str, str]]]: ...

def _run(
    scene: Scene,
    *,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    end_time: Optional[float] = None,
    output_interval: Optional[float] = None,
    kernel: str = "generated",
) -> Tuple[str, _History, List[Dict[str, Any]], Optional[Dict[str, Any]], float]: ...
def eval(
    scene: Scene,
    q: Optional[Union[Sequence[float], "npt.NDArray[np.floating[Any]]"]] = None,
    u: Optional[Union[Sequence[float], "npt.NDArray[np.floating[Any]]"]] = None,
    *,
    anchor: Optional[str] = None,
    kernel: str = "generated",
) -> Dict[str, Any]:
    """The equations of motion as a dict with NumPy ``M``, ``f``, ``qdd``, ``q``, ``u``."""
def _sensitivity_units() -> List[Tuple[str, str]]:
    """The unit of each column of ``sensitivity.csv``, by name."""
def _sensitivity(
    scene: Scene,
    step: float = 0.05,
    jobs: Optional[int] = None,
    *,
    progress: Optional[Callable[[int, int], Any]] = None,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    end_time: Optional[float] = None,
    output_interval: Optional[float] = None,
) -> str:
    """The sensitivity study's ``sensitivity.json`` record as JSON text."""
def _sweep(
    spec: Spec,
    rows: Optional[Iterable[Mapping[str, Any]]] = None,
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
) -> Union[Tuple[List[str], List[List[Any]], List[str]], str]: ...
