"""The FEniCSx engine (issue 12): plate scenes stepped by dolfinx 0.5 and PETSc under MPI,
step for step the schemes of the Rust solver, so that trajectories compare.

Modules (pure ones first; only ``problem``, ``qp``, ``schemes`` and ``run`` touch dolfinx/PETSc):

- ``scene``: the resolved scene (``scene.resolved.toml``) as data; scene expressions.
- ``layers``: the structured mesh arrays and the cell weights (src/plate/{mesh,layers}.rs).
- ``exact``: the paper's impacting bar and an exact L² error (chord integration).
- ``observe``: series rows and the summary, with the Rust columns and keys.
- ``output``: number format, summary.json, the atomic run folder with its marker.
- ``problem``: the distributed mesh, DG0 weights, M, S, F, Dirichlet and contact dofs.
- ``qp``: one step's contact problem as a bound-constrained QP (SNES ``vinewtonrsls``).
- ``schemes``: Newmark / Crank–Nicolson, backward Euler, hybrid.
- ``run``: the loop, the samples of src/driver.rs, rank 0's files.

A vector field (elastic solids, issue 11) is a small addition: ``Scene.field = "vector"`` makes
``problem._space`` a ``VectorFunctionSpace``; ``problem._stiffness_form`` gets the elastic
``σ(u) : ε(v)``; the contact dofs become those of the normal component on Γ_C
(``V.sub(0)`` dofs at x = 0, in the owned block numbering) and the Dirichlet condition the whole
vector. ``qp``, ``schemes``, ``observe`` and ``output`` work on dof vectors and contact index
lists and need no change.
"""
