"""Stop 68 probe: where a budgeted frame's host time goes, by Python function (cProfile).

The bench's 50 % frame (``hybrid bench``'s ``hybrid@50%`` row: ``stage_times=False``, a still camera
through ``hi.render_sequence``, the budget 50 % of the all-candidates trace's device time), the
default frame and the paper's, rendered first without the profiler (frame times, median), then
under cProfile; prints the functions by own time and by cumulative time, per frame.

    python3 docs/results/gpu/issue10/stop68/host_profile.py --variant cuda_ad_rgb $D scenes/showcase.xml
"""
import argparse
import cProfile
import io
import pstats
import statistics

import mitsuba as mi

parser = argparse.ArgumentParser()
parser.add_argument("scene")
parser.add_argument("--variant", default="llvm_ad_rgb")
parser.add_argument("-D", action="append", default=[])
parser.add_argument("--frames", type=int, default=60)
parser.add_argument("--kinds", nargs="+", default=["paper", "default"])
parser.add_argument("--top", type=int, default=45)
args = parser.parse_args()
mi.set_variant(args.variant)
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

scene, _ = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.D))
camera = sensor_to_world(scene.sensors()[0])
for kind in args.kinds:
    props = {"stage_times": False, **({"effects": "shadow,reflection,refraction"} if kind == "paper" else {})}
    every = hi.render_sequence(scene, [camera] * 23, layers=False, **{**props, "stage_times": True})
    trace_all = statistics.median(r.stats.times_ms["trace"] for r in every[3:])
    budget = {**props, "budget_ms": 0.5 * trace_all}
    plain = hi.render_sequence(scene, [camera] * (5 + args.frames), layers=False, **budget)[5:]
    print(f"== {kind}: all-candidates trace {trace_all:.3f} ms; 50 % frame {statistics.median(r.stats.times_ms['total'] for r in plain):.3f} ms, "
          f"issue {statistics.median(r.stats.times_ms['issue'] for r in plain):.3f} ms; host phases (median ms): "
          + ", ".join(f"{k} {statistics.median(r.stats.host_ms[k] for r in plain):.3f}" for k in plain[0].stats.host_ms),
          flush=True)
    profiler = cProfile.Profile()
    profiler.enable()
    hi.render_sequence(scene, [camera] * args.frames, layers=False, **budget)
    profiler.disable()
    for order in ("tottime", "cumulative"):
        out = io.StringIO()
        pstats.Stats(profiler, stream=out).sort_stats(order).print_stats(args.top)
        print(f"-- {kind}, by {order} ({args.frames} frames)\n" + out.getvalue().split("\n", 6)[-1], flush=True)
