"""Where a budgeted frame's host time goes, method by method (issue 10, stop 53).

A budgeted frame on the GPU is host-bound: on the camera path through the 226 objects its host
phases (``FrameStats.host_ms``) add up to about its whole frame time (stop 47: 4.02 of 4.15 ms at
25 %). This probe renders the path (``scripts/budget_benchmark.py``'s) with every candidate, to
learn the all-candidates trace time, then with budgets of ``--budgets`` × that time (``nested``,
the default), and prints per run the median frame and trace ms, the host phases, and the host
time of the renderer's methods and the functions they call, each wrapped with a clock (per call:
median; per frame: the mean over the frames, where a method is not called every frame). With
``--profile``, cProfile's top functions (by own time) of the last run follow.

    python3 docs/results/gpu/issue10/stop53/host_work.py --variant cuda_ad_rgb --resx 1280 --resy 720
"""
from __future__ import annotations

import argparse
import cProfile
import functools
import io
import pstats
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))

#: (module attribute path, method) pairs wrapped with a clock
WRAPPED = [("pipeline.HybridRenderer", m) for m in (
    "_frame", "_visibility", "_select", "_plan", "_plan_ahead", "_device", "_post", "_lesson", "_account", "_draw_ahead",
    "_account_times")] + [
    ("pipeline.StageClock", "frame_times"), ("pipeline", "candidates"), ("pipeline", "plan_frame"),
    ("pipeline", "visibility_terms"), ("pipeline", "learn_ambient"), ("pipeline", "pixel_growth"),
    ("pipeline", "subpixel_offsets"), ("pipeline", "ambient_table"), ("pipeline", "develop"),
    ("pipeline.PassCounts", "read"), ("budget.FrameState", "learn_rays"), ("budget.FrameState", "learn_errors"),
    ("budget.CostModel", "_fit"), ("budget.CostModel", "observe"), ("denoise.Denoiser", "__call__"),
    ("frozen.FrozenFunction", "__call__")]


def wrap_all(hi, times: dict) -> None:
    import importlib

    for where, name in WRAPPED:
        module, _, cls = where.partition(".")
        owner = importlib.import_module(f"hybrid_integrator.{module}")
        if cls:
            owner = getattr(owner, cls)
        original = getattr(owner, name)
        label = f"{where.split('.')[-1]}.{name}"

        def call(*a, _original=original, _label=label, **k):
            start = time.perf_counter()
            try:
                return _original(*a, **k)
            finally:
                times.setdefault(_label, []).append((time.perf_counter() - start) * 1e3)
        setattr(owner, name, functools.wraps(original)(call))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes" / "many_objects.xml")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--budgets", type=float, nargs="+", default=[0.25, 0.5])
    parser.add_argument("--profile", action="store_true", help="cProfile's top functions of the last run")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from budget_benchmark import PROBES, path_scene

    scene, cameras = path_scene(hi, args.scene, args.frames, resx=args.resx, resy=args.resy)
    times: dict[str, list[float]] = {}
    wrap_all(hi, times)
    trace_all = None
    runs = [("all candidates", {}), ("RT baseline", {"primary": "raytrace"})] + \
           [(f"nested {b:.0%}", {"budget_ms": b}) for b in args.budgets]
    for k, (label, props) in enumerate(runs):
        if "budget_ms" in props:
            props = {"budget_ms": props["budget_ms"] * trace_all}
        hi.render_sequence(scene, cameras[:6], spp=1, layers=False, **props)  # compiles, records, probes
        times.clear()
        profile = cProfile.Profile() if args.profile and k == len(runs) - 1 else None
        if profile:
            profile.enable()
        frames = hi.render_sequence(scene, cameras, spp=1, layers=False, **props)
        if profile:
            profile.disable()
        measured = frames[PROBES:] if "budget_ms" in props else frames
        median = lambda key, f=lambda s: s.times_ms: statistics.median(f(m.stats)[key] for m in measured)
        if label == "all candidates":
            trace_all = median("trace")
        host = {p: round(median(p, lambda s: s.host_ms), 3) for p in frames[0].stats.host_ms}
        print(f"\n== {label} {props}: frame {median('total'):.3f} ms, trace {median('trace'):.3f} ms, "
              f"issue {median('issue'):.3f} ms; host phases (sum {sum(host.values()):.3f}): {host}")
        for name, values in sorted(times.items(), key=lambda kv: -sum(kv[1])):
            print(f"  {name:32s} n={len(values):4d}  per call {statistics.median(values):7.3f} ms   "
                  f"per frame {sum(values) / len(frames):7.3f} ms")
        if profile:
            out = io.StringIO()
            pstats.Stats(profile, stream=out).sort_stats("tottime").print_stats(40)
            print(f"cProfile, {len(frames)} frames (divide by it per frame):\n{out.getvalue()}")


if __name__ == "__main__":
    main()
