"""Scaling of the FEniCSx engine against the serial Rust solver (issue 12, item 3).

    /usr/bin/python3 python/scripts/bench_engine.py MASSREDIST_BINARY [--sizes 16,32,64]
        [--solid-sizes 4,8,12,16] [--out docs/bench]

Plates: for each size n, scenes/plate-bump-quad-cn.toml (Q1 quads, mass mod3, Crank–Nicolson,
the y-dependent "bump" data, Δt = 0.01) on n × n cells with T = 0.4 (40 steps, the last ~15 in
contact). Solids: for each size n, the unit cube on n × n × n hexahedra (Q1, λ = 0, μ = ½,
ρ = 1, free lateral faces, the paper's data as a plane wave, mod3, Crank–Nicolson), Δt = 0.05,
T = 1.5 (30 steps: impact at t = 1, the last 10 in contact). Each scene is run by
- ``massredist run`` (Rust, serial: sparse Cholesky of K once, the contact Schur complement,
  exact LCP);
- ``massredist run --engine fenicsx --ranks R`` for R = 1, 2, with the step QP's linear solves
  by MUMPS LU ("direct") or by CG + hypre BoomerAMG, rtol 1e-12 ("cg-amg", set through
  PETSC_OPTIONS).
The solver settings (PETSc types) are a column of the table. Times: setup = the process's wall time minus its stepping time (process start, Python imports and
MPI start for the engine, mesh, assembly, factorisation); per step = stepping time / steps (the
Rust summary's ``wall_seconds``, the engine's ``step_seconds``; both include the per-step
observers). Writes ``engine-scaling.csv`` and ``engine-scaling.md`` into the output folder.
Timings depend on the machine and its load: the table says where and when it was measured.
"""
import argparse
import csv
import datetime
import json
import os
import platform
import re
import subprocess
import tempfile
import time

# The base scene: scenes/plate-bump-quad-cn.toml (n x n cells, T shortened below).
BASE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes", "plate-bump-quad-cn.toml")


def scene_text(n):
    """The base scene on n × n cells, T = 0.4 (40 steps; the edge's top starts 1/4 above the
    obstacle, so the contact starts at t ≈ 0.25 and the last steps have active sets)."""
    text = open(BASE).read()
    for key, value in (("nx", n), ("ny", n), ("end", 0.4)):
        text = re.sub(rf"^{key} = .*$", f"{key} = {value}", text, flags=re.M)
    return text

def solid_text(n):
    """The 3D hex solid on n × n × n cells (module docs)."""
    return f"""[solid]
dim = 3
nx = {n}
ny = {n}
nz = {n}
cells = "hex"
[mass]
kind = "mod3"
[scheme]
kind = "crank-nicolson"
[time]
dt = 0.05
end = 1.5
[output]
series = ["u0", "lambda", "energy"]
summary_l2 = false
"""


# The PETSc settings of each engine configuration (no commas: a CSV column).
SOLVERS = {"direct": "SNES vinewtonrsls + KSP preonly + PC lu (MUMPS)",
           "cg-amg": "SNES vinewtonrsls + KSP cg + PC hypre (BoomerAMG) rtol 1e-12"}

CG_AMG = ("-newmark_ksp_type cg -newmark_pc_type hypre -newmark_ksp_rtol 1e-12 "
          "-newmark_ksp_atol 1e-300")


def one_run(binary, scene, out, engine=None, ranks=1, petsc=""):
    cmd = [binary, "run", scene, "--out", out]
    if engine:
        cmd += ["--engine", "fenicsx", "--ranks", str(ranks)]
    env = dict(os.environ, PETSC_OPTIONS=petsc)
    start = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, capture_output=True)
    total = time.perf_counter() - start
    summary = json.load(open(os.path.join(out, "summary.json")))
    if engine:
        e = json.load(open(os.path.join(out, "engine.json")))
        stepping = e["step_seconds"]
    else:
        stepping = summary["wall_seconds"]
    return total, stepping, summary["steps"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("--sizes", default="16,32,64,128")
    ap.add_argument("--solid-sizes", default="4,8,12,16")
    ap.add_argument("--out", default="docs/bench")
    args = ap.parse_args()
    rows = []
    cases = [("plate", int(n), scene_text(int(n)), int(n) * (int(n) + 1))
             for n in args.sizes.split(",") if n]
    # Solid unknowns: 3 components on the nodes off the clamped face x = 1.
    cases += [("solid", int(n), solid_text(int(n)), 3 * int(n) * (int(n) + 1) ** 2)
              for n in args.solid_sizes.split(",") if n]
    with tempfile.TemporaryDirectory() as tmp:
        for geometry, n, text, unknowns in cases:
            scene = os.path.join(tmp, f"{geometry}{n}.toml")
            with open(scene, "w") as f:
                f.write(text)
            configs = [("rust", None, 1, "", "sparse Cholesky once + exact contact LCP")] + [
                (f"fenicsx {solver}", "fenicsx", r, petsc, SOLVERS[solver])
                for solver, petsc in (("direct", ""), ("cg-amg", CG_AMG)) for r in (1, 2)]
            for name, engine, ranks, petsc, solver in configs:
                out = os.path.join(tmp, f"{geometry}-{n}-{name.replace(' ', '-')}-{ranks}")
                total, stepping, steps = one_run(args.binary, scene, out, engine, ranks, petsc)
                rows.append({"geometry": geometry, "n": n, "unknowns": unknowns, "engine": name,
                             "ranks": ranks, "solver": solver, "setup_s": total - stepping,
                             "per_step_ms": 1e3 * stepping / steps})
                print(rows[-1], flush=True)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "engine-scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()[0]
    lines = [
        "# FEniCSx engine against the serial Rust solver",
        "",
        f"Measured {when} on {platform.machine()} with {os.cpu_count()} cores (load average "
        f"{load:.1f} at the end: other jobs shared the cores), by "
        f"`/usr/bin/python3 python/scripts/bench_engine.py {args.binary} --sizes {args.sizes} "
        f"--solid-sizes {args.solid_sizes}`; figure (engine-scaling.png/.svg) by "
        "`massredist bench --scaling-figure docs/bench/engine-scaling.csv`.",
        "Plate: scenes/plate-bump-quad-cn.toml on n × n cells, T = 0.4 (40 steps, the last ~15 "
        "in contact). Solid: the unit cube on n × n × n Q1 hexahedra, λ = 0, μ = ½, mod3, "
        "Crank–Nicolson, Δt = 0.05, T = 1.5 (30 steps, the last 10 in contact). Engine: SNES "
        "vinewtonrsls per step (the solver column: PETSc types; cg-amg set through PETSC_OPTIONS). "
        "Rust: sparse Cholesky once + exact contact LCP.",
        "setup = process wall time − stepping time; per step = stepping time / steps.",
        "",
        "| geometry | n | unknowns | engine | ranks | solver | setup (s) | per step (ms) |",
        "|---|---:|---:|---|---:|---|---:|---:|",
    ]
    lines += [f"| {r['geometry']} | {r['n']} | {r['unknowns']} | {r['engine']} | {r['ranks']} | "
              f"{r['solver']} | {r['setup_s']:.2f} | {r['per_step_ms']:.2f} |" for r in rows]
    with open(os.path.join(args.out, "engine-scaling.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
