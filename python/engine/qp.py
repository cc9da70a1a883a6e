"""One implicit step with contact as a bound-constrained quadratic program, solved by PETSc.

Every scheme solves, once or twice per step (src/contact/mod.rs),

    K U = r − σ Σ_c λ_c e_c,    0 ≤ u_c − lb_c ⊥ λ_c ≤ 0,

K symmetric positive definite. With ``μ = −σ λ`` this is the optimality system of

    min ½ Uᵀ K U − rᵀ U   subject to   u_c ≥ lb_c on the contact dofs,

i.e. the variational inequality ``lb ≤ U ⊥ K U − r`` (bounds −∞ off Γ_C): PETSc's SNES
``vinewtonrsls`` (reduced-space active-set Newton) with the constant Jacobian K, each Newton
system solved by a direct LU factorisation (MUMPS, distributed). The multipliers are read from
the residual, ``λ_c = −(K U − r)_c / σ`` on the active dofs and 0 on the inactive ones.

Tolerance: SNES stops when the residual norm on the inactive set is below
``atol = ATOL_FACTOR · max(1, ‖r‖∞)``; PETSc (3.18, ``SNESVIGetActiveSetIS``) counts a dof as
active when ``u_c ≤ lb_c + 1e-8`` and ``(K U − r)_c > 0``, so a dof closer than 1e-8 to its bound
may be set on it: ``VI_BOUND_TOL = 1e-8`` is the absolute accuracy of the contact values the
solver guarantees, and what the cross-checks derive their tolerances from.
"""
from mpi4py import MPI
from petsc4py import PETSc

ATOL_FACTOR = 1e-12
VI_BOUND_TOL = 1e-8
MAX_IT = 100


class NonFinite(ArithmeticError):
    """The step's residual norm is not finite: the state overflowed (a divergence, as the Rust
    schemes' non-finite state; src/schemes/mod.rs check_finite)."""


class BoundQP:
    """The step QP for a fixed K: one SNES with its factorisation set-up (module docs)."""

    def __init__(self, K, comm, prefix="step_"):
        self.K = K
        self.r = K.createVecLeft()
        self.residual = K.createVecLeft()
        snes = PETSc.SNES().create(comm)
        snes.setOptionsPrefix(prefix)
        snes.setType("vinewtonrsls")
        snes.setFunction(self._function, K.createVecLeft())
        snes.setJacobian(self._jacobian, K, K)
        PETSc.Options().setValue(prefix + "snes_linesearch_type", "basic")
        ksp = snes.getKSP()
        ksp.setType("preonly")
        pc = ksp.getPC()
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
        snes.setFromOptions()
        self.snes = snes
        self.upper = K.createVecLeft()
        self.upper.set(PETSc.INFINITY)

    def describe(self):
        """The solver as set up (after PETSc options such as ``-newmark_ksp_type cg
        -newmark_pc_type hypre``, which replace the direct solve by CG + BoomerAMG)."""
        ksp = self.snes.getKSP()
        pc = ksp.getPC()
        linear = f"KSP {ksp.getType()} + PC {pc.getType()}"
        if pc.getType() == "lu":
            linear += f" ({pc.getFactorSolverType()})"
        else:
            linear += f" (rtol {ksp.getTolerances()[0]:g})"
        return f"SNES {self.snes.getType()} (prefix {self.snes.getOptionsPrefix()}), {linear}"

    def _function(self, snes, x, f):
        self.K.mult(x, f)
        f.axpy(-1.0, self.r)

    def _jacobian(self, snes, x, J, P):
        return True

    def solve(self, r, lower, x):
        """Solves the QP for right-hand side r and bounds ``lower`` (module docs); ``x`` holds the
        initial guess on entry and U on exit. Returns ``(iterations, residual K U − r)``."""
        r.copy(self.r)
        atol = ATOL_FACTOR * max(1.0, r.norm(PETSc.NormType.INFINITY))
        self.snes.setTolerances(atol=atol, rtol=0.0, stol=0.0, max_it=MAX_IT)
        self.snes.setVariableBounds(lower, self.upper)
        self.snes.solve(None, x)
        reason = self.snes.getConvergedReason()
        if reason == PETSc.SNES.ConvergedReason.DIVERGED_FNORM_NAN:
            raise NonFinite()
        if reason <= 0:
            raise RuntimeError(f"SNES vinewtonrsls did not converge (reason {reason}, "
                               f"{self.snes.getIterationNumber()} iterations)")
        self._function(self.snes, x, self.residual)
        # PETSc's active set: within VI_BOUND_TOL of the bound with the residual pushing onto
        # it. The solver leaves such a dof where the Newton step found it (up to 1e-8 above
        # the bound); set it onto the bound, as the Rust solver does (exact complementarity),
        # so that the multiplier is read from the residual there and not taken as 0.
        xa, lo, res = x.getArray(), lower.getArray(), self.residual.getArray()
        snap = (xa <= lo + VI_BOUND_TOL) & (res > 0.0) & (xa != lo)
        if self.K.getComm().tompi4py().allreduce(bool(snap.any()), op=MPI.LOR):
            xa[snap] = lo[snap]
            self._function(self.snes, x, self.residual)
        return self.snes.getIterationNumber(), self.residual


def direct_solve(A, b, comm):
    """``A⁻¹ b`` by LU (MUMPS): the one-off solves outside the steps (A⁰, the load energy)."""
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    x = b.duplicate()
    ksp.solve(b, x)
    return x
