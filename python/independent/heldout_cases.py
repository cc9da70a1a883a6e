"""Held-out body scenes (issue 19, first "Done when"): generated here (meshes by heldout_meshes,
not shipped in scenes/), run by the `massredist` binary and by heldout_body, and compared key by
key: every key of the body's summary.json but max_pivots (the binary's LCP pivot count) and
wall_seconds, and the default series of a body at every step. Keys computed here are compared
within 1e-7 of their scale (`scales`); the rest (`bookkeeping`: the scene echoed, the bounding
box, nulls) exactly.

Usage: /usr/bin/python3 python/independent/heldout_cases.py MASSREDIST_BINARY [--keep DIR] [NAME...]
Prints one line per key and exits 1 if any key differs by more than 1e-7 of its scale (the
scale of each key is printed with it and explained in `SCALES`).
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import heldout_body  # noqa: E402
import heldout_fem  # noqa: E402
import heldout_meshes as hm  # noqa: E402
import shared  # noqa: E402


def disc_mesh(order, gap, half=False):
    centre = (0.0, 1.0 + gap)
    pts, tris = hm.disc(1.0, centre, 3, half=half)
    if order == 2:
        pts, tris = hm.to_p2(pts, tris, hm.on_circle(1.0, centre, hm.boundary_edge_keys(pts, tris)))
    return (pts, tris, order), {"top": lambda p, c=centre[1]: abs(p[1] - c) < 1e-12}


def rect_mesh():
    pts, tris = hm.rectangle(1.0, 0.5, 4, 2)
    pts, tris = hm.to_p2(pts, tris)
    return (pts, tris, 2), {"xmax": lambda p: abs(p[0] - 1.0) < 1e-12, "ymin": lambda p: abs(p[1]) < 1e-12}


def box_mesh(order):
    """The box (0, 1) x (0, 1) x (0, 0.5); P2 mapped by x' = x + 0.05 sin(pi y) z,
    y' = y + 0.05 sin(pi x) z, z' = z + 0.2 x z (0.5 - z): curved cells, planar bottom and top."""
    pts, tets = hm.box_tets((1.0, 1.0, 0.5), 2)
    if order == 2:
        pts, tets = hm.to_p2(pts, tets)
        x, y, z = pts.T.copy()
        pts = np.column_stack([x + 0.05 * np.sin(np.pi * y) * z, y + 0.05 * np.sin(np.pi * x) * z, z + 0.2 * x * z * (0.5 - z)])
    return (pts, tets, order), {"top": lambda p: abs(p[2] - 0.5) < 1e-12}


def q1_mesh(d):
    """Parallelograms (4 x 2, shear 0.3) or parallelepipeds (2^3, shear 0.2): Q1 cells on which
    a Gauss rule integrates mass and stiffness exactly."""
    if d == 2:
        pts, cells = hm.parallelograms(1.0, 0.5, 4, 2, 0.3)
        return (pts, cells, "q1"), {"top": lambda p: abs(p[1] - 0.5) < 1e-12}
    pts, cells = hm.parallelepipeds((1.0, 1.0, 0.5), 2, 0.2)
    return (pts, cells, "q1"), {"top": lambda p: abs(p[2] - 0.5) < 1e-12}


def case(name, mesh, scheme, mass, rule, gap=0.0, normal=None, force=None, v0=None, u0=None, clamped=None,
         contact="auto", lam=2.0, mu=1.0, rho=1.0, dt=0.01, end=0.3):
    (pts, cells, order), groups = mesh
    d = pts.shape[1]
    normal = normal or [0.0] * (d - 1) + [1.0]
    n = np.array(normal) / np.linalg.norm(normal)
    # The plane `gap` below the lowest node along n (point = X_low - gap n).
    low = pts[np.argmin(pts @ n)]
    point = [float(x) for x in low - gap * n]
    return dict(name=name, mesh=(pts, cells, order), groups=groups, scheme=scheme, mass=mass, rule=rule,
                normal=normal, point=point, force=force or ["0"] * (d - 1) + ["-1"], u0=u0 or ["0"] * d,
                v0=v0 or ["0"] * d, clamped=clamped, contact=contact, lam=lam, mu=mu, rho=rho, dt=dt, end=end)


def cases():
    disc2, disc2g, disc1g = disc_mesh(2, 0.0), disc_mesh(2, 0.03), disc_mesh(1, 0.03)
    half2 = disc_mesh(2, 0.0, half=True)
    tet10, tet4 = box_mesh(2), box_mesh(1)
    return [
        # Free P2 discs (curved boundary cells: the degree-5 Grundmann-Moller rule).
        case("disc-p2-rest-cn-mod3-g", disc2, "crank-nicolson", "mod3", "gm5"),
        case("disc-p2-drop-cn-mod1", disc2g, "crank-nicolson", "mod1", "gm5", gap=0.025, force=["0", "0"], v0=["0", "-1"], lam=20.0, mu=10.0, end=1.0),
        case("disc-p2-drop-be-mod2-g-tilted", disc2g, "backward-euler", "mod2", "gm5", gap=0.02, normal=[0.2, 1.0],
             v0=["0.1", "-1"], end=0.4),
        case("disc-p2-drop-hybrid-mod3-g", disc2g, "hybrid", "mod3", "gm5", gap=0.03, v0=["0", "-1"], end=0.4),
        case("disc-p2-rest-hybrid-mod1-gx", disc2, "hybrid", "mod1", "gm5", force=["0", "-1 - 0.5*x"],
             u0=["0", "0.01*x*x"]),
        case("disc-p2-drop-cn-standard-g", disc2g, "crank-nicolson", "standard", "gm5", gap=0.03, v0=["0", "-1"],
             u0=["0.01*y", "0.005*x*x"]),
        # GetFEM's singular mass as `custom` weights (0 on the cells with a contact facet).
        case("disc-p2-drop-cn-custom-g", disc2g, "crank-nicolson", "custom", "gm5", gap=0.025, v0=["0", "-1"]),
        case("disc-p1-rest-be-custom-g", disc_mesh(1, 0.0), "backward-euler", "custom", "gauss"),
        dict(case("disc-p2-drop-newmark-mod2-g", disc2g, "newmark", "mod2", "gm5", gap=0.025, v0=["0", "-1"]),
             beta=0.3, gamma=0.6),
        # Free P1 discs (any rule is exact: the collapsed Gauss one).
        case("disc-p1-drop-cn-standard-g", disc1g, "crank-nicolson", "standard", "gauss", gap=0.03, v0=["0", "-1"], end=0.4),
        case("disc-p1-drop-hybrid-mod2", disc1g, "hybrid", "mod2", "gauss", gap=0.025, force=["0", "0"], v0=["0.2", "-1"], lam=20.0, mu=10.0, end=1.3),
        # Half discs clamped on their flat top ("top"), curved bottom touching the floor.
        case("halfdisc-p2-clamped-cn-mod1-t", half2, "crank-nicolson", "mod1", "gm5", force=["0", "-2*sin(10*t)"],
             v0=["0", "-0.3"], clamped="top", end=0.4),
        case("halfdisc-p2-clamped-be-standard-gt", half2, "backward-euler", "standard", "gm5", gap=0.01,
             force=["0.3*cos(5*t)", "-1"], v0=["0", "-0.5"], clamped="top"),
        case("halfdisc-p2-clamped-hybrid-mod3-t", half2, "hybrid", "mod3", "gm5", force=["0.2*t", "-1"], clamped="top"),
        # A straight-sided P2 rectangle (the collapsed Gauss rule: exact), clamped on xmax.
        case("rect-p2-clamped-be-mod3-tilted", rect_mesh(), "backward-euler", "mod3", "gauss", gap=0.02,
             normal=[0.1, 1.0], force=["0", "0"], v0=["0", "-1"], clamped="xmax", contact="ymin"),
        case("rect-p2-clamped-cn-mod2-g", rect_mesh(), "crank-nicolson", "mod2", "gauss", gap=0.01,
             v0=["0", "-1"], clamped="xmax", contact="ymin"),
        # 3D: curved tetra10 (Grundmann-Moller), straight tetra (collapsed Gauss).
        case("tet10-drop-cn-mod3-gyz-tilted", tet10, "crank-nicolson", "mod3", "gm5", gap=0.02, normal=[0.1, 0.05, 1.0],
             force=["0", "0.1*z", "-1 - 0.2*y"], v0=["0", "0", "-1"], end=0.2),
        case("tet10-clamped-hybrid-mod2-g", tet10, "hybrid", "mod2", "gm5", gap=0.01, v0=["0", "0", "-1"],
             clamped="top", end=0.2),
        case("tet10-clamped-be-standard", tet10, "backward-euler", "standard", "gm5", gap=0.01, force=["0", "0", "0"],
             v0=["0", "0", "-1"], u0=["0.01*z", "0", "0.002*x*y"], clamped="top", end=0.2),
        case("tet4-drop-be-mod1", tet4, "backward-euler", "mod1", "gauss", gap=0.025, force=["0", "0", "0"],
             v0=["0", "0", "-1"], end=0.3),
        case("tet4-drop-hybrid-mod3-g", tet4, "hybrid", "mod3", "gauss", gap=0.02, v0=["0", "0", "-1"], end=0.3),
        # Q1: parallelogram quadrangles and parallelepiped hexahedra (tensor Gauss: exact).
        case("quad-drop-cn-mod3-g-tilted", q1_mesh(2), "crank-nicolson", "mod3", "tensor", gap=0.025, normal=[0.1, 1.0],
             v0=["0", "-1"]),
        case("quad-clamped-hybrid-mod1", q1_mesh(2), "hybrid", "mod1", "tensor", gap=0.01, force=["0", "0"],
             v0=["0", "-1"], clamped="top"),
        case("hex-drop-be-mod2-g", q1_mesh(3), "backward-euler", "mod2", "tensor", gap=0.025, v0=["0", "0", "-1"], end=0.2),
        case("hex-clamped-hybrid-mod3-g-tilted", q1_mesh(3), "hybrid", "mod3", "tensor", gap=0.01, normal=[0.0, 0.1, 1.0],
             v0=["0", "0", "-1"], clamped="top", end=0.2),
    ]


def scene_text(c, mesh_file):
    s = lambda v: ", ".join(f'"{x}"' for x in v)
    lines = ["[solid]", f"dim = {c['mesh'][0].shape[1]}", f'mesh = "{mesh_file}"', f"lame_lambda = {c['lam']!r}",
             f"lame_mu = {c['mu']!r}", f"density = {c['rho']!r}", f"force = [{s(c['force'])}]",
             f"initial = {{ displacement = [{s(c['u0'])}], velocity = [{s(c['v0'])}] }}"]
    return "\n".join(lines + shared.body_tail(c, c["scheme"])) + "\n"


def scales(mine, ours):
    """The scale each key is measured against (|difference| <= 1e-7 scale):
    - energies and energy increments: the largest |E^n| of the run (an increment is a difference
      of energies: relative to itself it would measure round-off, e.g. CN's 1e-16 steps);
    - displacements (final_u0, min_u0, final_u_mean, min_distance, mean displacement): the
      largest displacement key of the run, at least 1e-3 (the gaps are 0.01 - 0.03);
    - reactions (max/final contact force, max_lambda): max_contact_force, at least 1e-3;
      the complementarity product: that times the displacement scale;
    - momentum: its largest component, at least 1e-3 x total_mass;
    - total_mass, h: themselves (relative); times and counts: exact (1e-7 absolute)."""
    E = max(abs(mine["energy_max"]), abs(mine["energy_min"]), 1e-300)
    U = max(1e-3, abs(mine["min_u0"]), abs(mine["final_u0"]), abs(mine["final_u_mean"]),
            max(abs(x) for x in mine["final_mean_displacement"]))
    R = max(1e-3, abs(mine["max_contact_force"]))
    P = max(1e-3 * mine["total_mass"], max(abs(x) for x in mine["final_momentum"]))
    out = {k: E for k in ("energy_initial", "energy_final", "energy_min", "energy_max", "energy_max_increase",
                          "energy_max_increase_after_first")}
    out.update({k: U for k in ("final_u0", "min_u0", "final_u_mean", "min_distance", "final_mean_displacement",
                               "max_y_variation")})
    out.update(max_contact_force=R, final_contact_force=R, max_lambda=R, max_complementarity_product=R * U,
               final_momentum=P, total_mass=mine["total_mass"], h=mine["h"])
    return out


def compare(c, mine, ours):
    """Lines and the worst scaled difference of every key (energy_max_increase_step: the other
    side's step must be a step whose increment here equals the largest within 1e-7 E)."""
    sc = scales(mine, ours)
    worst, lines = 0.0, []
    for key, value in mine.items():
        if key in ("energy_increments", "series"):
            continue
        theirs = ours[key]
        if key == "energy_max_increase_step":
            inc = mine["energy_increments"]
            diff = abs(inc[theirs - 1] - inc.max()) / sc["energy_max"] if 1 <= theirs <= len(inc) else math.inf
            scale_txt = "E (its increment)"
        elif value is None or theirs is None:
            diff = 0.0 if value is None and theirs is None else math.inf
            scale_txt = "null"
        else:
            a, b = np.atleast_1d(np.array(value, float)), np.atleast_1d(np.array(theirs, float))
            s = sc.get(key, 1.0)
            diff = float(np.max(np.abs(a - b))) / s
            scale_txt = f"{s:.3g}" if key in sc else "exact"
        worst = max(worst, diff)
        flag = "" if diff <= 1e-7 else "   <-- DISAGREES"
        show = lambda v: json.dumps(v if not isinstance(v, float) else float(f"{v:.12g}"))
        lines.append(f"{c['name']:34s} {key:32s} numpy {show(value)[:40]:>40s}  massredist {show(theirs)[:40]:>40s}"
                     f"  scale {scale_txt:>9s}  {diff:.1e}{flag}")
    book = bookkeeping(c)
    for key, value in book.items():
        theirs = ours.get(key, "absent")
        same = theirs == value if not isinstance(value, float) else abs(theirs - value) <= 1e-12 * max(1.0, abs(value))
        worst = max(worst, 0.0 if same else math.inf)
        lines.append(f"{c['name']:34s} {key:32s} expected {json.dumps(value):>37s}  massredist {json.dumps(theirs):>40s}"
                     f"{'' if same else '   <-- DISAGREES'}")
    # Keys of the summary not checked here, said once per case.
    skipped = sorted(set(ours) - set(mine) - set(book))
    return worst, lines, skipped


def bookkeeping(c):
    """The summary's other keys: the scene echoed, the mesh's bounding box (the unused node far
    away must be dropped), no structured grid (0), the cell kind, and null for what a body has
    not (no exact solution, no divergence)."""
    pts, cells, order = c["mesh"]
    d = pts.shape[1]
    ext = pts.max(axis=0) - pts.min(axis=0)
    kind = {(2, 1): "triangle", (2, 2): "triangle6", (2, "q1"): "quad", (3, 1): "tet", (3, 2): "tetra10",
            (3, "q1"): "hex"}[(d, order)]
    out = dict(scheme=c["scheme"], mass=c["mass"], end=c["end"], dt=c["dt"], dim=d, lame_lambda=c["lam"],
               lame_mu=c["mu"], density=c["rho"], initial="fields", status="ok", divergence=None,
               steps_requested=round(c["end"] / c["dt"]), length=float(ext[0]), height=float(ext[1]), elements=0,
               nx=0, ny=0, cells=kind, energy_exact=None, impact_time_shift=None, release_time_shift=None,
               linf_l2_error=None, linf_l2_error_relative=None, max_contact_error=None, l2_lambda_error=None)
    if d == 3:
        out.update(depth=float(ext[2]), nz=0)
    return out


def compare_series(c, mine, path):
    """The default series of a body (series.csv: energy, contact_force, active_nodes,
    min_distance, momentum_*, mean_u_*) at every t_n, each column against the scale of its
    summary key (`scales`): one line per column with its largest difference."""
    sc = scales(mine, None)
    scale_of = dict(energy=sc["energy_max"], contact_force=sc["max_contact_force"], active_nodes=None,
                    min_distance=sc["min_distance"])
    with open(path) as f:
        head = f.readline().strip().split(",")
        rows = np.array([[float(x) for x in line.split(",")] for line in f if line.strip()])
    worst, lines = 0.0, []
    for key, values in mine["series"].items():
        col = rows[:, head.index(key)]
        s = scale_of.get(key, sc["final_momentum"] if key.startswith("momentum") else sc["final_mean_displacement"])
        diff = np.abs(np.array(values, float) - col).max() / (s or 1.0) if len(col) == len(values) else math.inf
        worst = max(worst, diff)
        flag = "" if diff <= 1e-7 else "   <-- DISAGREES"
        lines.append(f"{c['name']:34s} series {key:25s} {len(col)} rows  scale {('exact' if s is None else f'{s:.3g}'):>9s}"
                     f"  {diff:.1e}{flag}")
    return worst, lines


def main(argv):
    binary = argv[1]
    keep = argv[argv.index("--keep") + 1] if "--keep" in argv else None
    names = [a for a in argv[2:] if not a.startswith("--") and a != keep]
    shared.check_rules()
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        root = keep or tmp
        os.makedirs(root, exist_ok=True)
        for c in cases():
            if names and c["name"] not in names:
                continue
            mine = heldout_body.summary(c)
            pts, cells, order = c["mesh"]
            msh = os.path.join(root, c["name"] + ".msh")
            hm.write_msh(msh, pts, cells, order, c["groups"])
            path = os.path.join(root, c["name"] + ".toml")
            with open(path, "w") as f:
                f.write(scene_text(c, os.path.basename(msh)))
            out = os.path.join(root, c["name"])
            r = subprocess.run([binary, "run", path, "--out", out], capture_output=True, text=True)
            if r.returncode != 0:
                print(f"{c['name']}: massredist failed ({r.returncode}): {r.stderr}")
                return 1
            ours = json.load(open(os.path.join(out, "summary.json")))
            w, lines, skipped = compare(c, mine, ours)
            ws, series_lines = compare_series(c, mine, os.path.join(out, "series.csv"))
            worst = max(worst, w, ws)
            print("\n".join(lines + series_lines))
            print(f"{c['name']:34s} not compared: {', '.join(skipped)}")
    print(f"largest scaled difference: {worst:.2e} (limit 1e-7)")
    return 0 if worst <= 1e-7 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
