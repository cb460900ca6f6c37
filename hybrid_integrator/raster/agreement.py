"""How far the raster's primary visibility agrees with Mitsuba's ray tracer.

The hybrid is only as right as its first hits: a pixel whose raster hit differs from the camera
ray's hit is shaded as the wrong surface. This module traces Mitsuba's own camera rays through the
same sub-pixel positions (``scene.ray_intersect_preliminary``) and compares, pixel by pixel.
Disagreement is expected only where a pixel centre falls exactly on an edge or a silhouette.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from ..objects import object_indices
from ..primary import camera_rays, shape_indices
from .camera import RasterCamera
from .visibility import VisibilityBuffer


@dataclass(frozen=True)
class Agreement:
    """Fractions of pixels on which the raster and the ray tracer agree."""

    pixels: int
    hit_miss: float  # both hit something, or both see the background
    shape_and_triangle: float  # same shape and same triangle (or both background)
    median_relative_depth_error: float  # over pixels both hit on the same triangle
    p99_relative_depth_error: float

    def as_dict(self) -> dict:
        return asdict(self)


def visibility_agreement(scene: mi.Scene, sensor: mi.Sensor, vis: VisibilityBuffer) -> Agreement:
    """Compare ``vis`` with ``ray_intersect_preliminary`` along Mitsuba's camera rays: the same
    object and triangle, hit or miss, and the depth."""
    from ..api import rasterizer

    camera = RasterCamera.from_sensor(sensor)
    ray = camera_rays(sensor, camera.width, camera.height, vis.offset)
    pi = scene.ray_intersect_preliminary(ray)
    valid = pi.is_valid()
    hit = np.array(valid).reshape(vis.depth.shape)
    tables = rasterizer(scene).tables
    index = object_indices(tables.object, tables.first_triangle, shape_indices(tables.pointer_shape, pi.shape, valid), pi.prim_index, valid)
    shape = np.where(hit, np.array(index, dtype=np.int64).reshape(hit.shape), -1)
    prim = np.array(pi.prim_index, dtype=np.int64).reshape(hit.shape)
    # Mitsuba's camera rays start on the near plane; the raster's depth is measured from the eye
    eye = mi.Point3f(*(float(c) for c in camera.eye))
    depth = np.array(pi.t + dr.norm(ray.o - eye), dtype=np.float64).reshape(hit.shape)

    same = (shape == vis.shape_index) & (~hit | (prim == vis.prim_index))
    both = same & hit
    rel = np.abs(vis.depth[both] - depth[both]) / depth[both]
    return Agreement(pixels=int(hit.size), hit_miss=float(np.mean(hit == vis.hit)),
                     shape_and_triangle=float(np.mean(same)),
                     median_relative_depth_error=float(np.median(rel)) if rel.size else 0.0,
                     p99_relative_depth_error=float(np.percentile(rel, 99)) if rel.size else 0.0)
