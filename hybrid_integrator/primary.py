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

from .raster.camera import RasterCamera
from .raster.visibility import VisibilityBuffer


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
    ids = np.array(dr.reinterpret_array(mi.UInt32, scene.shapes_dr()), dtype=np.int64)
    table = np.zeros(ids.max() + 1, dtype=np.uint32)
    table[ids] = np.arange(len(ids), dtype=np.uint32)
    return dr.gather(mi.UInt32, mi.UInt32(table), dr.reinterpret_array(mi.UInt32, shape), valid)


def silhouettes(shape_index: np.ndarray) -> np.ndarray:
    """Pixels with a 4-neighbour that shows another shape (or the background)."""
    edge = np.zeros(shape_index.shape, dtype=bool)
    horizontal = shape_index[:, 1:] != shape_index[:, :-1]
    vertical = shape_index[1:, :] != shape_index[:-1, :]
    edge[:, 1:] |= horizontal
    edge[:, :-1] |= horizontal
    edge[1:, :] |= vertical
    edge[:-1, :] |= vertical
    return edge


def primary_hits(scene: mi.Scene, sensor: mi.Sensor, camera: RasterCamera, vis: VisibilityBuffer) -> PrimaryHits:
    """Rebuild Mitsuba's surface interactions from the visibility buffer ``vis``."""
    ray = camera_rays(sensor, camera, vis.offset)
    shape_index = mi.UInt32(np.maximum(vis.shape_index, 0).ravel().astype(np.uint32))
    edge = silhouettes(vis.shape_index) & ~vis.proxy
    refine = (vis.proxy | edge).ravel()
    raster_hit = mi.Bool(vis.hit.ravel() & ~refine)
    # Mitsuba's camera rays start on the near plane; the raster measures from the eye
    near_t = dr.norm(ray.o - mi.Point3f(*(float(c) for c in camera.eye)))

    pi = dr.zeros(mi.PreliminaryIntersection3f, dr.width(ray))
    pi.t = dr.select(raster_hit, mi.Float(vis.depth.ravel()) - near_t, dr.inf)
    pi.prim_uv = mi.Point2f(mi.Float(vis.bary[..., 0].ravel()), mi.Float(vis.bary[..., 1].ravel()))
    pi.prim_index = mi.UInt32(vis.prim_index.ravel())
    pi.shape_index = shape_index
    pi.shape = dr.gather(mi.ShapePtr, scene.shapes_dr(), shape_index, raster_hit)
    pi.valid = raster_hit

    if refine.any():
        retrace = mi.Bool(refine)
        pi = dr.select(retrace, scene.ray_intersect_preliminary(ray, False, retrace), pi)
    valid = pi.is_valid()
    si = pi.compute_surface_interaction(ray, mi.RayFlags.All, valid)
    return PrimaryHits(ray=ray, si=si, shape_index=shape_indices(scene, pi.shape, valid), valid=valid,
                       proxy_refined=int(vis.proxy.sum()), edge_refined=int(edge.sum()))
