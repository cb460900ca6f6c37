"""Where a stage-timed frame's host time goes (stop 51): the default frame and the DR frame, 30 frames
each after warm-up, median host ms per phase (``FrameStats.host_ms``; ``timing``: the kernel
history's readout) and median ``times_ms["total"]``; run on a tree, or with an older package first on
PYTHONPATH, to see where the readout moved.

    python3 docs/results/gpu/issue10/stop51/phases.py --variant cuda_ad_rgb scenes/showcase.xml -D …
"""
from __future__ import annotations

import argparse
import statistics
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator
    from hybrid_integrator.api import renderer as scene_renderer
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.pipeline import HybridSettings

    print(hybrid_integrator.__file__)
    defines = dict(d.split("=", 1) for d in args.defines)
    for path in args.scenes:
        scene, name = load_bench_scene(str(path), defines)
        renderer = scene_renderer(scene)
        for label, props in (("hybrid", {}), ("DR", {"candidates": ""})):
            settings = HybridSettings(**props)
            stats = [renderer.render(settings, spp=1, seed=k, layers=False).stats for k in range(args.frames + 3)][3:]
            phases = {k: statistics.median(s.host_ms[k] for s in stats) for k in stats[0].host_ms}
            stages = {k: statistics.median(s.times_ms[k] for s in stats) for k in ("raster", "lighting", "trace", "compose", "denoise")}
            print(f"{name:16} {label:7} total {statistics.median(s.times_ms['total'] for s in stats):7.3f} ms  "
                  + "  ".join(f"{k} {v:.3f}" for k, v in phases.items()) + "  | device: "
                  + "  ".join(f"{k} {v:.3f}" for k, v in stages.items()), flush=True)


if __name__ == "__main__":
    main()
