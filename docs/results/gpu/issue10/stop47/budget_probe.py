"""How much of a budget the selection spends, and why (issue 10, stop 47): per scene, the trace time
of every candidate (T), then budgets of 25 / 50 / 75 % of T, each from a fresh state for FRAMES
frames; per budget the median trace time against the budget, the cost model (t0, rates per kind,
margin) and the plan's rows (relevance, predicted cost, picked). No denoiser: the selection does
not depend on it.

    python docs/results/gpu/issue10/stop47/budget_probe.py --variant cuda_ad_rgb SCENE... -D resx=1280 -D resy=720 …
"""
from __future__ import annotations

import argparse
import json
import statistics

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=24)
    parser.add_argument("--fractions", default="0.25,0.5,0.75")
    parser.add_argument("--quantile", type=float, default=None, help="the cost model's margin quantile (default: its own)")
    parser.add_argument("-D", dest="defines", action="append", default=[])
    parser.add_argument("-o", dest="out", default=None)
    args = parser.parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import renderer
    from hybrid_integrator.budget import CostModel, FrameState
    from hybrid_integrator.pipeline import HybridSettings

    defines = dict(d.split("=", 1) for d in args.defines)
    report = []
    for path in args.scenes:
        text = open(path).read()
        scene = hi.load_scene(path, **{k: v for k, v in defines.items() if f"${k}" in text or k in ("resx", "resy")})
        frames = renderer(scene)
        state, trace = FrameState(), []
        for seed in range(8):
            f = frames.render(HybridSettings(denoise=False), seed=seed, spp=1, state=state, layers=False)
            trace.append(f.stats.times_ms["trace"])
        full = statistics.median(trace[2:])
        print(path, "all candidates: trace", round(full, 3), "ms", flush=True)
        entry = {"scene": path, "all_trace_ms": full, "budgets": []}
        for fraction in (float(x) for x in args.fractions.split(",")):
            settings = HybridSettings(denoise=False, budget_ms=fraction * full)
            model = CostModel() if args.quantile is None else CostModel(quantile=args.quantile)
            state, rows = FrameState(cost_model=model), []
            for seed in range(args.frames):
                f = frames.render(settings, seed=seed, spp=1, state=state, layers=False)
                rows.append((f.stats.predicted_trace_ms, f.stats.times_ms["trace"], f.stats.pixels_traced,
                             len(f.stats.selected), len(f.stats.shadow_only)))
            warm = rows[8:]
            m = state.cost_model.current()
            frame = frames._frame(settings, scene.sensors()[0], (), 1, False)
            plan = frames._plan(settings, frame, state, state.coverage)
            c = plan.candidates
            cost = m.extra_rows(c.rays)
            picked = np.zeros(len(c), dtype=bool)
            picked[plan.picked] = True
            order = np.argsort(-c.relevance)
            b = {"fraction": fraction, "budget_ms": fraction * full,
                 "trace_ms": statistics.median(r[1] for r in warm), "predicted_ms": statistics.median(r[0] for r in warm),
                 "pixels": statistics.median(r[2] for r in warm), "objects": statistics.median(r[3] for r in warm),
                 "tiers": statistics.median(r[4] for r in warm), "over": sum(r[1] > 1.1 * fraction * full for r in warm) / len(warm),
                 "t0": m.launch_ms, "rates": m.rates, "margin": m.margin, "room": fraction * full - m.launch(),
                 "rows": [{"name": frames.objects.names[c.index[i]], "tier": bool(c.tier[i]), "relevance": float(c.relevance[i]),
                           "cost": float(cost[i]), "pixels": int(c.pixels[i]), "picked": bool(picked[i])} for i in order[:14]]}
            entry["budgets"].append(b)
            print(f"  {fraction:.2f}: budget {b['budget_ms']:.2f} trace {b['trace_ms']:.2f} predicted {b['predicted_ms']:.2f} "
                  f"over+10% {b['over']:.2f} t0 {m.launch_ms:.3f} margin {m.margin:.2f} room {b['room']:.2f} "
                  f"rates(ns/ray) {', '.join(f'{k} {v * 1e6:.1f}' for k, v in m.rates.items())}", flush=True)
            for r in b["rows"]:
                print(f"      {'*' if r['picked'] else ' '} {r['name'][:24]:24s} {'tier ' if r['tier'] else 'whole'} "
                      f"R {r['relevance']:.4f} cost {r['cost']:.3f} px {r['pixels']}", flush=True)
        report.append(entry)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()
