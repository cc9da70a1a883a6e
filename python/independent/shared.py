"""What the independent references of this folder share among themselves, written once: the
quadrature rules, the layer weights of the paper's masses, the contact LCP, and the TOML tail of
a body scene. Written from the definitions only: nothing of massredist is imported or read
(numpy only), so that these references stay independent of the Rust code they check.

Quadrature:
- `GAUSS3`: 3-point Gauss-Legendre on [0, 1] (exact to degree 5: the 1D load integrals);
- `collapsed_gauss` (`gauss`): a collapsed (Duffy) tensor Gauss-Legendre rule with 6 points per
  direction, exact for polynomials of degree <= 9 on the simplex: on straight-sided cells it
  integrates the P2 mass (degree 4) and stiffness (degree 2) exactly, so it checks the other
  side's claim of exactness with a rule that has nothing in common with it;
- `grundmann_moller` (`gm5`): the Grundmann-Moller rule of degree 5 (A. Grundmann, H. M. Moller,
  SIAM J. Numer. Anal. 15 (1978), Theorem 4), computed here from its closed formula. On curved
  P2 cells the integrands are not polynomials (det J and J^-1 vary), the integrals depend on the
  rule, and the issue/README fix the rule as degree-5 Grundmann-Moller: the held-out curved
  scenes use it;
- `tensor_gauss` (`tensor`): Gauss-Legendre with 4 points per direction on [0, 1]^n for Q1
  cells, exact on parallelograms and parallelepipeds (the only Q1 cells the held-out scenes have).

Weights (paper section 3): `bar_weights` per element of a bar (element 0 at the contact node),
`layer_weights` per cell of a mesh (layer 0: cells with a contact node; layer 1: the cells that
share a node with layer 0).

The LCP of a step with exact contact, d = q + W mu >= 0, mu >= 0, d.mu = 0 with W SPD: `lcp`,
Murty's least-index principal pivoting (finite for P-matrices), to round-off.
"""
import itertools
import math

import numpy as np

GAUSS3 = [(0.5 - 0.3872983346207417, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.5 + 0.3872983346207417, 5.0 / 18.0)]


def compositions(total, parts):
    """All beta in N^parts with |beta| = total."""
    if parts == 1:
        return [(total,)]
    return [(first,) + rest for first in range(total, -1, -1) for rest in compositions(total - first, parts - 1)]


def grundmann_moller(n, s=2):
    """Points xi (m x n) and weights of the degree 2s+1 Grundmann-Moller rule (module docs):
    sum_i (-1)^i 2^-2s (d+n-2i)^d / (i! (d+n-i)!) sum_{|beta|=s-i} f((2 beta + 1)/(d+n-2i))."""
    d = 2 * s + 1
    pts, wts = [], []
    for i in range(s + 1):
        denom = d + n - 2 * i
        w = (-1) ** i * 2.0 ** (-2 * s) * denom ** d / (math.factorial(i) * math.factorial(d + n - i))
        for beta in compositions(s - i, n + 1):
            lam = [(2 * b + 1) / denom for b in beta]
            pts.append(lam[1:])
            wts.append(w)
    return np.array(pts), np.array(wts)


def collapsed_gauss(n, m=6):
    """Duffy-collapsed Gauss-Legendre on the reference simplex (module docs)."""
    x, w = np.polynomial.legendre.leggauss(m)
    x, w = (x + 1) / 2, w / 2
    pts, wts = [], []
    for idx in itertools.product(range(m), repeat=n):
        u = [x[k] for k in idx]
        wu = np.prod([w[k] for k in idx])
        if n == 2:
            pts.append((u[0], (1 - u[0]) * u[1]))
            wts.append(wu * (1 - u[0]))
        else:
            pts.append((u[0], (1 - u[0]) * u[1], (1 - u[0]) * (1 - u[1]) * u[2]))
            wts.append(wu * (1 - u[0]) ** 2 * (1 - u[1]))
    return np.array(pts), np.array(wts)


def check_rules():
    """Both rules integrate every monomial of degree <= 5 exactly (the Dirichlet integral
    a! b! c! / (a + b + c + n)!) and sum to 1/n!: a self-check run before every comparison."""
    for n in (2, 3):
        for rule in (grundmann_moller(n), collapsed_gauss(n)):
            p, w = rule
            for e in itertools.product(range(6), repeat=n):
                if sum(e) > 5:
                    continue
                exact = np.prod([math.factorial(k) for k in e]) / math.factorial(sum(e) + n)
                got = w @ np.prod(p ** np.array(e), axis=1)
                assert abs(got - exact) < 1e-15, (n, e, got, exact)


def tensor_gauss(n, m=4):
    """Gauss-Legendre, m points per direction on [0, 1]^n: exact on parallelogram and
    parallelepiped Q1 cells for the mass (degree 2 per variable) and the stiffness."""
    x, w = np.polynomial.legendre.leggauss(m)
    x, w = (x + 1) / 2, w / 2
    grid = np.array(np.meshgrid(*[x] * n, indexing="ij")).reshape(n, -1).T
    wts = np.prod(np.array(np.meshgrid(*[w] * n, indexing="ij")).reshape(n, -1), axis=0)
    return grid, wts


def bar_weights(kind, m):
    """Element weights of a named mass (paper section 3)."""
    w = np.ones(m)
    if kind == "standard":
        return w
    w[0] = 0.0
    if kind == "mod2":
        w[1:] = m / (m - 1.0)
    elif kind == "mod3":
        w[1] = 2.0
    elif kind != "mod1":
        raise ValueError(f"mass {kind}")
    return w


def layer_weights(cells, contact, volumes, kind):
    """Layer 0: cells holding a contact node; layer 1: other cells sharing a node with layer 0;
    weights standard 1 | mod1 (0, 1, 1) | mod2 (0, W, W), W = |Omega|/(|Omega| - A0) |
    mod3 (0, 1 + A0/A1, 1)."""
    layer = np.full(len(cells), 2)
    layer[[contact[c].any() for c in cells]] = 0
    near = np.zeros(len(contact), bool)
    for c in cells[layer == 0]:
        near[c] = True
    for k, c in enumerate(cells):
        if layer[k] != 0 and near[c].any():
            layer[k] = 1
    a0, a1, tot = volumes[layer == 0].sum(), volumes[layer == 1].sum(), volumes.sum()
    table = {"standard": [1, 1, 1], "mod1": [0, 1, 1], "mod2": [0, tot / (tot - a0), tot / (tot - a0)],
             "mod3": [0, 1 + a0 / a1, 1]}[kind]
    return np.array(table, float)[layer], layer


def lcp(q, W):
    """Murty's least-index method for d = q + W mu >= 0 <= mu, d.mu = 0 (W SPD)."""
    m = len(q)
    act = np.zeros(m, bool)
    tol_d = 1e-13 * max(1e-300, np.abs(q).max(initial=0.0))
    for _ in range(100 * m + 100):
        mu = np.zeros(m)
        if act.any():
            mu[act] = np.linalg.solve(W[np.ix_(act, act)], -q[act])
        d = q + W @ mu
        tol_mu = 1e-13 * max(1e-300, np.abs(mu).max(initial=0.0))
        bad = np.flatnonzero((act & (mu < -tol_mu)) | (~act & (d < -tol_d)))
        if len(bad) == 0:
            return np.where(act, mu, 0.0)
        act[bad[0]] = ~act[bad[0]]
    raise RuntimeError("Murty's method did not finish")


def body_tail(c, scheme):
    """Lines from solid.clamped to the end, for a case dict with normal, point, contact,
    clamped, mass, dt, end."""
    fmt = lambda v: ", ".join(repr(float(x)) for x in v)
    lines = [f'clamped = "{c["clamped"]}"'] if c["clamped"] else []
    lines += ["[obstacle]", f"normal = [{fmt(c['normal'])}]", f"point = [{fmt(c['point'])}]", f'contact = "{c["contact"]}"',
              "[mass]", f'kind = "{c["mass"]}"'] + ([f"weights = [{fmt(c['weights'])}]"] if c.get("weights") is not None else []) + [
              "[scheme]", f'kind = "{scheme}"'] + [f"{k} = {c[k]!r}" for k in ("beta", "gamma") if c.get(k) is not None] + [
              "[time]", f"dt = {c['dt']!r}",
              f"end = {c['end']!r}"]
    return lines
