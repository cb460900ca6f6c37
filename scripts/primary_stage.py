"""What the primary stage's Dr.Jit kernels cost: the raster's hits against camera rays (issue 10).

For each scene, one visibility buffer is drawn once; then three frozen functions of the scene and
that buffer are timed, each a hit per pixel with its surface interaction (what stage 1 hands to
the lighting):

- ``ties`` and ``silhouettes``: ``primary.primary_hits``, the raster's triangles intersected with
  the pixels' camera rays, the refined pixels' rays (proxies, and the outline pixels of that
  ``outline`` test, ``primary.OUTLINES``) traced in the same kernel, masked;
- ``camera rays``: ``primary.traced_hits``, every pixel's camera ray traced (the RT baseline).

With ``--parts``, the raster's kernel as the GPU's device pass makes it (``refine="trace"``: its
refined pixels left for the trace launch, ``primary.raster_hits``) is timed in parts, each
function adding a step to the one before, all evaluating what the device pass's primary stage
evaluates where they reach it:

- ``rays``: the camera rays with their differentials (which ``ties`` measures pixels with);
- ``resolve``: + the visibility buffer's triangles intersected with them (``primary.resolve``);
- ``outline``: + the ``ties`` test on the outline pixels (``primary.raster_intersections``);
- ``interactions``: + Mitsuba's surface interactions (``primary.raster_hits``, the whole kernel);
- ``camera rays (all)``: ``traced_hits`` with every field the RT baseline's primary stage evaluates;
- ``camera rays (ray only)``: its ``ray_intersect_preliminary`` alone.

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
    parser.add_argument("--parts", action="store_true", help="time the raster's kernel in parts (module docstring)")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    from hybrid_integrator.api import rasterizer
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.frozen import FrozenScene
    from hybrid_integrator.primary import (camera_rays, primary_hits, raster_hits, raster_intersections, resolve,
                                           traced_hits)
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

        def ties_rays(sensor):
            """the camera rays with the differentials the ``ties`` outline test measures pixels with"""
            return camera_rays(sensor, w, h, (0.5, 0.5), differentials=True)

        def plain_rays(sensor):
            """the RT baseline's camera rays"""
            return camera_rays(sensor, w, h, (0.5, 0.5))

        def preliminary(pi):
            """a preliminary intersection's fields, its shape pointers as ids (``evaluated``)"""
            return pi.t, pi.prim_uv, pi.prim_index, dr.reinterpret_array(mi.UInt32, pi.shape)

        def hits_of(scene, sensor, ids, tables, outline):
            hits = primary_hits(scene, ties_rays(sensor), ids, w, h, tables, outline)
            return hits.si.p, hits.si.n, hits.si.uv, hits.shape, hits.object, hits.valid, hits.refined

        def rays_of(scene, sensor, tables):
            hits = traced_hits(scene, plain_rays(sensor), tables)
            return hits.si.p, hits.si.n, hits.si.uv, hits.shape, hits.object, hits.valid

        def evaluated(hits):
            """what the device pass's primary stage evaluates (pipeline.device_pass), the pointer
            fields as their ids: a frozen function's pointer outputs abort Dr.Jit 1.5"""
            si = {k: getattr(hits.si, k) for k in mi.SurfaceInteraction3f.DRJIT_STRUCT}
            si.update({k: dr.reinterpret_array(mi.UInt32, si[k]) for k in ("shape", "instance")})
            return hits.ray, si, hits.shape, hits.object, hits.valid, hits.refined

        def rays(scene, sensor):
            return mi.Ray3f(ties_rays(sensor))

        def resolved(scene, sensor, ids, tables):
            ray = ties_rays(sensor)
            record = resolve(ids, ray, tables)
            return mi.Ray3f(ray), record.hit, record.shape, record.object, record.prim, record.t, record.uv

        def outlined(scene, sensor, ids, tables):
            ray = ties_rays(sensor)
            found, refined = raster_intersections(scene, ray, ids, w, h, tables, "ties")
            return mi.Ray3f(ray), *preliminary(found.pi), found.shape, found.object, found.valid, refined

        def interactions(scene, sensor, ids, tables):
            return evaluated(raster_hits(scene, ties_rays(sensor), ids, w, h, tables, "ties"))

        def camera_all(scene, sensor, tables):
            return evaluated(traced_hits(scene, plain_rays(sensor), tables))

        def camera_ray_only(scene, sensor):
            return preliminary(scene.ray_intersect_preliminary(plain_rays(sensor), False))

        frozen = FrozenScene(scene)  # as the device pass is frozen: the scene's variables in its place
        if args.parts:
            runs = {"rays": (frozen.freeze(rays), (sensor,)),
                    "resolve": (frozen.freeze(resolved), (sensor, ids, tables)),
                    "outline": (frozen.freeze(outlined), (sensor, ids, tables)),
                    "interactions": (frozen.freeze(interactions), (sensor, ids, tables)),
                    "camera rays (all)": (frozen.freeze(camera_all), (sensor, tables)),
                    "camera rays (ray only)": (frozen.freeze(camera_ray_only), (sensor,))}
        else:
            runs = {outline: (frozen.freeze(functools.partial(hits_of, outline=outline)), (sensor, ids, tables))
                    for outline in ("ties", "silhouettes")}
            runs["camera rays"] = (frozen.freeze(rays_of), (sensor, tables))
        times = timed_in_turn([lambda fn=fn, inputs=inputs: fn(*inputs) for fn, inputs in runs.values()], args.repeats)
        refined = {k: int(np.count_nonzero(np.array(runs[k][0](*runs[k][1])[-1])))
                   for k in (("outline",) if args.parts else ("ties", "silhouettes"))}
        lines.append(f"{name} ({w}×{h}, refined pixels: "
                     + ", ".join(f"{k} {n} ({n / (w * h):.2%})" for k, n in refined.items()) + ")")
        for k, (wall, device) in zip(runs, times):
            lines.append(f"  {k:22s} device {device:.3f} ms, wall {wall:.3f} ms")
    text = "\n".join(lines)
    print(text)
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text(text + "\n")


if __name__ == "__main__":
    main()
