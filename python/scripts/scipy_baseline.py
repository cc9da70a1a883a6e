"""Independent scipy baseline of a plate or solid run (issue 13), the reference of the ratios
`massredist bench` reports.

Problem: the unit square or cube, N cells per axis (Q1: quads, hexahedra), far face x = 1
clamped, contact face x = 0 with u_x >= 0, u0 = ((1 - x)/2, 0[, 0]), v0 = 0, weighted mass
"mod3" (cell layer 0 weight 0, layer 1 weight 2, others 1), Crank-Nicolson (Newmark 1/4, 1/2).
- plate: the scalar wave equation (rho = E = 1);
- solid (dim 2, plane strain, or 3): linear elasticity with lambda = 0, mu = 1/2, rho = 1,
  traction-free lateral faces; the contact unknowns are the x-components on x = 0.
Set-up: vectorised assembly (element matrices by 2^d-point Gauss quadrature), one `splu` of
K = M + dt^2/4 S, the contact Schur complement D = E^T K^-1 E (one blocked solve). Step: one
solve, the contact LCP by a primal-dual active set on D, one more solve if a node is active.

    /usr/bin/python3 python/scripts/scipy_baseline.py --kind plate --dim 2 --n 200 --steps 200 [--dt 0.01]

Prints JSON: the set-up phases and the median step time over the free steps (t < 1) and the
steps in contact (t > 1 + dt), all by time.perf_counter, and u_x at the first contact node at the end.
"""
import argparse, itertools, json, time
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

p = argparse.ArgumentParser()
p.add_argument("--kind", choices=["plate", "solid"], default="plate")
p.add_argument("--dim", type=int, choices=[2, 3], default=2)
p.add_argument("--n", type=int, default=100)
p.add_argument("--steps", type=int, default=200)
p.add_argument("--dt", type=float, default=0.01)
a = p.parse_args()
t0 = time.perf_counter()
d, N, dt, h = a.dim, a.n, a.dt, 1.0 / a.n
comps = 1 if a.kind == "plate" else d
# Local corners (bits of the local index: x, y[, z]); 2-point Gauss rule per axis on [0, h].
corners = np.array(list(itertools.product([0, 1], repeat=d)))[:, ::-1]
g = (np.array([-1.0, 1.0]) / np.sqrt(3.0) + 1.0) / 2.0
qp = np.array(list(itertools.product(g, repeat=d)))
wq = h ** d / 2 ** d
phi = np.prod(np.where(corners[None], qp[:, None], 1 - qp[:, None]), 2)  # (q, a)
grad = np.empty((len(qp), len(corners), d))
for k in range(d):
    f = np.where(corners[None], qp[:, None], 1 - qp[:, None])
    f[:, :, k] = np.where(corners[None, :, k], 1.0, -1.0) / h
    grad[:, :, k] = np.prod(f, 2)
me1 = wq * phi.T @ phi
if a.kind == "plate":
    me, ke = me1, wq * np.einsum("qak,qbk->ab", grad, grad)
else:
    lam, mu, nv = 0.0, 0.5, len(corners)
    me = np.kron(me1, np.eye(d))
    ke = np.zeros((nv * d, nv * d))
    for i in range(d):
        for j in range(d):
            blk = lam * np.einsum("qa,qb->ab", grad[:, :, i], grad[:, :, j]) + mu * np.einsum(
                "qa,qb->ab", grad[:, :, j], grad[:, :, i])
            if i == j:
                blk += mu * np.einsum("qak,qbk->ab", grad, grad)
            ke[i::d, j::d] += wq * blk
# Cells (i fastest), nodes node(i, j[, k]) = (k (N+1) + j)(N+1) + i, dofs node * comps + c.
cell = np.array(list(itertools.product(range(N), repeat=d)))[:, ::-1]  # columns: i, j[, k]
stride = (N + 1) ** np.arange(d)
nodes = (cell[:, None, :] + corners[None]) @ stride
dofs = (nodes[:, :, None] * comps + np.arange(comps)).reshape(len(cell), -1)
w = np.where(cell[:, 0] == 0, 0.0, np.where(cell[:, 0] == 1, 2.0, 1.0))
rows, cols = np.repeat(dofs, dofs.shape[1], 1).ravel(), np.tile(dofs, (1, dofs.shape[1])).ravel()
nn = (N + 1) ** d * comps
node_x = (np.arange(nn) // comps) % (N + 1)
keep = np.flatnonzero(node_x < N)  # drop every component on x = 1
M = sp.coo_matrix(((w[:, None] * me.ravel()).ravel(), (rows, cols)), (nn, nn)).tocsc()[keep][:, keep]
S = sp.coo_matrix((np.tile(ke.ravel(), len(cell)), (rows, cols)), (nn, nn)).tocsc()[keep][:, keep]
x = node_x[keep] * h
comp = keep % comps
C = np.flatnonzero((x == 0.0) & (comp == 0))
n, nc = len(keep), len(C)
t1 = time.perf_counter()
sig = 0.25 * dt * dt
lu = splu((M + sig * S).tocsc())
t2 = time.perf_counter()
E = np.zeros((n, nc))
E[C, np.arange(nc)] = 1.0
D = lu.solve(E)[C]
del E
t3 = time.perf_counter()
u = np.where(comp == 0, (1 - x) / 2, 0.0)
v, acc = np.zeros(n), np.zeros(n)
massless = np.asarray(M.diagonal() == 0.0)
pred = u + dt * v + 0.25 * dt * dt * acc
act = np.zeros(nc, bool)
times = []
for _ in range(a.steps):
    ts = time.perf_counter()
    old = u[massless].copy()
    us = lu.solve(M @ pred)
    q = us[C]
    mu_ = np.zeros(nc)
    for _it in range(10 * nc + 10):  # primal-dual active set (exact for this SPD D)
        mu_[:] = 0.0
        if act.any():
            mu_[act] = np.linalg.solve(D[np.ix_(act, act)], -q[act])
        wv = q + D @ mu_
        new = (mu_ > 0) | (~act & (wv < 0))
        new &= ~(act & (mu_ <= 0))
        if (new == act).all():
            break
        act = new
    if act.any():
        r = np.zeros(n)
        r[C] = mu_
        us = us + lu.solve(r)
        us[C[act]] = 0.0
    an = (us - pred) / sig
    v = v + dt * 0.5 * (acc + an)
    u, acc = us, an
    acc[massless] = 0.0
    v[massless] = (u[massless] - old) / dt
    pred = u + dt * v + 0.25 * dt * dt * acc
    times.append(time.perf_counter() - ts)
t4 = time.perf_counter()
tk = dt * np.arange(1, a.steps + 1)
free, contact = np.array(times)[tk < 1.0 - dt / 2], np.array(times)[tk > 1.0 + 1.5 * dt]
mean = lambda s: float(np.sort(s)[len(s) // 2]) if len(s) else float("nan")  # the median
print(json.dumps({
    "kind": a.kind, "dim": d, "n": N, "unknowns": int(n), "contact": int(nc), "steps": a.steps, "dt": dt,
    "assemble_s": t1 - t0, "factor_s": t2 - t1, "schur_s": t3 - t2, "setup_s": t3 - t0,
    "step_s": (t4 - t3) / max(a.steps, 1), "free_step_s": mean(free), "contact_step_s": mean(contact),
    "u00": float(u[C[0]]), "unorm": float(np.linalg.norm(u))}))
