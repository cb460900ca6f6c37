"""Host time of a frame's methods, default and budgeted (issue 10).

Wraps the renderer's own methods, the raster pass's parts and the heuristic's functions in one
process (no copy of their code) with ``time.perf_counter`` and renders the 226-object camera path
(``scenes/many_objects.xml`` and its ``_path.json``), or with ``--still`` a scene's own view,
twice: with every candidate traced, and with a budget (``--budget 0``: once), with the raster's
primary hits or (``--primary raytrace``) the RT baseline's camera rays. Prints per run the frame's median
``FrameStats.host_ms`` by phase and ``times_ms`` (device ms per stage, the host's issue time and the
frame's total), then per wrapped function its median time per call and its mean
time per frame: where the host's share of a frame goes, function by function.

    python3 scripts/host_phases.py --variant cuda_ad_rgb --resx 1280 --resy 720 --budget 2.47
    python3 scripts/host_phases.py --variant cuda_ad_rgb --resx 1280 --resy 720 --still scenes/armadillo_glass.xml -D models_dir=…
"""
from __future__ import annotations

import argparse
import collections
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--budget", type=float, default=2.47, help="the budgeted run's budget_ms")
    parser.add_argument("--still", type=Path, default=None, metavar="SCENE",
                        help="render SCENE's own view (still), not the 226 objects' camera path")
    parser.add_argument("--primary", default="raster", choices=("raster", "raytrace"),
                        help="the primary hits: the raster's, or camera rays (the RT baseline)")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import budget, heuristic, pipeline
    from hybrid_integrator.raster import camera, compute, interop, visibility

    times = collections.defaultdict(list)

    def wrap(owner, name: str) -> None:
        function, label = getattr(owner, name), f"{owner.__name__.rsplit('.', 1)[-1]}.{name}"

        def timed(*a, **k):
            start = time.perf_counter()
            out = function(*a, **k)
            times[label].append((time.perf_counter() - start) * 1e3)
            return out
        setattr(owner, name, timed)

    renderer = pipeline.HybridRenderer
    for owner, names in ((pipeline, ("candidates", "plan_frame", "learn_ambient", "visibility_terms", "develop",
                                     "subpixel_offsets", "ambient_table", "device_array")),
                         (renderer, ("_frame", "_visibility", "_select", "_device", "_post", "_account", "_plan",
                                     "_account_times")),
                         (budget.FrameState, ("learn_rays", "learn_errors")), (budget.CostModel, ("observe", "_fit")),
                         (pipeline.PassCounts, ("read",)), (heuristic.Coverage, ("of",)),
                         (pipeline.StageClock, ("frame_times",)), (pipeline.Denoiser, ("__call__",)),
                         (pipeline, ("gl_flush",)), (visibility.Rasterizer, ("render", "device_ids", "release")),
                         (compute.ComputeVisibility, ("render", "_run")), (camera.RasterCamera, ("relative_clip",)),
                         (interop._SharedImage, ("copy", "release"))):
        for name in names:
            wrap(owner, name)
    hi.register()
    defines = dict(d.split("=", 1) for d in args.defines)
    if args.still is None:
        from budget_benchmark import path_scene  # scripts/ is on sys.path when a script runs

        scene, cameras = path_scene(hi, ROOT / "scenes/many_objects.xml", args.frames, resx=args.resx, resy=args.resy,
                                    **defines)
    else:
        from hybrid_integrator.raster.camera import sensor_to_world

        from hybrid_integrator.bench import load_bench_scene

        scene, _ = load_bench_scene(str(args.still), {"resx": args.resx, "resy": args.resy, **defines})
        cameras = [sensor_to_world(scene.sensors()[0])] * args.frames
    for budget_ms in dict.fromkeys((0.0, args.budget)):  # --budget 0: the default frame alone
        props = dict(spp=1, layers=False, budget_ms=budget_ms, primary=args.primary)
        hi.render_sequence(scene, cameras[:3], **props)  # warm-up
        times.clear()
        frames = hi.render_sequence(scene, cameras, **props)[3:]
        stats = [f.stats for f in frames]
        print(f"budget_ms={budget_ms}: frame {statistics.median(s.times_ms['total'] for s in stats):.3f} ms, "
              f"trace {statistics.median(s.times_ms['trace'] for s in stats):.3f} ms")
        print("  host_ms", {k: round(statistics.median(s.host_ms[k] for s in stats), 3) for k in stats[0].host_ms})
        print("  times_ms", {k: round(statistics.median(s.times_ms[k] for s in stats), 3) for k in stats[0].times_ms})
        for name, values in times.items():
            print(f"  {name:32s} n={len(values):3d}  median {statistics.median(values):.3f} ms per call, "
                  f"{sum(values) / len(cameras):.3f} ms per frame")  # the wrapped calls of every frame


if __name__ == "__main__":
    main()
