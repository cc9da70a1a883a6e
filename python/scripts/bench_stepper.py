"""Times the independent numpy/scipy steppers on the 1D benchmark, for `massredist bench`.

    /usr/bin/python3 python/scripts/bench_stepper.py --elements 1000 --steps 3000 [--repeats 3]

Prints one JSON object on stdout: the interpreter and library versions and, per stepper, the
seconds per step of its time loop and the final displacement (so the caller can check that it
timed the same problem). Two kinds of stepper are timed:

- ``stepper.hybrid`` / ``stepper.crank_nicolson`` (python/crosscheck/stepper.py, the bridge's reference
  steppers, dense Cholesky);
- ``pttrs.hybrid`` / ``pttrs.crank_nicolson`` below: the same formulas with LAPACK's
  tridiagonal dpttrf/dpttrs, the fastest plain numpy/scipy form of a 1D implicit step.

The pttrs steppers time their own loop (time.perf_counter around it); for python/crosscheck/stepper.py,
whose loop cannot be timed from outside, the loop time is t(steps) − t(0) (the set-up, its
dense factorisation included, is subtracted). The fastest of ``--repeats`` calls is kept. Matrices are built in closed form (paper §3):
M_00 = h/3 w_0, M_ii = h/3 (w_{i-1} + w_i), M_{i,i+1} = h/6 w_i; S_00 = 1/h, S_ii = 2/h,
S_{i,i+1} = -1/h on the free vertices 0..m-1 of the bar (0, 1); u0 = (1 - x)/2, v0 = 0, f = 0.
"""
import argparse
import json
import os
import sys
import time

import numpy as np
import scipy
from scipy.linalg import lapack

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "crosscheck"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "independent"))
from shared import bar_weights  # noqa: E402  (the paper's element weights, written once)


def tridiagonals(kind, m):
    """(diag, off) of M and S on the free vertices, and h."""
    h = 1.0 / m
    w = bar_weights(kind, m)
    md = np.zeros(m)
    md += h / 3 * w  # element j -> vertex j
    md[1:] += h / 3 * w[:-1]  # element j -> vertex j+1 (vertex m is Dirichlet)
    mo = h / 6 * w[:-1]
    sd = np.full(m, 2.0 / h)
    sd[0] = 1.0 / h
    so = np.full(m - 1, -1.0 / h)
    return (md, mo), (sd, so), h


def dense(d, o):
    return np.diag(d) + np.diag(o, 1) + np.diag(o, -1)


def tri_mul(d, o, x):
    y = d * x
    y[:-1] += o * x[1:]
    y[1:] += o * x[:-1]
    return y


def pttrs_hybrid(M, S, u0, v0, dt, steps, h):
    """(P^hyb) of paper §5 on dofs 1..m-1 with f = 0, in the mean-acceleration form of
    stepper.hybrid: (M_r + Δt²/4 S_r) Ā = -S_r (Uⁿ + Δt/2 Vⁿ) + g e_1, Vⁿ⁺¹ = Vⁿ + Δt Ā,
    Uⁿ⁺¹ = Uⁿ + Δt/2 (Vⁿ + Vⁿ⁺¹), g the piecewise-linear contact term of u_1ⁿ⁺¹.
    Returns the final displacement on all m free dofs (u_0 = (u_1)⁺)."""
    (md, mo), (sd, so) = M, S
    md, mo, sd, so = md[1:], mo[1:], sd[1:], so[1:]
    kd, ke, info = lapack.dpttrf(md + dt**2 / 4 * sd, mo + dt**2 / 4 * so)
    assert info == 0
    e1 = np.zeros(len(md))
    e1[0] = 1.0
    k1, info = lapack.dpttrs(kd, ke, e1)
    q = dt**2 / 2 * k1[0]
    U = np.array(u0[1:], dtype=float)
    V = np.array(v0[1:], dtype=float)
    t0 = time.perf_counter()
    for _ in range(steps):
        u = U[0]
        A0, info = lapack.dpttrs(kd, ke, -tri_mul(sd, so, U + dt / 2 * V))
        p = u + dt * V[0] + dt**2 / 2 * A0[0]
        b, c = max(-u, 0.0), max(u, 0.0) / (2 * h)
        x = p + q * c
        if x > b:
            x = (p + q * c - q * b / (2 * h)) / (1 - q / (2 * h))
        g = c + max(x - b, 0.0) / (2 * h)
        V_new = V + dt * (A0 + g * k1)
        U = U + dt / 2 * (V_new + V)
        V = V_new
    seconds = time.perf_counter() - t0
    return np.concatenate([[max(U[0], 0.0)], U]), seconds


def pttrs_crank_nicolson(M, S, u0, v0, dt, steps):
    """Newmark (1/4, 1/2) with exact contact at dof 0 and f = 0 (paper §4.2.1):
    (S + 4/Δt² M) Uⁿ⁺¹ = 4/Δt² M P - λ e_0, P = Uⁿ + Δt Vⁿ + Δt²/4 Aⁿ (standard mass only)."""
    (md, mo), (sd, so) = M, S
    c = 4.0 / dt**2
    kd, ke, info = lapack.dpttrf(sd + c * md, so + c * mo)
    assert info == 0
    e0 = np.zeros(len(md))
    e0[0] = 1.0
    k0, info = lapack.dpttrs(kd, ke, e0)
    U = np.array(u0, dtype=float)
    V = np.array(v0, dtype=float)
    md_f, mo_f, info = lapack.dpttrf(md, mo)
    A, info = lapack.dpttrs(md_f, mo_f, -tri_mul(sd, so, U))
    t0 = time.perf_counter()
    for _ in range(steps):
        P = U + dt * V + dt**2 / 4 * A
        U_new, info = lapack.dpttrs(kd, ke, c * tri_mul(md, mo, P))
        if U_new[0] < 0.0:
            U_new -= U_new[0] / k0[0] * k0
            U_new[0] = 0.0
        A_new = c * (U_new - P)
        V = V + dt / 2 * (A + A_new)
        U, A = U_new, A_new
    return U, time.perf_counter() - t0


def loop_seconds(call, steps, repeats):
    """Fastest t(steps) − t(0) over `repeats` calls, and the last result."""
    best, result = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        call(0)
        t1 = time.perf_counter()
        result = call(steps)
        t2 = time.perf_counter()
        best = min(best, (t2 - t1) - (t1 - t0))
    return best, result


def self_timed(call, steps, repeats):
    """Fastest loop time reported by a stepper that times its own loop, and the last result."""
    best, result = float("inf"), None
    for _ in range(repeats):
        result, secs = call(steps)
        best = min(best, secs)
    return best, result


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--dense-steps", type=int, default=300, help="steps for the dense stepper.py runs")
    ap.add_argument("--skip-dense", action="store_true", help="time only the dpttrs steppers")
    a = ap.parse_args()
    m, steps = a.elements, a.steps
    out = {
        "python": sys.executable,
        "python_version": sys.version.split()[0],
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "elements": m,
        "runs": [],
        "missing": [],
    }
    try:
        import stepper
    except ImportError as e:  # the bridge's stepper is optional here
        stepper = None
        out["missing"].append(f"python/crosscheck/stepper.py: {e}")
    for kind, name in (("mod3", "hybrid"), ("standard", "crank-nicolson")):
        M, S, h = tridiagonals(kind, m)
        dt = h
        x = np.arange(m) * h
        u0, v0, F = (1.0 - x) / 2, np.zeros(m), np.zeros(m)
        calls = []
        if name == "hybrid":
            calls.append(("pttrs", lambda n: pttrs_hybrid(M, S, u0, v0, dt, n, h)))
            if stepper is not None and not a.skip_dense:
                Md, Sd = dense(*M), dense(*S)
                calls.append(("stepper", lambda n: stepper.hybrid(Md, Sd, F, u0, v0, dt, n, h)[0][-1]))
        else:
            calls.append(("pttrs", lambda n: pttrs_crank_nicolson(M, S, u0, v0, dt, n)))
            if stepper is not None and not a.skip_dense:
                Md, Sd = dense(*M), dense(*S)
                calls.append(("stepper", lambda n: stepper.crank_nicolson(Md, Sd, F, u0, v0, dt, n)[0][-1]))
        for impl, call in calls:
            if impl == "pttrs":
                n = steps
                secs, u = self_timed(call, n, a.repeats)
            else:
                n = min(steps, a.dense_steps)
                secs, u = loop_seconds(call, n, a.repeats)
            out["runs"].append(
                {
                    "implementation": impl,
                    "scheme": name,
                    "mass": kind,
                    "steps": n,
                    "seconds_per_step": secs / n,
                    "u_final": [float(v) for v in u],
                }
            )
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
