"""Where a hybrid frame's time goes: host (Python profile) and device (stage times) (issue 10).

Renders ``--frames`` frames of one still camera after a warm-up (``--spp`` passes each), with the
host profiled by cProfile, and prints the median device time of every stage
(``FrameStats.times_ms``), the median host issue and frame times, the host time by phase, and the
host functions that took the most time per frame. ``--kernels`` lists the last frame's kernels
(stage, hash, lanes, operations, device ms); ``--path`` times Mitsuba's ``path`` at 1 spp the same
way (wall, host issue and its kernels).

    python scripts/frame_profile.py scenes/showcase.xml -D showcase_dir=../shared/scenes/cbox
    python3 scripts/frame_profile.py scenes/showcase.xml --variant cuda_ad_rgb -D resx=1280 -D resy=720 ...
"""
from __future__ import annotations

import argparse
import cProfile
import io
import pstats
import statistics
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--spp", type=int, default=1, help="samples (raster and device passes) per frame")
    parser.add_argument("--primary", default="raster", choices=("raster", "raytrace"))
    parser.add_argument("--refine", default=None, choices=("auto", "primary", "trace"),
                        help="where the raster's refined pixels are traced (default: the integrator's)")
    parser.add_argument("--raster", default=None, choices=("auto", "draw", "compute"),
                        help="how the raster pass rasterizes (default: the integrator's)")
    parser.add_argument("--outline", default=None, choices=("auto", "ties", "silhouettes"),
                        help="which outline pixels are refined (default: the integrator's)")
    parser.add_argument("--candidates", default=None, help="the integrator's candidates ('' for the raster layer alone)")
    parser.add_argument("--rr-depth", type=int, default=None, help="the integrator's rr_depth (default: its own)")
    parser.add_argument("--top", type=int, default=25)
    parser.add_argument("--kernels", action="store_true", help="list the last frame's kernels by stage")
    parser.add_argument("--path", action="store_true", help="also time Mitsuba's path at 1 spp: wall and kernels")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import sensor_to_world
    from hybrid_integrator.bench import load_bench_scene

    scene, _ = load_bench_scene(str(args.scene), dict(d.split("=", 1) for d in args.defines))
    camera = sensor_to_world(scene.sensors()[0])
    props = {"primary": args.primary, **({"candidates": args.candidates} if args.candidates is not None else {}),
             **{k: getattr(args, k) for k in ("refine", "raster", "outline") if getattr(args, k) is not None},
             **({"rr_depth": args.rr_depth} if args.rr_depth is not None else {})}
    hi.render_sequence(scene, [camera] * 3, spp=args.spp, layers=False, **props)  # compiles and records
    profile = cProfile.Profile()
    profile.enable()
    frames = hi.render_sequence(scene, [camera] * args.frames, spp=args.spp, layers=False, **props)
    profile.disable()
    times = {k: statistics.median(f.stats.times_ms[k] for f in frames) for k in frames[0].stats.times_ms}
    print(f"{args.scene.name} {args.variant} {props}, {args.spp} spp: median ms per frame", {k: round(v, 3) for k, v in times.items()})
    host = {k: statistics.median(f.stats.host_ms[k] for f in frames) for k in frames[0].stats.host_ms}
    print("median host ms per phase", {k: round(v, 3) for k, v in host.items()}, "readback:", frames[0].stats.readback)
    if args.kernels:
        print_kernels(hi.api.renderer(scene).clock.last)
    if args.path:
        profile_path(scene, args.frames)
    out = io.StringIO()
    pstats.Stats(profile, stream=out).sort_stats("tottime").print_stats(args.top)
    print(f"host profile over {args.frames} frames (divide by {args.frames} for per-frame time):")
    print(out.getvalue())


def print_kernels(entries) -> None:
    """One line per kernel (or reduction/copy) of a frame: stage, hash, lanes, operations, device ms."""
    print("stage      hash      type        lanes   ops      ms")
    for stage, e in entries:
        print(f"{stage:10s} {str(e.get('hash', ''))[:8]:8s}  {str(e.get('type', '')).split('.')[-1]:10s}"
              f"{e.get('size', 0):9d} {e.get('operation_count', 0):6d} {float(e.get('execution_time', 0.0)):7.3f}")


def profile_path(scene, frames: int) -> None:
    """Mitsuba's ``path`` at 1 spp as the bench times it (one sync per frame): wall ms and the
    device ms of its kernels, medians over ``frames`` warm frames."""
    import time

    import drjit as dr
    import mitsuba as mi

    integrator = mi.load_dict({"type": "path", "max_depth": -1})
    walls, kernels, issue = [], [], []
    with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
        for k in range(frames + 3):
            dr.kernel_history_clear()
            start = time.perf_counter()
            image = mi.render(scene, integrator=integrator, spp=1, seed=k)
            issued = time.perf_counter()
            dr.eval(image)
            dr.sync_thread()
            end = time.perf_counter()
            history = dr.kernel_history()
            if k >= 3:
                walls.append((end - start) * 1e3)
                issue.append((issued - start) * 1e3)
                kernels.append(sum(float(e.get("execution_time", 0.0)) for e in history))
    print(f"path 1 spp: median wall {statistics.median(walls):.2f} ms, host issue {statistics.median(issue):.2f} ms, "
          f"kernels {statistics.median(kernels):.2f} ms")
    print_kernels([("path", e) for e in history])


if __name__ == "__main__":
    main()
