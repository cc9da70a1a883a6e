"""GetFEM as a live peer of massredist's curved obstacles (issue 30, check 3): the static problem
of a half disc clamped on its flat top and pressed by a body force onto a rigid obstacle given
as a signed-distance expression, solved by GetFEM itself.

Run with Debian's interpreter (``/usr/bin/python3``, python3-getfem 5.4):

    /usr/bin/python3 python/crosscheck/getfem_obstacle.py --mesh fixtures/meshes/half_disc_p2.msh \
        --obstacle "sqrt(sqr(x)+sqr(y+30))-30" --force 0 -0.05 --out getfem.json

What GetFEM does here, and what it is given:

- the mesh, the elements, the integration, the elasticity and the source term as in
  ``getfem_disc.py`` (its gmsh import of the same file; P1 or isoparametric P2 Lagrange;
  ``IM_TRIANGLE(6)``);
- the clamped nodes: the dofs of the gmsh physical group ``--clamped`` (region 2, "top", of
  ``half_disc_p2.msh``) fixed by GetFEM's Dirichlet brick with multipliers;
- the contact nodes: every node of the physical group ``--contact`` (region 3, "arc"), the same
  nodes as massredist's ``obstacle.contact = "arc"``;
- the contact: GetFEM's frictionless nodal contact with a rigid obstacle brick
  (``add_nodal_contact_with_rigid_obstacle_brick``, non-symmetric Alart–Curnier augmented
  Lagrangian, one multiplier per contact node), the obstacle the expression ``--obstacle`` in
  GetFEM's weak-form language (``sqr``, ``sqrt``, ``abs``; no ``^``). GetFEM 5.4 takes a node's
  gap as the expression's value and its normal as −∇φ/|∇φ| with ∇φ a forward difference of
  step 1e-3 × the radius of the node's first cell (getfem_contact_and_friction_nodal.cc):
  exact for a piecewise-affine φ away from its kinks, off by about step/(2R) radians on a circle
  of radius R. The script measures that rule's error at the nodes that press (each radius of
  the node's cells tried, against a central difference a million times finer), so that the
  caller can bound the difference it causes.

The problem is the static one, solved by GetFEM's Newton with MUMPS to a residual below
``--max-res``. The output (JSON) holds, in GetFEM's numbering: the cells (their node
coordinates), the nodes (coordinates) and their displacement, the contact nodes with their
multipliers (GetFEM's sign: λ_n ≤ 0 in contact) and the largest normal deviation of the
forward difference from the central one with a step 1e-3 smaller (a measure of its error).
"""
import argparse

import numpy as np

import getfem as gf
from getfem_disc import common_arguments, load, node_numbering, run_main


def fd_normal(phi, point, eps):
    """GetFEM's rule: the forward difference of φ with step eps, normalised (the inward normal
    of the body's side, ∇φ/|∇φ|; GetFEM stores its negative)."""
    f0 = phi(point)
    grad = np.array([(phi(point + eps * e) - f0) / eps for e in np.eye(len(point))])
    return grad / np.linalg.norm(grad)


def run(args):
    mesh, degree = load(args.mesh)
    mfu = gf.MeshFem(mesh, 2)
    mfu.set_classical_fem(degree)
    mim = gf.MeshIm(mesh, gf.Integ(args.integ))
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_initialized_data("clambda", [args.lame_lambda])
    md.add_initialized_data("cmu", [args.lame_mu])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "clambda", "cmu")
    md.add_initialized_data("volumicload", list(args.force))
    md.add_source_term_brick(mim, "u", "volumicload")
    md.add_Dirichlet_condition_with_multipliers(mim, "u", mfu, args.clamped_region)
    contact_dofs = mfu.basic_dof_on_region(args.contact_region)
    ncontact = len(contact_dofs) // 2
    md.add_variable("lambda_n", ncontact)
    md.add_initialized_data("r", [args.r])
    md.add_nodal_contact_with_rigid_obstacle_brick(mim, "u", "lambda_n", "r", args.contact_region, args.obstacle, 1)
    noisy = ["noisy"] if args.noisy else []
    nit, converged = md.solve("max_res", args.max_res, "max_iter", 200, "lsolver", "mumps", *noisy)
    if not converged:
        raise RuntimeError(f"GetFEM's Newton did not reach max_res {args.max_res} in 200 iterations")
    u = np.asarray(md.variable("u")).ravel()
    lam_n = np.asarray(md.variable("lambda_n")).ravel()
    nodes = node_numbering(mfu)
    contact = np.asarray(contact_dofs[0::2] // 2, dtype=int)
    # The forward-difference normals GetFEM takes, against a central difference 1e-3 finer (a
    # reference for the exact one): the largest angle over the contact nodes and their cells.
    expr = args.obstacle
    names = {"sqr": np.square, "sqrt": np.sqrt, "abs": np.abs, "sin": np.sin, "cos": np.cos, "exp": np.exp}

    def phi(p):
        return eval(expr, {"__builtins__": {}}, {**names, "x": p[0], "y": p[1]})

    radius = mesh.convex_radius()
    cells_of = {}
    for cv, r in zip(mesh.cvid(), radius):
        for pid in mesh.pid_from_cvid(cv)[0]:
            cells_of.setdefault(tuple(np.round(mesh.pts(pid).ravel(), 12)), []).append(r)
    deviation = 0.0
    for k in contact[lam_n < 0.0]:
        p = nodes[k]
        fine = 1e-6 * min(cells_of.get(tuple(np.round(p, 12)), [1.0]))
        central = np.array([(phi(p + fine * e) - phi(p - fine * e)) / (2 * fine) for e in np.eye(2)])
        central /= np.linalg.norm(central)
        for r in cells_of.get(tuple(np.round(p, 12)), []):
            deviation = max(deviation, float(np.linalg.norm(fd_normal(phi, p, 1e-3 * r) - central)))
    cells = [mesh.pts(mesh.pid_from_cvid(cv)[0]).T.tolist() for cv in mesh.cvid()]
    return {
        "getfem": gf.__version__ if hasattr(gf, "__version__") else "5.4",
        "numpy": np.__version__,
        "mesh": args.mesh,
        "degree": degree,
        "obstacle": args.obstacle,
        "force": list(args.force),
        "max_res": args.max_res,
        "newton_iterations": int(nit),
        "cells": cells,
        "nodes": nodes.tolist(),
        "u": u.reshape(-1, 2).tolist(),
        "contact_nodes": contact.tolist(),
        "lambda_n": lam_n.tolist(),
        "normal_deviation": deviation,
    }


def parser():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mesh", required=True, help="an ASCII gmsh file of triangles or triangle6")
    p.add_argument("--obstacle", required=True, help="the signed distance φ(x, y) (muparser), > 0 on the body's side")
    p.add_argument("--clamped-region", type=int, default=2, help="the gmsh physical group held fixed")
    p.add_argument("--contact-region", type=int, default=3, help="the gmsh physical group of the contact nodes")
    p.add_argument("--force", type=float, nargs=2, default=[0.0, -0.05])
    p.add_argument("--integ", default="IM_TRIANGLE(6)", help="GetFEM's integration method")
    common_arguments(p, 1e-12)
    return p


def summary(args, result):
    active = sum(1 for lam in result["lambda_n"] if lam < 0.0)
    return (
        f"getfem_obstacle: {args.mesh}: {len(result['contact_nodes'])} contact nodes, {active} pressing, "
        f"Newton iterations {result['newton_iterations']}, forward-difference normals within "
        f"{result['normal_deviation']:.2e}"
    )


def main(argv=None):
    run_main(argv, parser, run, summary)


if __name__ == "__main__":
    main()
