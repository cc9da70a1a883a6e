"""An independent implementation of a body against a rigid plane (issue 19, docs/scenes.md "Bodies:
any shape against a rigid plane"): assembly on P1/P2/Q1 meshes (heldout_fem), contact nodes, gaps,
layers, load, Newmark(beta, gamma) (Crank-Nicolson: 1/4, 1/2), backward Euler and the paper's hybrid scheme,
and every summary key of a body run. Dense numpy; world coordinates (no rotated frame): one
contact row n^T per contact node, B U + g >= 0, reaction mu >= 0 along n, mu.(B U + g) = 0.

- M_(a,i),(b,j) = delta_ij rho sum_c w_c int_c phi_a phi_b; F_(a,i)(t) = sum_b (int phi_a phi_b) f_i(X_b, t)
  (the nodal interpolant of the force per unit volume: not times rho, not weighted).
- Massless unknowns (zero mass diagonal): CN gives them a = 0, v = (u^{n+1} - u^n)/dt.
- Each step's contact problem is the LCP d = q + W mu >= 0, mu >= 0, d.mu = 0 with W SPD,
  solved by Murty's least-index principal pivoting (finite for P-matrices) to round-off.
- Hybrid (paper section 5; docs/schemes.md): Q = the massless unknowns, Phi(U) = the quasi-static
  Signorini problem S_QQ u_Q = F_Q(t) - S_QI U_I + B_Q^T mu on Q; start from Phi(U^0); midpoint
  (M + dt^2/4 S) Xbar = M (U^n + dt/2 V^n) + dt^2/4 (F(t_{n+1/2}) + B^T mubar) with
  n.Xbar_i >= (n.u_i^n - g_i)/2; U^{n+1} = 2 Xbar - U^n, V^{n+1} = 2 (U^{n+1} - U^n)/dt - V^n;
  then U_Q^{n+1} = Phi(U^{n+1}) at t_{n+1}, V_Q^{n+1} = (U_Q^{n+1} - U_Q^n)/dt; the reported
  reaction is Phi's.
"""
import math

import numpy as np

import heldout_fem as fem
from shared import collapsed_gauss, grundmann_moller, layer_weights, lcp, tensor_gauss

EXPR = {"sin": math.sin, "cos": math.cos, "exp": math.exp, "sqrt": math.sqrt, "pi": math.pi}


def evaluate(text, point, t=0.0):
    names = dict(EXPR, x=point[0], y=point[1], z=point[2] if len(point) > 2 else 0.0, t=t)
    return float(eval(text, {"__builtins__": {}}, names))


def build(case):
    """The discrete body of a case: matrices on the free unknowns, contact rows, report data."""
    pts, cells, order = case["mesh"]
    d = pts.shape[1]
    nn = len(pts)
    rule = {"gm5": grundmann_moller, "gauss": collapsed_gauss, "tensor": tensor_gauss}[case["rule"]](d)
    n = np.array(case["normal"], float)
    n /= np.linalg.norm(n)
    gap_all = (pts - np.array(case["point"])) @ n
    assert (gap_all >= 0).all(), "no node starts inside the obstacle"
    clamped = np.array([case["groups"][case["clamped"]](p) for p in pts]) if case.get("clamped") else np.zeros(nn, bool)
    facets = fem.boundary_facets(cells, d, order)
    contact = np.zeros(nn, bool)
    if case["contact"] == "auto":
        for _, verts, nodes, opp in facets:
            nf, _ = fem.facet_normal(pts, verts, opp)
            if nf @ n < -0.01:
                contact[nodes] = True
    else:
        contact = np.array([case["groups"][case["contact"]](p) for p in pts])
    contact &= ~clamped
    areas = np.zeros(nn)
    for _, verts, nodes, opp in facets:
        if contact[nodes].all():
            _, meas = fem.facet_normal(pts, verts, opp)
            areas[nodes] += meas * np.array(fem.area_shares(len(nodes), d))
    elems = [fem.element(pts[c], order, case["lam"], case["mu"], rule) for c in cells]
    volumes = np.array([e[2] for e in elems])
    if case["mass"] == "custom":
        # GetFEM's "singular mass": no mass on the cells with a facet on the contact boundary.
        on = {k for k, _, nodes, _ in facets if contact[nodes].all()}
        w = np.array([0.0 if k in on else 1.0 for k in range(len(cells))])
        case["weights"] = w
    else:
        w, _ = layer_weights(cells, contact, volumes, case["mass"])
    N = d * nn
    M, S, M1 = np.zeros((N, N)), np.zeros((N, N)), np.zeros((nn, nn))
    for (m, s, _), c, wc in zip(elems, cells, w):
        dofs = (d * c[:, None] + np.arange(d)).ravel()
        S[np.ix_(dofs, dofs)] += s
        M1[np.ix_(c, c)] += m
        for i in range(d):
            M[np.ix_(d * c + i, d * c + i)] += case["rho"] * wc * m
    free = np.array([k for k in range(N) if not clamped[k // d]])
    cn = np.flatnonzero(contact)
    pos = {k: r for r, k in enumerate(free)}
    B = np.zeros((len(cn), len(free)))
    for r, a in enumerate(cn):
        for i in range(d):
            B[r, pos[d * a + i]] = n[i]

    def load(t):
        f = np.array([[evaluate(e, p, t) for e in case["force"]] for p in pts])
        return (M1 @ f).ravel()[free]

    def field(exprs):
        return np.array([[evaluate(e, p) for e in exprs] for p in pts]).ravel()[free]

    lumped = M.reshape(nn, d, nn, d)[:, 0, :, 0].sum(axis=0)
    return dict(d=d, M=M[np.ix_(free, free)], S=S[np.ix_(free, free)], B=B, g=gap_all[cn], a=areas[cn],
                load=load, U0=field(case["u0"]), V0=field(case["v0"]), comp=free % d,
                lumped=lumped[free // d], lumped1=M1.sum(axis=0)[free // d], volume=M1.sum(),
                total_mass=case["rho"] * (w * volumes).sum(), unknowns=len(free),
                h=max(np.linalg.norm(pts[c][:, None] - pts[c][None], axis=2).max() for c in cells))


def contact_solve(Kinv, B, rhs_free, sigma, bound):
    """X = K^-1 (rhs + sigma B^T mu) with B X + bound >= 0 complementary to mu >= 0."""
    X = Kinv @ rhs_free
    mu = lcp(B @ X + bound, sigma * B @ Kinv @ B.T)
    return X + sigma * Kinv @ (B.T @ mu), mu


def newmark_or_euler(sys, dt, steps, euler, beta=0.25, gamma=0.5):
    """States (U, V, mu) at t_0 .. t_N for Newmark(beta, gamma) (Crank-Nicolson: 1/4, 1/2) or
    backward Euler."""
    M, S, B, g = sys["M"], sys["S"], sys["B"], sys["g"]
    massless = np.diag(M) == 0
    massive = ~massless
    U, V = sys["U0"].copy(), sys["V0"].copy()
    A = np.zeros(len(U))
    r = sys["load"](0.0) - S @ U
    A[massive] = np.linalg.solve(M[np.ix_(massive, massive)], r[massive])
    sigma = dt * dt if euler else beta * dt * dt
    Kinv = np.linalg.inv(M + sigma * S)
    out = [(U, V, np.zeros(len(g)))]
    for k in range(1, steps + 1):
        pred = U + dt * V if euler else U + dt * V + (0.5 - beta) * dt * dt * A
        Unew, mu = contact_solve(Kinv, B, M @ pred + sigma * sys["load"](k * dt), sigma, g)
        if euler:
            Vnew, Anew = (Unew - U) / dt, A
        else:
            Anew = (Unew - pred) / sigma
            Vnew = V + dt * ((1 - gamma) * A + gamma * Anew)
            Vnew[massless] = (Unew[massless] - U[massless]) / dt
            Anew[massless] = 0.0
        U, V, A = Unew, Vnew, Anew
        out.append((U, V, mu))
    return out


def hybrid(sys, dt, steps):
    """States (U, V, mu) at t_0 .. t_N of the hybrid scheme (module docs)."""
    M, S, B, g = sys["M"], sys["S"], sys["B"], sys["g"]
    Q = np.diag(M) == 0
    I = ~Q
    assert (np.abs(B[:, I]) == 0).all(), "the hybrid scheme needs massless contact nodes"
    SQQinv = np.linalg.inv(S[np.ix_(Q, Q)])
    BQ = B[:, Q]
    W = BQ @ SQQinv @ BQ.T

    def phi(U, t):
        U = U.copy()
        free = SQQinv @ (sys["load"](t)[Q] - S[np.ix_(Q, I)] @ U[I])
        mu = lcp(BQ @ free + g, W)
        U[Q] = free + SQQinv @ (BQ.T @ mu)
        return U, mu

    sigma = dt * dt / 4
    Kinv = np.linalg.inv(M + sigma * S)
    U, mu = phi(sys["U0"], 0.0)
    V = sys["V0"].copy()
    out = [(U, V, mu)]
    for k in range(1, steps + 1):
        rhs = M @ (U + 0.5 * dt * V) + sigma * sys["load"]((k - 0.5) * dt)
        Xbar, _ = contact_solve(Kinv, B, rhs, sigma, 0.5 * (g - B @ U))
        Unew = 2 * Xbar - U
        Vnew = 2 * (Unew - U) / dt - V
        Unew, mu = phi(Unew, k * dt)
        Vnew[Q] = (Unew[Q] - U[Q]) / dt
        U, V = Unew, Vnew
        out.append((U, V, mu))
    return out


def summary(case):
    """Every numeric summary key of a body run (docs/scenes.md's definitions, "Bodies"), from this module."""
    sys = build(case)
    dt, steps = case["dt"], round(case["end"] / case["dt"])
    scheme = case["scheme"]
    if scheme == "hybrid":
        states = hybrid(sys, dt, steps)
    else:
        states = newmark_or_euler(sys, dt, steps, scheme == "backward-euler", case.get("beta") or 0.25,
                                  case.get("gamma") or 0.5)
    M, S, B, g, a, d = sys["M"], sys["S"], sys["B"], sys["g"], sys["a"], sys["d"]
    rep = dict(total_mass=sys["total_mass"], unknowns=sys["unknowns"], h=sys["h"], steps=steps,
               max_y_variation=0.0, max_contact_force=-np.inf, min_distance=np.inf, min_u0=np.inf,
               max_lambda=-np.inf, max_complementarity_product=0.0, first_impact_time=None, first_release_time=None,
               # CN, Newmark, BE and hybrid are implicit: no stable limit (docs/scenes.md, summary.json)
               stable_step=None, stable_step_method=None,
               # frictionless contact: the friction keys of every solid read 0 and empty
               friction_dissipation=0.0, tangential_impulse=[0.0] * d, final_stick_nodes=0,
               final_slip_nodes=0, max_cone_excess=0.0)
    energies = []
    series = {k: [] for k in ("contact_force", "active_nodes", "min_distance")}
    axes = "xyz"[:d]
    for k, (U, V, mu) in enumerate(states):
        t = k * dt
        un = B @ U
        dist = un + g
        touching = mu > 0.0  # contact read off the force, R_i > 0 (docs/scenes.md, "Bodies")
        energies.append(0.5 * V @ M @ V + 0.5 * U @ S @ U - sys["load"](t) @ U)
        series["contact_force"].append(mu.sum())
        series["active_nodes"].append(int(touching.sum()))
        series["min_distance"].append(dist.min())
        for i, x in enumerate(axes):
            series.setdefault(f"momentum_{x}", []).append((sys["lumped"] * V)[sys["comp"] == i].sum())
            series.setdefault(f"mean_u_{x}", []).append((sys["lumped1"] * U)[sys["comp"] == i].sum() / sys["volume"])
        rep["max_contact_force"] = max(rep["max_contact_force"], mu.sum())
        rep["min_distance"] = min(rep["min_distance"], dist.min())
        rep["min_u0"] = min(rep["min_u0"], un.min())
        rep["max_lambda"] = max(rep["max_lambda"], (-mu).max())
        rep["max_complementarity_product"] = max(rep["max_complementarity_product"], np.abs(dist * mu).max())
        if rep["first_impact_time"] is None:
            if touching.any():
                rep["first_impact_time"] = t
        elif rep["first_release_time"] is None and not touching.any():
            rep["first_release_time"] = t
    rep.update(final_u0=un.mean(), final_u_mean=a @ un / a.sum(), final_contact_force=mu.sum(),
               final_active_nodes=int(touching.sum()),
               final_momentum=[float((sys["lumped"] * V)[sys["comp"] == i].sum()) for i in range(d)],
               final_mean_displacement=[float((sys["lumped1"] * U)[sys["comp"] == i].sum() / sys["volume"]) for i in range(d)])
    E = np.array(energies)
    dE = np.diff(E)
    rep.update(energy_initial=E[0], energy_final=E[-1], energy_min=E.min(), energy_max=E.max(),
               energy_max_increase=dE.max(), energy_max_increase_step=int(np.argmax(dE)) + 1,
               energy_max_increase_after_first=dE[1:].max(), energy_increments=dE, series=dict(series, energy=E))
    return rep
