"""Independent scipy baseline of a Q1 plate run (issue 13): unit square, nx = ny = N cells, far
edge x = 1 clamped, contact edge x = 0 with u >= 0, u0 = (1 - x)/2, v0 = 0, weighted mass "mod3"
(cell column 0 weight 0, column 1 weight 2, others 1), Crank-Nicolson (Newmark 1/4, 1/2).
Set-up: vectorised assembly, one `splu`, the contact Schur complement D = E^T K^-1 E. Step: one
solve, the contact LCP by a primal-dual active set on D, one more solve if a node is active.

    /usr/bin/python3 python/scipy_baseline.py --n 200 --steps 200 [--dt 0.01]

Prints JSON: setup and per-step seconds (time.perf_counter) and u(0, 0) at the end."""
import argparse, json, time
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

p = argparse.ArgumentParser(); p.add_argument("--n", type=int, default=100)
p.add_argument("--steps", type=int, default=200); p.add_argument("--dt", type=float, default=0.01)
a = p.parse_args(); t0 = time.perf_counter(); N, dt = a.n, a.dt; h = 1.0 / N
# Q1 element matrices on an h x h square, local nodes (0,0), (1,0), (1,1), (0,1).
me = h * h / 36 * np.array([[4, 2, 1, 2], [2, 4, 2, 1], [1, 2, 4, 2], [2, 1, 2, 4]], float)
ke = np.array([[4, -1, -2, -1], [-1, 4, -1, -2], [-2, -1, 4, -1], [-1, -2, -1, 4]], float) / 6
i, j = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")  # cell (i, j): x index i
i, j = i.ravel(), j.ravel(); node = lambda x, y: y * (N + 1) + x
cells = np.stack([node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)], 1)
w = np.where(i == 0, 0.0, np.where(i == 1, 2.0, 1.0))
rows, cols = np.repeat(cells, 4, 1).ravel(), np.tile(cells, (1, 4)).ravel()
nn = (N + 1) ** 2; keep = np.flatnonzero(np.arange(nn) % (N + 1) < N)  # drop x = 1
M = sp.coo_matrix(((w[:, None] * me.ravel()).ravel(), (rows, cols)), (nn, nn)).tocsc()[keep][:, keep]
S = sp.coo_matrix((np.tile(ke.ravel(), N * N), (rows, cols)), (nn, nn)).tocsc()[keep][:, keep]
x = (keep % (N + 1)) * h; C = np.flatnonzero(x == 0.0); n = len(keep)
sig = 0.25 * dt * dt; lu = splu((M + sig * S).tocsc())
E = np.zeros((n, len(C))); E[C, np.arange(len(C))] = 1.0; D = lu.solve(E)[C]; del E
u = (1 - x) / 2; v = np.zeros(n); acc = np.zeros(n); pred = u + dt * v + 0.25 * dt * dt * acc
act = np.zeros(len(C), bool); t1 = time.perf_counter()
for _ in range(a.steps):
    old = u[C].copy(); us = lu.solve(M @ pred); q = us[C]; mu = np.zeros(len(C))
    for _it in range(10 * len(C) + 10):  # primal-dual active set (exact for this SPD D)
        mu[:] = 0.0
        if act.any(): mu[act] = np.linalg.solve(D[np.ix_(act, act)], -q[act])
        wv = q + D @ mu; new = (mu > 0) | (~act & (wv < 0)); new &= ~(act & (mu <= 0))
        if (new == act).all(): break
        act = new
    if act.any():
        r = np.zeros(n); r[C] = mu; us = us + lu.solve(r); us[C[act]] = 0.0
    an = (us - pred) / sig; v = v + dt * 0.5 * (acc + an); u, acc = us, an
    acc[C] = 0.0; v[C] = (u[C] - old) / dt; pred = u + dt * v + 0.25 * dt * dt * acc
t2 = time.perf_counter()
print(json.dumps({"n": N, "unknowns": n, "contact": len(C), "steps": a.steps, "setup_s": t1 - t0,
                  "step_s": (t2 - t1) / max(a.steps, 1), "u00": float(u[C[0]])}))
