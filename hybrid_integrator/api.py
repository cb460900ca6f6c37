"""The package's Python API for the raster stage."""
from __future__ import annotations

from collections import OrderedDict

import mitsuba as mi

from .environment import require_jit_rgb_variant
from .primary import primary_hits
from .raster.camera import RasterCamera, resolve_sensor
from .raster.gbuffer import GBuffer, check_aovs, compute_aovs
from .raster.visibility import Rasterizer

#: rasterizers of the scenes drawn most recently (geometry stays on the GPU between frames)
_RASTERIZERS: "OrderedDict[int, tuple[mi.Scene, Rasterizer]]" = OrderedDict()
_CACHE_SIZE = 4


def rasterizer(scene: mi.Scene) -> Rasterizer:
    """The :class:`Rasterizer` of ``scene``, made (and its geometry uploaded) on first use.

    The few most recent scenes keep theirs. Geometry is read when the rasterizer is made: after
    editing vertex positions through ``mi.traverse``, call :func:`forget` for that scene."""
    key = id(scene)
    entry = _RASTERIZERS.get(key)
    if entry is None or entry[0] is not scene:
        entry = (scene, Rasterizer(scene))
        _RASTERIZERS[key] = entry
        while len(_RASTERIZERS) > _CACHE_SIZE:
            _RASTERIZERS.popitem(last=False)
    _RASTERIZERS.move_to_end(key)
    return entry[1]


def forget(scene: mi.Scene) -> None:
    """Drop the cached rasterizer of ``scene`` (its GPU geometry is re-read on next use)."""
    _RASTERIZERS.pop(id(scene), None)


def rasterize(scene: mi.Scene, sensor: int | mi.Sensor = 0, offset: tuple[float, float] = (0.5, 0.5),
              aovs=()) -> GBuffer:
    """Rasterize the visibility buffer of ``scene`` as seen by ``sensor`` (paper §3.1).

    ``offset`` is the sub-pixel sample position in [0,1)² (the pixel centre by default); ``aovs``
    names any of the paper's Table 2 targets (``position``, ``normal``, ``albedo``,
    ``specular``, ``optical``, or ``"all"``) to derive from Mitsuba's BSDFs. Arrays are numpy,
    indexed ``[row, column]`` with row 0 at the top of the image."""
    require_jit_rgb_variant()
    aovs = check_aovs(aovs)
    if not all(0.0 <= float(o) < 1.0 for o in offset):
        from .errors import HybridError
        raise HybridError(f"sub-pixel offset {tuple(offset)} must lie in [0, 1)²")
    sensor = resolve_sensor(scene, sensor)
    camera = RasterCamera.from_sensor(sensor)
    raster = rasterizer(scene)
    vis = raster.draw(camera, offset)
    targets = compute_aovs(scene, primary_hits(scene, sensor, camera, vis), vis.depth.shape, aovs) if aovs else {}
    return GBuffer(**vars(vis), **targets, shape_ids=tuple(s.name for s in raster.shapes))
