"""The series rows and the summary of a run, with the columns and keys of the Rust run
(src/observe.rs, src/run/plate.rs, src/driver.rs). Pure: fed one sample (a dict of numbers) per
state shown; no dolfinx, no MPI (rank 0 feeds it values already reduced over the ranks).
"""
import math

COLUMNS = ("u0", "u1", "u_mean", "lambda", "contact_force", "energy", "l2_error", "exact_u0",
           "exact_lambda", "pivots")


class SummaryObserver:
    """Accumulates summary.json exactly as src/observe.rs SummaryObserver does."""

    def __init__(self, steps, h, dt, lower0, exact=None, energy_exact=math.nan, first_contact=None,
                 with_l2=False):
        self.steps, self.h, self.dt, self.lower0 = steps, h, dt, lower0
        self.exact, self.energy_exact, self.first_contact = exact, energy_exact, first_contact
        self.with_l2 = with_l2 and exact is not None
        self.linf_l2 = self.linf_interp = self.max_contact = self.lambda_sq = 0.0
        self.energy = [math.nan, math.nan, math.inf, -math.inf]
        self.prev_energy = math.nan
        self.max_increase = (-math.inf, 0)
        self.max_increase_after_first = -math.inf
        self.first_impact = self.first_release = None
        self.final_u0 = self.final_u_mean = self.final_force = math.nan
        self.min_u0, self.max_lambda, self.max_product = math.inf, -math.inf, 0.0
        self.max_y, self.max_pivots, self.last_n, self.last_term = 0.0, 0, 0, 0.0
        self.divergence = None

    def observe(self, s):
        n, t, e = s["n"], s["t"], s["energy"]
        self.last_n = n
        if n == 0:
            self.energy[0] = e
        else:
            de = e - self.prev_energy
            if de > self.max_increase[0]:
                self.max_increase = (de, n)
            if n >= 2:
                self.max_increase_after_first = max(self.max_increase_after_first, de)
        self.prev_energy = e
        self.energy[1] = e
        self.energy[2], self.energy[3] = min(self.energy[2], e), max(self.energy[3], e)
        u0 = s["u0"]
        self.final_u0 = u0
        self.min_u0 = min(self.min_u0, s["min_uc"])
        self.max_lambda = max(self.max_lambda, s["max_lambda"])
        self.max_product = max(self.max_product, s["max_product"])
        self.max_y = max(self.max_y, s["y_variation"])
        self.max_pivots = max(self.max_pivots, s["pivots"])
        self.final_u_mean, self.final_force = s["u_mean"], s["contact_force"]
        # Impact and release node by node (src/observe.rs): the first t with SOME contact value
        # on its bound, release the first later t with none.
        if self.first_impact is None:
            if s["min_uc"] <= self.lower0:
                self.first_impact = t
        elif self.first_release is None and s["min_uc"] > self.lower0:
            self.first_release = t
        if self.exact is not None:
            self.max_contact = max(self.max_contact, abs(u0 - self.exact.u0(t)))
            w = 0.5 if n in (0, self.steps) else 1.0
            self.last_term = self.dt * (s["lambda"] - self.exact.lambda_(t)) ** 2
            self.lambda_sq += w * self.last_term
            if self.with_l2:
                self.linf_l2 = max(self.linf_l2, s["l2_error"])
                self.linf_interp = max(self.linf_interp, s["exact_interp_norm"])

    def diverged(self, divergence):
        if self.last_n != self.steps:
            self.lambda_sq = max(self.lambda_sq - 0.5 * self.last_term, 0.0)
        self.divergence = divergence

    def finish(self, wall_seconds):
        has = self.exact is not None
        ex = lambda v: v if has else None
        l2 = lambda v: v if has and self.with_l2 else None
        shift = lambda t, k: t - self.first_contact[k] if t is not None and self.first_contact else None
        return {
            "status": "diverged" if self.divergence else "ok",
            "divergence": self.divergence,
            "steps": self.steps, "h": self.h, "dt": self.dt,
            "linf_l2_error": l2(self.linf_l2),
            "linf_l2_error_relative": l2(self.linf_l2 / self.linf_interp if self.linf_interp else math.nan),
            "max_contact_error": ex(self.max_contact),
            "l2_lambda_error": ex(math.sqrt(self.lambda_sq)),
            "energy_initial": self.energy[0], "energy_final": self.energy[1],
            "energy_min": self.energy[2], "energy_max": self.energy[3],
            "energy_exact": ex(self.energy_exact),
            "first_impact_time": self.first_impact, "first_release_time": self.first_release,
            "impact_time_shift": shift(self.first_impact, 0),
            "release_time_shift": shift(self.first_release, 1),
            "final_u0": self.final_u0, "min_u0": self.min_u0, "max_lambda": self.max_lambda,
            "max_complementarity_product": self.max_product,
            "energy_max_increase": self.max_increase[0],
            "energy_max_increase_step": self.max_increase[1],
            "energy_max_increase_after_first": self.max_increase_after_first,
            "max_y_variation": self.max_y,
            "max_pivots": self.max_pivots,
            "final_u_mean": self.final_u_mean, "final_contact_force": self.final_force,
            "wall_seconds": wall_seconds,
        }


def series_row(columns, s, exact):
    """One row of series.csv: t, then the requested columns (src/observe.rs SeriesRecorder)."""
    t = s["t"]
    values = {"u0": s["u0"], "u1": s.get("u1", math.nan), "u_mean": s["u_mean"], "lambda": s["lambda"],
              "contact_force": s["contact_force"], "energy": s["energy"], "l2_error": s["l2_error"],
              "exact_u0": exact.u0(t) if exact else math.nan,
              "exact_lambda": exact.lambda_(t) if exact else math.nan, "pivots": float(s["pivots"])}
    return [t] + [values[c] for c in columns]
