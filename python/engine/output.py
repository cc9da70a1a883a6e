"""The run folder, as src/output.rs writes it: series.csv (shortest round-trip numbers, Rust's
format), summary.json (keys in Rust's order, non-finite numbers as null like serde_json),
scene.resolved.toml, and the marker file; written into a temporary sibling
``.NAME.tmp-<pid>`` and renamed into place, so the folder appears complete or not at all.
Only rank 0 calls these.
"""
import json
import math
import os
import shutil
import sys

import numpy as np

MARKER = ".massredist-output"


def fmt(x):
    """src/output.rs fmt_f64: plain for 0 and 1e-4 ≤ |x| < 1e15, else Rust's `{:e}`."""
    x = float(x)
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if x == 0.0 or 1e-4 <= abs(x) < 1e15:
        return np.format_float_positional(x, trim="-")
    m, e = np.format_float_scientific(x, trim="-", exp_digits=1).split("e")
    return f"{m}e{int(e)}"


def series_csv(header, rows):
    return "\n".join([",".join(header)] + [",".join(fmt(v) for v in r) for r in rows]) + "\n"


def _json_ready(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _json_ready(v) for k, v in value.items()}
    return value


def summary_json(head, summary):
    return json.dumps(_json_ready({**head, **summary}), indent=2) + "\n"


class OutputError(Exception):
    """The output folder cannot be used (exit code 2, as a Rust run)."""


def _listed(path):
    try:
        with open(os.path.join(path, MARKER)) as f:
            return set(f.read().splitlines()[1:])
    except OSError:
        return None


def prepare(out):
    """The temporary sibling of ``out`` (created), after the checks of src/output.rs without
    --force: ``out`` is absent, an empty folder, or a folder massredist wrote (marked, holding
    only what its marker lists)."""
    out = os.path.abspath(out)
    if os.path.lexists(out):
        if not os.path.isdir(out) or os.path.islink(out):
            raise OutputError(f"{out} is not a folder; choose another output folder")
        entries = set(os.listdir(out)) - {MARKER}
        listed = _listed(out)
        if entries and (listed is None or not entries <= listed):
            raise OutputError(f"{out} is a folder massredist did not write (or holds entries its "
                              f"marker does not list); choose another output folder")
    parent, name = os.path.split(out)
    os.makedirs(parent, exist_ok=True)
    staging = os.path.join(parent, f".{name}.tmp-{os.getpid()}")
    os.mkdir(staging)
    return staging


def commit(staging, out):
    """Writes the marker listing the entries, then renames ``staging`` to ``out`` (replacing a
    folder massredist wrote, which ``prepare`` checked)."""
    names = sorted(n for n in os.listdir(staging) if n != MARKER)
    head = (f"massredist engine (python/fenicsx_engine.py) wrote this folder (`{' '.join(sys.argv)}`); "
            "a later massredist run may replace it. Entries written:\n")
    with open(os.path.join(staging, MARKER), "w") as f:
        f.write(head + "".join(n + "\n" for n in names))
    out = os.path.abspath(out)
    if os.path.isdir(out):
        old = staging + "-old"
        os.rename(out, old)
        os.rename(staging, out)
        shutil.rmtree(old)
    else:
        os.rename(staging, out)


def write_files(folder, files):
    for name, text in files.items():
        with open(os.path.join(folder, name), "w") as f:
            f.write(text)
