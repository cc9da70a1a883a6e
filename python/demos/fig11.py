# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # The paper's Figure 11 in ten lines
#
# Crank–Nicolson on the impacting bar (6 elements, Δt = 1/100, T = 3): the contact
# displacement u(0, t) and reaction λ(t) with the standard mass and the three redistributed
# masses, against the exact solution. Run from the repository root:
# `python python/demos/fig11.py` (writes `fig11.png`, or into `$MASSREDIST_DEMO_OUT`).

# %%
import os

try:
    import matplotlib
except ModuleNotFoundError:
    raise SystemExit("this demo draws with matplotlib: pip install matplotlib (or pip install './python/pkg[demos]')")
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import massredist as mr

fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
for kind in ["standard", "mod1", "mod2", "mod3"]:
    run = mr.run(f"scenes/fig11-{kind}.toml")
    top.plot(run.series["t"], run.series["u0"], label=kind); bottom.plot(run.series["t"], run.series["lambda"])
t, ex = run.series["t"], mr.exact("scenes/fig11-mod3.toml")
top.plot(t, ex.u0(t), "k--", label="exact"); bottom.plot(t, ex.reaction(t), "k--"); top.legend()
top.set_ylabel("u(0, t)"); bottom.set_ylabel("λ(t)"); bottom.set_xlabel("t")
fig.savefig(os.path.join(os.environ.get("MASSREDIST_DEMO_OUT", "."), "fig11.png"), dpi=120)

# %% [markdown]
# The standard mass chatters (λ oscillates while in contact); the redistributed masses follow
# the exact solution. The same numbers as `massredist run scenes/fig11-*.toml`.
