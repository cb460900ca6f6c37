"""Stop 45's probe: the compute visibility pass (``raster/compute.py``) of other trees and with other
constants, in one process, per scene: the GL time of the whole pass (a timer query around it,
median of ``--repeats`` rounds, the versions in turn in each round), each stage's
(``raster_compute_probe.stage_times``), and whether each version's visibility buffer is this
tree's bit for bit (triangle numbers differ between processes, not within one).

Versions: each ``--tree NAME=PATH`` (that tree's ``raster/compute.py`` and shader: main before this
stop, and so on), ``new`` (this tree), ``lanesN`` (this tree with N invocations per medium triangle).

    python3 docs/results/gpu/issue10/stop45/variants.py --variant cuda_ad_rgb --tree old=.w44 SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import importlib.util
import pathlib
import re
import statistics
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[5] / "scripts"))
from raster_cull_probe import parser, rasterizers  # noqa: E402
from raster_compute_probe import stage_times  # noqa: E402


#: the stage names of every version's ``compute`` module (the tile-parts diff renamed and added some)
STAGES = ("CLEAR", "SMALL_DEPTH", "MEDIUM_GROUPS", "GROUPS", "MEDIUM_DEPTH", "TILES_DEPTH", "TILES",
          "SMALL_NUMBERS", "MEDIUM_NUMBERS", "TILES_NUMBERS", "RESOLVE")


def tree_module(name: str, root: str):
    """``raster/compute.py`` of the tree at ``root`` as a module of this package (its relative
    imports are this tree's), reading that tree's shader."""
    path = pathlib.Path(root) / "hybrid_integrator" / "raster"
    spec = importlib.util.spec_from_file_location(f"hybrid_integrator.raster.compute_{name}", path / "compute.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    shader = (path / "shaders" / "visibility.comp").read_text()
    module.shader_source = lambda _: shader
    return module


def with_lanes(compute, n: int):
    """This tree's module with ``n`` invocations per medium triangle."""
    module = tree_module(f"lanes{n}", str(pathlib.Path(compute.__file__).parents[2]))
    shader = module.shader_source("")
    module.shader_source = lambda _: re.sub(r"const uint MEDIUM_LANES = \d+u;", f"const uint MEDIUM_LANES = {n}u;", shader)
    return module


def main() -> None:
    import numpy as np

    from hybrid_integrator.raster import compute

    p = parser(__doc__)
    p.add_argument("--tree", action="append", default=[], metavar="NAME=PATH")
    args = p.parse_args()
    modules = {name: tree_module(name, root) for name, root in (t.split("=", 1) for t in args.tree)}
    modules.update({"new": compute, **{f"lanes{n}": with_lanes(compute, n) for n in (32, 128)}})
    for name, _, raster, camera, query in rasterizers(args):
        fbo = raster.target(camera.width, camera.height)
        passes = {v: m.ComputeVisibility(raster.ctx, raster.vertices, raster.faces, len(raster.geometry.faces))
                  for v, m in modules.items()}

        def render(v, offset=(0.5, 0.5)):
            """Version ``v``'s pass; each module knows only which of its own passes the context has
            bound: every pass binds its buffers again"""
            for m in modules.values():
                m._BOUND.clear()
            return passes[v].render(camera, offset, fbo)

        same = {v: True for v in passes}
        for offset in ((0.5, 0.5), (0.13, 0.77)):
            ids = {v: raster.read_ids(render(v, offset)).copy() for v in passes}
            for v in passes:
                same[v] = same[v] and bool(np.array_equal(ids[v], ids["new"]))
        times = {v: [] for v in passes}
        for r in range(args.repeats + 2):
            for v in passes:
                with query:
                    render(v)
                raster.ctx.finish()
                if r >= 2:
                    times[v].append(query.elapsed * 1e-6)
        large, medium = passes["new"].tiers()
        print(f"{name}: large {large:,}, medium {medium:,} triangles", flush=True)
        for v, p in passes.items():
            names = {getattr(modules[v], n): n.lower() for n in STAGES if hasattr(modules[v], n)}
            stages = {names[k]: round(t, 4) for k, t in stage_times(raster, lambda v=v: render(v),
                                                                     args.repeats, type(p)).items()}
            print(f"  {v:8s} pass {statistics.median(times[v]):.4f} ms (bit for bit as new: {same[v]}); "
                  f"stages {stages}", flush=True)


if __name__ == "__main__":
    main()
