# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # A Δt × mass sweep: work against precision
#
# One scene (the paper's bar with Crank–Nicolson), its time step and mass redistribution changed
# key by key with `Scene.replace` (the mesh refined with it, h = Δt), each run's L∞(0,T; L²) error and wall time read from its
# summary: a work–precision diagram. The runs go in two parallel threads (the GIL is released
# while Rust steps), so a run's wall time includes what it shares of the machine: for timings
# to quote, use `max_workers=1`. Run from the repository root; writes `work_precision.png`.

# %%
import os
from concurrent.futures import ThreadPoolExecutor

try:
    import matplotlib
except ModuleNotFoundError:
    raise SystemExit("this demo draws with matplotlib: pip install matplotlib (or pip install './python/pkg[demos]')")

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import massredist as mr

base = mr.load("scenes/fig11-mod3.toml").replace({"output.series": ["energy"]})
masses = ["standard", "mod1", "mod2", "mod3"]
steps = [1 / 50, 1 / 100, 1 / 200, 1 / 400, 1 / 800]
scenes = {
    (m, dt): base.replace({"mass.kind": m, "time.dt": dt, "bar.elements": round(1 / dt)}) for m in masses for dt in steps
}

# %%
with ThreadPoolExecutor(max_workers=2) as pool:
    runs = dict(zip(scenes, pool.map(mr.run, scenes.values())))

# %%
fig, ax = plt.subplots(figsize=(6, 4.5))
for m in masses:
    work = [runs[m, dt].summary["wall_seconds"] for dt in steps]
    error = [runs[m, dt].summary["linf_l2_error"] for dt in steps]
    ax.loglog(work, error, "o-", label=m)
    print(m, " ".join(f"{e:.3e}" for e in error))
ax.set_xlabel("wall time of the run [s]")
ax.set_ylabel(r"$\max_n \|u_h(t_n) - u(t_n)\|_{L^2}$")
ax.set_title("Crank–Nicolson, h = Δt = 1/50 … 1/800")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(os.environ.get("MASSREDIST_DEMO_OUT", "."), "work_precision.png"), dpi=120)

# %% [markdown]
# Every run went to its end and the error falls with Δt for the redistributed masses:

# %%
assert all(r.ok for r in runs.values())
for m in ["mod2", "mod3"]:
    assert runs[m, steps[-1]].summary["linf_l2_error"] < runs[m, steps[0]].summary["linf_l2_error"]
