"""The scene as the engine reads it: the JSON document that ``massredist`` writes
(``scene.engine.json``, src/engine/document.rs), as plain data.

Pure: reads a JSON text, returns a :class:`Scene`; no dolfinx, no MPI. The document is the
resolved, validated scene with every value written out, and massredist has already refused what
the engine cannot run (naming the key to change), so this reader decides nothing: it takes each
value, and a key missing from the document, or a document of another ``format``, is an error
(massredist and this folder from different trees), never a default.
"""
import ast
import json
import math
from dataclasses import dataclass

import numpy as np

# The document's version (src/engine/document.rs FORMAT).
FORMAT = 1

# The keys of each table of the document, by geometry kind (src/engine/document.rs).
GEOMETRY_KEYS = {
    "plate": ("length", "height", "nx", "ny", "cells", "density", "modulus", "far_end", "gap", "initial",
              "force"),
    "solid": ("dim", "length", "height", "depth", "nx", "ny", "nz", "cells", "density", "lame_lambda",
              "lame_mu", "gap", "lateral", "force", "initial"),
    "body": ("dim", "density", "lame_lambda", "lame_mu"),
}
MASS_KEYS = ("kind", "weights")
TIME_KEYS = ("dt", "end", "steps")
OUTPUT_KEYS = ("series", "every", "summary_l2", "vtu_every", "divergence_factor")
# The parameters of each scheme kind (src/engine/document.rs SchemeDoc).
SCHEME_KEYS = {"crank-nicolson": ("beta", "gamma"), "newmark": ("beta", "gamma"), "backward-euler": (),
               "hybrid": ()}


class SceneError(ValueError):
    """A document the engine cannot read; the message names the key."""


@dataclass
class Scene:
    """The document's values, one attribute each; ``None`` where a key does not apply to the
    geometry (a plate's Lamé parameters, a 2D solid's depth), as in the document."""
    geometry: str          # "plate" | "solid" (the structured box) | "body" (body.json, engine.body)
    length: float | None
    height: float | None
    depth: float | None
    nx: int | None
    ny: int | None
    nz: int | None
    dim: int | None
    cells: str | None      # "quad" | "triangle" | "hex" | "tet"
    density: float
    modulus: float | None  # plates
    far_end: str | None    # plates: "clamped" | "free" (a solid is clamped on x = L)
    gap: float | None
    lateral: str | None    # solids: "free" | "roller"
    lame_lambda: float | None
    lame_mu: float | None
    initial: object        # "paper" | "bump" | {"displacement": ..., "velocity": ...}
    force: object          # plates: float | str (expression in x, y); solids: one float per component
    mass: str              # standard | mod1 | mod2 | mod3 | custom
    weights: list | None
    scheme: str
    beta: float | None
    gamma: float | None
    dt: float
    end: float
    steps: int
    series: list
    every: int
    summary_l2: bool
    vtu_every: int | None
    divergence_factor: float

    @property
    def solid(self):
        """An elastic solid (a vector field, issue 11): the box or a body."""
        return self.geometry != "plate"

    @property
    def body(self):
        """A body against a plane (its data in body.json, engine.body)."""
        return self.geometry == "body"

    @property
    def field(self):
        return "vector" if self.solid else "scalar"

    @property
    def extent(self):
        return (self.length, self.height, self.depth)[: 3 if self.dim == 3 else 2]

    @property
    def face_area(self):
        """|Γ_C|: H (plates, 2D solids) or H·D (3D solids)."""
        return self.height * (self.depth if self.dim == 3 else 1.0)

    @property
    def has_paper_exact(self):
        """The paper's closed form applies to a plate (src/run/plate.rs: paper data, default
        body); solids: engine.exact.plane_wave."""
        return (not self.solid and self.initial == "paper" and self.density == 1.0
                and self.modulus == 1.0 and self.far_end == "clamped" and self.gap == 0.0
                and self.force == 0.0)


def _take(table, keys, name=None):
    """The values of ``keys`` in the document's ``table`` (named ``name`` in messages; None: the
    document itself)."""
    if not isinstance(table, dict):
        raise SceneError(f"{name or 'the document'}: a table expected in the engine's scene document, "
                         f"found {table!r}")
    missing = [k for k in keys if k not in table]
    if missing:
        path = f"{name}.{missing[0]}" if name else missing[0]
        raise SceneError(f"{path}: missing from the engine's scene document (format {FORMAT}: "
                         "massredist writes every key; are massredist and python/engine/ from one tree?)")
    return {k: table[k] for k in keys}


def _kind(table, name, kinds):
    kind = _take(table, ("kind",), name)["kind"]
    if kind not in kinds:
        raise SceneError(f'{name}.kind = "{kind}": not a kind of the document\'s format {FORMAT} '
                         f'({" | ".join(kinds)})')
    return kind


def parse(text):
    """A :class:`Scene` from the text of ``scene.engine.json``."""
    doc = json.loads(text)
    top = _take(doc, ("format", "geometry", "mass", "scheme", "time", "output"))
    if top["format"] != FORMAT:
        raise SceneError(f"format = {top['format']!r}: this engine reads format {FORMAT} "
                         "(massredist and python/engine/ are from different trees)")
    kind = _kind(top["geometry"], "geometry", tuple(GEOMETRY_KEYS))
    g = _take(top["geometry"], GEOMETRY_KEYS[kind], "geometry")
    scheme = _kind(top["scheme"], "scheme", tuple(SCHEME_KEYS))
    s = _take(top["scheme"], SCHEME_KEYS[scheme], "scheme")
    m = _take(top["mass"], MASS_KEYS, "mass")
    t = _take(top["time"], TIME_KEYS, "time")
    o = _take(top["output"], OUTPUT_KEYS, "output")
    # Every attribute not in this geometry's table does not apply to it (None).
    values = {name: None for name in ("length", "height", "depth", "nx", "ny", "nz", "dim", "modulus",
                                      "far_end", "gap", "lateral", "lame_lambda", "lame_mu", "initial",
                                      "force", "cells")}
    values.update(g)
    return Scene(geometry=kind, **values, mass=m["kind"], weights=m["weights"], scheme=scheme,
                 beta=s.get("beta"), gamma=s.get("gamma"), **t, **o)


# --- scene expressions (src/expr: x, y, L, H, pi; + - * / ^ **; sin cos tan exp log sqrt abs
# min max), evaluated on numpy arrays. Python's ** has the precedence src/expr documents for ^
# (binds tighter than unary minus, right-associative), so ^ is translated to **.
_FUNCS = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "log": np.log,
          "sqrt": np.sqrt, "abs": np.abs, "min": np.fmin, "max": np.fmax}
_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Constant, ast.Load,
          ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)


def expression(text, names):
    """A function of the variables ``names`` (keyword arrays) for a scene expression."""
    tree = ast.parse(text.replace("^", "**"), mode="eval")
    for node in ast.walk(tree):
        if not isinstance(node, _NODES):
            raise SceneError(f"expression {text!r}: {type(node).__name__} is not allowed")
        if isinstance(node, ast.Name) and node.id not in _FUNCS and node.id not in names:
            raise SceneError(f"expression {text!r}: unknown name {node.id!r}")
    tree = ast.fix_missing_locations(_Float64().visit(tree))
    code = compile(tree, "<scene expression>", "eval")
    scope = {"__builtins__": {}, "_f64": np.float64, **_FUNCS}

    def evaluate(**env):
        env = {k: np.float64(v) if isinstance(v, (int, float)) else v for k, v in env.items()}
        with np.errstate(all="ignore"):
            return np.asarray(eval(code, scope, env), dtype=float)
    return evaluate


class _Float64(ast.NodeTransformer):
    """Every number a numpy float64, as src/expr computes in f64: ``9^9^9`` is inf there and
    here, not an exact integer of 370 million digits that Python would compute for minutes, and
    ``10^400``, ``1/0`` are inf, not an OverflowError or a ZeroDivisionError (issue 22, D9)."""

    def visit_Constant(self, node):
        try:
            value = float(node.value)
        except OverflowError:  # an integer literal beyond the f64 range
            value = math.inf
        call = ast.Call(ast.Name("_f64", ast.Load()), [ast.Constant(value)], [])
        return ast.copy_location(call, node)


def initial_fields(scene):
    """``(u0(x, y), v0(x, y))`` as numpy functions (src/plate/scene.rs, PlateInitial); for a
    solid, functions ``(i, x, y, z)`` of the component i (src/solid/spec.rs, SolidInitial)."""
    if scene.solid:
        return solid_initial_fields(scene)
    L, H = scene.length, scene.height
    base = lambda x: (L - x) / 2.0
    if scene.initial == "paper":
        return (lambda x, y: base(x)), (lambda x, y: 0.0 * x)
    if scene.initial == "bump":
        return (lambda x, y: base(x) * (1.0 + 0.5 * np.cos(math.pi * y / H))), (lambda x, y: 0.0 * x)
    if isinstance(scene.initial, dict):
        env = {"L": L, "H": H, "pi": math.pi}
        fu = expression(scene.initial["displacement"], ("x", "y", "L", "H", "pi"))
        fv = expression(scene.initial["velocity"], ("x", "y", "L", "H", "pi"))
        return (lambda x, y: fu(x=x, y=y, **env) + 0.0 * x), (lambda x, y: fv(x=x, y=y, **env) + 0.0 * x)
    raise SceneError(f"geometry.initial = {scene.initial!r}: not a value of the document's format {FORMAT}")


def solid_initial_fields(scene):
    """Component functions ``(i, x, y, z)`` of u⁰ and v⁰ of a solid: ``"paper"`` is
    u = ((L − x)/2, 0[, 0]), v = 0; otherwise one expression per component in x, y[, z] and
    L, H[, D], pi (massredist writes both arrays, one expression per component)."""
    L = scene.length
    if scene.initial == "paper":
        return (lambda i, x, y, z: (L - x) / 2.0 if i == 0 else 0.0 * x), (lambda i, x, y, z: 0.0 * x)
    three = scene.dim == 3
    names = ("x", "y", "z", "L", "H", "D", "pi") if three else ("x", "y", "L", "H", "pi")
    env = {"L": L, "H": scene.height, "pi": math.pi, **({"D": scene.depth} if three else {})}

    def field(key):
        exprs = [str(e) for e in scene.initial[key]]
        fs = [expression(e, names) for e in exprs]
        def f(i, x, y, z):
            coords = {"x": x, "y": y, **({"z": z} if three else {})}
            return fs[i](**coords, **env) + 0.0 * x
        return f
    return field("displacement"), field("velocity")


def force_field(scene):
    """The body force f(x, y) as a numpy function (constant or expression); for a solid, the
    constant vector as a function ``(i, x, y, z)``."""
    if scene.solid:
        return lambda i, x, y, z: scene.force[i] + 0.0 * x
    if isinstance(scene.force, str):
        f = expression(scene.force, ("x", "y", "L", "H", "pi"))
        return lambda x, y: f(x=x, y=y, L=scene.length, H=scene.height, pi=math.pi) + 0.0 * x
    return lambda x, y: scene.force + 0.0 * x
