"""GetFEM as a live peer of massredist's friction (issue 29, check 5): the static frictional
problem of a P1 disc pressed onto the plane y = 0 by a body force with a normal and a tangential
part, so that the middle of the contact sticks and its ends slide, solved by GetFEM itself.

Run with Debian's interpreter (``/usr/bin/python3``, python3-getfem 5.4):

    /usr/bin/python3 python/crosscheck/getfem_friction.py --mesh fixtures/meshes/disc_p1.msh \
        --force 0.02 -0.1 --mu 0.3 --out getfem.json

What GetFEM does here, and what it is given:

- the mesh, the elements, the integration, the elasticity and the source term as in
  ``getfem_disc.py`` (its gmsh import of the same file; P1 Lagrange; ``IM_TRIANGLE(6)``);
- the contact boundary: the demo's rule (``getfem_disc.contact_faces``), the same nodes as
  massredist's ``contact = "auto"``;
- the contact: GetFEM's nodal contact with a rigid obstacle brick with Coulomb friction
  (``add_nodal_contact_with_rigid_obstacle_brick`` with a tangential multiplier and a friction
  coefficient; the non-symmetric Alart–Curnier augmented Lagrangian, one normal and one
  tangential multiplier per contact node). Without ``alpha`` and ``wt`` data the brick's slip is
  the tangential displacement itself, measured from the unloaded state: the static problem in
  one load step. Solved by GetFEM's Newton with MUMPS to a residual below ``--max-res``.

The problem is the static one, or with ``--dt`` one backward-Euler step from rest, (M/Δt² + K) U =
F + contact, as massredist poses it: a free disc's static problem is only semi-coercive (its
rigid motions are held by contact and friction alone), and GetFEM's Newton does not converge on
it (measured: residual 8.5 after 200 iterations); with Δt = 1e6 the inertia term is about 3e-13
of the stiffness and both codes solve the same equations.

The output (JSON) holds, in GetFEM's numbering: the cells (their node coordinates), the nodes
(coordinates) and their displacement,
the contact nodes with their normal and tangential multipliers (GetFEM's signs: λ_n ≤ 0 in
contact), the Newton iterations and the residual reached.
"""
import argparse

import numpy as np

import getfem as gf
from getfem_disc import common_arguments, contact_faces, load, mass_matrix, node_numbering, run_main


def run(args):
    mesh, degree = load(args.mesh)
    normal = np.asarray(args.normal, dtype=float)
    normal = normal / np.linalg.norm(normal)
    tangent = np.array([-normal[1], normal[0]])
    mfu = gf.MeshFem(mesh, 2)
    mfu.set_classical_fem(degree)
    mim = gf.MeshIm(mesh, gf.Integ("IM_TRIANGLE(6)"))
    faces, _ = contact_faces(mesh, normal)
    GAMMAC = 1
    mesh.set_region(GAMMAC, faces)
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_initialized_data("clambda", [args.lame_lambda])
    md.add_initialized_data("cmu", [args.lame_mu])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "clambda", "cmu")
    md.add_initialized_data("volumicload", list(args.force))
    md.add_source_term_brick(mim, "u", "volumicload")
    contact_dofs = mfu.basic_dof_on_region(GAMMAC)
    ncontact = len(contact_dofs) // 2
    md.add_variable("lambda_n", ncontact)
    md.add_variable("lambda_t", ncontact)
    md.add_initialized_data("r", [args.r])
    md.add_initialized_data("friction_coeff", [args.mu])
    obstacle = f"({normal[0]!r})*(x-({args.point[0]!r}))+({normal[1]!r})*(y-({args.point[1]!r}))"
    md.add_nodal_contact_with_rigid_obstacle_brick(
        mim, "u", "lambda_n", "lambda_t", "r", "friction_coeff", GAMMAC, obstacle, 1
    )
    noisy = ["noisy"] if args.noisy else []

    def solve(what):
        nit, converged = md.solve("max_res", args.max_res, "max_iter", 200, "lsolver", "mumps", *noisy)
        if not converged:
            raise RuntimeError(f"{what}: GetFEM's Newton did not reach max_res {args.max_res} in 200 iterations")
        return int(nit)

    iterations = []
    if args.dt is None:
        iterations.append(solve("static"))
    else:
        # One backward-Euler step from rest: the inertia M/Δt² on the left, M (U⁰ + Δt V⁰)/Δt² = 0
        # on the right. Newton from zero converges for Δt = 100 (15 iterations) but not beyond
        # (the system tends to the semi-coercive static one): a continuation in Δt, ×10 at a time
        # from 100, each solve starting from the last one's answer.
        mass = mass_matrix(mesh, mfu, gf.Integ("IM_TRIANGLE(6)"), np.ones(len(mesh.cvid())), args.density)
        dts = [100.0]
        while dts[-1] * 10.0 < args.dt:
            dts.append(dts[-1] * 10.0)
        dts = [d for d in dts if d < args.dt] + [args.dt]
        brick = None
        for dt in dts:
            inertia = gf.Spmat("copy", mass)
            inertia.scale(1.0 / (dt * dt))
            if brick is None:
                brick = md.add_explicit_matrix("u", "u", inertia, 1, 1)
            else:
                md.set_private_matrix(brick, inertia)
            iterations.append(solve(f"dt = {dt}"))
    u = np.asarray(md.variable("u")).ravel()
    lam_n = np.asarray(md.variable("lambda_n")).ravel()
    lam_t = np.asarray(md.variable("lambda_t")).ravel()
    nodes = node_numbering(mfu)
    contact = np.asarray(contact_dofs[0::2] // 2, dtype=int)
    cells = [mesh.pts(mesh.pid_from_cvid(cv)[0]).T.tolist() for cv in mesh.cvid()]
    return {
        "getfem": gf.__version__ if hasattr(gf, "__version__") else "5.4",
        "numpy": np.__version__,
        "mesh": args.mesh,
        "degree": degree,
        "mu": args.mu,
        "force": list(args.force),
        "normal": normal.tolist(),
        "tangent": tangent.tolist(),
        "max_res": args.max_res,
        "dt": args.dt,
        "newton_iterations": iterations,
        "cells": cells,
        "nodes": nodes.tolist(),
        "u": u.reshape(-1, 2).tolist(),
        "contact_nodes": contact.tolist(),
        "lambda_n": lam_n.tolist(),
        "lambda_t": lam_t.tolist(),
    }


def parser():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mesh", required=True, help="an ASCII gmsh file of triangles")
    p.add_argument("--force", type=float, nargs=2, default=[0.02, -0.1])
    p.add_argument("--mu", type=float, default=0.3, help="Coulomb's coefficient")
    p.add_argument("--normal", type=float, nargs=2, default=[0.0, 1.0])
    p.add_argument("--point", type=float, nargs=2, default=[0.0, 0.0])
    p.add_argument("--density", type=float, default=1.0)
    p.add_argument("--dt", type=float, default=None, help="one backward-Euler step from rest of this length (default: static)")
    common_arguments(p, 1e-12)
    return p


def summary(args, result):
    return (
        f"getfem_friction: {args.mesh}: {len(result['contact_nodes'])} contact nodes, Newton iterations "
        f"{result['newton_iterations']} (Δt continuation)"
    )


def main(argv=None):
    run_main(argv, parser, run, summary)


if __name__ == "__main__":
    main()
