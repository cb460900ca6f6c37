"""Budgets on the bench scenes' own (still) cameras, frame by frame: how many frames trace
something, with nested selection as it is and as it was before stop 54 (issue 10, stop 54).

Until stop 54, nested selection (``selection_graph.select_rows``) took the longest run of nodes by
decreasing R/C that fits, so where the first node alone costs more than the budget it selected
nothing; since, the run starts at the first node that fits alone. The bench reports the median
frame's pixels traced: on the H200 the showcase at 25 % traced none in three of four runs. This
probe renders each scene with every candidate (the all-candidates trace time), then at each of
``--fractions`` of it for ``--frames`` frames after the cost model's three probe frames, with
``rule`` ``run from the first that fits`` (the code) and ``first node or nothing`` (the rule
before, restored in this process for the comparison), and prints per run the fraction of frames
that trace something, of frames within budget + 10 %, the mean relevance captured and the median
frame and trace ms.

    python3 docs/results/gpu/issue10/stop54/still_budget.py --variant cuda_ad_rgb $D scenes/showcase.xml ...
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))
PROBES = 3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+", type=Path)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.25, 0.5, 0.75])
    parser.add_argument("--old-first", action="store_true", help="the rule before first in each pair of runs")
    parser.add_argument("-D", dest="defines", action="append", default=[], help="scene parameter NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import selection_graph
    from hybrid_integrator.api import _integrator

    hi.register()
    params = dict(d.split("=", 1) for d in args.defines)
    from hybrid_integrator import budget

    rules = _rules(selection_graph, budget)
    for path in args.scenes:
        scene = hi.load_scene(path, **{k: v for k, v in params.items() if f"${k}" in path.read_text()})
        full = _integrator({})
        trace = [full.render_result(scene, seed=k, spp=1, layers=False).stats.times_ms["trace"] for k in range(12)]
        all_ms = statistics.median(trace[2:])
        print(f"{path.name}: all-candidates trace {all_ms:.2f} ms", flush=True)
        for fraction in args.fractions:
            for rule, (run, rows) in (reversed(rules.items()) if args.old_first else rules.items()):
                selection_graph._run, budget.select_rows = run, rows
                integrator = _integrator({"budget_ms": fraction * all_ms})
                stats = [integrator.render_result(scene, seed=k, spp=1, layers=False).stats
                         for k in range(PROBES + args.frames)][PROBES:]
                traced = np.array([s.pixels_traced > 0 for s in stats])
                within = np.array([s.times_ms["trace"] <= 1.1 * fraction * all_ms for s in stats])
                print(f"  {fraction:.0%} {rule:30s} frames that trace {traced.mean():.0%}, within budget + 10 % "
                      f"{within.mean():.0%}, relevance {np.mean([s.relevance_captured for s in stats]):.3f}, "
                      f"frame {statistics.median(s.times_ms['total'] for s in stats):.2f} ms, "
                      f"trace {statistics.median(s.times_ms['trace'] for s in stats):.2f} ms", flush=True)
        selection_graph._run, budget.select_rows = rules["run from the first that fits"]


def _rules(selection_graph, budget) -> dict:
    """Per rule, the ``_run`` and the ``select_rows`` to patch in: the rule before stop 54 keeps a
    call's first run, even empty (``select_rows`` calls ``_run`` a second time only to retry an
    empty run from the first node that fits)."""
    new_run, rows = selection_graph._run, selection_graph.select_rows
    calls = [0]

    def first_run(order, cost, limit):
        calls[0] += 1
        return new_run(order, cost, limit) if calls[0] == 1 else order[:0]

    def counted_rows(*args, **kwargs):
        calls[0] = 0
        return rows(*args, **kwargs)

    return {"run from the first that fits": (new_run, rows), "first node or nothing": (first_run, counted_rows)}


if __name__ == "__main__":
    main()
