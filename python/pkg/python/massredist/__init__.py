"""massredist from Python: weighted finite element mass redistribution for dynamic contact.

The same core as the ``massredist`` command line (a Rust crate, compiled into
``massredist._core``): scenes are the CLI's TOML scenes, validated with the CLI's checks and
messages; a run steps the CLI's schemes with its divergence rule and returns its
``summary.json`` as a dict, with the series and the final fields as numpy arrays.

>>> import massredist as mr
>>> run = mr.run(mr.load("scenes/fig11-mod3.toml"))
>>> run.summary["linf_l2_error"], run.series["energy"][-1]

- :func:`load` reads a scene (a TOML file, TOML text or a dict); :meth:`Scene.replace`
  changes keys for a sweep; :func:`check` sets it up and returns it with every default filled.
- :func:`run` runs it (the GIL is released while Rust steps; Ctrl-C raises
  ``KeyboardInterrupt`` within a fraction of a second); ``callback`` sees the state every k
  steps.
- :func:`operators` gives the assembled weighted mass, stiffness, load, contact unknowns and
  cell weights (``scipy.sparse`` matrices when scipy is importable).
- :func:`exact` gives the exact solution of a bar scene, vectorised over x and t.

Errors in a scene raise :class:`SceneError` (a ``ValueError``; ``.key`` names the key).
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
import tomllib
from dataclasses import dataclass, field, is_dataclass
from dataclasses import fields as dataclass_fields
from typing import Any, Callable, Mapping, NamedTuple, Union

import numpy as np

from . import _core
from ._core import RunError, Scene, SceneError, __version__

__all__ = [
    "Scene",
    "SceneError",
    "RunError",
    "State",
    "Fields",
    "Run",
    "Operators",
    "Exact",
    "load",
    "check",
    "run",
    "operators",
    "exact",
    "__version__",
]

SceneLike = Union[Scene, str, "os.PathLike[str]", Mapping[str, Any]]


MeshLike = Union[tuple[Any, Any], tuple[Any, Any, str]]

_KINDS = {(2, 3): "triangle", (2, 4): "quad", (3, 4): "tetra", (3, 8): "hexahedron"}


def _mesh_arrays(mesh: MeshLike) -> tuple[np.ndarray, np.ndarray, str]:
    points = np.ascontiguousarray(mesh[0], dtype=np.float64)
    cells = np.ascontiguousarray(mesh[1], dtype=np.int64)
    if points.ndim != 2 or cells.ndim != 2:
        raise SceneError(f"mesh: points and cells must be 2D arrays (got {points.ndim}D and {cells.ndim}D)")
    if len(mesh) > 2:
        kind = str(mesh[2])
    else:
        dim = 3 if points.shape[1] == 3 and np.ptp(points[:, 2]) > 0 else 2
        kind = _KINDS.get((dim, cells.shape[1]), f"{cells.shape[1]}-vertex cells")
    return points, cells, kind


def load(
    source: SceneLike,
    *,
    base: str | os.PathLike[str] | None = None,
    mesh: MeshLike | None = None,
) -> Scene:
    """A validated scene from a TOML file, TOML text or a dict of tables.

    ``source`` is a :class:`Scene` (returned as is), a ``dict`` such as
    ``{"bar": {"elements": 6}, "time": {"dt": 0.01, "end": 3.0}}``, a path (``str`` or
    ``os.PathLike``) of a ``.toml`` file, or TOML text (a ``str`` with a newline, ``=`` or ``[``).
    A mesh file named by the scene is relative to the file's folder, or to ``base`` (default:
    the current folder) for text and dicts.

    ``mesh=(points, cells)`` (or ``(points, cells, kind)``, kind as meshio names it: triangle,
    quad, tetra, hexahedron) gives the body of a ``[plate]`` or ``[solid]`` scene as arrays
    instead of a mesh file (e.g. a dolfinx mesh's ``geometry.x`` and ``geometry.dofmap``,
    vertices in meshio's order): the table's ``mesh`` becomes ``"<arrays>"`` and the arrays go
    through the checks of a mesh file. Raises :class:`SceneError` (a ``ValueError``) with
    the CLI's message; its ``key`` attribute names the key at fault.
    """
    base_s = None if base is None else os.fspath(base)
    arrays = None if mesh is None else _mesh_arrays(mesh)
    if arrays is not None:
        if isinstance(source, Scene):
            return Scene.from_toml(source.source_toml(), os.fspath(source.base), arrays)
        if isinstance(source, Mapping):
            return Scene.from_dict(dict(source), base_s, arrays)
        if isinstance(source, os.PathLike) or (isinstance(source, str) and "=" not in source and "\n" not in source):
            path = os.fspath(source)
            with open(path, encoding="utf-8") as f:
                return Scene.from_toml(f.read(), base_s or os.path.dirname(path) or ".", arrays)
        return Scene.from_toml(source, base_s, arrays)
    if isinstance(source, Scene):
        return source
    if isinstance(source, Mapping):
        return Scene.from_dict(dict(source), base_s)
    if isinstance(source, os.PathLike):
        return Scene.from_file(os.fspath(source))
    if isinstance(source, str):
        if "\n" in source or "=" in source or source.lstrip().startswith("["):
            return Scene.from_toml(source, base_s)
        return Scene.from_file(source)
    raise TypeError(f"load: a Scene, a path, TOML text or a dict is needed, not {type(source).__name__}")


def check(scene: SceneLike) -> dict[str, Any]:
    """Sets a scene up as ``massredist check`` does (assembly, exact solution, factorisation)
    and returns it with every default filled in, as a dict of tables."""
    return tomllib.loads(_core.check(load(scene)))


class State(NamedTuple):
    """The state a :func:`run` callback receives every ``every`` steps.

    ``u``, ``v`` and ``reaction`` are views of the run's state: the same read-only arrays at
    every call, refreshed in place before it (no allocation per call). Copy what you keep:
    ``kept.append(state.u.copy())``."""

    n: int
    """The step number (t = n Δt)."""
    t: float
    u: np.ndarray
    """Displacement at the mesh nodes, shape (nodes, components)."""
    v: np.ndarray
    """Velocity at the mesh nodes, shape (nodes, components)."""
    reaction: np.ndarray
    """Contact reactions λ_c ≤ 0, one per contact unknown (``Fields.contact_nodes`` order)."""
    energy: float
    """The discrete energy ½VᵀMV + ½UᵀSU − UᵀF."""


def _equal(a: Any, b: Any) -> bool:
    """Equality of values that may hold numpy arrays (equal shapes, dtypes and entries; NaN
    equal to NaN), in dicts and dataclasses, for :class:`Fields` and :class:`Run`."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        if not (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)):
            return False
        nan = a.dtype.kind in "fc"
        return a.shape == b.shape and a.dtype == b.dtype and bool(np.array_equal(a, b, equal_nan=nan))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_equal(a[k], b[k]) for k in a)
    if is_dataclass(a) and type(a) is type(b):
        return all(_equal(getattr(a, f.name), getattr(b, f.name)) for f in dataclass_fields(a))
    return bool(a == b) or (isinstance(a, float) and isinstance(b, float) and a != a and b != b)


@dataclass(frozen=True, eq=False)
class Fields:
    """The final state of a run with its mesh."""

    t: float
    u: np.ndarray
    """Displacement at the mesh nodes, shape (nodes, components) (0 on clamped nodes)."""
    v: np.ndarray
    """Velocity at the mesh nodes, shape (nodes, components)."""
    reaction: np.ndarray
    """Contact reactions λ_c ≤ 0 at ``contact_nodes``."""
    points: np.ndarray
    """Node coordinates, shape (nodes, dim)."""
    cells: np.ndarray
    """Cell vertices, shape (cells, vertices per cell), int64."""
    cell_kind: str
    """meshio's name of the cells: line, triangle, quad, tetra, hexahedron."""
    weights: np.ndarray
    """The mass weight of each cell (the redistribution)."""
    contact_nodes: np.ndarray
    """The mesh node of each contact reaction."""

    def __eq__(self, other: object) -> bool:
        return _equal(self, other)

    __hash__ = None  # type: ignore[assignment]  (holds arrays)


@dataclass(frozen=True, eq=False)
class Run:
    """What :func:`run` returns."""

    status: str
    """"ok" (every step taken) or "diverged" (the CLI's divergence rule stopped the run)."""
    summary: dict[str, Any]
    """The CLI's ``summary.json``, key for key (``wall_seconds`` is this run's)."""
    series: dict[str, np.ndarray]
    """``"t"`` and each column of ``output.series``, one value per recorded step."""
    fields: Fields
    scene: Scene = field(repr=False)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def __eq__(self, other: object) -> bool:
        """Equal status, summary (``wall_seconds`` included: two runs of one scene differ in it),
        series, fields and scene; a pickled copy equals its original."""
        return _equal(self, other)

    __hash__ = None  # type: ignore[assignment]  (holds arrays)


def run(
    scene: SceneLike,
    *,
    callback: Callable[[State], Any] | None = None,
    every: int = 1,
    vtu_dir: str | os.PathLike[str] | None = None,
    progress: bool = False,
) -> Run:
    """Runs a scene as ``massredist run`` does, in memory (no files).

    The GIL is released while Rust steps, so runs in several threads go in parallel. Ctrl-C
    (in the main thread) raises ``KeyboardInterrupt`` within about 20 ms plus one step.
    ``callback(state)`` (a :class:`State`) is called at steps 0, every, 2·every, …; an
    exception it raises stops the run and propagates. A run that diverges is a result:
    ``status == "diverged"`` and ``summary["divergence"]`` says where and why.

    A scene with ``output.vtu = true`` writes its VTU frames (``vtu/frame_NNNNN.vtu`` and the
    ``.pvd`` collection, as ``massredist run`` does) into ``vtu_dir``, created if missing; without
    ``vtu_dir`` it is refused (:class:`SceneError` naming ``output.vtu``), and so is ``vtu_dir``
    for a scene that writes no frames. A folder that holds frames already raises
    ``FileExistsError`` before the run.

    ``progress=True`` shows the run's progress on stderr (percent of the steps, t, elapsed
    seconds), refreshed about every percent of the steps, beside ``callback``.
    """
    sc = load(scene)
    if every < 1:
        raise ValueError(f"every = {every}: allowed range is [1, ∞)")
    hook = None
    if callback is not None:

        def hook(n: int, t: float, u: np.ndarray, v: np.ndarray, reaction: np.ndarray, energy: float) -> None:
            callback(State(n, t, u, v, reaction, energy))

    if progress:
        hook, every = _with_progress(hook, every, sc.steps)
    started = time.perf_counter()
    d = _core.run(sc, hook, every, None if vtu_dir is None else os.fspath(vtu_dir))
    table = d["series"]
    series = {"t": table[:, 0]}
    for k, name in enumerate(d["columns"]):
        series[name] = table[:, k + 1]
    fields = Fields(
        t=d["t"],
        u=d["u"],
        v=d["v"],
        reaction=d["reaction"],
        points=d["points"],
        cells=d["cells"],
        cell_kind=d["cell_kind"],
        weights=d["weights"],
        contact_nodes=d["contact_nodes"],
    )
    summary = json.loads(d["summary_json"])
    if progress:
        done = f"massredist: {summary['steps']} of {sc.steps} steps, {d['status']}, {time.perf_counter() - started:.1f} s"
        sys.stderr.write(f"\r{done:<72}\n")
    return Run(status=d["status"], summary=summary, series=series, fields=fields, scene=sc)


def _with_progress(hook: Any, every: int, steps: int) -> tuple[Any, int]:
    """The run's hook with a progress line on stderr: the hook called every ``every`` steps as
    before, the line every ``stride`` steps (about 1 % of them, a multiple of ``every``)."""
    stride = every * max(1, steps // (100 * every))
    start = time.perf_counter()

    def with_line(n: int, t: float, u: np.ndarray, v: np.ndarray, reaction: np.ndarray, energy: float) -> None:
        if hook is not None and n % every == 0:
            hook(n, t, u, v, reaction, energy)
        if n % stride == 0 or n == steps:
            percent = 100.0 * n / max(steps, 1)
            elapsed = time.perf_counter() - start
            sys.stderr.write(f"\rmassredist: {percent:5.1f} % of {steps} steps, t = {t:.6g}, {elapsed:.1f} s")
            sys.stderr.flush()

    return with_line, math.gcd(every, stride) if hook is not None else stride


def _sparse(triple: tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, int]]) -> Any:
    data, indices, indptr, shape = triple
    try:
        import scipy.sparse
    except ImportError:
        return triple
    return scipy.sparse.csr_matrix((data, indices, indptr), shape=shape)


@dataclass(frozen=True)
class Operators:
    """The assembled contact system M Ü + S U = F − Σ_c λ_c e_c (paper eq. (3.1)) over the
    free unknowns, and its mesh."""

    mass: Any
    """The weighted (redistributed) mass M: ``scipy.sparse.csr_matrix``, or without scipy a
    CSR triple ``(data, indices, indptr, shape)``."""
    stiffness: Any
    """The stiffness S (same form as ``mass``)."""
    load: np.ndarray
    """F (at t = 0 for a time-dependent load)."""
    contact: np.ndarray
    """The contact unknowns (indices into the free unknowns, λ order)."""
    lower: np.ndarray
    """The obstacle bound lb_c = −gap_c of each contact unknown."""
    massless: np.ndarray
    """Per unknown: M_ii = 0."""
    u0: np.ndarray
    v0: np.ndarray
    """The interpolated initial data on the free unknowns."""
    weights: np.ndarray
    """One mass weight per cell."""
    points: np.ndarray
    cells: np.ndarray
    cell_kind: str
    contact_nodes: np.ndarray


def operators(scene: SceneLike) -> Operators:
    """The assembled operators of a scene (set up as ``run`` sets it up)."""
    d = _core.operators(load(scene))
    d["mass"] = _sparse(d["mass"])
    d["stiffness"] = _sparse(d["stiffness"])
    return Operators(**d)


class Exact:
    """The exact solution of a bar scene up to its ``time.end``: the paper's closed form for its
    benchmark (eq. (4.2), sign corrected), characteristics for any other bar without body
    force. Every method broadcasts its arguments as numpy does."""

    def __init__(self, core: _core.ExactBar) -> None:
        self._core = core
        self.length: float = core.length
        self.end: float = core.end

    def u(self, x: Any, t: Any) -> np.ndarray:
        """u(x, t), broadcast over x and t (x in [0, L], t in [0, T])."""
        xb, tb = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(t, dtype=np.float64))
        out = self._core.u(np.ascontiguousarray(xb).ravel(), np.ascontiguousarray(tb).ravel())
        return out.reshape(xb.shape)

    def u0(self, t: Any) -> np.ndarray:
        """u(0, t), the contact displacement."""
        tb = np.asarray(t, dtype=np.float64)
        return self._core.u0(np.ascontiguousarray(tb).ravel()).reshape(tb.shape)

    def reaction(self, t: Any) -> np.ndarray:
        """λ(t) = E u_x(0, t) ≤ 0, the contact reaction."""
        tb = np.asarray(t, dtype=np.float64)
        return self._core.reaction(np.ascontiguousarray(tb).ravel()).reshape(tb.shape)


def exact(scene: SceneLike) -> Exact:
    """The exact solution of a ``[bar]`` scene (:class:`Exact`); a :class:`SceneError` for
    other scenes and for a bar with a body force."""
    return Exact(_core.exact(load(scene)))
