"""The resolved plate or solid scene that ``massredist`` writes (``scene.resolved.toml``), as
plain data.

Pure: reads a TOML text, returns a :class:`Scene`; no dolfinx, no MPI. Every default is already
filled in by the Rust side (``massredist check`` / ``run`` write the resolved scene), so this
reader only takes values and rejects what the engine does not run yet, naming the key.
"""
import ast
import math
import tomllib
from dataclasses import dataclass, field as dc_field

import numpy as np

# Scheme kinds the engine steps (src/schemes/*.rs): Newmark family, backward Euler, hybrid.
SCHEMES = ("crank-nicolson", "newmark", "backward-euler", "hybrid")


class SceneError(ValueError):
    """A scene the engine cannot run; the message names the key and what is allowed."""


@dataclass
class Scene:
    length: float
    height: float
    nx: int
    ny: int
    cells: str            # "quad" | "triangle"
    density: float
    modulus: float
    far_end: str          # "clamped" | "free"
    gap: float
    initial: object       # "paper" | "bump" | {"displacement": str, "velocity": str}
    force: object         # float | str (expression in x, y)
    mass: str             # standard | mod1 | mod2 | mod3 | custom
    weights: list | None
    scheme: str
    beta: float
    gamma: float
    dt: float
    end: float
    steps: int
    series: list
    every: int
    summary_l2: bool
    vtu_every: int | None
    divergence_factor: float
    field: str = "scalar"  # "scalar" (plates) | "vector" (elastic solids, issue 11)
    raw: dict = dc_field(default_factory=dict)
    # Solids only (field = "vector"; the [solid] table, src/solid/spec.rs).
    dim: int = 2
    depth: float = 0.0
    nz: int = 0
    lame_lambda: float = 0.0
    lame_mu: float = 0.5
    lateral: str = "free"   # "free" | "roller"
    # A body against a plane (an [obstacle] table): its data are in body.json (engine.body).
    body: bool = False

    @property
    def solid(self):
        return self.field == "vector"

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


def parse(text):
    """A :class:`Scene` from the text of ``scene.resolved.toml``."""
    raw = tomllib.loads(text)
    if "plate" not in raw and "solid" not in raw:
        raise SceneError("the engine runs [plate] and [solid] scenes (bars are 1D and serial)")
    p, m, s, t, o = (raw.get(k, {}) for k in ("plate", "mass", "scheme", "time", "output"))
    if "solid" in raw:
        p = raw["solid"]
    if "obstacle" in raw and "solid" in raw:
        p = raw["solid"]
    elif "mesh" in p:
        raise SceneError("plate.mesh: mesh files are not run by the engine yet (structured plates only)")
    kind = s.get("kind", "crank-nicolson")
    if kind not in SCHEMES:
        raise SceneError(f'scheme.kind = "{kind}": the engine runs {", ".join(SCHEMES)}')
    if s.get("formulation", "full") != "full":
        raise SceneError('scheme.formulation: only "full" on plates')
    beta, gamma = (0.25, 0.5) if kind != "newmark" else (s["beta"], s["gamma"])
    dt, end = float(t["dt"]), float(t["end"])
    steps = round(end / dt)
    vtu_every = o.get("vtu_every") if o.get("vtu", False) else None
    common = dict(mass=m.get("kind", "mod3"), weights=m.get("weights"), scheme=kind, beta=float(beta),
                  gamma=float(gamma), dt=dt, end=end, steps=steps, series=list(o.get("series", [])),
                  every=int(o.get("every", 1)), summary_l2=bool(o.get("summary_l2", True)),
                  vtu_every=int(vtu_every) if vtu_every else None,
                  divergence_factor=float(o.get("divergence_factor", 1e6)), raw=raw)
    if "obstacle" in raw:
        return _body(p, common)
    if "solid" in raw:
        return _solid(p, common)
    return Scene(
        length=float(p["length"]), height=float(p["height"]), nx=int(p["nx"]), ny=int(p["ny"]),
        cells=p.get("cells", "quad"), density=float(p.get("density", 1.0)),
        modulus=float(p.get("modulus", 1.0)), far_end=p.get("far_end", "clamped"),
        gap=float(p.get("gap", 0.0)), initial=p.get("initial", "paper"),
        force=p.get("force", 0.0) if isinstance(p.get("force", 0.0), str) else float(p.get("force", 0.0)),
        **common)


# The cells of each dimension (src/solid/spec.rs parse_solid).
SOLID_CELLS = {2: ("quad", "triangle"), 3: ("hex", "tet")}


def _solid(p, common):
    """A solid :class:`Scene` from the resolved ``[solid]`` table (CONTRACT: every key written)."""
    dim = int(p.get("dim", 2))
    if dim not in SOLID_CELLS:
        raise SceneError(f"solid.dim = {dim}: allowed 2 | 3")
    cells = p.get("cells", SOLID_CELLS[dim][0])
    if cells not in SOLID_CELLS[dim]:
        raise SceneError(f'solid.cells = "{cells}": allowed {" | ".join(SOLID_CELLS[dim])} (dim = {dim})')
    lateral = p.get("lateral", "free")
    if lateral not in ("free", "roller"):
        raise SceneError(f'solid.lateral = "{lateral}": allowed "free" | "roller"')
    force = [float(f) for f in p.get("force", [0.0] * dim)]
    if len(force) != dim:
        raise SceneError(f"solid.force = {force}: one number per component ({dim})")
    initial = p.get("initial", "paper")
    if not (initial == "paper" or isinstance(initial, dict)):
        raise SceneError(f'solid.initial = {initial!r}: allowed "paper" or {{ displacement, velocity }}')
    return Scene(
        length=float(p.get("length", 1.0)), height=float(p.get("height", 1.0)), nx=int(p.get("nx", 20)),
        ny=int(p.get("ny", 20)), cells=cells, density=float(p.get("density", 1.0)), modulus=math.nan,
        far_end="clamped", gap=float(p.get("gap", 0.0)), initial=initial, force=force,
        field="vector", dim=dim, depth=float(p.get("depth", 1.0)) if dim == 3 else 0.0,
        nz=int(p.get("nz", 20)) if dim == 3 else 0, lame_lambda=float(p.get("lame_lambda", 0.0)),
        lame_mu=float(p.get("lame_mu", 0.5)), lateral=lateral, **common)


def _body(p, common):
    """A body :class:`Scene`: the mesh, weights, contact set, initial fields and force are in
    body.json (written by massredist, read by engine.body); the table gives the dimension."""
    dim = int(p.get("dim", 2))
    return Scene(length=1.0, height=1.0, nx=1, ny=1, cells="body", density=float(p.get("density", 1.0)),
                 modulus=math.nan, far_end="body", gap=0.0, initial="body", force=[0.0] * dim,
                 field="vector", dim=dim, lame_lambda=float(p.get("lame_lambda", 0.0)),
                 lame_mu=float(p.get("lame_mu", 0.5)), body=True, **common)


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
    raise SceneError(f"plate.initial = {scene.initial!r}: allowed \"paper\", \"bump\" or expressions")


def solid_initial_fields(scene):
    """Component functions ``(i, x, y, z)`` of u⁰ and v⁰ of a solid: ``"paper"`` is
    u = ((L − x)/2, 0[, 0]), v = 0; otherwise one expression per component in x, y[, z] and
    L, H[, D], pi (a missing array is all zeros)."""
    L = scene.length
    if scene.initial == "paper":
        return (lambda i, x, y, z: (L - x) / 2.0 if i == 0 else 0.0 * x), (lambda i, x, y, z: 0.0 * x)
    three = scene.dim == 3
    names = ("x", "y", "z", "L", "H", "D", "pi") if three else ("x", "y", "L", "H", "pi")
    env = {"L": L, "H": scene.height, "pi": math.pi, **({"D": scene.depth} if three else {})}

    def field(key):
        exprs = [str(e) for e in scene.initial.get(key, ["0"] * scene.dim)]
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
