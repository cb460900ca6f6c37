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

A pixel is traced when its object is selected this frame (``heuristic.py``, ``budget.py``: the
candidates of §4.1 narrowed by the relevance/cost heuristic) and it needs at least one of the
effects its object deserves; every other pixel shows the raster layer (§5).

**Part of an object.** A budget picks whole objects (or their shadow tiers, ``heuristic.py``), and
the one it cannot afford whole used to be left out however much budget remained: on the H100 the
glass Armadillo's whole trace (5.2 ms) never fit 75 % of the frame's trace time, so the budgets of
25, 50 and 75 % all bought the floor's shadows alone, at one error. What is left after the
selection now buys a part of one more object (``budget.plan_frame``): its pixels at 1, 2 or 3 of
the four positions of each 2×2 pixel quad (:data:`QUAD_KEPT`; 2 of 4 is a checkerboard), as
checkerboard rendering does, at that fraction of the object's rays. The object's per-object
``config`` carries the positions left out above its effect set (:func:`part_config`). Its pixels
there are *filled* where their BSDF has a delta lobe (:data:`FILL_LOBES`): they show the mean of
their traced neighbours on the same object (``compose.fill_left_out``), which the denoiser then
treats as any traced light. Elsewhere they keep the raster layer. A mirror's or a glass's traced
light is what the raster cannot show at all, and its neighbours' values have little noise; a
diffuse or glossy surface's traced light at 1 spp is mostly noise, and a fill averages it into
blotches two pixels wide that the denoiser keeps as detail (it removes only noise that is
independent from pixel to pixel). On the CPU at 320×180 (FLIP of the denoised frame against
``path``, 1–3 quarters): the glass Armadillo 0.0615 / 0.0570 / 0.0494 filled against
0.1288 / 0.0885 / 0.0602 not, but its diffuse floor 0.3005 / 0.2746 / 0.2108 filled against
0.2077 / 0.2040 / 0.2041 not, and the dining room's largest diffuse object 0.8019 / 0.7595 /
0.6822 against 0.7195 / 0.6853 / 0.6366 (docs/results/gpu/issue10/stop71).
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
from .errors import HybridError

EFFECTS = ("shadow", "reflection", "refraction", "indirect")
DEFAULT_EFFECTS = EFFECTS  # every term traced where selected: the traced pixels are unbiased (issue 11)


#: the bit above which a per-object ``config`` holds the quad positions its part leaves out
PART_SHIFT = 8
#: per number of quarters of an object traced, the positions of each 2×2 pixel quad kept
#: (position = x mod 2 + 2 · (y mod 2)): one; a diagonal pair (a checkerboard); all but one
QUAD_KEPT = {1: (0,), 2: (0, 3), 3: (0, 1, 3), 4: (0, 1, 2, 3)}
#: the lobes of a left-out pixel's BSDF that have it filled from its traced neighbours (module
#: docstring): delta reflection, delta transmission and null (what the raster layer cannot show)
FILL_LOBES = mi.BSDFFlags.Delta


def part_config(config: int, quarters: int) -> int:
    """An object's ``config`` (the index of its effect set) traced on ``quarters`` of its pixels
    (1–4, :data:`QUAD_KEPT`): the positions left out, as bits above :data:`PART_SHIFT`."""
    if config < 0 or quarters not in QUAD_KEPT:
        raise ValueError(f"part_config({config}, {quarters}): an effect set >= 0 and 1-4 quarters")
    left_out = sum(1 << p for p in range(4) if p not in QUAD_KEPT[quarters])
    return int(config) | (left_out << PART_SHIFT)


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
    if not isinstance(value, str) and not (isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value)):
        raise HybridError(f"effects={value!r} must be names of effects, as \"shadow, reflection\" or a list of them")
    names = [v.strip() for v in (value.split(",") if isinstance(value, str) else value) if v.strip()]
    unknown = [n for n in names if n not in EFFECTS]
    if unknown:
        raise HybridError(f"unknown effect(s) {unknown}: choose from {list(EFFECTS)}")
    return tuple(e for e in EFFECTS if e in names)


@dataclass(frozen=True)
class Selection:
    """Per-pixel outcome of the selection stage for one pass (on the device)."""

    traced: mi.Bool  # the pixel's primary hit is ray traced
    config: mi.UInt32  # which of the effect sets its object deserves (an index into ``configs``)
    long: mi.Bool  # its paths are expected to be long (:func:`long_paths`): the trace may launch them first
    #: a pixel of an object traced in part, at a quad position left out (module docstring); None
    #: where no pixel position was given
    left_out: mi.Bool | None = None
    #: those of them filled from their traced neighbours (:data:`FILL_LOBES`); None as ``left_out``
    filled: mi.Bool | None = None


def needs(flags: mi.UInt32, effects: tuple[str, ...], has_emitters: bool) -> mi.Bool:
    """Whether a BSDF with ``flags`` has a lobe one of ``effects`` acts on (the table above)."""
    need = mi.Bool(False)
    if "shadow" in effects and has_emitters:
        need |= mi.has_flag(flags, mi.BSDFFlags.Smooth)
    continued = lobes(effects)
    if continued:
        need |= (flags & continued) != 0
    return need


def select_pixels(si: mi.SurfaceInteraction3f, ray: mi.Ray3f, obj: mi.UInt32, valid: mi.Bool,
                  object_config: mi.Int32, configs: tuple[tuple[str, ...], ...], has_emitters: bool,
                  pixel: mi.UInt32 | None = None, width: int = 0) -> Selection:
    """Traced pixels: pixels of the selected objects (``object_config`` ≥ 0, per object: the index
    of the object's effect set in ``configs``; −1: not traced this frame) whose BSDF needs one of
    those effects. ``object_config`` is data, not code: a new selection reuses the same kernels.
    With each lane's ``pixel`` (its index in a film ``width`` pixels wide), an object's config may
    also leave out quad positions (:func:`part_config`): its pixels there are not traced but
    ``left_out``, and ``filled`` where their BSDF has a lobe of :data:`FILL_LOBES`."""
    raw = dr.select(valid, dr.gather(mi.Int32, object_config, obj, valid), -1)
    config = dr.select(raw >= 0, raw & ((1 << PART_SHIFT) - 1), -1)
    flags = si.bsdf(ray).flags()
    traced = mi.Bool(False)
    for k, effects in enumerate(configs):  # every set, selected or not: the same kernel every frame
        traced |= (config == k) & needs(flags, effects, has_emitters)
    traced &= valid
    left_out = filled = None
    if pixel is not None:
        position = (pixel & 1) | (((pixel // width) & 1) << 1)
        left_out = traced & (raw >= 0) & (((mi.UInt32(raw) >> (PART_SHIFT + position)) & 1) != 0)
        filled = left_out & ((flags & int(FILL_LOBES)) != 0)
        traced &= ~left_out
    return Selection(traced=traced, config=mi.UInt32(dr.maximum(config, 0)), long=long_paths(flags),
                     left_out=left_out, filled=filled)


#: lanes per block of the compaction's first-level prefix sums (``compact``): the largest block
#: that Dr.Jit's CUDA backend scans in one thread block, each block on its own
SCAN_BLOCK = 1024


def compact(mask: mi.Bool, *first: mi.Bool | None, two_level: bool | None = None,
            regions: int | None = None) -> tuple[mi.UInt32, mi.Bool, mi.UInt32]:
    """Stream compaction without a host round trip: lane ``j`` < n (n = set lanes) gets the index of
    the ``j``-th set lane, in order: an exclusive prefix sum gives each set lane its slot (packed;
    on the LLVM backend then dealt over the threads, below). The arrays keep the full width, so the kernels that follow have a fixed size (they are recorded
    once, ``dr.freeze``) and the lanes past ``n`` do nothing; ``dr.compress`` would instead read
    ``n`` back to the host to size its result. With ``first`` masks (None: left out), the set lanes
    of the first mask come first, then those of the second that are not in the first, ..., then
    the rest, each part in order (a stable partition). The parts' counts share the bit fields of
    one integer per lane (a field of ``bits`` holds any count up to the width), so that one prefix
    sum numbers every part: each prefix sum is a kernel and a scan more in every replay of the
    frozen pass, before its trace launches (three parts of a 1280×720 frame: one 64-bit sum).

    On CUDA the prefix sum has two levels: each block of ``SCAN_BLOCK`` lanes is scanned on its own
    (``dr.block_prefix_sum``), the blocks' totals (``dr.block_sum``; 900 for 1280×720) are scanned,
    and a lane adds its block's offset. Dr.Jit's one scan over the whole width (``dr.prefix_sum``)
    chains its 900 thread blocks, each waiting for the sums of those before it: on an H200,
    0.039 ms for one part and 0.063–0.065 ms for three, against 0.011 + 0.005 + 0.004 ms for the
    two levels (docs/results/gpu/issue10/stop39/probe.log). On the LLVM backend the one scan is
    the faster (57,600 lanes: 0.048 against 0.061 ms of kernels on this project's CPU); ``two_level``
    (default: on CUDA) chooses.

    On the LLVM backend the set lanes are then dealt over ``regions`` equal parts of the width
    (default: Dr.Jit's thread count; 1, none, on CUDA), in chunks of ``SPREAD_CHUNK`` lanes taken
    in turn (:func:`spread_lanes`): Dr.Jit's LLVM backend splits a launch of up to
    2 × 16384 × threads lanes into one block per thread, so set lanes packed at the front all fell
    into the first thread's block. On this project's two cores, at 320×180, the glass Armadillo
    traced alone took 28.2 ms against 23.2 for the Armadillo and its floor; dealt, 15.1 against
    20.7 (docs/results/gpu/issue10/stop47). Chunks keep the SIMD packets full. The lane order changes
    no result: each pixel's random numbers are its own.
    Returns (index, lane active, slot of each set lane); a lane that holds no set lane is inactive
    and its index unspecified.
    """
    parts, rest = [], mask
    for group in (g for g in first if g is not None):
        parts.append(rest & group)
        rest = rest & ~group
    parts.append(rest)
    width = dr.width(mask)
    bits = max(width.bit_length(), 1)
    per_word = 64 // bits
    lane = dr.arange(mi.UInt32, width)
    if two_level is None:
        two_level = dr.backend_v(mask) == dr.JitBackend.CUDA
    two_level = two_level and width > SCAN_BLOCK
    slot, n = mi.UInt32(0), mi.UInt32(0)
    for start in range(0, len(parts), per_word):
        word = parts[start:start + per_word]
        dtype = mi.UInt64 if bits * len(word) > 32 else mi.UInt32
        flags = dtype(0)
        for k, part in enumerate(word):
            flags |= dtype(part) << (bits * k)
        if two_level:
            dr.eval(flags)  # the block scans read it from memory
            totals = dr.block_sum(flags, SCAN_BLOCK)
            offsets = dr.prefix_sum(totals)
            last = mi.UInt32(dr.width(totals) - 1)
            total = dr.gather(dtype, offsets, last) + dr.gather(dtype, totals, last)
            within = dr.block_prefix_sum(flags, SCAN_BLOCK) + dr.gather(dtype, offsets, lane // SCAN_BLOCK)
        else:
            within = dr.prefix_sum(flags)
            last = mi.UInt32(width - 1)
            total = dr.gather(dtype, within, last) + dr.gather(dtype, flags, last)
        for k, part in enumerate(word):
            shift, ones = bits * k, (1 << bits) - 1
            slot = dr.select(part, n + mi.UInt32((within >> shift) & ones), slot)
            n = n + mi.UInt32((total >> shift) & ones)
    if regions is None:
        regions = dr.thread_count() if dr.backend_v(mask) == dr.JitBackend.LLVM else 1
    slot, packed = spread_lanes(slot, lane, width, regions)
    index = dr.empty(mi.UInt32, width)  # lanes that hold no set lane: unspecified (read by none, not cleared)
    dr.scatter(index, lane, slot, mask)
    return index, packed < n, slot


#: lanes dealt together by :func:`spread_lanes`: a multiple of every SIMD width of Dr.Jit's LLVM backend
SPREAD_CHUNK = 64


def spread_lanes(packed: mi.UInt32, lane: mi.UInt32, width: int, regions: int) -> tuple[mi.UInt32, mi.UInt32]:
    """A permutation of ``width`` lanes that deals packed lanes over ``regions`` equal parts: packed
    chunk ``c`` (``SPREAD_CHUNK`` lanes) goes to part ``c % regions``, at chunk ``c // regions`` of
    it; the parts (each a whole number of chunks) cover as much of the width as they can, and the
    lanes past them stay where they are. Returns each packed lane's (``packed``) place, and each
    ``lane``'s packed lane (the inverse)."""
    part = width // (SPREAD_CHUNK * regions) * SPREAD_CHUNK
    if regions <= 1 or part == 0:
        return packed, lane
    covered = regions * part
    chunk, within = packed // SPREAD_CHUNK, packed % SPREAD_CHUNK
    place = (chunk % regions) * part + (chunk // regions) * SPREAD_CHUNK + within
    offset = lane % part
    back = ((offset // SPREAD_CHUNK) * regions + lane // part) * SPREAD_CHUNK + offset % SPREAD_CHUNK
    return dr.select(packed < covered, place, packed), dr.select(lane < covered, back, lane)


#: lobes whose paths are the frame's longest: a refracted path crosses at least two interfaces of
#: its object, and total internal reflection adds more (glass, rough glass)
LONG_LOBES = mi.BSDFFlags.DeltaTransmission | mi.BSDFFlags.GlossyTransmission


def long_paths(flags):
    """Pixels whose primary BSDF ``flags`` (``mi.UInt32``, or one BSDF's as an int) have a lobe of
    ``LONG_LOBES``."""
    return (flags & int(LONG_LOBES)) != 0


def refracts(bsdfs) -> bool:
    """Whether one of ``bsdfs`` (Mitsuba BSDFs; None: a shape without one) has a lobe of
    ``LONG_LOBES``: then some traced pixels may have the frame's longest paths."""
    return any(b is not None and long_paths(int(b.flags())) for b in bsdfs)
