"""The budget's cost model frame by frame: why a budget traces what it traces (issues 4, 10).

Renders a still view of SCENE with every candidate traced, takes the median trace time, then
renders ``--frames`` frames with a budget of ``--fraction`` of it (one integrator, so the cost
model and what was learnt carry from frame to frame; the first three frames are the model's
probes) and prints per frame: the trace stage's time and the model's prediction for it, the
objects traced (and those traced by their shadow tier), and the model after the frame: its fixed
part t0, its margin and its rates per ray kind (``budget.CostModel``). Several ``--fraction``
values run one after the other, each with a fresh integrator. ``--json`` also writes every frame's
observation (the rays it traced and was expected to trace, by kind, and the trace's time): the
data to compare cost models on.

    python scripts/cost_model_trace.py scenes/showcase.xml --fraction 0.5 -D resx=320 -D resy=180 -D showcase_dir=../shared/scenes/cbox
"""
from __future__ import annotations

import argparse
import statistics
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--fraction", type=float, nargs="+", default=[0.5],
                        help="the budgets, as fractions of the all-candidates trace time")
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--json", type=Path, default=None, help="write the frames' observations here")
    parser.add_argument("--partial-objects", action="store_true", help="the integrator's partial_objects")
    args = parser.parse_args()

    import json

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.budget import KINDS
    from hybrid_integrator.raster.camera import sensor_to_world

    hi.register()
    scene, _ = load_bench_scene(str(args.scene), dict(d.split("=", 1) for d in args.defines))  # the -D it takes
    camera = sensor_to_world(scene.sensors()[0])
    everything = hi.render_sequence(scene, [camera] * 6, spp=1, layers=False)[2:]
    trace_all = statistics.median(f.stats.times_ms["trace"] for f in everything)
    runs = []
    for fraction in args.fraction:
        budget = fraction * trace_all
        print(f"all candidates: trace {trace_all:.2f} ms; budget {budget:.2f} ms ({fraction:.0%})")
        integrator = hi.api._integrator({"budget_ms": budget, "partial_objects": args.partial_objects})
        frames, last = [], None
        for k in range(args.frames):
            stats = integrator.render_result(scene, seed=k, spp=1, layers=False).stats
            model = integrator.state.cost_model
            observed = model.history[-1] if model.history and model.history[-1] is not last else None
            last = model.history[-1] if model.history else None
            model = model.current()
            rates = " ".join(f"{kind} {rate:.2e}" for kind, rate in model.rates.items())
            print(f"{k:3d}  trace {stats.times_ms['trace']:6.2f}  predicted {stats.predicted_trace_ms:6.2f}  "
                  f"t0 {model.launch_ms:6.2f}  margin {model.margin:4.2f}  rates {rates}  "
                  f"traced {list(stats.selected)} (shadow tiers {list(stats.shadow_only)}; part "
                  f"{stats.partial_object or '-'} {stats.partial_quarters}/4)")
            frames.append({"trace_ms": stats.times_ms["trace"], "predicted_ms": stats.predicted_trace_ms,
                           "pixels": stats.pixels_traced, "selected": list(stats.selected),
                           "shadow_only": list(stats.shadow_only),
                           "observed": None if observed is None else
                           {"rays": observed[0], "ms": observed[1], "expected": observed[2]}})
        runs.append({"fraction": fraction, "budget_ms": budget, "frames": frames})
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"scene": str(args.scene), "variant": args.variant, "trace_all_ms": trace_all,
                                         "kinds": list(KINDS), "runs": runs}, indent=1))

if __name__ == "__main__":
    main()
