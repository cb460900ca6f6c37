"""Host time of the budget's cost-model fit (``budget.CostModel``), which a budgeted frame runs
once, before its next plan is made (``pipeline.HybridRenderer._account``, while the GPU denoises).

A full window of observations (48 passes; rays by kind drawn from a fixed seed, times from a
linear model with noise), then ``observe`` one more pass (which refits) ``--repeats`` times; prints
the median microseconds per fit.

    python scripts/cost_model_fit.py
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2000)
    args = parser.parse_args()

    import numpy as np

    from hybrid_integrator.budget import CostModel
    from hybrid_integrator.heuristic import KINDS

    rng = np.random.default_rng(7)
    model = CostModel()

    def observe() -> None:
        rays = dict(zip(KINDS, rng.uniform(0.0, 2e6, len(KINDS))))
        model.observe(rays, 0.4 + 3e-6 * sum(rays.values()) * rng.uniform(0.9, 1.1))

    for _ in range(model.window):
        observe()
    times = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        observe()
        times.append((time.perf_counter() - start) * 1e6)
    print(f"cost model fit over {len(model.history)} observations: median {statistics.median(times):.0f} µs "
          f"per observe (refit included), {args.repeats} repeats")


if __name__ == "__main__":
    main()
