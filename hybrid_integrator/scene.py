"""Loading Mitsuba scenes for the pipeline, with errors that name the problem."""
from __future__ import annotations

from pathlib import Path

import mitsuba as mi

from .environment import require_jit_rgb_variant
from .errors import HybridError


def load_scene(path: str | Path, optimize: bool = False, **params) -> mi.Scene:
    """``mi.load_file`` with clear errors for a missing or malformed file.

    ``optimize=False`` by default: Mitsuba would otherwise merge meshes that share a BSDF, and the
    pipeline selects and reports objects one by one (paper §4). ``params`` fill the scene's
    ``$name`` defaults (``resx=1280``, ``spp=4``, ...)."""
    require_jit_rgb_variant()
    path = Path(path)
    if not path.is_file():
        raise HybridError(f"scene file not found: {path}")
    try:
        return mi.load_file(str(path), optimize=optimize, **params)
    except Exception as exc:  # Mitsuba raises RuntimeError with the parser's message
        raise HybridError(f"cannot load scene {path}: {exc}") from exc
