"""An independent numpy implementation of the 1D method classes of issue 20, against the
`massredist` binary: central differences with the lumped weighted mass (massless contact node
quasi-static, exact or penalty contact; the forward-increment multiplier on a massive contact
node), Newmark/Crank-Nicolson with penalty contact, and Moreau-Jean (theta, restitution).

Nothing of massredist is used but its scene files (read here with tomllib) and, in the Rust
test (tests/methods_heldout.rs), its command line. Written from the definitions (issue 20 "What to
build", docs/schemes.md "Method classes beside the paper's schemes"), dense numpy, our own P1 assembly:

- bar (0, L), m elements, nodes x_i = L i/m; element j between nodes j and j+1 has weight w_j,
  mass rho h w_j/6 [[2, 1], [1, 2]], stiffness E/h [[1, -1], [-1, 1]]; a clamped far end drops
  node m; the load F_i = int f w_h phi_i (3-point Gauss per element; constant f exactly);
- masses: standard w = 1; mod1 w_0 = 0; mod2 w_0 = 0, w_j = m/(m-1); mod3 w_0 = 0, w_1 = 2;
- lumped mass: row sums over all nodes before the Dirichlet node is removed,
  rho h/2 (w_{i-1} + w_i);
- the obstacle: u_0 >= -gap; lambda <= 0 the contact force (R = -lambda >= 0); penalty
  lambda = kappa min(0, u_0 + gap).

Central differences (velocity Verlet): A^n_I = M_L^-1 (F - K U^n - lambda e_0)_I on the unknowns
with mass; U^{n+1}_I = U^n_I + dt V^n_I + dt^2/2 A^n_I; a massless contact node from its
quasi-static row K_00 u_0 + K_01 u_1 = F_0 - lambda (exact: u_0 = max(-gap, (F_0 - K_01 u_1)/K_00);
penalty: the spring solved exactly), at t_0 too (the data's u_0 replaced); its velocity
(u^{n+1} - u^n)/dt. A massive contact node: exact contact by the forward-increment multiplier
(Carpenter-Taylor-Katona 1991): u~ = u^n + dt v^{n-1/2} + k dt^2 a (a without contact; at n = 0
u~ = u^0 + dt v^0 + dt^2/2 a, k = 1/2), lambda = min(0, (u~ + gap) m_0/(k dt^2)); penalty:
lambda = kappa min(0, u_0^n + gap). Energy 1/2 V.M_L V + 1/2 U.K U - F.U + 1/2 kappa (d^-)^2.

Newmark (beta = 1/4, gamma = 1/2) with penalty: (M + beta dt^2 K) U^{n+1} = M U~ + beta dt^2
(F - lambda^{n+1} e_0), U~ = U^n + dt V^n + (1/2 - beta) dt^2 A^n, lambda^{n+1} = kappa
min(0, u_0^{n+1} + gap): piecewise linear in u_0, solved exactly (one node: one or two linear
solves). A^0 from the massive rows of M A = F - K U - lambda^0 e_0; a massless node has a = 0 and
v = (u^{n+1} - u^n)/dt. Energy 1/2 V.M V + 1/2 U.K U - F.U + spring.

Moreau-Jean: M (V^{n+1} - V^n) = dt (F - K U^{n+theta}) + P e_0, U^{n+1} = U^n + dt ((1-theta) V^n +
theta V^{n+1}); active when u_0^n + dt/2 v_0^n + gap <= 0, then 0 <= v_0^{n+1} + e v_0^n _|_ P >= 0
(one node: closed form); lambda = -P/dt. Energy 1/2 V.M V + 1/2 U.K U - F.U (consistent M).

Summary keys as the binary defines them: first impact = first t_n with lambda < 0, first
release = first later t_n with lambda = 0 (contact read off the force); min_u0, max_lambda, final_u0, final_contact_force,
energy_initial/final/min/max.

Usage: /usr/bin/python3 python/independent/methods_1d.py SCENE.toml [SCENE.toml ...]
prints one JSON object per scene: {"scene", "summary": {...}, "series": {"t", "u0", "u1", "lambda",
"energy"}}. Pure functions below; I/O only in main().
"""
import json
import math
import os
import sys
import tomllib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shared import GAUSS3, bar_weights  # noqa: E402



def expression(text, length):
    """A scene expression in x (and L, pi, the usual functions) as a Python function."""
    names = {"L": length, "pi": math.pi, "sin": math.sin, "cos": math.cos, "tan": math.tan, "exp": math.exp,
             "log": math.log, "sqrt": math.sqrt, "abs": abs, "min": min, "max": max}
    code = compile(str(text).replace("^", "**"), "<scene>", "eval")
    return lambda x: float(eval(code, {"__builtins__": {}}, dict(names, x=x)))


def assemble(length, m, rho, modulus, w, far_end, force):
    """(M, K, F, lumped) on the unknowns (nodes 0..m-1 clamped, 0..m free); force a number or f(x)."""
    h = length / m
    n_all = m + 1
    M = np.zeros((n_all, n_all))
    K = np.zeros((n_all, n_all))
    F = np.zeros(n_all)
    for j in range(m):
        idx = [j, j + 1]
        M[np.ix_(idx, idx)] += rho * h * w[j] / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
        K[np.ix_(idx, idx)] += modulus / h * np.array([[1.0, -1.0], [-1.0, 1.0]])
        if callable(force):
            xa = length * j / m
            a = sum(gw * h * force(xa + g * h) * (1.0 - g) for g, gw in GAUSS3)
            b = sum(gw * h * force(xa + g * h) * g for g, gw in GAUSS3)
        else:
            a = b = force * h / 2.0
        F[j] += w[j] * a
        F[j + 1] += w[j] * b
    lumped = M.sum(axis=1)
    n = m if far_end == "clamped" else m + 1
    return M[:n, :n], K[:n, :n], F[:n], lumped[:n]


def central_difference(M, K, F, lumped, lb, kappa, dt, steps, u, v):
    """Velocity Verlet on the lumped mass (module docstring); yields (u, v, lambda, energy) at n = 0..steps."""
    n = len(u)
    mass = lumped > 0.0
    inv = np.where(mass, 1.0 / np.where(mass, lumped, 1.0), 0.0)
    u, v = u.copy(), v.copy()
    lam = 0.0

    def quasi_static():
        # K_00 u_0 + K_01 u_1 = F_0 - lambda (row 0: the only coupling is to node 1).
        free = (F[0] - K[0, 1] * u[1]) / K[0, 0]
        if kappa is None:
            u[0] = max(lb, free)
        else:
            u[0] = free if free >= lb else (F[0] - K[0, 1] * u[1] + kappa * lb) / (K[0, 0] + kappa)
        return F[0] - K[0, 0] * u[0] - K[0, 1] * u[1]

    def accelerations(k):
        a = inv * (F - K @ u)
        lam_c = None
        if mass[0]:
            if kappa is not None:
                lam_c = kappa * min(0.0, u[0] - lb)
            else:
                predicted = u[0] + dt * v[0] + k * dt * dt * a[0]
                lam_c = min(0.0, (predicted - lb) * lumped[0] / (k * dt * dt))
            a[0] -= lam_c * inv[0]
        return a, lam_c

    def energy():
        spring = 0.0 if kappa is None else 0.5 * kappa * min(0.0, u[0] - lb) ** 2
        return 0.5 * np.dot(lumped * v, v) + 0.5 * u @ K @ u - F @ u + spring

    if not mass[0]:
        lam = quasi_static()
    a, lam_c = accelerations(0.5)
    if lam_c is not None:
        lam = lam_c
    yield u.copy(), v.copy(), lam, energy()
    for _ in range(steps):
        old = u[0]
        v += 0.5 * dt * a
        u += dt * v * mass
        if not mass[0]:
            lam = quasi_static()
        a, lam_c = accelerations(1.0)
        if lam_c is not None:
            lam = lam_c
        v += 0.5 * dt * a
        if not mass[0]:
            v[0] = (u[0] - old) / dt
        yield u.copy(), v.copy(), lam, energy()
    del n


def newmark_penalty(M, K, F, lb, kappa, dt, steps, u, v, beta=0.25, gamma=0.5):
    """Newmark with the penalty spring at t_{n+1}, solved exactly (module docstring)."""
    u, v = u.copy(), v.copy()
    massive = np.diag(M) > 0.0
    lam = kappa * min(0.0, u[0] - lb)
    a = np.zeros_like(u)
    r = F - K @ u
    r[0] -= lam
    a[massive] = np.linalg.solve(M[np.ix_(massive, massive)], r[massive])
    sigma = beta * dt * dt
    W = M + sigma * K
    Winv = np.linalg.inv(W)

    def energy():
        return 0.5 * v @ M @ v + 0.5 * u @ K @ u - F @ u + 0.5 * kappa * min(0.0, u[0] - lb) ** 2

    yield u.copy(), v.copy(), lam, energy()
    for _ in range(steps):
        pred = u + dt * v + (0.5 - beta) * dt * dt * a
        rhs = M @ pred + sigma * F
        trial = Winv @ rhs
        lam = 0.0
        if trial[0] < lb:
            # u_0 = trial_0 + Z mu, mu = sigma kappa (lb - u_0), Z = (W^-1)_00.
            z = Winv[0, 0]
            u0 = (trial[0] + z * sigma * kappa * lb) / (1.0 + z * sigma * kappa)
            mu = sigma * kappa * (lb - u0)
            trial = trial + mu * Winv[:, 0]
            lam = -mu / sigma
        old = u.copy()
        a_new = (trial - pred) / sigma
        v = v + dt * ((1.0 - gamma) * a + gamma * a_new)
        a = a_new
        u = trial
        a[~massive] = 0.0
        v[~massive] = (u[~massive] - old[~massive]) / dt
        yield u.copy(), v.copy(), lam, energy()


def moreau_jean(M, K, F, lb, theta, e, dt, steps, u, v):
    """Moreau-Jean's theta-scheme with Newton's impact law on node 0 (module docstring)."""
    u, v = u.copy(), v.copy()
    Winv = np.linalg.inv(M + theta * theta * dt * dt * K)

    def energy():
        return 0.5 * v @ M @ v + 0.5 * u @ K @ u - F @ u

    yield u.copy(), v.copy(), 0.0, energy()
    for _ in range(steps):
        rhs = M @ v + dt * (F - K @ (u + theta * (1.0 - theta) * dt * v))
        V = Winv @ rhs
        lam = 0.0
        if u[0] + 0.5 * dt * v[0] - lb <= 0.0 and V[0] < -e * v[0]:
            P = (-e * v[0] - V[0]) / Winv[0, 0]
            V = V + P * Winv[:, 0]
            lam = -P / dt
        u = u + dt * ((1.0 - theta) * v + theta * V)
        v = V
        yield u.copy(), v.copy(), lam, energy()


def run_scene(scene):
    """The series and summary keys of one scene (a parsed TOML table)."""
    bar, time = scene["bar"], scene["time"]
    length, m = float(bar.get("length", 1.0)), int(bar["elements"])
    rho, modulus = float(bar.get("density", 1.0)), float(bar.get("modulus", 1.0))
    far_end, gap = bar.get("far_end", "clamped"), float(bar.get("gap", 0.0))
    force = bar.get("force", 0.0)
    force = expression(force, length) if isinstance(force, str) else float(force)
    w = bar_weights(scene["mass"]["kind"], m)
    M, K, F, lumped = assemble(length, m, rho, modulus, w, far_end, force)
    n = len(F)
    xs = np.array([length * i / m for i in range(n)])
    if bar.get("initial", "paper") == "paper":
        u, v = (length - xs) / 2.0, np.zeros(n)
    else:
        du, dv = expression(bar["initial"]["displacement"], length), expression(bar["initial"]["velocity"], length)
        u, v = np.array([du(x) for x in xs]), np.array([dv(x) for x in xs])
    dt = float(time["dt"])
    steps = int(round(float(time["end"]) / dt))
    lb = -gap
    contact = scene.get("contact", {"method": "exact"})
    kappa = float(contact["penalty"]) if contact.get("method") == "penalty" else None
    kind = scene["scheme"]["kind"]
    if kind == "central-difference":
        states = central_difference(M, K, F, lumped, lb, kappa, dt, steps, u, v)
    elif kind in ("crank-nicolson", "newmark") and kappa is not None:
        s = scene["scheme"]
        states = newmark_penalty(M, K, F, lb, kappa, dt, steps, u, v, float(s.get("beta", 0.25)),
                                 float(s.get("gamma", 0.5)))
    elif kind == "moreau-jean":
        s = scene["scheme"]
        states = moreau_jean(M, K, F, lb, float(s.get("theta", 0.5)), float(s.get("restitution", 0.0)), dt,
                             steps, u, v)
    else:
        raise ValueError(f"scheme {kind} with contact {contact}")
    series = {"t": [], "u0": [], "u1": [], "lambda": [], "energy": []}
    impact = release = None
    for k, (uk, _, lam, en) in enumerate(states):
        t = k * dt
        for key, val in (("t", t), ("u0", uk[0]), ("u1", uk[1]), ("lambda", lam), ("energy", en)):
            series[key].append(float(val))
        if impact is None and lam < 0.0:
            impact = t
        elif impact is not None and release is None and not lam < 0.0:
            release = t
    e = series["energy"]
    summary = {"final_u0": series["u0"][-1], "min_u0": min(series["u0"]), "max_lambda": max(series["lambda"]),
               "final_contact_force": series["lambda"][-1], "energy_initial": e[0], "energy_final": e[-1],
               "energy_min": min(e), "energy_max": max(e), "first_impact_time": impact,
               "first_release_time": release, "steps": steps}
    return {"summary": summary, "series": series}


def main(paths):
    for path in paths:
        with open(path, "rb") as f:
            scene = tomllib.load(f)
        out = run_scene(scene)
        out["scene"] = path
        print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv[1:])
