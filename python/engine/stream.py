"""The engine's channel to ``massredist`` (src/engine/stream.rs has the protocol): rank 0 writes
one framed record per line to the process's original standard output and reads the reply to
each state on its standard input; everything else any rank prints goes to standard error.

Records are ``@massredist/1 `` followed by a JSON object whose numbers Python writes with
``repr`` (shortest round-trip: no digit lost); a non-finite number is the string ``"nan"``,
``"inf"`` or ``"-inf"``. The replies: ``go`` (the state is shown: go on), ``last`` (shown, and
the run stops there), ``hide`` (not shown: its energy is not finite; stop); the end of the input
counts as ``hide``. Collective: every rank calls :meth:`Channel.state`; rank 0 alone talks to
massredist and broadcasts the reply.
"""
import json
import math
import os
import sys

PREFIX = "@massredist/1 "
REPLIES = ("go", "last", "hide")


def _number(x):
    x = float(x)
    return x if math.isfinite(x) else repr(x)   # "nan", "inf", "-inf"


def encode(kind, fields):
    """One protocol line (with its newline): floats as numbers or non-finite strings, bools and
    ints as JSON."""
    return PREFIX + json.dumps({"kind": kind, **_values(fields)}) + "\n"


def _values(fields):
    """Numbers as in :func:`encode`; nested objects (a body's reports) and lists of numbers too."""
    out = {}
    for k, v in fields.items():
        if isinstance(v, dict):
            out[k] = _values(v)
        elif isinstance(v, (list, tuple)):
            out[k] = [_number(x) for x in v]
        else:
            out[k] = v if isinstance(v, (bool, int)) and not isinstance(v, float) else _number(v)
    return out


def isolate_stdout():
    """Keeps the process's standard output for the protocol (returned as a text stream) and
    points file descriptor 1 at standard error, so that nothing else (Python, PETSc, dolfinx's
    C++ layer) can write into the record stream. Call before importing dolfinx."""
    sys.stdout.flush()
    proto = os.fdopen(os.dup(1), "w", buffering=1)
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    return proto


class Channel:
    """Rank 0's records and massredist's replies (see the module docs)."""

    def __init__(self, comm, out, replies=sys.stdin):
        self.comm, self.out, self.replies = comm, out, replies

    def send(self, kind, **fields):
        if self.comm.rank == 0:
            self.out.write(encode(kind, fields))
            self.out.flush()

    def state(self, sample):
        """Sends one state's sample and returns massredist's reply (on every rank)."""
        reply = None
        if self.comm.rank == 0:
            self.send("sample", **sample)
            reply = self.replies.readline().strip() or "hide"
            if reply not in REPLIES:
                raise RuntimeError(f"massredist replied {reply!r}; expected one of {', '.join(REPLIES)}")
        return self.comm.bcast(reply, root=0)
