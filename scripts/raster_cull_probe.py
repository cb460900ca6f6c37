"""Probe: the OpenGL visibility draw with and without face culling (``Rasterizer.cull``; a GL
timer query around ``Rasterizer.render``, its clear and draw, median of ``--repeats`` draws), and
how many pixels keep their triangle, per scene.

    python3 scripts/raster_cull_probe.py --variant cuda_ad_rgb SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import argparse
import statistics
import subprocess
import sys


def parser(doc: str) -> argparse.ArgumentParser:
    """The probes' command line (this one's, ``raster_order_probe.py``'s, ``refine_ab.py``'s,
    ``gain_anatomy.py``'s)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--repeats", type=int, default=30)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    return parser


def arguments(doc: str) -> argparse.Namespace:
    """The probes' parsed command line (:func:`parser`)."""
    return parser(doc).parse_args()


def each_scene_alone(script: str, args: argparse.Namespace, options: list[str], header: int) -> bool:
    """Where ``args`` names several scenes, run ``script`` (a probe printing a Markdown table) once
    per scene in a process of its own, with ``options`` and ``args``' variant, repeats and defines,
    and print the tables as one (their first ``header`` lines once); return whether it did. Several
    scenes in one process made the later scenes' frames slower for every integrator alike on the
    H200 (``refine_ab.py``)."""
    if len(args.scenes) < 2:
        return False
    options = ["--variant", args.variant, "--repeats", str(args.repeats), *options, *(f"-D{d}" for d in args.defines)]
    for k, spec in enumerate(args.scenes):
        table = subprocess.run([sys.executable, script, spec, *options], check=True, stdout=subprocess.PIPE,
                               text=True).stdout.splitlines()
        print("\n".join(table if k == 0 else table[header:]), flush=True)
    return True


def rasterizers(args: argparse.Namespace):
    """Per scene of ``args``: its name, the scene, its ``Rasterizer``, its camera and a GL timer query."""
    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.raster.visibility import Rasterizer

    for spec in args.scenes:
        scene, name = load_bench_scene(spec, dict(d.split("=", 1) for d in args.defines))
        raster = Rasterizer(scene)
        yield name, scene, raster, RasterCamera.from_sensor(scene.sensors()[0]), raster.ctx.query(time=True)


def timed_draw(raster, camera, query, repeats: int, method: str = "draw"):
    """The median GL time (ms) of ``Rasterizer.render`` by ``method`` (the draw: its clear and
    draw) over ``repeats`` passes after two, and the last pass's target."""
    times = []
    for r in range(repeats + 2):
        with query:
            fbo = raster.render(camera, method=method)
        raster.ctx.finish()
        if r >= 2:
            times.append(query.elapsed * 1e-6)
    return statistics.median(times), fbo


def main() -> None:
    import numpy as np

    args = arguments(__doc__)
    for name, _, raster, camera, query in rasterizers(args):
        results = {}
        for mode in (None, "back", "front"):
            raster.cull = mode
            ms, fbo = timed_draw(raster, camera, query, args.repeats)
            results[mode or "none"] = (ms, raster.read_ids(fbo))
        base = results["none"][1]
        tris = len(raster.geometry.faces)
        for mode, (ms, ids) in results.items():
            print(f"{name}: {tris:,} triangles, cull {mode:5s}: GL {ms:.3f} ms, same triangle on "
                  f"{100 * np.mean(ids == base):.3f} % of pixels", flush=True)


if __name__ == "__main__":
    main()
