"""Where a hybrid frame's time goes: host (Python profile) and device (stage times) (issue 10).

Renders ``--frames`` frames of one still camera after a warm-up, with the host profiled by
cProfile, and prints the median device time of every stage (``FrameStats.times_ms``), the median
host issue and frame times, and the host functions that took the most time per frame.

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
    parser.add_argument("--primary", default="raster", choices=("raster", "raytrace"))
    parser.add_argument("--candidates", default=None, help="the integrator's candidates ('' for the raster layer alone)")
    parser.add_argument("--top", type=int, default=25)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene

    scene, _ = load_bench_scene(str(args.scene), dict(d.split("=", 1) for d in args.defines))
    camera = mi.ScalarTransform4f(np.array(mi.traverse(scene.sensors()[0])["to_world"].matrix).reshape(4, 4))
    props = {"primary": args.primary, **({"candidates": args.candidates} if args.candidates is not None else {})}
    hi.render_sequence(scene, [camera] * 3, spp=1, layers=False, **props)  # compiles and records
    profile = cProfile.Profile()
    profile.enable()
    frames = hi.render_sequence(scene, [camera] * args.frames, spp=1, layers=False, **props)
    profile.disable()
    times = {k: statistics.median(f.stats.times_ms[k] for f in frames) for k in frames[0].stats.times_ms}
    print(f"{args.scene.name} {args.variant} {props}: median ms per frame", {k: round(v, 3) for k, v in times.items()})
    host = {k: statistics.median(f.stats.host_ms[k] for f in frames) for k in frames[0].stats.host_ms}
    print("median host ms per phase", {k: round(v, 3) for k, v in host.items()}, "readback:", frames[0].stats.readback)
    out = io.StringIO()
    pstats.Stats(profile, stream=out).sort_stats("tottime").print_stats(args.top)
    print(f"host profile over {args.frames} frames (divide by {args.frames} for per-frame time):")
    print(out.getvalue())


if __name__ == "__main__":
    main()
