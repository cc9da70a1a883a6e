"""GetFEM as a live peer of massredist (issue 19, item 6): the disc of GetFEM's
``interface/tests/matlab-octave/demo_dynamic_contact.m`` stepped by GetFEM itself.

Run with Debian's interpreter (``/usr/bin/python3``, python3-getfem 5.4):

    /usr/bin/python3 python/crosscheck/getfem_disc.py --mesh fixtures/meshes/disc_p2_22a.msh \
        --mass singular --steps 300 --out getfem.json

What GetFEM does here, and what it is given:

- the mesh: GetFEM's own gmsh import of the same ``.msh`` file massredist reads (ASCII MSH 2.2
  or 4.1; GetFEM 5.4 cannot read binary gmsh files); P1 or isoparametric P2 Lagrange elements
  as the file's cells (``GT_PK(2, k)``, ``classical fem`` of degree k);
- the assembly: GetFEM's mass matrix (times ρ), its plane-strain isotropic elasticity
  ``(λ div u I + 2 μ ε(u)) : ∇v`` and its volumic source ``∫ f · v``, all with the integration
  method ``IM_TRIANGLE(6)`` (exact for the mass of these isoparametric P2 cells, whose
  integrand u·v det J has degree 6; the stiffness of curved cells is rational and no rule is
  exact: between degree 6 and 13 GetFEM's stiffness changes by 6e-10 relative);
- the mass: ``standard``, or the demo's "singular mass" (``singular_mass = 1``: no integration,
  so no mass, on the cells with a facet on the contact boundary; mass 1 elsewhere); the per-cell
  weights are written out so that massredist can pose them with ``mass.kind = "custom"``;
- the contact boundary: the demo's rule, the outer faces whose unit normal (GetFEM's, at the
  face centre) has ``n_f · normal < −0.01``;
- the contact: GetFEM's nodal contact with a rigid obstacle brick
  (``add_nodal_contact_with_rigid_obstacle_brick``, non-symmetric Alart–Curnier augmented
  Lagrangian, one multiplier per node of the boundary), the obstacle the signed distance
  ``normal · (x − point)``, solved by GetFEM's Newton with MUMPS to a residual below
  ``--max-res`` at every step; the complementarity of the result is measured and written out;
- the time scheme: Newmark (β, γ) written, as in the demo, on the M-weighted quantities
  MUⁿ, MVⁿ, MAⁿ:

      (M/(β Δt²) + K) U^{n+1} = F + (MUⁿ + Δt MVⁿ + Δt² (½ − β) MAⁿ)/(β Δt²) − Bᵀλ
      MA^{n+1} = (MU^{n+1} − MUⁿ − Δt MVⁿ − Δt² (½ − β) MAⁿ)/(β Δt²)
      MV^{n+1} = MVⁿ + Δt ((1 − γ) MAⁿ + γ MA^{n+1})

  with MU⁰ = M U⁰, MV⁰ = M V⁰ and MA⁰ = F − K U⁰ (λ⁰ = 0) on the rows with mass and 0 on the
  massless rows. The demo leaves that last choice open for a 2D singular mass (it stops with
  "Take it into account !"); with it the massless rows stay quasi-static, MAⁿ = 0 there at every
  step, which is massredist's convention (src/schemes/mod.rs: A⁰ from the equation of motion on
  the unknowns with mass, massless velocities and accelerations entering no equation), so both
  codes step the same scheme. With the standard mass no row is massless and MA⁰ = F − K U⁰.

The output (JSON) holds, in GetFEM's numbering: the cells (their node coordinates and weights),
the nodes (coordinates) and their displacement at every step, the contact nodes, and per step
the Newton iterations and the complementarity of the nodal contact.
"""
import argparse
import json
import sys

import numpy as np

import getfem as gf

# The demo's threshold on n_f · normal for a contact face (demo_dynamic_contact.m).
CONTACT_THRESHOLD = -0.01


def load(path):
    """GetFEM's import of a gmsh file; the degree (1 or 2) of its one geometric transformation."""
    mesh = gf.Mesh("import", "gmsh", path)
    gts, _ = mesh.geotrans()  # the distinct transformations (one object when there is one)
    kinds = {gt.char() for gt in (gts if isinstance(gts, (list, tuple)) else [gts])}
    degrees = {"GT_PK(2,1)": 1, "GT_PK(2,2)": 2}
    if len(kinds) != 1 or next(iter(kinds)) not in degrees:
        raise ValueError(f"{path}: cells {sorted(kinds)}; expected one of {sorted(degrees)}")
    return mesh, degrees[next(iter(kinds))]


def chord_normal(mesh, cv, face):
    """The outward unit normal of a face from its two end vertices (the straight-sided normal of
    the issue's rule; for a P1 face it is GetFEM's own)."""
    fp = mesh.pts(mesh.pid_in_faces(np.array([[cv], [face]]))).T
    # The end vertices: the farthest pair (a P2 face's third point lies between them).
    i, j = max(((i, j) for i in range(len(fp)) for j in range(i)), key=lambda p: np.sum((fp[p[0]] - fp[p[1]]) ** 2))
    t = fp[i] - fp[j]
    n = np.array([t[1], -t[0]]) / np.hypot(t[0], t[1])
    centre = mesh.pts(mesh.pid_from_cvid(cv)[0]).mean(axis=1)
    return n if n @ (fp[i] - centre) > 0.0 else -n


def contact_faces(mesh, normal):
    """The outer faces (convex id, face number) with n_f · normal < −0.01 (the demo's rule), n_f
    the straight-sided normal ([`chord_normal`]); and the faces GetFEM's own normals select.

    The two differ on curved P2 faces: GetFEM 5.4's ``normal_of_faces`` of a GT_PK(2,2) face is
    the normal at one of its end points (measured on the gmsh disc: (−1, −0.0006) on the face
    from (−20, 20) to (−19.3, 14.8), whose chord normal is (−0.99, −0.13)), so the demo's rule
    would drop that face and keep its mirror image. The chord normal is the issue's rule and
    equals GetFEM's normal at the face centre for P1."""
    border = mesh.outer_faces()
    own = mesh.normal_of_faces(border)
    chord = np.array([chord_normal(mesh, cv, f) for cv, f in border.T]).T
    mine = border[:, normal @ chord < CONTACT_THRESHOLD]
    getfems = border[:, normal @ own < CONTACT_THRESHOLD]
    return mine, getfems


def cell_weights(mesh, faces, mass):
    """Per-cell weights in GetFEM's cell order: 1 everywhere (standard), or 0 on the cells with
    a contact face (the demo's singular mass)."""
    cvids = mesh.cvid()
    w = np.ones(len(cvids))
    if mass == "singular":
        w[np.isin(cvids, faces[0])] = 0.0
    elif mass != "standard":
        raise ValueError(f"mass {mass!r}: expected standard | singular")
    return w


def mass_matrix(mesh, mfu, integ, weights, rho):
    """ρ ∫ u·v over the cells of weight 1 (the demo's ``mim_sing``: no integration on the
    weight-0 cells)."""
    cvids = mesh.cvid()
    if not np.all((weights == 0.0) | (weights == 1.0)):
        raise ValueError("weights must be 0 or 1 (GetFEM's singular mass)")
    mim = gf.MeshIm(mesh)  # no integration method on any cell, as the demo's mim_sing
    mim.set_integ(integ, cvids[weights == 1.0])
    m = gf.asm_mass_matrix(mim, mfu)
    m.scale(rho)
    return m


def diagonal(a):
    """The diagonal of a GetFEM sparse matrix, from its CSC arrays (``Spmat.diag`` prints a
    debugging line on stdout)."""
    jc, ir = a.csc_ind()
    val = a.csc_val()
    d = np.zeros(a.size()[0])
    for j in range(len(jc) - 1):
        for k in range(jc[j], jc[j + 1]):
            if ir[k] == j:
                d[j] = val[k]
    return d


def spmv(a, x):
    return np.asarray(a.mult(x)).ravel()


def common_arguments(p, max_res):
    """The arguments every GetFEM peer takes: Lamé's coefficients, the augmentation parameter,
    Newton's residual, its trace and the JSON file written."""
    p.add_argument("--lame-lambda", type=float, default=20.0)
    p.add_argument("--lame-mu", type=float, default=20.0)
    p.add_argument("--r", type=float, default=50.0, help="augmentation parameter (about Young's modulus)")
    p.add_argument("--max-res", type=float, default=max_res)
    p.add_argument("--noisy", action="store_true", help="GetFEM's Newton prints its residuals")
    p.add_argument("--out", required=True, help="the JSON file written")


def run_main(argv, parser, run, summary):
    """A peer's command line: parse ``argv`` with ``parser``, run GetFEM quietly, write the result
    as JSON to ``--out`` and print ``summary(args, result)`` on stderr."""
    args = parser().parse_args(argv)
    gf.util_trace_level(0)
    result = run(args)
    with open(args.out, "w") as f:
        json.dump(result, f)
    print(summary(args, result), file=sys.stderr)


def node_numbering(mfu):
    """GetFEM's vector dofs come in pairs (x, y) per node: the node coordinates, one per pair."""
    pts = mfu.basic_dof_nodes()
    if not np.array_equal(pts[:, 0::2], pts[:, 1::2]):
        raise ValueError("the dofs of a node are not consecutive")
    return pts[:, 0::2].T


def build_model(mfu, mim, region, lame, force, normal, point, r):
    """The elastic model with GetFEM's bricks: elasticity, volumic source, nodal contact with the
    rigid plane; the inertia term and the Newmark right-hand side are explicit bricks added by
    the caller."""
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_initialized_data("clambda", [lame[0]])
    md.add_initialized_data("cmu", [lame[1]])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "clambda", "cmu")
    md.add_initialized_data("volumicload", list(force))
    md.add_source_term_brick(mim, "u", "volumicload")
    ncontact = len(mfu.basic_dof_on_region(region)) // 2
    md.add_variable("lambda_n", ncontact)
    md.add_initialized_data("r", [r])
    obstacle = f"({normal[0]!r})*(x-({point[0]!r}))+({normal[1]!r})*(y-({point[1]!r}))"
    md.add_nodal_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "r", region, obstacle, 1)
    return md


def complementarity(u, lam, nodes, contact, normal, point):
    """Per step: the smallest distance d_i = n·(X_i + u_i − p) over the contact nodes, the
    largest multiplier of the wrong sign, and max |d_i λ_i| (GetFEM's λ_n ≤ 0 in contact)."""
    x = nodes[contact]
    un = u.reshape(-1, 2)[contact] @ np.asarray(normal)
    d = (x - np.asarray(point)) @ np.asarray(normal) + un
    return float(d.min()), float(lam.max()) if len(lam) else 0.0, float(np.abs(d * lam).max())


def newmark(md, ind_rhs, mkf, massless, initial, args, state):
    """Newmark (β, γ) on MUⁿ, MVⁿ, MAⁿ (module docs), each step solved by GetFEM's model (the
    inertia and the right-hand side as explicit bricks); returns Uⁿ, Newton iterations and
    ``state(u, λ)`` per step."""
    M, K, F = mkf
    u0, v0 = initial
    beta, gamma, dt = args.beta, args.gamma, args.dt
    mu, mv = spmv(M, u0), spmv(M, v0)
    ma = F - spmv(K, u0)
    ma[massless] = 0.0  # massredist's convention (module docs)
    ncontact = len(np.asarray(md.variable("lambda_n")).ravel())
    history, newton, comp = [u0.tolist()], [], [state(u0, np.zeros(ncontact))]
    c = dt * dt * (0.5 - beta)
    noisy = ["noisy"] if args.noisy else []
    for step in range(1, args.steps + 1):
        pred = mu + dt * mv + c * ma
        md.set_private_rhs(ind_rhs, pred / (beta * dt * dt))
        nit, converged = md.solve("max_res", args.max_res, "max_iter", 50, "lsolver", "mumps", *noisy)
        if not converged:
            raise RuntimeError(f"step {step}: GetFEM's Newton did not reach max_res {args.max_res} in 50 iterations")
        u = np.asarray(md.variable("u")).ravel()
        lam = np.asarray(md.variable("lambda_n")).ravel()
        mu_new = spmv(M, u)
        ma_new = (mu_new - pred) / (beta * dt * dt)
        mv = mv + dt * ((1.0 - gamma) * ma + gamma * ma_new)
        mu, ma = mu_new, ma_new
        history.append(u.tolist())
        newton.append(int(nit))
        comp.append(state(u, lam))
    return history, newton, comp


def run(args):
    mesh, degree = load(args.mesh)
    normal = np.asarray(args.normal, dtype=float)
    normal = normal / np.linalg.norm(normal)
    mfu = gf.MeshFem(mesh, 2)
    mfu.set_classical_fem(degree)
    integ = gf.Integ("IM_TRIANGLE(6)")
    mim = gf.MeshIm(mesh, integ)
    faces, getfem_faces = contact_faces(mesh, normal)
    GAMMAC = 1
    mesh.set_region(GAMMAC, faces)
    weights = cell_weights(mesh, faces, args.mass)
    M = mass_matrix(mesh, mfu, integ, weights, args.density)
    lame = (args.lame_lambda, args.lame_mu)
    md = build_model(mfu, mim, GAMMAC, lame, args.force, normal, args.point, args.r)
    K = gf.asm_generic(mim, 2, "(clambda*Div_u*Id(meshdim)+2*cmu*Sym(Grad_u)):Grad_Test_u", -1, md)
    start, n = (int(i) for i in md.interval_of_variable("u"))  # the model orders its unknowns
    if n != mfu.nbdof():
        raise ValueError(f"u has {n} unknowns in the model, {mfu.nbdof()} dofs")
    rows = list(range(start, start + n))
    K = gf.Spmat("copy", K, rows, rows)
    F = np.asarray(gf.asm_generic(mim, 1, "volumicload.Test_u", -1, md)).ravel()[start : start + n]
    beta, gamma, dt = args.beta, args.gamma, args.dt
    inertia = gf.Spmat("copy", M)
    inertia.scale(1.0 / (beta * dt * dt))
    md.add_explicit_matrix("u", "u", inertia, 1, 1)
    ind_rhs = md.add_explicit_rhs("u", np.zeros(n))

    nodes = node_numbering(mfu)
    contact_dofs = mfu.basic_dof_on_region(GAMMAC)
    contact = np.asarray(contact_dofs[0::2] // 2, dtype=int)
    massless = diagonal(M) == 0.0
    u0 = np.zeros(n)
    v0 = np.tile(np.asarray(args.velocity, dtype=float), n // 2)
    state = lambda u, lam: list(complementarity(u, lam, nodes, contact, normal, args.point))  # noqa: E731
    history, newton, comp = newmark(md, ind_rhs, (M, K, F), massless, (u0, v0), args, state)
    cells = []
    for cv in mesh.cvid():
        pids = mesh.pid_from_cvid(cv)[0]
        cells.append(mesh.pts(pids).T.tolist())
    return {
        "getfem": gf.__version__ if hasattr(gf, "__version__") else "5.4",
        "numpy": np.__version__,
        "mesh": args.mesh,
        "degree": degree,
        "mass": args.mass,
        "beta": beta,
        "gamma": gamma,
        "dt": dt,
        "steps": args.steps,
        "integration": "IM_TRIANGLE(6)",
        "max_res": args.max_res,
        "cells": cells,
        "weights": weights.tolist(),
        "nodes": nodes.tolist(),
        "contact_nodes": contact.tolist(),
        "contact_faces": faces.T.tolist(),
        "getfem_normal_contact_faces": getfem_faces.T.tolist(),
        "massless_nodes": np.nonzero(massless[0::2])[0].tolist(),
        "newton_iterations": newton,
        "complementarity": comp,
        "u": history,
    }


def parser():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mesh", required=True, help="an ASCII gmsh file of triangles or triangle6")
    p.add_argument("--mass", default="singular", choices=["standard", "singular"])
    p.add_argument("--dt", type=float, default=0.01)
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--beta", type=float, default=0.25)
    p.add_argument("--gamma", type=float, default=0.5)
    p.add_argument("--density", type=float, default=1.0)
    p.add_argument("--force", type=float, nargs=2, default=[0.0, -0.1])
    p.add_argument("--velocity", type=float, nargs=2, default=[0.0, 0.0], help="initial velocity (uniform)")
    p.add_argument("--normal", type=float, nargs=2, default=[0.0, 1.0])
    p.add_argument("--point", type=float, nargs=2, default=[0.0, 0.0])
    common_arguments(p, 1e-9)
    return p


def summary(args, result):
    c = np.asarray(result["complementarity"])
    return (
        f"getfem_disc: {args.mesh} P{result['degree']} {args.mass}: {args.steps} steps, Newton iterations "
        f"{min(result['newton_iterations'])}..{max(result['newton_iterations'])}, min distance {c[:, 0].min():.3e}, "
        f"max |d λ| {c[:, 2].max():.3e}"
    )


def main(argv=None):
    run_main(argv, parser, run, summary)


if __name__ == "__main__":
    main()
