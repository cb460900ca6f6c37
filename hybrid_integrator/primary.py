"""Primary hits: from a visibility buffer to exact Mitsuba surface interactions (paper §3.2).

The hybrid's ray tracer starts where the rasterizer stopped. For every pixel the visibility buffer
names the shape, the triangle and the barycentrics of the first hit; a Mitsuba
``PreliminaryIntersection3f`` built from them and completed with
``compute_surface_interaction`` against the real camera ray is the *same* interaction Mitsuba's own
ray tracer would have produced (position from the barycentrics, shading frame, UVs, ``wi``), so the
secondary rays and the BSDFs that follow are Mitsuba's, unchanged.

Two kinds of pixel are *refined*, i.e. their primary hit is re-found by tracing their camera ray
(``ray_intersect_preliminary``) instead of trusting the raster, and both are counted in the frame
statistics:

- pixels of tessellated analytic shapes (``proxy``): the proxy only says that the exact shape may
  be there;
- *silhouette* pixels, whose 4-neighbourhood shows another shape or the background. The
  rasterizer snaps vertices to a fixed-point sub-pixel grid (1/256 pixel on Mesa), so a sample
  lying that close to an object's outline can land on the wrong side of it; on a straight outline
  aligned with the pixel grid this flips a whole column at once. Within one shape the same
  mistake only swaps two triangles that share the edge, which changes nothing visible.
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .cache import scene_state
from .raster.camera import RasterCamera


@dataclass
class PrimaryHits:
    """Camera rays and first-hit interactions of every pixel (row-major, row 0 at the top)."""

    ray: mi.Ray3f
    si: mi.SurfaceInteraction3f
    #: index into ``scene.shapes()`` of each pixel's hit (after proxy refinement)
    shape_index: mi.UInt32
    #: the pixel's first hit is a surface (background pixels and proxy misses are False)
    valid: mi.Bool
    #: pixels whose hit came from a ray because the raster saw an analytic shape's proxy
    proxy_refined: int = 0
    #: silhouette pixels whose hit came from a ray (see the module docstring)
    edge_refined: int = 0


def camera_rays(sensor: mi.Sensor, camera: RasterCamera, offset: tuple[float, float]) -> mi.Ray3f:
    """Mitsuba's camera rays through every pixel at sub-pixel ``offset`` (the rays the raster
    stands in for, and the primary rays of the pure ray-tracing baseline)."""
    index = dr.arange(mi.UInt32, camera.width * camera.height)
    # opaque: the offset changes every pass, and a literal would recompile the kernel each time
    ox, oy = (dr.opaque(mi.Float, float(o)) for o in offset)
    position = mi.Point2f((mi.Float(index % camera.width) + ox) / camera.width,
                          (mi.Float(index // camera.width) + oy) / camera.height)
    ray, _ = sensor.sample_ray(0.0, 0.5, position, mi.Point2f(0.5, 0.5))
    return ray


def shape_indices(scene: mi.Scene, shape: mi.ShapePtr, valid: mi.Bool) -> mi.UInt32:
    """Index into ``scene.shapes()`` of each lane's ``shape`` pointer.

    ``PreliminaryIntersection3f.shape_index`` is filled by the LLVM backend's ray tracer but not by
    OptiX, so indices are recovered from the pointers themselves: a shape pointer is an id in
    Dr.Jit's registry, mapped back through a small lookup table."""
    table = scene_state(scene, "shape_table", lambda: _shape_table(scene))
    return dr.gather(mi.UInt32, table, dr.reinterpret_array(mi.UInt32, shape), valid)


def _shape_table(scene: mi.Scene) -> mi.UInt32:
    """Registry id of each shape → its index in ``scene.shapes()`` (read once per scene)."""
    ids = np.array(dr.reinterpret_array(mi.UInt32, scene.shapes_dr()), dtype=np.int64)
    table = np.zeros(ids.max() + 1, dtype=np.uint32)
    table[ids] = np.arange(len(ids), dtype=np.uint32)
    return mi.UInt32(table)


def silhouettes(shape_id: mi.UInt32, width: int, height: int) -> mi.Bool:
    """Pixels with a 4-neighbour inside the image that shows another shape (or the background);
    ``shape_id`` per pixel, row-major."""
    i = dr.arange(mi.UInt32, width * height)
    x, y = i % width, i // width
    edge = mi.Bool(False)
    for inside, j in ((x + 1 < width, i + 1), (x > 0, i - 1), (y + 1 < height, i + width), (y > 0, i - width)):
        edge |= inside & (dr.gather(mi.UInt32, shape_id, j, inside) != shape_id)
    return edge


def primary_hits(scene: mi.Scene, sensor: mi.Sensor, camera: RasterCamera, words: mi.UInt32, distance: mi.Float,
                 offset: tuple[float, float], is_proxy: np.ndarray) -> PrimaryHits:
    """Rebuild Mitsuba's surface interactions from the raster targets (``Rasterizer.read_targets``,
    uploaded as they are), decoded on the device; ``is_proxy`` flags each scene shape drawn as a
    proxy."""
    ray = camera_rays(sensor, camera, offset)
    i = dr.arange(mi.UInt32, camera.width * camera.height)
    shape_id = dr.gather(mi.UInt32, words, 4 * i)  # 0: background
    hit = shape_id > 0
    shape_index = dr.select(hit, shape_id - 1, 0)
    proxy = hit & dr.gather(mi.Bool, mi.Bool(is_proxy), shape_index, hit) if is_proxy.size else mi.Bool(False)
    edge = silhouettes(shape_id, camera.width, camera.height) & ~proxy
    refine = proxy | edge
    raster_hit = hit & ~refine
    # Mitsuba's camera rays start on the near plane; the raster measures from the eye
    near_t = dr.norm(ray.o - mi.Point3f(*(float(c) for c in camera.eye)))

    pi = dr.zeros(mi.PreliminaryIntersection3f, dr.width(ray))
    pi.t = dr.select(raster_hit, distance - near_t, dr.inf)
    pi.prim_uv = mi.Point2f(*(dr.reinterpret_array(mi.Float, dr.gather(mi.UInt32, words, 4 * i + k)) for k in (2, 3)))
    pi.prim_index = dr.gather(mi.UInt32, words, 4 * i + 1)
    pi.shape_index = shape_index
    pi.shape = dr.gather(mi.ShapePtr, scene.shapes_dr(), shape_index, raster_hit)
    pi.valid = raster_hit
    pi = dr.select(refine, scene.ray_intersect_preliminary(ray, False, refine), pi)
    valid = pi.is_valid()
    si = pi.compute_surface_interaction(ray, mi.RayFlags.All, valid)
    counts = dr.count(proxy), dr.count(edge)
    dr.eval(*counts)
    return PrimaryHits(ray=ray, si=si, shape_index=shape_indices(scene, pi.shape, valid), valid=valid,
                       proxy_refined=int(dr.ravel(counts[0])[0]), edge_refined=int(dr.ravel(counts[1])[0]))
