"""The paper's impacting bar (src/exact.rs, ImpactingBar) extended in y, and the exact L² error
of a P1/Q1 field against it. Pure numpy.

The L² error is computed differently from the Rust crate (which clips cells at the kinks):
per cell, ``∫∫ e² = ∫ g(x) dx`` with ``g(x) = ∫ e(x, y)² dy`` over the cell's vertical chord.
On a triangle or rectangle, e = u_h − u with u_h affine (triangle) or bilinear (rectangle) and u
affine in x between its kinks, the chord ends are affine in x between the vertices' x, and
``g = |chord| (e_lo² + e_lo e_hi + e_hi²)/3`` is a polynomial of degree ≤ 3 in x on every
interval between breakpoints (vertex x's and kinks): Simpson's rule on each is exact, so the
only error is round-off.
"""
import math

import numpy as np


class ImpactingBar:
    def __init__(self, length):
        self.length = length

    def _phase(self, t):
        """Reduced time τ = (t/L) mod 3 (flight τ ≤ 1, contact 1 < τ ≤ 2, release)."""
        return np.mod(t / self.length, 3.0)

    def u(self, x, t):
        """u(x, t) (vectorised in x)."""
        y = np.asarray(x, dtype=float) / self.length
        tau = self._phase(t)
        if tau <= 1.0:
            v = (1.0 - np.maximum(y, tau)) / 2.0
        elif tau <= 2.0:
            s = tau - 1.0
            v = -np.minimum(np.minimum(y, 1.0 - y), min(s, 1.0 - s)) / 2.0
        else:
            v = np.minimum(tau - 2.0, 1.0 - y) / 2.0
        return self.length * v

    def u0(self, t):
        return float(self.u(0.0, t))

    def lambda_(self, t):
        """The contact force λ(t) = u_x(0+, t): −1/2 while in contact (τ ∈ (1, 2)), else 0."""
        tau = self._phase(t)
        return -0.5 if 1.0 < tau < 2.0 else 0.0

    def kinks(self, t):
        """x where u(·, t) may have a kink (a superset: extra breakpoints are harmless)."""
        tau = self._phase(t)
        s = tau - 1.0 if 1.0 < tau <= 2.0 else None
        cand = [tau] if tau <= 1.0 else ([s, 1.0 - s, 0.5] if s is not None else [3.0 - tau])
        return self.length * np.asarray([c for c in cand if 0.0 < c < 1.0])

    def energy(self):
        return self.length / 8.0

    def first_contact(self):
        """The exact first contact phase (t_impact, t_release) = (L, 2L)."""
        return (self.length, 2.0 * self.length)


class ScaledBar:
    """The paper's bar with density ρ and modulus E (wave speed c = sqrt(E/ρ)):
    ``u(x, t) = U(x, c t)`` with U the unit-speed solution (ρ u_tt = E u_xx is the unit
    equation in τ = c t; the data (v = 0) and the contact conditions are invariant), the contact
    pressure ``E u_x(0, t) = E Λ(c t)`` and the energy ``E L/8`` (as src/exact.rs by
    characteristics for these data)."""

    def __init__(self, length, density, modulus):
        self.bar, self.length = ImpactingBar(length), length
        self.c, self.modulus = math.sqrt(modulus / density), modulus

    def u(self, x, t):
        return self.bar.u(x, self.c * t)

    def u0(self, t):
        return self.bar.u0(self.c * t)

    def lambda_(self, t):
        return self.modulus * self.bar.lambda_(self.c * t)

    def kinks(self, t):
        return self.bar.kinks(self.c * t)

    def energy(self):
        return self.modulus * self.length / 8.0

    def first_contact(self):
        return (self.length / self.c, 2.0 * self.length / self.c)


def plane_wave(scene):
    """The exact solution the Rust run compares with, where the engine has it: the paper's
    closed form (plates: paper data on the default body; solids: the paper's data as a plane
    wave, λ = 0 or roller faces, no gap, no force, any λ + 2μ and ρ); None otherwise."""
    if not scene.solid:
        return ImpactingBar(scene.length) if scene.has_paper_exact else None
    plane = (scene.initial == "paper" and scene.gap == 0.0 and not any(scene.force)
             and (scene.lame_lambda == 0.0 or scene.lateral == "roller"))
    if not plane:
        return None
    e = scene.lame_lambda + 2.0 * scene.lame_mu
    if e == 1.0 and scene.density == 1.0:
        return ImpactingBar(scene.length)
    return ScaledBar(scene.length, scene.density, e)


def l2_error_squared(cell_points, cell_values, kind, exact, t):
    """``Σ_cells ∫ (u_h − u(·, t))²`` over the given cells (module docs).

    ``cell_points``: (k, nv, 2) vertex coordinates; ``cell_values``: (k, nv) u_h at them;
    ``kind``: "triangle" or "quad" (rectangles with axis-parallel sides)."""
    px, py = cell_points[..., 0], cell_points[..., 1]
    if kind == "triangle":
        # u_h = c0 + cx x + cy y on each triangle.
        ones = np.ones_like(px)
        A = np.stack([ones, px, py], axis=-1)
        coef = np.linalg.solve(A, cell_values[..., None])[..., 0]
        uh = lambda x, y: coef[:, 0] + coef[:, 1] * x + coef[:, 2] * y
    else:
        x0, x1, y0, y1 = px.min(1), px.max(1), py.min(1), py.max(1)
        # corner values by position: (x0,y0), (x1,y0), (x0,y1), (x1,y1)
        right, top = np.isclose(px, x1[:, None]), np.isclose(py, y1[:, None])
        corner = np.zeros((len(px), 4))
        for k in range(cell_values.shape[1]):
            corner[np.arange(len(px)), right[:, k] + 2 * top[:, k]] = cell_values[:, k]
        def uh(x, y):
            s, r = (x - x0) / (x1 - x0), (y - y0) / (y1 - y0)
            return ((1 - s) * (1 - r) * corner[:, 0] + s * (1 - r) * corner[:, 1]
                    + (1 - s) * r * corner[:, 2] + s * r * corner[:, 3])
    nv = px.shape[1]
    edges = [(a, (a + 1) % nv) for a in range(nv)]

    def chord(x):
        lo, hi = np.full(len(x), np.inf), np.full(len(x), -np.inf)
        for a, b in edges:
            xa, xb, ya, yb = px[:, a], px[:, b], py[:, a], py[:, b]
            vertical = xa == xb
            inside = (np.minimum(xa, xb) <= x) & (x <= np.maximum(xa, xb)) & ~vertical
            with np.errstate(divide="ignore", invalid="ignore"):
                y = np.where(inside, ya + (yb - ya) * (x - xa) / np.where(vertical, 1.0, xb - xa), np.nan)
            on = vertical & (xa == x)
            lo = np.fmin(lo, np.where(inside, y, np.where(on, np.minimum(ya, yb), np.inf)))
            hi = np.fmax(hi, np.where(inside, y, np.where(on, np.maximum(ya, yb), -np.inf)))
        return lo, np.maximum(hi, lo)

    def g(x):
        lo, hi = chord(x)
        ue = exact.u(x, t)
        e_lo, e_hi = uh(x, lo) - ue, uh(x, hi) - ue
        return (hi - lo) * (e_lo * e_lo + e_lo * e_hi + e_hi * e_hi) / 3.0

    kinks = exact.kinks(t)
    xmin, xmax = px.min(1), px.max(1)
    brk = np.concatenate([px, np.broadcast_to(kinks, (len(px), len(kinks)))], axis=1)
    brk = np.sort(np.clip(brk, xmin[:, None], xmax[:, None]), axis=1)
    total = 0.0
    for k in range(brk.shape[1] - 1):
        a, b = brk[:, k], brk[:, k + 1]
        if not (b > a).any():
            continue
        # Simpson's rule (zero-width intervals add 0); u is continuous, so its value at a kink
        # is that of both pieces.
        total += float(np.sum((b - a) / 6.0 * (g(a) + 4.0 * g(0.5 * (a + b)) + g(b))))
    return max(total, 0.0)


def l2_error_squared_box(cell_points, cell_values, exact, t):
    """``Σ_cells ∫ (u_h − u(x, t))²`` over axis-parallel boxes with trilinear u_h (a solid's u_x
    on hexahedra), as src/solid/geometry.rs: on a line (y, z) fixed u_h is linear in x, so
    ``∫ (u_h − u)² dx`` (u piecewise linear between its kinks) is exact by Simpson's rule on
    the pieces, and it is a polynomial of degree ≤ 2 in y and in z: the 2 × 2-point Gauss rule
    across the cell integrates it exactly.

    ``cell_points``: (k, 8, 3) vertex coordinates; ``cell_values``: (k, 8) u_h at them."""
    p = cell_points
    lo, hi = p.min(axis=1), p.max(axis=1)
    # corner values by position: index = (x high) + 2 (y high) + 4 (z high)
    slot = sum((np.isclose(p[..., a], hi[:, a, None]) << a) for a in range(3))
    corner = np.zeros((len(p), 8))
    rows = np.arange(len(p))
    for k in range(8):
        corner[rows, slot[:, k]] = cell_values[:, k]
    g = (0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0))
    x0, x1 = lo[:, 0], hi[:, 0]
    kinks = exact.kinks(t)
    brk = np.sort(np.clip(np.concatenate([np.column_stack([x0, x1]),
                                          np.broadcast_to(kinks, (len(p), len(kinks)))], axis=1),
                          x0[:, None], x1[:, None]), axis=1)
    total = 0.0
    for r in g:
        for s in g:
            w = [(1 - r) * (1 - s), r * (1 - s), (1 - r) * s, r * s]     # (y, z) corners 00 10 01 11
            left = sum(w[m] * corner[:, 2 * m] for m in range(4))
            right = sum(w[m] * corner[:, 2 * m + 1] for m in range(4))
            e = lambda x: left + (right - left) * (x - x0) / (x1 - x0) - exact.u(x, t)
            line = 0.0
            for k in range(brk.shape[1] - 1):
                a, b = brk[:, k], brk[:, k + 1]
                line = line + (b - a) / 6.0 * (e(a) ** 2 + 4.0 * e(0.5 * (a + b)) ** 2 + e(b) ** 2)
            total += float(np.sum(0.25 * (hi[:, 1] - lo[:, 1]) * (hi[:, 2] - lo[:, 2]) * line))
    return max(total, 0.0)
