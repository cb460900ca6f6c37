"""Variants of the trace loop, for measuring what its parts cost (stop 48; not the package's code):
``STOP48_LOOP`` names them, comma-separated, and ``context.py`` applies them before rendering.

- ``nocount``: no rays counted per kind in the loop (the cost model then learns nothing);
- ``masked``: the direct light and the emitter hit as masked code, not Dr.Jit branches.
"""
import os

import drjit as dr
import mitsuba as mi

import hybrid_integrator.trace as trace


class _MaskedDr:
    """Dr.Jit, but ``if_stmt`` runs both branches and selects (masked code)."""

    def __getattr__(self, name):
        return getattr(dr, name)

    @staticmethod
    def if_stmt(args, cond, true_fn, false_fn, label=None):
        t, f = true_fn(*args), false_fn(*args)
        if isinstance(t, tuple):
            return tuple(dr.select(cond, a, b) for a, b in zip(t, f))
        return dr.select(cond, t, f)


def apply() -> list[str]:
    names = [n for n in os.environ.get("STOP48_LOOP", "").split(",") if n]
    if "nocount" in names:
        direct = trace._direct
        trace._kind_of = lambda sampled_type: {k: mi.Bool(False) for k in trace.RAY_KINDS[1:]}
        trace._direct = lambda *a: (direct(*a)[0], mi.UInt32(0))
    if "masked" in names:
        trace.dr = _MaskedDr()
    return names
