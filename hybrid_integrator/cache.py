"""Per-scene state kept between frames: GPU geometry, lights, material constants.

Mitsuba scenes cannot be weakly referenced, so the few most recently used scenes keep theirs
(strong references, least recently used dropped first). After editing a scene's geometry or
materials through ``mi.traverse``, call :func:`forget` for it.
"""
from __future__ import annotations

from collections import OrderedDict
from typing import Callable

import mitsuba as mi

_CACHE: "OrderedDict[int, tuple[mi.Scene, dict[str, object]]]" = OrderedDict()
_CACHE_SIZE = 4


def scene_state(scene: mi.Scene, name: str, factory: Callable[[], object]):
    """The ``name`` entry of ``scene``'s state, made by ``factory`` on first use."""
    key = id(scene)
    entry = _CACHE.get(key)
    if entry is None or entry[0] is not scene:
        entry = (scene, {})
        _CACHE[key] = entry
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    _CACHE.move_to_end(key)
    if name not in entry[1]:
        entry[1][name] = factory()
    return entry[1][name]


def forget(scene: mi.Scene) -> None:
    """Drop everything kept for ``scene`` (re-read on next use)."""
    _CACHE.pop(id(scene), None)
