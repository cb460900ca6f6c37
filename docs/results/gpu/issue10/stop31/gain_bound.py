"""Stop 31 probe: an upper bound on what a primary stage without a ray-tracing call would give Gain.

``primary_parts.py`` found that the raster's hits cost 0.05-0.07 ms of device time when their
kernel traces no ray, against 0.21-0.60 ms with the refined pixels' masked rays. This probe times
the bench's paired Gain (``bench.paired_gain``: the all-candidates hybrid's and the RT baseline's
frames in turn, 20 pairs after 3) per scene twice in one process: with the renderer's own primary
hits, then with a stand-in that refines no pixel (every pixel keeps the raster's triangle: wrong
at silhouettes and on analytic shapes' proxies, so an upper bound on the time saved, not a
renderer), and once more with the renderer's own. Prints the paired Gain's median [quartiles] and
both sides' median frames.

    python3 docs/results/gpu/issue10/stop31/gain_bound.py --variant cuda_ad_rgb scenes/*.xml $D
"""
import argparse

parser = argparse.ArgumentParser()
parser.add_argument("scenes", nargs="+")
parser.add_argument("--variant", default="llvm_ad_rgb")
parser.add_argument("--frames", type=int, default=20)
parser.add_argument("-D", dest="defines", action="append", default=[])
args = parser.parse_args()

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant(args.variant)
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator import pipeline, primary  # noqa: E402
from hybrid_integrator.bench import load_bench_scene, paired_gain  # noqa: E402

hi.register()
own = primary.primary_hits


def unrefined_hits(scene, ray, triangle_id, width, height, tables):
    """``primary.primary_hits`` with no pixel refined: no ray-tracing call in the kernel."""
    record = primary.resolve(triangle_id, ray, tables)
    pi = dr.zeros(mi.PreliminaryIntersection3f, dr.width(ray))
    pi.t, pi.prim_uv, pi.prim_index, pi.shape_index = dr.select(record.hit, record.t, dr.inf), record.uv, record.prim, record.shape
    pi.shape = dr.gather(mi.ShapePtr, scene.shapes_dr(), record.shape, record.hit)
    pi.valid = record.hit
    si = pi.compute_surface_interaction(ray, mi.RayFlags.All, record.hit)
    return primary.PrimaryHits(ray=ray, si=si, shape=record.shape, object=record.object, valid=record.hit,
                               refined=mi.UInt32(0))


params = {"resx": 1280, "resy": 720, **dict(d.split("=", 1) for d in args.defines)}
for spec in args.scenes:
    scene, name = load_bench_scene(spec, params)
    for label, hits in (("own", own), ("no refinement", unrefined_hits), ("own again", own)):
        pipeline.primary_hits = hits
        hi.forget(scene)  # a new renderer records its device pass with these hits
        g = paired_gain(scene, {"freeze": True}, args.frames, 1, 0)
        print(f"{name:16s} {label:14s} paired Gain {g['median']:.3f} [{g['q25']:.3f}, {g['q75']:.3f}]  "
              f"hybrid {g['hybrid_ms']:.2f} ms, RT {g['rt_ms']:.2f} ms", flush=True)
