"""An independent implementation of small P1 body scenes (Crank-Nicolson and backward Euler) (issue 19) in numpy, against the
`massredist` binary's summary keys.

Nothing of massredist is used but its command line: the mesh, the P1 plane-strain assembly, the
layers and weights, the load, Newmark/Crank-Nicolson with exact contact and the reports are
written here from the definitions (docs/scenes.md, "Bodies: any shape against a rigid plane"):

- the structured (0, L) x (0, H) mesh split along the diagonal (x_i, y_j)-(x_i+1, y_j+1);
- contact in WORLD coordinates, not in a rotated frame: B U >= -g with one row n^T per contact
  node, the reaction mu >= 0 along n, the step's LCP  d = q + W mu >= 0, mu >= 0, d.mu = 0
  (W = sigma B K^-1 B^T) solved by `shared.lcp`;
- Newmark(1/4, 1/2) on the massive unknowns, the massless ones quasi-static with
  v = (u^{n+1} - u^n)/dt, a = 0 (the scheme's definition for massless rows); backward Euler
  U^{n+1} = U^n + dt V^{n+1}, V^{n+1} = V^n + dt A^{n+1} (every unknown);
- energy 1/2 V.M V + 1/2 U.S U - F.U, momentum 1^T M V (weighted), mean displacement
  1^T M_std U / |Omega|, min_distance, final_active_nodes and the first impact read off the force
  (mu_i > 0, docs/scenes.md "Bodies"), max_contact_force = max sum mu.

Usage: /usr/bin/python3 python/independent/body_p1.py MASSREDIST_BINARY
Exits 1 if a summary key differs by more than 1e-7 (relative to max(1, |value|)).
"""
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import shared  # noqa: E402

CASES = [
    # A free block dropped on y = 0 under gravity, contact "auto", mod3.
    dict(name="drop-mod3", L=1.0, H=0.5, nx=4, ny=2, lam=1.0, mu=1.0, rho=1.0, force=(0.0, -2.0),
         vel=(0.0, -1.0), normal=(0.0, 1.0), point=(0.0, -0.05), contact="auto", clamped=None,
         mass="mod3", dt=0.01, end=0.6),
    # A block clamped on ymax, contact "ymin" against a tilted plane, mod1, no force.
    dict(name="clamped-tilted-mod1", L=1.0, H=1.0, nx=3, ny=3, lam=2.0, mu=1.0, rho=1.5, force=(0.0, 0.0),
         vel=(0.0, -0.5), normal=(0.1, 1.0), point=(0.0, -0.02), contact="ymin", clamped="ymax",
         mass="mod1", dt=0.01, end=0.5),
    # Backward Euler on the first two.
    dict(name="drop-mod3-be", L=1.0, H=0.5, nx=4, ny=2, lam=1.0, mu=1.0, rho=1.0, force=(0.0, -2.0),
         vel=(0.0, -1.0), normal=(0.0, 1.0), point=(0.0, -0.05), contact="auto", clamped=None,
         mass="mod3", dt=0.01, end=0.6, scheme="backward-euler"),
    dict(name="clamped-tilted-mod1-be", L=1.0, H=1.0, nx=3, ny=3, lam=2.0, mu=1.0, rho=1.5, force=(0.0, 0.0),
         vel=(0.0, -0.5), normal=(0.1, 1.0), point=(0.0, -0.02), contact="ymin", clamped="ymax",
         mass="mod1", dt=0.01, end=0.5, scheme="backward-euler"),
    # The same with the standard mass and gravity.
    dict(name="clamped-tilted-standard", L=1.0, H=1.0, nx=3, ny=3, lam=2.0, mu=1.0, rho=1.5, force=(0.3, -1.0),
         vel=(0.0, -0.5), normal=(0.1, 1.0), point=(0.0, -0.02), contact="ymin", clamped="ymax",
         mass="standard", dt=0.01, end=0.5),
]


def mesh(c):
    nx, ny = c["nx"], c["ny"]
    pts = np.array([[c["L"] * i / nx, c["H"] * j / ny] for j in range(ny + 1) for i in range(nx + 1)])
    pts[:, 0][np.isclose(pts[:, 0], c["L"])] = c["L"]
    node = lambda i, j: j * (nx + 1) + i
    tris = []
    for j in range(ny):
        for i in range(nx):
            tris += [(node(i, j), node(i + 1, j), node(i + 1, j + 1)), (node(i, j), node(i + 1, j + 1), node(i, j + 1))]
    return pts, np.array(tris)


def element(p, lam, mu):
    """P1 mass (without rho) and plane-strain stiffness of one triangle, dofs (a, i) -> 2a + i."""
    (x1, y1), (x2, y2), (x3, y3) = p
    det = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1)
    area = abs(det) / 2
    b = np.array([y2 - y3, y3 - y1, y1 - y2]) / det
    g = np.array([x3 - x2, x1 - x3, x2 - x1]) / det
    B = np.zeros((3, 6))
    B[0, 0::2], B[1, 1::2], B[2, 0::2], B[2, 1::2] = b, g, g, b
    D = np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])
    m = area / 12 * (np.ones((3, 3)) + np.eye(3))
    return m, area * B.T @ D @ B, area


def outward_normals(pts, tris):
    """Boundary edges (a, b) with their outward unit normals."""
    count = {}
    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            count.setdefault(tuple(sorted((a, b))), []).append(t)
    out = []
    for (a, b), ts in count.items():
        if len(ts) == 1:
            t = pts[b] - pts[a]
            n = np.array([t[1], -t[0]]) / np.hypot(*t)
            if n @ (pts[a] - pts[ts[0]].mean(axis=0)) < 0:
                n = -n
            out.append(((a, b), n))
    return out


def simulate(c):
    pts, tris = mesh(c)
    nn = len(pts)
    n = np.array(c["normal"]) / np.hypot(*c["normal"])
    gap_all = (pts - np.array(c["point"])) @ n
    assert (gap_all >= 0).all()
    face = {"xmin": pts[:, 0] == 0, "xmax": pts[:, 0] == c["L"], "ymin": pts[:, 1] == 0, "ymax": pts[:, 1] == c["H"]}
    clamped = face[c["clamped"]] if c["clamped"] else np.zeros(nn, bool)
    if c["contact"] == "auto":
        contact = np.zeros(nn, bool)
        for (a, b), nf in outward_normals(pts, tris):
            if nf @ n < -0.01:
                contact[[a, b]] = True
    else:
        contact = face[c["contact"]].copy()
    contact &= ~clamped
    areas = np.array([element(pts[t], 0, 1)[2] for t in tris])
    w, _ = shared.layer_weights(tris, contact, areas, c["mass"])
    N = 2 * nn
    M, S, M1 = np.zeros((N, N)), np.zeros((N, N)), np.zeros((N, N))
    for k, t in enumerate(tris):
        m, s, _ = element(pts[t], c["lam"], c["mu"])
        dofs = np.array([[2 * a, 2 * a + 1] for a in t]).ravel()
        S[np.ix_(dofs, dofs)] += s
        for i in range(2):
            M[np.ix_(dofs[i::2], dofs[i::2])] += c["rho"] * w[k] * m
            M1[np.ix_(dofs[i::2], dofs[i::2])] += m
    F = M1 @ np.tile(np.array(c["force"]), nn)
    free = np.array([d for d in range(N) if not clamped[d // 2]])
    Mf, Sf, Ff = M[np.ix_(free, free)], S[np.ix_(free, free)], F[free]
    cnodes = np.flatnonzero(contact)
    B = np.zeros((len(cnodes), len(free)))
    pos = {d: k for k, d in enumerate(free)}
    for r, a in enumerate(cnodes):
        B[r, pos[2 * a]], B[r, pos[2 * a + 1]] = n
    g = gap_all[cnodes]
    massless = np.diag(Mf) == 0
    massive = ~massless
    dt, beta, gamma = c["dt"], 0.25, 0.5
    euler = c.get("scheme") == "backward-euler"
    steps = round(c["end"] / dt)
    U = np.zeros(len(free))
    V = np.tile(np.array(c["vel"]), nn)[free]
    A = np.zeros(len(free))
    A[massive] = np.linalg.solve(Mf[np.ix_(massive, massive)], (Ff - Sf @ U)[massive])
    sigma = dt * dt if euler else beta * dt * dt
    K = Mf + sigma * Sf
    Kinv = np.linalg.inv(K)
    W = sigma * B @ Kinv @ B.T
    lump = M.sum(axis=0)[free]
    lump1 = M1.sum(axis=0)[free]
    volume = M1.sum() / 2
    rep = dict(max_contact_force=-np.inf, min_distance=np.inf)

    def report(U, V, mu):
        d = B @ U + g
        rep["energy_final"] = 0.5 * V @ Mf @ V + 0.5 * U @ Sf @ U - Ff @ U
        rep["max_contact_force"] = max(rep["max_contact_force"], mu.sum())
        rep["min_distance"] = min(rep["min_distance"], d.min())
        rep["final_active_nodes"] = int((mu > 0.0).sum())
        comp = free % 2
        rep["final_momentum"] = [float((lump * V)[comp == i].sum()) for i in range(2)]
        rep["final_mean_displacement"] = [float((lump1 * U)[comp == i].sum() / volume) for i in range(2)]
        rep.setdefault("energy_initial", rep["energy_final"])
        if "first_impact_time" not in rep and (mu > 0.0).any():
            rep["first_impact_time"] = report.t

    report.t = 0.0
    report(U, V, np.zeros(len(g)))
    for step in range(1, steps + 1):
        report.t = step * dt
        pred = U + dt * V + (0.5 - beta) * dt * dt * A
        pred[massless] = U[massless] + dt * V[massless]
        if euler:
            pred = U + dt * V
        rhs = Mf @ pred + sigma * Ff
        Ufree = Kinv @ rhs
        q = B @ Ufree + g
        mu = shared.lcp(q, W)
        Unew = Ufree + sigma * Kinv @ (B.T @ mu)
        Anew = (Unew - pred) / sigma
        Vnew = V + dt * ((1 - gamma) * A + gamma * Anew)
        Vnew[massless] = (Unew[massless] - U[massless]) / dt
        Anew[massless] = 0.0
        if euler:
            Vnew = (Unew - U) / dt
        U, V, A = Unew, Vnew, Anew
        report(U, V, mu)
    return rep


def scene_text(c):
    fmt = lambda v: ", ".join(repr(float(x)) for x in v)
    lines = [
        "[solid]", "dim = 2", f"length = {c['L']!r}", f"height = {c['H']!r}", f"nx = {c['nx']}", f"ny = {c['ny']}",
        'cells = "triangle"', f"lame_lambda = {c['lam']!r}", f"lame_mu = {c['mu']!r}", f"density = {c['rho']!r}",
        f"force = [{fmt(c['force'])}]",
        f"initial = {{ displacement = [0, 0], velocity = [{fmt(c['vel'])}] }}",
    ]
    lines += shared.body_tail(c, c.get("scheme", "crank-nicolson"))
    return "\n".join(lines) + "\n"


def main(binary):
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for c in CASES:
            path = os.path.join(tmp, c["name"] + ".toml")
            with open(path, "w") as f:
                f.write(scene_text(c))
            out = os.path.join(tmp, c["name"])
            subprocess.run([binary, "run", path, "--out", out], check=True, capture_output=True)
            ours = json.load(open(os.path.join(out, "summary.json")))
            mine = simulate(c)
            for key, value in mine.items():
                a, b = np.atleast_1d(np.array(value, float)), np.atleast_1d(np.array(ours[key], float))
                diff = float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(a))))
                worst = max(worst, diff)
                flag = "" if diff <= 1e-7 else "   <-- DISAGREES"
                print(f"{c['name']:26s} {key:24s} numpy {value!s:>42s} massredist {ours[key]!s:>42s} {diff:.1e}{flag}")
    print(f"largest relative difference: {worst:.2e} (limit 1e-7)")
    return 0 if worst <= 1e-7 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
