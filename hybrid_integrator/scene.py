"""Loading Mitsuba scenes for the pipeline, with errors that name the problem."""
from __future__ import annotations

from pathlib import Path

import mitsuba as mi

from .environment import require_jit_rgb_variant
from .errors import HybridError
from .objects import batch_by_material


def load_scene(path: str | Path, batch: bool = True, **params) -> mi.Scene:
    """``mi.load_file`` with clear errors for a missing or malformed file.

    Every ``<shape>`` of the file is an object of the heuristic (paper §4): the file is loaded
    with ``optimize=False``, then, with ``batch`` (the default), the meshes that share a material
    are merged into one Mitsuba mesh each while the scene keeps the record of which object every
    triangle belongs to (``objects.batch_by_material``): the hybrid's per-frame cost then follows
    the number of materials, not of objects. ``params`` fill the scene's ``$name`` defaults
    (``resx=1280``, ``spp=4``, ...)."""
    require_jit_rgb_variant()
    path = Path(path)
    if path.is_dir():
        raise HybridError(f"{path} is a directory: give a scene file (.xml)")
    if not path.is_file():
        raise HybridError(f"scene file not found: {path}")
    try:
        scene = mi.load_file(str(path), optimize=False, **params)
    except Exception as exc:  # Mitsuba raises RuntimeError with the parser's message
        raise HybridError(f"cannot load scene {path}: {exc}") from exc
    return batch_by_material(scene) if batch else scene
