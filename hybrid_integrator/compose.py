"""Stage 5, composition: the ray-traced effects layer over the raster layer (paper §5, §6).

The paper blends the two colour attachments with a weight "relative to the desired amount of ray
tracing effects"; since only traced pixels carry a ray-traced value, superimposing them is safe.
Here: ``blend · rt + (1 − blend) · raster`` on traced pixels, the raster layer elsewhere.

An object traced in part (``selection.py``: a budget's last object, at 1–3 of the four positions
of each 2×2 pixel quad) has pixels with no traced value of their own; :func:`fill_left_out` gives
those with a delta lobe (``selection.FILL_LOBES``: a mirror, a glass) the mean of their traced
8-neighbours on the same object (every left-out pixel has one where the object continues: the
kept positions of :data:`selection.QUAD_KEPT` touch every position of the quad and its
neighbours), the reconstruction of checkerboard rendering. A pixel with no such neighbour (the
object's edge), and a left-out pixel without a delta lobe, keeps the raster layer.
"""
from __future__ import annotations

import drjit as dr
import mitsuba as mi

#: a pixel's 8-neighbourhood, (dx, dy)
NEIGHBOURS = tuple((dx, dy) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if dx or dy)


def compose(raster: mi.Color3f, rt: mi.Color3f, traced: mi.Bool, blend: float) -> mi.Color3f:
    return dr.select(traced, blend * rt + (1.0 - blend) * raster, raster)


def fill_left_out(rt: mi.Color3f, traced: mi.Bool, left_out: mi.Bool, obj: mi.UInt32, width: int,
                  height: int) -> tuple[mi.Color3f, mi.Bool]:
    """The traced layer ``rt`` (per pixel, row-major, ``width`` × ``height``) with each ``left_out``
    pixel set to the mean of its ``traced`` 8-neighbours of the same object ``obj``; returns it and
    the pixels that now carry a traced value (``traced`` and the filled ones)."""
    index = dr.arange(mi.UInt32, width * height)
    x, y = mi.Int32(index % width), mi.Int32(index // width)
    total, count = dr.zeros(mi.Color3f, width * height), dr.zeros(mi.Float, width * height)
    for dx, dy in NEIGHBOURS:
        nx, ny = x + dx, y + dy
        inside = left_out & (nx >= 0) & (nx < width) & (ny >= 0) & (ny < height)
        n = mi.UInt32(ny * width + nx)
        use = inside & dr.gather(mi.Bool, traced, n, inside) & (dr.gather(mi.UInt32, obj, n, inside) == obj)
        total += dr.gather(mi.Color3f, rt, n, use)
        count += dr.select(use, 1.0, 0.0)
    filled = left_out & (count > 0)
    return dr.select(filled, total / dr.maximum(count, 1.0), rt), traced | filled
