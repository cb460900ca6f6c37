"""The host time of the CUDA driver calls a frame makes itself (interop, the counts' copy, the
denoiser's copies and events), call by call (issue 10, stop 58).

Stop 53's ``host_work.py`` under cProfile put ~1.1 ms per budgeted frame on the H200's host into
``raster.interop._Driver.call_current``, the one function through which the package calls the CUDA
driver (ctypes). That sum mixes work with waits (``cuEventSynchronize`` waits for the frame's
counts). This probe wraps ``call_current`` and ``_Driver.current`` (the context push and pop
around each group of calls) with a clock, renders the 226 objects' camera path as
``scripts/budget_benchmark.py`` does (all candidates, the RT baseline, nested budgets of
``--budgets`` × the all-candidates trace time), and prints per driver function its calls per
frame, median host ms per call and host ms per frame.

    python3 docs/results/gpu/issue10/stop58/driver_calls.py --variant cuda_ad_rgb --resx 1280 --resy 720
"""
from __future__ import annotations

import argparse
import contextlib
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))


def wrap_driver(times: dict) -> None:
    """Clock every ``_Driver.call_current`` by driver function name, and ``_Driver.current``."""
    from hybrid_integrator.raster import interop

    call_current, current = interop._Driver.call_current, interop._Driver.current

    def timed_call(self, name, *args):
        start = time.perf_counter()
        try:
            return call_current(self, name, *args)
        finally:
            times.setdefault(name, []).append((time.perf_counter() - start) * 1e3)

    @contextlib.contextmanager
    def timed_current(self):
        start = time.perf_counter()
        with current(self):
            inner = time.perf_counter()
            yield
            after = time.perf_counter()
        times.setdefault("(context push + pop)", []).append((inner - start + time.perf_counter() - after) * 1e3)

    interop._Driver.call_current, interop._Driver.current = timed_call, timed_current


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes" / "many_objects.xml")
    parser.add_argument("--variant", default="cuda_ad_rgb")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--resx", type=int, default=1280)
    parser.add_argument("--resy", type=int, default=720)
    parser.add_argument("--budgets", type=float, nargs="+", default=[0.5])
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from budget_benchmark import PROBES, path_scene

    scene, cameras = path_scene(hi, args.scene, args.frames, resx=args.resx, resy=args.resy)
    times: dict[str, list[float]] = {}
    wrap_driver(times)
    trace_all = None
    runs = [("all candidates", {}), ("RT baseline", {"primary": "raytrace"})] + \
           [(f"nested {b:.0%}", {"budget_ms": b}) for b in args.budgets]
    for label, props in runs:
        if "budget_ms" in props:
            props = {"budget_ms": props["budget_ms"] * trace_all}
        hi.render_sequence(scene, cameras[:6], spp=1, layers=False, **props)  # compiles, records, probes
        times.clear()
        frames = hi.render_sequence(scene, cameras, spp=1, layers=False, **props)
        measured = frames[PROBES:] if "budget_ms" in props else frames
        median = lambda key: statistics.median(m.stats.times_ms[key] for m in measured)
        if label == "all candidates":
            trace_all = median("trace")
        print(f"\n== {label}: frame {median('total'):.3f} ms, trace {median('trace'):.3f} ms")
        for name, values in sorted(times.items(), key=lambda kv: -sum(kv[1])):
            print(f"  {name:28s} per frame {len(values) / len(frames):5.2f} calls  per call {statistics.median(values):7.4f} ms"
                  f"  max {max(values):7.3f}   per frame {sum(values) / len(frames):7.4f} ms")


if __name__ == "__main__":
    main()
