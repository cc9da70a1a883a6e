"""The time schemes of src/schemes/, step for step, on the distributed problem.

Each implicit step is ``(M + σ S) X = M Ũ + σ F − σ Σ λ_c e_c`` with contact, one
:class:`~engine.qp.BoundQP` (σ = β Δt² for Newmark / Crank–Nicolson, Δt² for backward Euler,
Δt²/4 for the hybrid scheme's mid-step). Massless unknowns (zero mass diagonal: the contact
nodes with mod1/2/3, every component of a solid's) are treated as in Rust: Newmark keeps ``a = 0`` and reports
``v = (u^{n+1} − uⁿ)/Δt`` there, A⁰ solves ``M A⁰ = F − S U⁰`` on the unknowns with mass only;
backward Euler needs nothing special; the hybrid scheme replaces the contact values by the
quasi-static map Φ (a second bound-constrained QP with ``S_QQ`` over the massless unknowns, bounds
on the contact ones only), src/schemes/hybrid.rs. All four map onto bound-constrained QPs.
"""
import numpy as np
from dolfinx import fem
from dolfinx.fem import petsc as fpetsc
from petsc4py import PETSc

from .qp import BoundQP, direct_solve


class Step:
    """What a scheme shares: state vectors u, v (PETSc, owned dofs), λ on the owned contact
    dofs, the iteration matrix and its QP, and the per-step contact diagnostics."""

    def __init__(self, problem, sigma, name):
        self.p, self.n, self.dt, self.sigma = problem, 0, problem.scene.dt, sigma
        self.K = fpetsc.assemble_matrix(problem.form_k(sigma), problem.bcs, 1.0)
        self.K.assemble()
        self.qp = BoundQP(self.K, problem.comm, prefix=name + "_")
        self.u, self.v = problem.u0.copy(), problem.v0.copy()
        self.rhs, self.x = self.K.createVecLeft(), self.K.createVecLeft()
        nc = len(problem.contact)
        # A body: −g_i per contact dof (engine.body); else the scene's one gap.
        self.lb = problem.lb.copy() if hasattr(problem, "lb") else np.full(nc, 0.0 - problem.scene.gap)
        self.lam = np.zeros(nc)
        self.iterations = 0
        # Per step: (min_c u_c − lb_c, max λ_c, max |(u_c − lb_c) λ_c|, largest multiplier on an
        # inactive dof), the engine's complementarity record.
        self.check = (np.inf, -np.inf, 0.0, 0.0)

    def contact_solve(self, pred, lower_values, sigma, lam):
        """rhs = M pred + σ F, then the QP with bounds ``lower_values``; U in ``self.x``."""
        p = self.p
        p.M.mult(pred, self.rhs)
        self.rhs.axpy(sigma, p.F)
        self.u.copy(self.x)
        xa = self.x.getArray()
        xa[p.contact] = np.maximum(xa[p.contact], lower_values)
        its, res = self.qp.solve(self.rhs, p.lower(lower_values), self.x)
        self._multipliers(self.x.getArray()[p.contact], lower_values, res.getArray()[p.contact], sigma, lam)
        return its

    def _multipliers(self, uc, lb, mu, sigma, lam):
        active = uc <= lb
        lam[:] = np.where(active, -mu / sigma, 0.0)
        inactive_mu = np.abs(mu[~active]).max(initial=0.0) / sigma
        gap = uc - lb
        self.check = (min(self.check[0], gap.min(initial=np.inf)), max(self.check[1], lam.max(initial=-np.inf)),
                      max(self.check[2], np.abs(gap * lam).max(initial=0.0)), max(self.check[3], inactive_mu))

    def step(self):
        self.check = (np.inf, -np.inf, 0.0, 0.0)
        self.iterations = self._advance()
        self.n += 1


class Newmark(Step):
    """Newmark(β, γ); Crank–Nicolson is (1/4, 1/2) (src/schemes/newmark.rs)."""

    def __init__(self, problem, beta=0.25, gamma=0.5):
        dt = problem.scene.dt
        super().__init__(problem, beta * dt * dt, "newmark")
        self.beta, self.gamma = beta, gamma
        self.a = initial_acceleration(problem, self.u)
        c = (0.5 - beta) * dt * dt
        self.pred = self.u.copy()
        self.pred.axpy(dt, self.v)
        self.pred.axpy(c, self.a)
        self.massless = np.flatnonzero(problem.massless)

    def _advance(self):
        dt, beta, gamma, sigma = self.dt, self.beta, self.gamma, self.sigma
        c = (0.5 - beta) * dt * dt
        old = self.u.getArray()[self.massless].copy()
        its = self.contact_solve(self.pred, self.lb, sigma, self.lam)
        u, v, a, pred, x = (w.getArray() for w in (self.u, self.v, self.a, self.pred, self.x))
        a_new = (x - pred) / sigma
        v[:] = v + dt * ((1.0 - gamma) * a + gamma * a_new)
        u[:] = x
        a[:] = a_new
        pred[:] = u + dt * v + c * a
        i = self.massless
        a[i] = 0.0
        v[i] = (u[i] - old) / dt
        pred[i] = u[i] + dt * v[i]
        return its


class BackwardEuler(Step):
    """Backward Euler (src/schemes/backward_euler.rs)."""

    def __init__(self, problem):
        dt = problem.scene.dt
        super().__init__(problem, dt * dt, "backward_euler")
        self.pred = self.u.copy()
        self.pred.axpy(dt, self.v)

    def _advance(self):
        its = self.contact_solve(self.pred, self.lb, self.sigma, self.lam)
        u, v, pred, x = (w.getArray() for w in (self.u, self.v, self.pred, self.x))
        v[:] = (x - u) / self.dt
        u[:] = x
        pred[:] = u + self.dt * v
        return its


class Hybrid(Step):
    """The paper's hybrid scheme (src/schemes/hybrid.rs): a Crank–Nicolson mid-step with the
    bounds ``(u_Cⁿ + lb)/2``, then the quasi-static contact values ``u_C = Φ(U)``."""

    def __init__(self, problem):
        dt = problem.scene.dt
        c = problem.contact
        if not problem.massless[c].all():
            raise ValueError("hybrid needs massless contact nodes (mass.kind = mod1, mod2, mod3)")
        super().__init__(problem, dt * dt / 4.0, "hybrid")
        self.phi = QuasiStatic(problem)
        self.its0 = self.phi.apply(self.u, self.lb, self.lam, self)
        self.lam_bar = np.zeros(len(c))
        self.pred = self.u.copy()
        self.pred.axpy(0.5 * dt, self.v)

    def _advance(self):
        dt, c, q = self.dt, self.p.contact, self.phi.q
        uc = self.u.getArray()[c].copy()
        uq = self.u.getArray()[q].copy()
        its = self.contact_solve(self.pred, 0.5 * (uc + self.lb), self.sigma, self.lam_bar)
        u, v, pred, x = (w.getArray() for w in (self.u, self.v, self.pred, self.x))
        u_new = 2.0 * x - u
        v[:] = 2.0 * (u_new - u) / dt - v
        u[:] = u_new
        its += self.phi.apply(self.u, self.lb, self.lam, self)
        u, v, pred = (w.getArray() for w in (self.u, self.v, self.pred))
        v[q] = (u[q] - uq) / dt                 # every quasi-static unknown (src/schemes/hybrid.rs)
        pred[:] = u + 0.5 * dt * v
        return its


class QuasiStatic:
    """Φ: ``S_QQ u + S_QI U − F_Q = −λ`` on the massless unknowns Q = C ∪ F, with
    ``0 ≤ u_c − lb ⊥ λ_c ≤ 0`` on the contact dofs C and λ = 0, no bound, on the free massless
    ones F (a solid's tangential components on Γ_C, frictionless; src/schemes/hybrid.rs) — the
    QP ``min ½ uᵀ S_QQ u − (F_Q − S_QI U)ᵀ u`` over ``u_C ≥ lb``."""

    def __init__(self, problem):
        self.p = p = problem
        free = np.setdiff1d(np.flatnonzero(p.massless), p.contact)
        self.q = np.union1d(p.contact, free).astype(np.int32)
        self.pos = np.searchsorted(self.q, p.contact)            # C inside Q
        start = p.S.getOwnershipRange()[0]
        self.is_q = PETSc.IS().createGeneral(self.q + start, comm=p.comm)
        self.sqq = p.S.createSubMatrix(self.is_q, self.is_q)
        self.qp = BoundQP(self.sqq, p.comm, prefix="phi_")
        self.work = p.S.createVecLeft()
        self.su = p.S.createVecLeft()
        self.r, self.uq = self.sqq.createVecLeft(), self.sqq.createVecLeft()
        self.lower = self.sqq.createVecLeft()
        self.lower.set(PETSc.NINFINITY)

    def apply(self, u, lb, lam, owner):
        q, pos, c = self.q, self.pos, self.p.contact
        u.copy(self.work)
        self.work.getArray()[q] = 0.0
        self.p.S.mult(self.work, self.su)                                   # S_·I U
        self.r.getArray()[:] = self.p.F.getArray()[q] - self.su.getArray()[q]
        uq = self.uq.getArray()
        uq[:] = u.getArray()[q]
        uq[pos] = np.maximum(u.getArray()[c], lb)
        self.lower.getArray()[pos] = lb
        its, res = self.qp.solve(self.r, self.lower, self.uq)
        uq = self.uq.getArray()
        u.getArray()[q] = uq
        owner._multipliers(uq[pos], lb, res.getArray()[pos], 1.0, lam)
        return its


def initial_acceleration(problem, u):
    """A⁰: ``M A⁰ = F − S U⁰`` on the unknowns with mass, 0 on massless and Dirichlet ones."""
    p = problem
    start = p.M.getOwnershipRange()[0]
    held = np.union1d(np.flatnonzero(p.massless), p.dirichlet).astype(np.int32) + start
    m = p.M.copy()
    m.zeroRowsColumns(held, diag=1.0)
    rhs = p.F.copy()
    su = p.S.createVecLeft()
    p.S.mult(u, su)
    rhs.axpy(-1.0, su)
    rhs.getArray()[held - start] = 0.0
    return direct_solve(m, rhs, p.comm)


def make(problem):
    s = problem.scene
    if s.scheme in ("crank-nicolson", "newmark"):
        return Newmark(problem, s.beta, s.gamma)
    if s.scheme == "backward-euler":
        return BackwardEuler(problem)
    return Hybrid(problem)
