"""What the primary stage's Dr.Jit kernels cost: the raster's hits against camera rays (issue 10).

For each scene, one visibility buffer is drawn once; then three frozen functions of the scene and
that buffer are timed, each a hit per pixel with its surface interaction (what stage 1 hands to
the lighting):

- ``ties`` and ``silhouettes``: ``primary.primary_hits``, the raster's triangles intersected with
  the pixels' camera rays, the refined pixels' rays (proxies, and the outline pixels of that
  ``outline`` test, ``primary.OUTLINES``) traced in the same kernel, masked;
- ``camera rays``: ``primary.traced_hits``, every pixel's camera ray traced (the RT baseline).

Per function: the median device time of its kernels (Dr.Jit's kernel history, CUDA events on the
GPU) and the median wall time of a call synchronized once, over ``--repeats`` calls, taken in
turn. (Stop 28 also timed the refined rays compacted into a launch of their own, commit df7581b:
slower on four of five scenes, docs/results/gpu/issue10/stop28/primary_stage_compacted.txt.)

    python scripts/primary_stage.py scenes/showcase.xml -D showcase_dir=../shared/scenes/cbox
    python3 scripts/primary_stage.py --variant cuda_ad_rgb scenes/*.xml $D -o $OUT/primary_stage.txt
"""
from __future__ import annotations

import argparse
import functools
from pathlib import Path

from trace_overhead import timed_in_turn  # scripts/ is on sys.path when a script runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--repeats", type=int, default=41)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    from hybrid_integrator.api import rasterizer
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.frozen import FrozenScene
    from hybrid_integrator.primary import camera_rays, primary_hits, traced_hits
    from hybrid_integrator.raster.camera import RasterCamera

    params = dict(d.split("=", 1) for d in args.defines)
    lines = [f"{args.variant}: the primary stage's kernels, median of {args.repeats} calls each "
             "(device ms from the kernel history; wall ms with one synchronization per call)"]
    for path in args.scenes:
        scene, name = load_bench_scene(str(path), params)
        sensor = scene.sensors()[0]
        camera = RasterCamera.from_sensor(sensor)
        w, h = camera.width, camera.height
        raster = rasterizer(scene)
        ids = raster.device_ids(raster.render(camera, (0.5, 0.5), "auto"))
        tables = raster.tables

        def hits_of(scene, sensor, ids, tables, outline):
            hits = primary_hits(scene, camera_rays(sensor, w, h, (0.5, 0.5), differentials=True), ids, w, h, tables,
                                outline)
            return hits.si.p, hits.si.n, hits.si.uv, hits.shape, hits.object, hits.valid, hits.refined

        def rays_of(scene, sensor, tables):
            hits = traced_hits(scene, camera_rays(sensor, w, h, (0.5, 0.5)), tables)
            return hits.si.p, hits.si.n, hits.si.uv, hits.shape, hits.object, hits.valid

        frozen = FrozenScene(scene)  # as the device pass is frozen: the scene's variables in its place
        runs = {outline: (frozen.freeze(functools.partial(hits_of, outline=outline)), (sensor, ids, tables))
                for outline in ("ties", "silhouettes")}
        runs["camera rays"] = (frozen.freeze(rays_of), (sensor, tables))
        times = timed_in_turn([lambda fn=fn, inputs=inputs: fn(*inputs) for fn, inputs in runs.values()], args.repeats)
        refined = {k: int(np.count_nonzero(np.array(runs[k][0](*runs[k][1])[-1]))) for k in ("ties", "silhouettes")}
        lines.append(f"{name} ({w}×{h}, refined pixels: "
                     + ", ".join(f"{k} {n} ({n / (w * h):.2%})" for k, n in refined.items()) + ")")
        for k, (wall, device) in zip(runs, times):
            lines.append(f"  {k:12s} device {device:.3f} ms, wall {wall:.3f} ms")
    text = "\n".join(lines)
    print(text)
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text(text + "\n")


if __name__ == "__main__":
    main()
