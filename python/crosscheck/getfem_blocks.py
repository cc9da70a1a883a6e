"""GetFEM as a live peer of massredist's two bodies (issue 30, check 3): the static problem of two
P1 blocks on a matching interface, the upper one clamped on its top and pushed by a body force
onto the lower one, clamped on its bottom, solved by GetFEM itself.

Run with Debian's interpreter (``/usr/bin/python3``, python3-getfem 5.4):

    /usr/bin/python3 python/crosscheck/getfem_blocks.py --mesh blocks.json --force 0.5 -1 --out getfem.json

What GetFEM does here, and what it is given:

- the two meshes, as lists of triangles (``--mesh``, JSON ``{"bodies": [{"name", "points",
  "cells"}, …]}``, the first body the upper one; massredist writes it from its own box meshes,
  study/src/crosscheck_getfem.rs), each a GetFEM mesh of its own (``GT_PK(2,1)``), P1 Lagrange
  vector elements, ``IM_TRIANGLE(2)`` (exact for P1 stiffness and the constant source);
- linear elasticity (``--lame-lambda``, ``--lame-mu``) on both, the volume force ``--force`` on
  the upper body only;
- the clamped sides found by GetFEM: the upper body's outer faces facing up, the lower body's
  facing down (``outer_faces_with_direction``), fixed by the Dirichlet brick with multipliers;
- the contact: the upper body's outer faces facing down (its nodes the slaves) against the lower
  body's facing up (the masters), GetFEM's frictionless nodal contact between non-matching
  meshes brick (``add_nodal_contact_between_nonmatching_meshes_brick``, non-symmetric
  Alart–Curnier augmented Lagrangian, one multiplier per slave node): its gap and normal are
  those of each slave node's projection onto the master faces in the reference configuration
  (small sliding), here the node facing it, at the distance between them.

The problem is the static one, solved by GetFEM's Newton with MUMPS to a residual below
``--max-res``. The output (JSON) holds per body, in GetFEM's numbering, the nodes and their
displacement, and the slave nodes (of the upper body) with their multipliers (GetFEM's sign:
λ_n ≤ 0 in contact).
"""
import argparse
import json

import numpy as np

import getfem as gf
from getfem_disc import common_arguments, node_numbering, run_main

TOP, BOTTOM = 1, 2
ANGLE = 0.01  # radians: the flat sides of a box (their outward normals exactly ±e_y)


def block(body):
    """One body's GetFEM mesh from its triangles; its top (region 1) and bottom (region 2)."""
    mesh = gf.Mesh("empty", 2)
    pts = np.asarray(body["points"], dtype=float)
    gt = gf.GeoTrans("GT_PK(2,1)")
    for cell in body["cells"]:
        if len(cell) != 3:
            raise ValueError(f"body {body['name']}: a cell of {len(cell)} nodes (P1 triangles only)")
        mesh.add_convex(gt, pts[cell].T)
    mesh.set_region(TOP, mesh.outer_faces_with_direction([0.0, 1.0], ANGLE))
    mesh.set_region(BOTTOM, mesh.outer_faces_with_direction([0.0, -1.0], ANGLE))
    return mesh


def run(args):
    with open(args.mesh) as f:
        bodies = json.load(f)["bodies"]
    if len(bodies) != 2:
        raise ValueError(f"{args.mesh}: {len(bodies)} bodies (two: the upper one first)")
    meshes = [block(b) for b in bodies]
    md = gf.Model("real")
    md.add_initialized_data("clambda", [args.lame_lambda])
    md.add_initialized_data("cmu", [args.lame_mu])
    md.add_initialized_data("volumicload", list(args.force))
    mfus, mims, names = [], [], ["u1", "u2"]
    for mesh, name in zip(meshes, names):
        mfu = gf.MeshFem(mesh, 2)
        mfu.set_classical_fem(1)
        mim = gf.MeshIm(mesh, gf.Integ("IM_TRIANGLE(2)"))
        md.add_fem_variable(name, mfu)
        md.add_isotropic_linearized_elasticity_brick(mim, name, "clambda", "cmu")
        mfus.append(mfu)
        mims.append(mim)
    md.add_source_term_brick(mims[0], "u1", "volumicload")
    md.add_Dirichlet_condition_with_multipliers(mims[0], "u1", mfus[0], TOP)
    md.add_Dirichlet_condition_with_multipliers(mims[1], "u2", mfus[1], BOTTOM)
    slaves = mfus[0].basic_dof_on_region(BOTTOM)
    md.add_initialized_data("r", [args.r])
    md.add_nodal_contact_between_nonmatching_meshes_brick(
        mims[0], mims[1], "u1", "u2", "lambda_n", "r", BOTTOM, TOP, 1, 0, 1
    )
    noisy = ["noisy"] if args.noisy else []
    nit, converged = md.solve("max_res", args.max_res, "max_iter", 200, "lsolver", "mumps", *noisy)
    if not converged:
        raise RuntimeError(f"GetFEM's Newton did not reach max_res {args.max_res} in 200 iterations")
    out = []
    for body, mfu, name in zip(bodies, mfus, names):
        u = np.asarray(md.variable(name)).ravel()
        out.append({"name": body["name"], "nodes": node_numbering(mfu).tolist(), "u": u.reshape(-1, 2).tolist()})
    return {
        "getfem": gf.__version__ if hasattr(gf, "__version__") else "5.4",
        "numpy": np.__version__,
        "force": list(args.force),
        "max_res": args.max_res,
        "newton_iterations": int(nit),
        "bodies": out,
        "slave_nodes": (np.asarray(slaves[0::2]) // 2).astype(int).tolist(),
        "lambda_n": np.asarray(md.variable("lambda_n")).ravel().tolist(),
    }


def parser():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mesh", required=True, help="the JSON of the two bodies' triangles, the upper body first")
    p.add_argument("--force", type=float, nargs=2, default=[0.5, -1.0], help="the upper body's volume force")
    common_arguments(p, 1e-12)
    return p


def summary(args, result):
    active = sum(1 for lam in result["lambda_n"] if lam < 0.0)
    return (
        f"getfem_blocks: {len(result['slave_nodes'])} slave nodes, {active} pressing, "
        f"Newton iterations {result['newton_iterations']}"
    )


def main(argv=None):
    run_main(argv, parser, run, summary)


if __name__ == "__main__":
    main()
