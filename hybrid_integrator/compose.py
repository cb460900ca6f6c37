"""Stage 5, composition: the ray-traced effects layer over the raster layer (paper §5, §6).

The paper blends the two colour attachments with a weight "relative to the desired amount of ray
tracing effects"; since only traced pixels carry a ray-traced value, superimposing them is safe.
Here: ``blend · rt + (1 − blend) · raster`` on traced pixels, the raster layer elsewhere.
"""
from __future__ import annotations

import drjit as dr
import mitsuba as mi


def compose(raster: mi.Color3f, rt: mi.Color3f, traced: mi.Bool, blend: float) -> mi.Color3f:
    return dr.select(traced, blend * rt + (1.0 - blend) * raster, raster)
