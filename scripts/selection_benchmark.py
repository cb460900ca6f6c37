"""How much relevance each selector captures against the optimum, and what it costs to compute.

Random instances: N objects with costs ~ U(1, 10) and relevances ~ U(0, 1) (independent, as when
relevance is screen presence and cost is material complexity), budgets of 25 %, 50 % and 75 % of
the total cost. For each selector (``graph`` with N = 4 relevance pointers, ``greedy`` by R/C,
``exact`` 0/1 knapsack through HiGHS), the captured relevance divided by the optimum's, and the
median time per selection.

    python scripts/selection_benchmark.py -o docs/results/cpu/selection
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import numpy as np

from hybrid_integrator.selection_graph import SELECTORS, Node, select

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--instances", type=int, default=200)
    parser.add_argument("--sizes", type=int, nargs="*", default=[10, 50, 200])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs/results/cpu/selection")
    args = parser.parse_args()
    rng = np.random.default_rng(2012)
    rows = []
    for n in args.sizes:
        for fraction in (0.25, 0.5, 0.75):
            captured = {m: [] for m in SELECTORS}
            times = {m: [] for m in SELECTORS}
            for _ in range(args.instances):
                nodes = [Node(k, float(c), float(r)) for k, (c, r) in enumerate(zip(rng.uniform(1, 10, n), rng.uniform(0, 1, n)))]
                budget = fraction * sum(x.cost for x in nodes)
                value = {}
                for method in SELECTORS:
                    start = time.perf_counter()
                    chosen = select(method, nodes, budget)
                    times[method].append((time.perf_counter() - start) * 1e3)
                    value[method] = sum(x.relevance for x in chosen)
                for method in SELECTORS:
                    captured[method].append(value[method] / value["exact"] if value["exact"] > 0 else 1.0)
            for method in SELECTORS:
                rows.append({"objects": n, "budget_fraction": fraction, "selector": method,
                             "mean_captured": float(np.mean(captured[method])), "min_captured": float(np.min(captured[method])),
                             "median_ms": statistics.median(times[method])})
            print(rows[-3:], flush=True)
    command = f"python scripts/selection_benchmark.py --instances {args.instances} --sizes {' '.join(map(str, args.sizes))}"
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps({"command": command, "rows": rows}, indent=2))
    md = ["# Selectors on random instances", "", f"Command: `{command}`", "",
          "Relevance captured / optimum (mean and worst over instances), median time per selection.", "",
          "| objects | budget | selector | mean captured | worst captured | median ms |", "|---|---|---|---|---|---|"]
    md += [f"| {r['objects']} | {r['budget_fraction']:.0%} | {r['selector']} | {r['mean_captured']:.4f} | {r['min_captured']:.4f} | {r['median_ms']:.3f} |" for r in rows]
    args.output.with_suffix(".md").write_text("\n".join(md) + "\n")


if __name__ == "__main__":
    main()
