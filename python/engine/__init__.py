"""The FEniCSx engine (issue 12): plate and solid scenes stepped by dolfinx 0.5 and PETSc under
MPI, step for step the schemes of the Rust solver, so that trajectories compare.

Modules (pure ones first; only ``problem``, ``qp``, ``schemes`` and ``run`` touch dolfinx/PETSc):

- ``scene``: the scene as massredist hands it over (``scene.engine.json``: a plate, a solid box
  or a body, every value written out; src/engine/document.rs) as data; scene expressions.
- ``layers``: the structured 2D/3D mesh arrays and the cell weights (src/fem/{mesh,layers}.rs).
- ``exact``: the paper's impacting bar (scaled to any wave speed for solids) and exact L² errors
  (chord integration on 2D cells, Gauss lines on boxes).
- ``stream``: the channel to massredist (records out on rank 0's stdout, replies in on its
  stdin); massredist's observers write series.csv and summary.json, its divergence rule stops
  the run (src/engine/).
- ``problem``: the distributed mesh, DG0 weights, M, S, F, held and contact dofs.
- ``qp``: one step's contact problem as a bound-constrained QP (SNES ``vinewtonrsls``).
- ``schemes``: Newmark / Crank–Nicolson, backward Euler, hybrid.
- ``run``: the loop, each state's diagnostics (reduced over the ranks), engine.json and the
  XDMF time series.

A solid is a vector field (``Scene.solid``): a ``VectorFunctionSpace`` with the elastic
``λ div u div v + 2μ ε(u):ε(v)``; the contact dofs are the x-components of the nodes on x = 0
(block index × d), the held dofs every component on x = L and, with roller faces, the normal
component on the lateral faces. ``qp`` and ``schemes`` work on dof vectors and index lists alike
for both fields.
"""
