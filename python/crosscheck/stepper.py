"""Independent numpy/scipy time steppers for the 1D contact benchmark (paper sections 3-5;
section numbers follow the LaTeX source: 3 discretization, 4 benchmark and Newmark, 5 hybrid).

Both take the weighted mass ``M`` and stiffness ``S`` on the m free dofs (vertices 0..m-1 of the
bar, the Dirichlet vertex m removed; dof 0 is the contact node) and solve

    M U'' + S U = F - λ e_0,   0 <= u_0 ⊥ λ <= 0.

They are written from the paper, not from the Rust code, so that they can check it.
"""
import numpy as np
import scipy.linalg as la
import scipy.sparse as sp


def _dense(matrix):
    return matrix.toarray() if sp.issparse(matrix) else np.array(matrix, dtype=np.float64)


def _is_massless(M):
    """w_0 = 0: row and column 0 of M vanish, the contact node carries no mass (section 3)."""
    return not M[0].any()


def crank_nicolson(M, S, F, u0, v0, dt, steps):
    """Newmark (β, γ) = (1/4, 1/2) with exact contact at dof 0 (section 4.2.1, eq. (4.3)).

        U^{n+1} = U^n + Δt V^n + Δt²/4 (A^n + A^{n+1})
        V^{n+1} = V^n + Δt/2 (A^n + A^{n+1})
        M A^{n+1} + S U^{n+1} = F - λ^{n+1} e_0,   0 <= u_0^{n+1} ⊥ λ^{n+1} <= 0.

    U^0 = u0, V^0 = v0, λ^0 = 0, and M A^0 = F - S U^0. When w_0 = 0 the contact node's
    acceleration is not a state variable: A_0 = 0 throughout and A^0 solves rows 1..m-1 only
    (column 0 of M vanishes, so A_0 never enters U). Returns ``(U (steps+1, m), λ (steps+1,))``.
    """
    M, S = _dense(M), _dense(S)
    F = np.asarray(F, dtype=np.float64)
    m = len(M)
    massless = _is_massless(M)

    U = np.array(u0, dtype=np.float64)
    V = np.array(v0, dtype=np.float64)
    A = np.zeros(m)
    r0 = F - S @ U
    if massless:
        A[1:] = la.solve(M[1:, 1:], r0[1:], assume_a="pos")
    else:
        A = la.solve(M, r0, assume_a="pos")

    # Eliminating A^{n+1} = 4/Δt² (U^{n+1} - P), P = U^n + Δt V^n + Δt²/4 A^n, gives
    # K U^{n+1} = F + 4/Δt² M P - λ e_0 with K = S + 4/Δt² M (SPD: S is, M is semi-definite).
    c = 4.0 / dt**2
    K = la.cho_factor(S + c * M)
    e0 = np.zeros(m)
    e0[0] = 1.0
    k0 = la.cho_solve(K, e0)  # response to a unit contact force, k0[0] > 0

    Us, lams = [U.copy()], [0.0]
    for _ in range(steps):
        P = U + dt * V + dt**2 / 4 * A
        U_new = la.cho_solve(K, F + c * (M @ P))
        lam = 0.0
        if U_new[0] < 0.0:
            # One contact dof: choose λ so that u_0 = 0 exactly; λ = u*_0 / k0_0 < 0.
            lam = U_new[0] / k0[0]
            U_new -= lam * k0
            U_new[0] = 0.0
        A_new = c * (U_new - P)
        if massless:
            A_new[0] = 0.0
        V = V + dt / 2 * (A + A_new)
        U, A = U_new, A_new
        Us.append(U.copy())
        lams.append(lam)
    return np.array(Us), np.array(lams)


def hybrid(M, S, F, u0, v0, dt, steps, h):
    """The hybrid scheme (P^hyb) of section 5 on the reduced dofs 1..m-1 (requires w_0 = 0).

        U^{n+1} = U^n + Δt/2 (V^{n+1} + V^n),   V^{n+1} = V^n + Δt/2 (A^{n+1} + A^n),
        M_r (A^{n+1}+A^n)/2 + S_r (U^{n+1}+U^n)/2 = F_r + g e_1,
        g = H(-u_1^n)/(2h) (u_1^n + u_1^{n+1})^+ + H(u_1^n)/(2h) ((u_1^n)^+ + (u_1^{n+1})^+),

    with M_r = M[1:,1:] = h M*, S_r = S[1:,1:] = S*/h (the paper's (P^hyb) writes M*, S*; the
    scaling of (P^mod_U) needs h M* and S*/h). The contact node follows u_0 = (u_1)^+ (eq. (3.3))
    and the contact row (u_0 - u_1)/h = -λ gives λ = min(u_1, 0)/h. Returns the full
    ``(U (steps+1, m), λ (steps+1,))``, the contact column being (u_1)^+ also at n = 0.
    """
    M, S = _dense(M), _dense(S)
    F = np.asarray(F, dtype=np.float64)
    if not _is_massless(M):
        raise ValueError("the hybrid scheme needs w_0 = 0 (row 0 of M must vanish)")
    Mr, Sr, Fr = M[1:, 1:], S[1:, 1:], F[1:]
    U = np.array(u0, dtype=np.float64)[1:]
    V = np.array(v0, dtype=np.float64)[1:]
    # Only the mean acceleration Ā = (A^{n+1}+A^n)/2 enters the scheme, so A^0 is never needed.
    # With Ā: V^{n+1} = V^n + Δt Ā, U^{n+1} = U^n + Δt V^n + Δt²/2 Ā, and
    # (M_r + Δt²/4 S_r) Ā = F_r - S_r (U^n + Δt/2 V^n) + g e_1.
    K = la.cho_factor(Mr + dt**2 / 4 * Sr)
    e1 = np.zeros(len(Mr))
    e1[0] = 1.0
    k1 = la.cho_solve(K, e1)
    q = dt**2 / 2 * k1[0]  # ∂u_1^{n+1}/∂g
    if not q < 2 * h:
        raise ValueError(f"hybrid step not uniquely solvable: q = {q} >= 2h = {2 * h}")

    Us = [U.copy()]
    for _ in range(steps):
        u = U[0]
        A0 = la.cho_solve(K, Fr - Sr @ (U + dt / 2 * V))
        p = U[0] + dt * V[0] + dt**2 / 2 * A0[0]  # u_1^{n+1} when g = 0
        # In every case of H, g(x) = c + (x - b)^+/(2h) with x = u_1^{n+1}, b = (-u)^+,
        # c = u^+/(2h) (u = u_1^n; u = 0 gives the H = 1/2 average of both formulas).
        # x = p + q g(x) is piecewise linear and increasing (q < 2h): try the left piece.
        b, c = max(-u, 0.0), max(u, 0.0) / (2 * h)
        x = p + q * c
        if x > b:
            x = (p + q * c - q * b / (2 * h)) / (1 - q / (2 * h))
        g = c + max(x - b, 0.0) / (2 * h)
        A_mean = A0 + g * k1
        V_new = V + dt * A_mean
        U = U + dt / 2 * (V_new + V)
        V = V_new
        Us.append(U.copy())

    Ur = np.array(Us)
    u1 = Ur[:, 0]
    return np.column_stack([np.maximum(u1, 0.0), Ur]), np.minimum(u1, 0.0) / h
