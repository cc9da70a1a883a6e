"""Type stubs of the compiled core (python/pkg/src). Use the wrappers of ``massredist``."""

import os
from typing import Any, Callable

import numpy as np
import numpy.typing as npt

__version__: str

class SceneError(ValueError):
    """A scene the CLI would refuse, with the CLI's message."""

    key: str | None
    """The key the message names (``"time.dt"``), None if it names none."""

class RunError(RuntimeError):
    """A scheme failed while stepping (not a divergence: that is a result)."""

class Scene:
    """A validated scene: one geometry table (``[bar]``, ``[plate]`` or ``[solid]``) and the
    shared sections (``[mass]``, ``[scheme]``, ``[time]``, ``[output]``)."""

    @staticmethod
    def from_toml(
        text: str,
        base: str | os.PathLike[str] | None = None,
        mesh: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], str] | None = None,
    ) -> Scene:
        """A scene from TOML text; a mesh file is relative to ``base`` (default "."); ``mesh``
        (points, cells, meshio kind) stands for the [plate] or [solid] table's mesh file."""
    @staticmethod
    def from_file(path: str | os.PathLike[str]) -> Scene:
        """A scene from a TOML file (read as the CLI reads it)."""
    @staticmethod
    def from_dict(
        tables: dict[str, Any],
        base: str | os.PathLike[str] | None = None,
        mesh: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], str] | None = None,
    ) -> Scene:
        """A scene from a dict of tables; values: bool, int, float, str, lists, dicts, numpy."""
    def replace(self, changes: dict[str, Any] | None = None, **tables: Any) -> Scene:
        """A new scene with dotted keys changed (``{"time.dt": 0.005}``) and/or tables as
        keywords (``time={"dt": 0.005}``); None removes a key (its default applies)."""
    def resolved_toml(self) -> str:
        """The scene with every default filled in, as TOML."""
    def source_toml(self) -> str:
        """The tables as given, as TOML."""
    @property
    def table(self) -> str:
        """"bar", "plate" or "solid"."""
    @property
    def dt(self) -> float: ...
    @property
    def end(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def base(self) -> str: ...
    def __getitem__(self, key: str) -> Any:
        """The value of a dotted key in the resolved scene (``scene["time.dt"]``; a table gives
        a dict); KeyError if the resolved scene has no such key."""
    def __eq__(self, other: object) -> bool:
        """Equal resolved scenes, mesh folders and array meshes."""
    def __hash__(self) -> int: ...
    def __reduce__(self) -> tuple[Any, tuple[str, str, Any]]:
        """Pickling (multiprocessing, joblib): the tables as given, validated again on load."""

class ExactBar:
    """The exact solution of a bar scene; use ``massredist.Exact`` (broadcasting)."""

    @property
    def length(self) -> float: ...
    @property
    def end(self) -> float: ...
    def u(self, x: npt.NDArray[np.float64], t: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]: ...
    def u0(self, t: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]: ...
    def reaction(self, t: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]: ...

def check(scene: Scene) -> str:
    """Sets the scene up as ``massredist check`` does; the resolved TOML."""

def run(
    scene: Scene,
    callback: Callable[[int, float, np.ndarray, np.ndarray, np.ndarray, float], Any] | None = None,
    every: int = 1,
    vtu_dir: str | None = None,
) -> dict[str, Any]:
    """A run: status, summary_json, columns, series, t, u, v, reaction and the mesh; the VTU
    frames of a scene with ``output.vtu`` go into ``vtu_dir`` (required for such a scene).

    ``callback(n, t, u, v, reaction, energy)`` receives views: the same read-only arrays at
    every call, refreshed in place."""

def operators(scene: Scene) -> dict[str, Any]:
    """The assembled operators (CSR triples) and the mesh."""

def exact(scene: Scene) -> ExactBar:
    """The exact solution of a bar scene."""
