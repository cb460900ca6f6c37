"""Stage 3, selection: which pixels the ray tracer touches (paper §3.2, §4.1).

Sabino et al. ray trace only *candidate* objects, chosen in pre-production (§4.1), and only the
secondary rays their materials call for: the G-buffer's optical properties say whether a pixel
needs reflection or refraction rays (§3.2, Fig. 1f). Here the material test reads the lobes of the
pixel's own Mitsuba BSDF:

============  ===============================================  ============================
effect        traced where the BSDF has                         secondary rays
============  ===============================================  ============================
shadow        a non-delta lobe (something light can reach)      shadow rays to sampled emitters
reflection    delta or glossy reflection                        BSDF-sampled reflection rays
refraction    delta or glossy transmission, or a null lobe      BSDF-sampled refraction rays
indirect      diffuse reflection or transmission                BSDF-sampled diffuse rays
============  ===============================================  ============================

A pixel is traced when its shape is selected this frame (``heuristic.py``, ``budget.py``: the
candidates of §4.1 narrowed by the relevance/cost heuristic) and it needs at least one of the
effects its object deserves; every other pixel shows the raster layer (§5).
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .errors import HybridError

EFFECTS = ("shadow", "reflection", "refraction", "indirect")
DEFAULT_EFFECTS = ("shadow", "reflection", "refraction")


def count(mask: mi.Bool) -> int:
    """Number of set lanes, on the host."""
    return int(dr.ravel(dr.count(mask))[0])


def lobes(effects: tuple[str, ...]) -> int:
    """The BSDF lobes whose sampled directions are followed for ``effects`` (BSDFFlags bits)."""
    F = mi.BSDFFlags
    table = {"reflection": F.DeltaReflection | F.GlossyReflection,
             "refraction": F.DeltaTransmission | F.GlossyTransmission | F.Null,
             "indirect": F.DiffuseReflection | F.DiffuseTransmission}
    flags = 0
    for effect in effects:
        flags |= int(table.get(effect, 0))
    return flags


def parse_effects(value) -> tuple[str, ...]:
    """``"shadow, reflection"`` or a sequence of names → a tuple in canonical order."""
    names = [v.strip() for v in (value.split(",") if isinstance(value, str) else value) if v.strip()]
    unknown = [n for n in names if n not in EFFECTS]
    if unknown:
        raise HybridError(f"unknown effect(s) {unknown}: choose from {list(EFFECTS)}")
    return tuple(e for e in EFFECTS if e in names)


@dataclass(frozen=True)
class Selection:
    """Per-pixel outcome of the selection stage for one pass."""

    traced: mi.Bool  # the pixel's primary hit is ray traced
    config: mi.UInt32  # which of the effect sets its object deserves (an index into ``configs``)
    count: int  # number of traced pixels


def needs(flags: mi.UInt32, effects: tuple[str, ...], has_emitters: bool) -> mi.Bool:
    """Whether a BSDF with ``flags`` has a lobe one of ``effects`` acts on (the table above)."""
    need = mi.Bool(False)
    if "shadow" in effects and has_emitters:
        need |= mi.has_flag(flags, mi.BSDFFlags.Smooth)
    continued = lobes(effects)
    if continued:
        need |= (flags & continued) != 0
    return need


def select_pixels(si: mi.SurfaceInteraction3f, ray: mi.Ray3f, shape_index: mi.UInt32, valid: mi.Bool,
                  shape_config: np.ndarray, configs: tuple[tuple[str, ...], ...], has_emitters: bool) -> Selection:
    """Traced pixels: pixels of the selected shapes (``shape_config`` ≥ 0, per scene shape: the
    index of the shape's effect set in ``configs``) whose BSDF needs one of those effects."""
    if not shape_config.size or shape_config.max() < 0:
        return Selection(traced=dr.zeros(mi.Bool, dr.width(valid)), config=dr.zeros(mi.UInt32, dr.width(valid)), count=0)
    config = dr.gather(mi.Int32, mi.Int32(shape_config.astype(np.int32)), shape_index, valid)
    config = dr.select(valid, config, -1)
    flags = si.bsdf(ray).flags()
    traced = mi.Bool(False)
    for k, effects in enumerate(configs):  # every set, selected or not: the same kernel every frame
        traced |= (config == k) & needs(flags, effects, has_emitters)
    traced &= valid
    return Selection(traced=traced, config=mi.UInt32(dr.maximum(config, 0)), count=count(traced))
