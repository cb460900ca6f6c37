"""The trace stage in one launch or split in two at a path depth (issue 10): what it costs.

At one path per pixel a trace launch ends in a tail of long paths, and its warps keep lanes
whose paths have ended beside the few that go on (``trace.py``). ``trace.trace_effects(split=K)``
stops every path at depth K, compacts the paths still alive onto the first lanes and continues
them in a second launch. This probe times, per scene, the default frame's trace (every effect,
every hit pixel from Mitsuba's camera rays, glass pixels first where the scene has glass, as the
device pass launches them) frozen with ``dr.freeze``, for each ``--splits`` value (0: one launch):
the median device time of its kernels (Dr.Jit's kernel history, CUDA events on the GPU) and the
median wall time of a call synchronized once, the splits taken in turn; and it checks that each
split traces the same rays as one launch.

    python scripts/trace_split.py scenes/showcase.xml -D showcase_dir=../shared/scenes/cbox
    python3 scripts/trace_split.py --variant cuda_ad_rgb scenes/*.xml $D -o $OUT/trace_split.txt
"""
from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--splits", type=int, nargs="+", default=[0, 2, 3, 4, 6])
    parser.add_argument("--repeats", type=int, default=21)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import rasterizer
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.primary import camera_rays, traced_hits
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.selection import EFFECTS, long_paths, refracts
    from hybrid_integrator.trace import trace_effects

    params = dict(d.split("=", 1) for d in args.defines)
    lines = [f"{args.variant}: the default frame's trace stage, median of {args.repeats} calls per split "
             "(device ms from the kernel history; wall ms with one synchronization per call)"]
    for path in args.scenes:
        scene, name = load_bench_scene(str(path), params)
        sensor = scene.sensors()[0]
        camera = RasterCamera.from_sensor(sensor)
        n_objects = len(hi.scene_objects(scene))
        hits = traced_hits(scene, camera_rays(sensor, camera.width, camera.height, (0.5, 0.5)), rasterizer(scene).tables)
        glass = refracts(shape.bsdf() for shape in scene.shapes())
        long = long_paths(hits.si.bsdf(hits.ray).flags()) & hits.valid if glass else None
        dr.eval(hits.ray, hits.si, hits.valid, hits.object, long)

        def call(scene, ray, si, traced, obj, long, seed, split):
            rt, _, counts = trace_effects(scene, ray, si, traced, EFFECTS, -1, 5, False, seed=seed, obj=obj,
                                          n_objects=n_objects, long=long, split=split)
            return rt, counts.per_object

        frozen = {k: dr.freeze(lambda *a, k=k: call(*a, split=k)) for k in args.splits}
        inputs = (scene, hits.ray, hits.si, hits.valid, hits.object, long, dr.opaque(mi.UInt64, 1))
        rays = {k: np.array(fn(*inputs)[1]) for k, fn in frozen.items()}
        wall: dict[int, list[float]] = {k: [] for k in frozen}
        device: dict[int, list[float]] = {k: [] for k in frozen}
        with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
            for fn in frozen.values():  # records again with its literals made opaque
                dr.eval(fn(*inputs))
            dr.sync_thread()
            for _ in range(args.repeats):
                for k, fn in frozen.items():
                    dr.kernel_history_clear()
                    start = time.perf_counter()
                    dr.eval(fn(*inputs))
                    dr.sync_thread()
                    wall[k].append((time.perf_counter() - start) * 1e3)
                    device[k].append(sum(float(e.get("execution_time", 0.0)) for e in dr.kernel_history()))
        lines.append(f"{name} ({camera.width}×{camera.height}, {int(np.count_nonzero(np.array(hits.valid)))} pixels, "
                     f"{int(rays[args.splits[0]][:-1].sum())} rays, glass first: {glass})")
        for k in frozen:
            lines.append(f"  split {k:2d}: device {statistics.median(device[k]):.3f} ms, wall {statistics.median(wall[k]):.3f} ms, "
                         f"same rays: {np.array_equal(rays[k], rays[args.splits[0]])}")
    text = "\n".join(lines)
    print(text)
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text(text + "\n")


if __name__ == "__main__":
    main()
