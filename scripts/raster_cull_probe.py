"""Probe: the OpenGL visibility draw with and without face culling (``Rasterizer.cull``; a GL
timer query around ``Rasterizer.render``, its clear and draw, median of ``--repeats`` draws), and
how many pixels keep their triangle, per scene.

    python3 scripts/raster_cull_probe.py --variant cuda_ad_rgb SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import argparse
import statistics


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.raster.visibility import Rasterizer

    for spec in args.scenes:
        scene, name = load_bench_scene(spec, dict(d.split("=", 1) for d in args.defines))
        raster = Rasterizer(scene)
        camera = RasterCamera.from_sensor(scene.sensors()[0])
        query = raster.ctx.query(time=True)
        results = {}
        for mode in (None, "back", "front"):
            raster.cull = mode
            times, ids = [], None
            for r in range(args.repeats + 2):
                with query:
                    fbo = raster.render(camera)
                raster.ctx.finish()
                if r >= 2:
                    times.append(query.elapsed * 1e-6)
                ids = raster.read_ids(fbo)
            results[mode or "none"] = (statistics.median(times), ids)
        base = results["none"][1]
        tris = len(raster.geometry.faces)
        for mode, (ms, ids) in results.items():
            print(f"{name}: {tris:,} triangles, cull {mode:5s}: GL {ms:.3f} ms, same triangle on "
                  f"{100 * np.mean(ids == base):.3f} % of pixels", flush=True)


if __name__ == "__main__":
    main()
