"""Stop 31 probe: what the primary stage's kernels spend their device time on, raster against
camera rays (``scripts/primary_stage.py`` times the two whole; this splits them).

Per scene, one visibility buffer drawn once, then frozen functions timed in turn (device ms from
the kernel history, wall ms with one synchronization per call):

- ``raster``: ``primary.primary_hits`` (as the device pass: resolve, silhouettes, the refined
  pixels' rays traced in the same kernel, masked, Mitsuba's surface interaction);
- ``raster, compressed rays``: the refined pixels' rays in a launch of exactly their number
  (``dr.compress``, whose size Dr.Jit reads back to the host), scattered back; the rest in
  kernels without a ray tracing call;
- ``raster, no rays``: the raster's own hits, no pixel refined (no ray tracing call in the kernel);
- ``raster, no SI``: ``primary_hits``' preliminary intersection, refined pixels traced, without
  ``compute_surface_interaction``;
- ``camera rays``: ``primary.traced_hits`` (``scene.ray_intersect``);
- ``camera rays, preliminary``: ``scene.ray_intersect_preliminary`` alone (the traversal);
- ``rays, fewer flags`` / ``raster, fewer flags``: both with ``RayFlags.All`` less the normals'
  derivatives (``dNSdUV``, ``dNGdUV``).

    python3 docs/results/gpu/issue10/stop31/primary_parts.py --variant cuda_ad_rgb --repeats 31 scenes/*.xml $D
"""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))
from raster_cull_probe import arguments  # noqa: E402  (the raster probes' command line)
from trace_overhead import timed_in_turn  # noqa: E402

args = arguments(__doc__)

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

mi.set_variant(args.variant)
from hybrid_integrator.api import rasterizer  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.frozen import FrozenScene  # noqa: E402
from hybrid_integrator.objects import object_indices  # noqa: E402
from hybrid_integrator.primary import camera_rays, primary_hits, resolve, shape_indices, silhouettes  # noqa: E402
from hybrid_integrator.raster.camera import RasterCamera  # noqa: E402

ALL = int(mi.RayFlags.All)
FEWER = ALL & ~(int(mi.RayFlags.dNSdUV) | int(mi.RayFlags.dNGdUV))
params = {"resx": 1280, "resy": 720, **dict(d.split("=", 1) for d in args.defines)}
print(f"{args.variant}: median of {args.repeats} calls each, device ms (kernel history) / wall ms")
for spec in args.scenes:
    scene, name = load_bench_scene(spec, params)
    sensor = scene.sensors()[0]
    camera = RasterCamera.from_sensor(sensor)
    w, h = camera.width, camera.height
    raster = rasterizer(scene)
    ids = raster.device_ids(raster.render(camera, (0.5, 0.5), "auto"))

    def rays(sensor):
        return camera_rays(sensor, w, h, (0.5, 0.5))

    def raster_hits(scene, sensor, ids, tables):
        hits = primary_hits(scene, rays(sensor), ids, w, h, tables)
        return hits.si.p, hits.si.n, hits.si.uv, hits.shape, hits.object, hits.valid

    def raster_pi(scene, sensor, ids, tables, refine_rays=True):
        ray = rays(sensor)
        record = resolve(ids, ray, tables)
        edge = (silhouettes(dr.select(record.hit, record.object + 1, 0), w, h) | (record.hit & ~record.inside)) & ~record.proxy
        refine = (record.proxy | edge) if refine_rays else mi.Bool(False)
        hit = record.hit & ~refine
        pi = dr.zeros(mi.PreliminaryIntersection3f, w * h)
        pi.t, pi.prim_uv, pi.prim_index, pi.shape_index = dr.select(hit, record.t, dr.inf), record.uv, record.prim, record.shape
        pi.shape = dr.gather(mi.ShapePtr, scene.shapes_dr(), record.shape, hit)
        pi.valid = hit
        if refine_rays:
            pi = dr.select(refine, scene.ray_intersect_preliminary(ray, False, refine), pi)
        return ray, pi, record

    def raster_compressed(scene, sensor, ids, tables):
        """The refined pixels' rays gathered into a launch of their own with ``dr.compress`` (its
        size read back to the host: the launch has as many lanes as rays), scattered back."""
        ray, pi, record = raster_pi(scene, sensor, ids, tables, refine_rays=False)
        edge = (silhouettes(dr.select(record.hit, record.object + 1, 0), w, h) | (record.hit & ~record.inside)) & ~record.proxy
        refine = record.proxy | edge
        pi.t, pi.valid = dr.select(refine, dr.inf, pi.t), pi.valid & ~refine
        index = dr.compress(refine)
        traced = scene.ray_intersect_preliminary(dr.gather(mi.Ray3f, ray, index), False)
        dr.eval(pi, traced)
        dr.scatter(pi, traced, index)
        valid = pi.is_valid()
        shape = dr.select(refine, shape_indices(tables.pointer_shape, pi.shape, valid), record.shape)
        obj = dr.select(refine, object_indices(tables.object, tables.first_triangle, shape, pi.prim_index, valid),
                        record.object)
        si = pi.compute_surface_interaction(ray, ALL, valid)
        return si.p, si.n, si.uv, shape, obj, valid

    def raster_no_rays(scene, sensor, ids, tables):
        ray, pi, record = raster_pi(scene, sensor, ids, tables, refine_rays=False)
        si = pi.compute_surface_interaction(ray, ALL, pi.is_valid())
        return si.p, si.n, si.uv, record.shape, record.object, pi.is_valid()

    def raster_no_si(scene, sensor, ids, tables):
        ray, pi, record = raster_pi(scene, sensor, ids, tables)
        valid = pi.is_valid()
        return pi.t, pi.prim_uv, pi.prim_index, shape_indices(tables.pointer_shape, pi.shape, valid), valid

    def raster_fewer(scene, sensor, ids, tables):
        ray, pi, record = raster_pi(scene, sensor, ids, tables)
        si = pi.compute_surface_interaction(ray, FEWER, pi.is_valid())
        return si.p, si.n, si.uv, record.shape, record.object, pi.is_valid()

    def camera(scene, sensor, tables, flags=ALL):
        si = scene.ray_intersect(rays(sensor), flags, False)
        valid = si.is_valid()
        return si.p, si.n, si.uv, shape_indices(tables.pointer_shape, si.shape, valid), valid

    def camera_fewer(scene, sensor, tables):
        return camera(scene, sensor, tables, FEWER)

    def camera_prelim(scene, sensor, tables):
        pi = scene.ray_intersect_preliminary(rays(sensor))
        valid = pi.is_valid()
        return pi.t, pi.prim_uv, pi.prim_index, shape_indices(tables.pointer_shape, pi.shape, valid), valid

    frozen = FrozenScene(scene)
    with_ids, without = (sensor, ids, raster.tables), (sensor, raster.tables)
    runs = {"raster": (raster_hits, with_ids), "raster, compressed rays": (raster_compressed, with_ids),
            "raster, no rays": (raster_no_rays, with_ids),
            "raster, no SI": (raster_no_si, with_ids), "raster, fewer flags": (raster_fewer, with_ids),
            "camera rays": (camera, without), "camera rays, preliminary": (camera_prelim, without),
            "rays, fewer flags": (camera_fewer, without)}
    calls = [lambda fn=frozen.freeze(fn), inputs=inputs: fn(*inputs) for fn, inputs in runs.values()]
    a = [dr.eval(v) or v for v in frozen.freeze(raster_hits)(*with_ids)]
    b = [dr.eval(v) or v for v in frozen.freeze(raster_compressed)(*with_ids)]
    import numpy as np

    valid = np.array(a[-1])
    same = bool(np.array_equal(valid, np.array(b[-1]))) and all(
        np.allclose(np.array(x)[..., valid] if np.array(x).ndim > 1 else np.array(x)[valid],
                    np.array(y)[..., valid] if np.array(y).ndim > 1 else np.array(y)[valid], rtol=1e-4, atol=1e-5)
        for x, y in zip(a[:-1], b[:-1]))
    print(f"{name} ({w}x{h}); compressed rays give the masked kernel's hits: {same}")
    for label, (wall, device) in zip(runs, timed_in_turn(calls, args.repeats)):
        print(f"  {label:26s} device {device:.3f} / wall {wall:.3f}", flush=True)
