"""What is kept between frames and runs: per-scene state in memory (GPU geometry, lights,
material constants) and files on disk (ground truths, generated meshes).

Mitsuba scenes cannot be weakly referenced, so the few most recently used scenes keep theirs
(strong references, least recently used dropped first). An edit of a scene's geometry through
``mi.traverse`` is found at the next frame and its state made again (``api.rasterizer``); after
editing anything else through it (materials, lights), call :func:`forget` for the scene (its
frozen device pass replays with a snapshot of its variables: ``frozen.py``). A scene kept alive here can cost the other
scenes' frames too: a scene's snapshot holds the variables of every shape alive when it is taken
(Dr.Jit records a virtual call for every registered instance), so scenes loaded earlier lengthen
its replays and scenes loaded later do not (``docs/results/cpu/cached_scenes``); :func:`forget` a
scene that is done with.
"""
from __future__ import annotations

import os
from collections import OrderedDict
from pathlib import Path
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


def disk_cache(name: str) -> Path:
    """The folder ``name`` of the on-disk cache: ``$HYBRID_CACHE``, else ``~/.cache/hybrid_integrator``
    (under ``$XDG_CACHE_HOME`` when set)."""
    root = os.environ.get("HYBRID_CACHE") or Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "hybrid_integrator"
    return Path(root) / name
