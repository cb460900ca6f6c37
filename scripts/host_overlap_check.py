"""Checks of the frame's host work behind the GPU (issue 10, stop 24).

1. **Counts.** On CUDA a frame's counts reach the host behind its device passes
   (``interop.HostCopy``: an asynchronous copy and an event), and the host learns from them while
   the GPU still denoises. For a default frame, a budgeted one and a 2-spp one, this prints whether
   the words so read equal a plain read-back of the same arrays after the frame.
2. **Kernel history.** The stage times come from Dr.Jit's kernel history (a CUDA event pair per
   kernel). This renders DR and default frames with the history on (as the pipeline runs) and off,
   interleaved, and prints the median frame time of each.

    python3 scripts/host_overlap_check.py --variant cuda_ad_rgb scenes/armadillo_glass.xml scenes/showcase.xml -D resx=1280 -D resy=720 -D models_dir=...
"""
from __future__ import annotations

import argparse
import contextlib
import statistics
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="cuda_ad_rgb")
    parser.add_argument("--frames", type=int, default=40, help="frames per kind for the kernel history (half of them with it)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import sensor_to_world
    from hybrid_integrator import pipeline
    from hybrid_integrator.bench import load_bench_scene

    defines = dict(d.split("=", 1) for d in args.defines)
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        camera = sensor_to_world(scene.sensors()[0])
        renderer = hi.api.renderer(scene)
        if renderer._counts is not None:
            seen = {"words": [], "outputs": []}
            read, device = pipeline.PassCounts.read.__func__, renderer._device

            def spy_read(cls, words, n):
                seen["words"].append(words.copy())
                return read(cls, words, n)

            def spy_device(*a):
                seen["outputs"].append(device(*a))
                return seen["outputs"][-1]

            pipeline.PassCounts.read, renderer._device = classmethod(spy_read), spy_device
            try:
                for spp, props in ((1, {}), (1, {"budget_ms": 2.0}), (2, {})):
                    seen["words"].clear()
                    seen["outputs"].clear()
                    frames = hi.render_sequence(scene, [camera] * 6, spp=spp, layers=False, **props)
                    plain = [np.array(o.counts) for o in seen["outputs"][-spp:]]
                    equal = all(np.array_equal(a, b) for a, b in zip(plain, seen["words"][-spp:]))
                    print(f"{path.name} {spp} spp {props}: counts equal a plain read-back: {equal} "
                          f"(pixels traced {frames[-1].stats.pixels_traced}, rays {frames[-1].stats.secondary_rays})")
            finally:
                pipeline.PassCounts.read = classmethod(read)
                del renderer._device
        history = dr.scoped_set_flag
        for label, props in (("DR", {"candidates": ""}), ("default", {})):
            integrator = hi.api._integrator(dict(props))
            for seed in range(4):  # compiles and records
                integrator.render_result(scene, seed=seed, spp=1, layers=False)
            totals = {"with kernel history": [], "without": []}
            try:
                for k in range(args.frames):
                    on = k % 2 == 0
                    dr.scoped_set_flag = history if on else (lambda *a, **kw: contextlib.nullcontext())
                    frame = integrator.render_result(scene, seed=10 + k, spp=1, layers=False)
                    totals["with kernel history" if on else "without"].append(frame.stats.times_ms["total"])
            finally:
                dr.scoped_set_flag = history
            print(f"{path.name} {label} frame, median ms:", {k: round(statistics.median(v), 3) for k, v in totals.items()})


if __name__ == "__main__":
    main()
