"""One frame of the hybrid pipeline (paper §6, Fig. 4): raster → lighting → selection → ray
tracing → composition, repeated once per sample at a jittered sub-pixel offset and splatted into
the film.

:meth:`HybridRenderer.render` is the paper's Fig. 4 as code: draw every sample pass's visibility
buffer with OpenGL (stage 1; the GPU draws while the host goes on), plan the selection on the host
(stage 3, from the last frame's coverage), then per sample pass run the *device pass*
(:func:`device_pass`): primary hits, G-buffer and
deferred lighting (stage 2), the selected pixels, their secondary rays (stage 4) and the
composition (stage 5), all Dr.Jit kernels, frozen with ``dr.freeze`` so that a frame replays
recorded kernels instead of tracing Python again. (With ``refine="trace"``, the default on CUDA,
the raster's few refined pixels find their hits in stage 4's launch, so the device pass runs
stages 1, 3, 4, 2, 5: :func:`refined_lanes`.) The backend is synchronized once per frame, at
its end. The frame's few counts (one small array per pass) are read back before that: on the GPU
they are copied to the host behind the device passes (``interop.HostCopy``, a CUDA event), and the
host learns from them (coverage, errors, ambient light) while the GPU still develops and denoises
the frame, instead of after it. With a still camera, a budget's plan for the next frame is made
earlier still, while the GPU traces, from the coverage this frame was planned from
(:meth:`HybridRenderer._plan_ahead`): on the H200 the host's work once the counts are in is longer
than the 1.1 ms denoiser, so the frame waits for any more of it.

Each sample pass rasterizes the whole frame at one sub-pixel offset (a scrambled Halton sequence,
one point per pass), so all pixels of a pass share the offset, and ``spp`` passes give
anti-aliasing. Every pass is splatted with the film's reconstruction filter at
``pixel + offset``, exactly where Mitsuba would splat a camera ray through that film position, so
the image converges to what Mitsuba computes. ``primary="raytrace"`` replaces the raster pass by
Mitsuba's camera rays and changes nothing else: the paper's pure ray-tracing baseline (§8).

**Timing.** ``FrameStats.times_ms`` holds each stage's *device* time: the OpenGL draw from a GL
timer query, the Dr.Jit kernels of each stage from Dr.Jit's kernel history (CUDA events on the
GPU), attributed to the stage that launched them (:class:`StageClock`); ``total`` is the frame's
wall-clock time, from the call until its image and statistics are on hand after its one
synchronization, and ``issue`` the part of it the host took to issue the frame's work. With
``frames_in_flight=2`` (``inflight.py``) a frame does not synchronize: the next frame reads its
counts and its times (``total`` then is device time between CUDA events; its stages are NaN).
The kernel history is instrumentation (a pair of CUDA events around every launch, read back after
the synchronization): ``stage_times=False`` leaves it off, and the frame's stages are then NaN;
a budget learns from the trace's time, so its frames keep it on every ``timing_interval``-th frame
of a sequence (:meth:`HybridSettings.times_frame`).
"""
from __future__ import annotations

import contextlib
import dataclasses
import functools
import math
import time
import typing
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

import drjit as dr
import mitsuba as mi
import numpy as np
from scipy.stats import qmc

from .budget import FramePlan, FrameState, plan_frame
from .compose import compose, fill_left_out
from .denoise import QUALITIES, Denoiser, Guides
from .errors import HybridError, UnsupportedSceneError
from . import history
from .frozen import FrozenFunction, FrozenScene
from .heuristic import (BLOCKS, RELEVANCE, Coverage, active_kinds, add_error, by_kind, candidate_kinds, candidates,
                        coverage_sums, default_kinds, pixel_growth, visibility_terms)
from .inflight import FRAMES_IN_FLIGHT, FrameSpan, InFlight
from .lighting import INPUTS, DeferredLighting, LightTable, ambient_table, learn_ambient, shade, with_ambient
from .objects import scene_objects
from .primary import PrimaryHits, camera_rays, first_hits, primary_hits, raster_hits, resolve_outline, resolved, traced_hits
from .raster.camera import RasterCamera, camera_pose, resolve_sensor
from .raster.context import gl_elapsed_ms, gl_flush
from .raster.gbuffer import ShapeConstants, aov_values, check_aovs, shape_constants
from .raster.interop import HostCopy, device_array
from .raster.visibility import Rasterizer, TriangleTables, resolve_method
from .selection import DEFAULT_EFFECTS, Selection, parse_effects, part_config, refracts, select_pixels
from .selection_graph import SELECTORS
from .temporal import Accumulator, Surface
from .trace import RAY_KINDS, LaneHits, LanePrimary, RouletteCap, trace_effects

PRIMARY_SOURCES = ("raster", "raytrace")
#: where the raster's refined pixels (primary.py: silhouettes, proxies, misses) are traced
REFINE_STAGES = ("auto", "primary", "trace")
STAGES = ("raster", "lighting", "select", "trace", "compose", "temporal", "denoise")
SHADOW_ONLY = ("shadow",)  # the effect set of a shadow tier (heuristic.candidates)
HOST_PHASES = ("setup", "select", "raster", "replay", "develop", "post", "readback", "ahead", "timing")
#: ``raster_ahead``: whether a frame draws the next frame's visibility buffer at its end
#: (:meth:`HybridRenderer._draw_ahead`): ``auto``, where the buffer reaches Dr.Jit through
#: CUDA–OpenGL interop (a CUDA variant); ``on``; ``off``
RASTER_AHEAD = ("auto", "on", "off")


def resolve_refine(refine: str, traces: bool = True, variant: str | None = None) -> str:
    """``refine`` (:data:`REFINE_STAGES`) with ``auto`` resolved for ``variant`` (default: the
    current one) and the frame: the trace stage's launch (``trace``) on CUDA where the frame can
    trace some object (``traces``), else the primary stage (``primary``). On an H200 a kernel that
    traces any ray costs its traversal's latency, which the primary stage's re-trace of a few
    pixels then saves: the frames of the four bench scenes were 0.99–1.06× as fast as
    ``primary``'s (about 2 % faster on average), those of the 226 objects 0.98×
    (``docs/results/gpu/issue10/stop33``). A frame that traces no object would launch the trace for
    the refined pixels alone, which costs more than their masked re-trace (DR frames of 1.7–2.6 ms
    against 1.5–1.9 there); on the CPU the trace kernel grows by about what the primary stage
    saves (``docs/results/cpu/refine``)."""
    if refine not in REFINE_STAGES:
        raise HybridError(f"refine='{refine}' is not one of {list(REFINE_STAGES)}")
    if refine == "auto":
        return "trace" if traces and (variant or mi.variant() or "").startswith("cuda") else "primary"
    return refine


#: the Python types a property of each plain declared type accepts (``HybridSettings._check_types``)
_PROPERTY_TYPES = {int: (int, np.integer), float: (int, float, np.integer, np.floating), bool: (bool, np.bool_),
                   str: (str,)}
_PROPERTY_NAMES = {int: "an integer", float: "a number", bool: "a boolean (true or false)", str: "a string"}


def check_frame_numbers(spp, seed) -> tuple[int, int]:
    """A frame's ``spp`` and ``seed`` as ints, or a :class:`HybridError` naming the one that is not
    a whole number >= 0 (``2.5`` samples would be truncated, a negative seed fails deep in NumPy's
    generator, ``True`` is no count)."""
    for name, value, what in (("spp", spp, "a whole number of samples per pixel >= 1 (0: the scene's sampler's)"),
                              ("seed", seed, "a whole number >= 0")):
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < 0:
            raise HybridError(f"{name}={value!r} is impossible: give {what}")
    return int(spp), int(seed)


@functools.lru_cache(maxsize=None)
def _declared_types(cls) -> dict:
    """A dataclass's fields' declared types, resolved once."""
    return typing.get_type_hints(cls)


@dataclass(frozen=True)
class HybridSettings:
    """The ``hybrid`` integrator's properties (see ``plugins/hybrid.py`` for their meaning)."""

    max_depth: int = -1
    rr_depth: int = 5
    #: from this depth on, Russian roulette goes on with probability at most ``rr_tail_prob``
    #: (-1: never, ``path``'s roulette; ``trace.RouletteCap``). None (the default): the cap's own
    #: depth where the frame is denoised, -1 where it is not (:attr:`roulette`)
    rr_tail_depth: int | None = None
    rr_tail_prob: float = RouletteCap._field_defaults["tail_prob"]
    hide_emitters: bool = False
    primary: str = "raster"
    raster: str = "auto"
    refine: str = "auto"
    outline: str = "auto"
    effects: tuple[str, ...] = DEFAULT_EFFECTS
    candidates: object = None  # None: every object; "id[:kind|kind], ..." or {id: kinds} (heuristic.py)
    blend: float = 1.0
    budget_ms: float = 0.0
    selection: str = "nested"
    relevance: str = "error"
    importance: float = 0.0
    freeze: bool = True
    denoise: bool = True
    denoise_quality: str = "fast"
    temporal: bool = False
    secondary_spp: int = 1
    learn_ambient: bool = True
    shadow_tier: bool = True
    #: with a budget, what the selection leaves buys a part of one more object's pixels (1–3 of
    #: each 2×2 quad's four; mirrors and glass filled in between: ``selection.py``), not nothing
    partial_objects: bool = True  # default since stop 75 (docs/results/gpu/issue10/stop75); off: whole objects only
    raster_ahead: str = "auto"
    frames_in_flight: int = 1
    #: time each stage on the device (Dr.Jit's kernel history: ``FrameStats.times_ms``); off, a
    #: frame without a budget runs and reads no history: its stages are NaN, its ``total`` as
    #: before, and the frame is shorter on the H200 by what the history costs it (the events
    #: around every launch, and their readout: since stop 51 while the GPU denoises, where it does,
    #: ``HybridRenderer._read_ahead``): within the measurement's noise for a denoised hybrid or RT
    #: frame (-0.08 to +0.03 ms on two scenes), 0.05-0.10 for DR's (docs/results/gpu/issue10/stop51;
    #: 0.19-0.26 for the hybrid before, stop 50).
    #: Off, a budgeted frame still times its stages on every ``timing_interval``-th frame of its
    #: sequence, on every frame until its cost model is calibrated, and after an untimed frame
    #: whose wall time jumped: the model learns the trace's time from those (:meth:`times_frame`)
    stage_times: bool = True
    #: with a budget and ``stage_times`` off, how often a frame reads the trace's device time (1:
    #: every frame). The kernel history is the one clock inside the frozen device pass, and it costs
    #: a budgeted frame's host a pair of CUDA events per launch, before the GPU reaches the trace,
    #: and their readout: on an H200, frames without it were 0.2-0.9 ms shorter along the 226
    #: objects' path at 25-75 %, and a budget timed every 4th frame 1.04-1.19x as fast as one timed
    #: on every frame, in turn (docs/results/gpu/issue10/stop59); the Armadillo's budgeted frames, bound
    #: by the GPU, 0.96-0.98x there, and 1.17-1.18x in stop 60's machine start (``ahead_ab.py``)
    timing_interval: int = 4

    @property
    def roulette(self) -> RouletteCap:
        """Russian roulette's cap on going on (``rr_tail_depth``, ``rr_tail_prob``). Unless
        ``rr_tail_depth`` is given, only a denoised frame has it: its price is fireflies that only
        the denoiser removes (:class:`trace.RouletteCap`)."""
        depth = self.rr_tail_depth
        if depth is None:
            depth = RouletteCap._field_defaults["tail_depth"] if self.denoise else -1
        return RouletteCap(depth, self.rr_tail_prob)

    @property
    def in_flight(self) -> bool:
        """Whether a frame is rendered in flight: two frames in flight and no budget (a budget
        learns from the trace's time, which only a synchronization gives; ``inflight.py``)."""
        return self.frames_in_flight > 1 and self.budget_ms <= 0

    def times_frame(self, frames: int = 0, calibrated: bool = True, jumped: bool = False) -> bool:
        """Whether a frame keeps and reads Dr.Jit's kernel history for its stages' device times:
        with ``stage_times``; without, a budgeted frame whose cost model is not calibrated yet,
        whose sequence has learnt from a multiple of ``timing_interval`` frames before it
        (``frames``), or that follows a frame whose wall time jumped (``jumped``:
        ``budget.FrameState.watch``); never in flight (Dr.Jit reads its history only after a
        synchronization, so a frame in flight never reads it: until stop 50 it kept one anyway,
        its events recorded for nothing). ``dr.freeze`` keeps a recording per state of the
        history's flag, so that timed and untimed frames each replay their own."""
        if self.in_flight:
            return False
        return self.stage_times or (self.budget_ms > 0 and (not calibrated or jumped
                                                            or frames % self.timing_interval == 0))

    def _check_types(self) -> None:
        """Each property of a plain type has a value of that type (Mitsuba's own properties are
        typed: ``<boolean>``, ``<integer>``, ``<float>``, ``<string>``; from Python, ``"no"``
        for a boolean would be read as true and ``2.5`` paths per hit traced as ``range(2.5)``
        fails deep in the frame). A float takes an integer, and is stored as a float; a
        ``bool`` is no number here (``max_depth=True`` is a mistake, not 1)."""
        # the declared types resolved (a field's ``type`` is its annotation's text until Dr.Jit's
        # traversal of a dataclass resolves it in place: both are seen)
        for name, declared in _declared_types(type(self)).items():
            value = getattr(self, name)
            arguments = typing.get_args(declared)
            if type(None) in arguments:  # an optional property: unset (None), or of its type
                if value is None:
                    continue
                declared = next(a for a in arguments if a is not type(None))
            accepted = _PROPERTY_TYPES.get(declared)
            if accepted is None:
                continue
            if not isinstance(value, accepted) or (declared is not bool and isinstance(value, (bool, np.bool_))):
                raise HybridError(f"{name}={value!r} must be {_PROPERTY_NAMES[declared]} (got {type(value).__name__})")
            object.__setattr__(self, name, declared(value))

    @classmethod
    def from_properties(cls, values: dict) -> "HybridSettings":
        """The settings of the integrator's properties (names as in ``plugins/hybrid.py``);
        an unknown name or a bad value is a :class:`HybridError` naming it."""
        names = {f.name for f in dataclasses.fields(cls)}
        for name in values:
            if name not in names:
                raise HybridError(f"the hybrid integrator has no property '{name}': it takes {sorted(names)}")
        return cls(**values)

    def __post_init__(self):
        self._check_types()
        if self.primary not in PRIMARY_SOURCES:
            raise HybridError(f"primary='{self.primary}' is not one of {list(PRIMARY_SOURCES)}")
        resolve_method(self.raster)  # a clear error for an unknown method
        resolve_refine(self.refine)  # a clear error for an unknown stage
        resolve_outline(self.outline, "compute")  # a clear error for an unknown test
        object.__setattr__(self, "effects", parse_effects(self.effects))
        if self.denoise_quality not in QUALITIES:
            raise HybridError(f"denoise_quality='{self.denoise_quality}' is not one of {list(QUALITIES)}")
        if self.raster_ahead not in RASTER_AHEAD:
            raise HybridError(f"raster_ahead='{self.raster_ahead}' is not one of {list(RASTER_AHEAD)}")
        if self.frames_in_flight not in FRAMES_IN_FLIGHT:
            raise HybridError(f"frames_in_flight={self.frames_in_flight} is not one of {list(FRAMES_IN_FLIGHT)}")
        if self.relevance not in RELEVANCE:
            raise HybridError(f"relevance='{self.relevance}' is not one of {list(RELEVANCE)}")
        if self.selection not in SELECTORS:
            raise HybridError(f"selection='{self.selection}' is not one of {list(SELECTORS)}")
        if not (math.isfinite(self.importance) and self.importance >= 0.0):
            raise HybridError(f"importance={self.importance} must be a number >= 0")
        if not (math.isfinite(self.blend) and 0.0 <= self.blend <= 1.0):
            raise HybridError(f"blend={self.blend} must lie in [0, 1]")
        if not (math.isfinite(self.budget_ms) and self.budget_ms >= 0.0):
            raise HybridError(f"budget_ms={self.budget_ms} is impossible: give a time in ms >= 0 (0 = unlimited)")
        if self.max_depth < -1:
            raise HybridError(f"max_depth={self.max_depth} must be -1 (unlimited) or >= 0")
        if self.rr_depth < 1:
            raise HybridError(f"rr_depth={self.rr_depth} must be >= 1")
        if self.rr_tail_depth is not None and self.rr_tail_depth < -1:
            raise HybridError(f"rr_tail_depth={self.rr_tail_depth} must be -1 (no tail cap, as path) or >= 0")
        if not (math.isfinite(self.rr_tail_prob) and 0.0 < self.rr_tail_prob <= 1.0):
            raise HybridError(f"rr_tail_prob={self.rr_tail_prob} must lie in (0, 1]: the largest probability with which "
                              "Russian roulette continues a path from rr_tail_depth on")
        if self.timing_interval < 1:
            raise HybridError(f"timing_interval={self.timing_interval} must be >= 1 (1: a budget times every frame)")
        if self.secondary_spp < 1:
            raise HybridError(f"secondary_spp={self.secondary_spp} must be >= 1 (paths traced from each primary hit)")


@dataclass
class FrameStats:
    """What one frame cost and did. Times are milliseconds, summed over the frame's sample passes:
    per stage the device time (module docstring; ``raster`` includes ``gl``, the OpenGL clear and
    draw, which is NaN where the GL driver timed nothing: Mesa's llvmpipe, the first draw of a
    process; the copy of its target into Dr.Jit's array is in no stage), ``issue`` the host's time to issue the frame, ``total`` its
    wall-clock time until its image and statistics are on hand (after its one synchronization),
    the readout of its stage times (``host_ms["timing"]``) included: a budget needs the trace's
    time, and a caller's frame loop waits for it (until stop 48 it was left out: 0.4-1.0 ms per
    frame on the H200, read through ``drjit.kernel_history``; ``history.py``)."""

    width: int
    height: int
    spp: int
    primary: str
    times_ms: dict[str, float] = field(default_factory=lambda: dict.fromkeys(STAGES + ("gl", "issue", "total"), 0.0))
    rays: dict[str, int] = field(default_factory=lambda: dict.fromkeys(("camera",) + RAY_KINDS, 0))
    pixels_traced: int = 0  # traced pixel-samples, summed over passes
    proxy_refinements: int = 0  # pixel-samples of analytic-shape proxies refined by a ray
    edge_refinements: int = 0  # silhouette pixel-samples and raster misses re-traced (primary.py)
    emitter_refinements: int = 0  # pixel-samples of area emitters re-traced past them (hide_emitters, primary.py)
    #: times the scene's state was made again because its geometry was edited (api.rasterizer)
    geometry_reloads: int = 0
    lights_left_out: tuple[str, ...] = ()  # emitters the raster layer cannot show
    readback: str = ""  # how the raster target reached Dr.Jit: cuda-gl-interop, or host (reason)
    #: sample passes whose visibility buffer the frame before drew (``raster_ahead``), and passes
    #: it drew for this frame that this frame could not use (another camera, sub-pixel offset or
    #: set-up, or another pass drew into the target since): drawn for nothing
    raster_ahead: int = 0
    raster_discarded: int = 0
    raster_method: str = ""  # the raster pass that made it: draw or compute (raster/visibility.py)
    fallback: str = ""  # what the frame did instead of the hybrid pipeline, and why ("": nothing)
    #: what the frozen device pass took for the scene (frozen.py): ``read set``, the variables of
    #: the snapshot its recording reads; ``variables``, the whole snapshot of the scene's Dr.Jit
    #: variables taken once (the pass's first call, which learns the read set, and where a later
    #: recording read beyond it); ``scene``, the scene itself, walked by Dr.Jit on every call (where
    #: the snapshot cannot serve); ``unfrozen``: asked to freeze, the pass runs unfrozen because
    #: Dr.Jit cannot record it even given the scene (a BSDF registered outside the scene); "": the
    #: pass ran unfrozen as asked (``freeze=False``, an orthographic sensor)
    frozen_inputs: str = ""
    budget_ms: float = 0.0  # 0: unlimited
    predicted_trace_ms: float = 0.0  # what the cost model expected the trace stage to take
    predicted_rays: int = 0  # the secondary rays it expected (``secondary_rays``: traced)
    #: host ms of making the plan this frame traced by (eq. 1–3 and the selector, ``budget.FramePlan.host_ms``):
    #: a still camera's frame uses a plan made while the frame before traced, so its ``select`` phase
    #: does not hold this; 0 without a budget
    plan_ms: float = 0.0
    #: host time (ms) by phase: frame set-up, selection, the raster pass and its interop copy, the
    #: device pass (a frozen replay: Dr.Jit walks its inputs, the scene's variables among them,
    #: then launches), film development, post-processing, the statistics and what the next frame
    #: learns from them (``readback``: on the GPU while it develops and denoises the frame), the
    #: next frame's raster pass issued behind this frame's work (``ahead``), and ``timing``:
    #: reading Dr.Jit's kernel history for the stage times (``history.py``; counted in ``total``)
    host_ms: dict[str, float] = field(default_factory=lambda: dict.fromkeys(HOST_PHASES, 0.0))
    candidates_visible: int = 0
    selected: tuple[str, ...] = ()  # objects traced this frame, most relevant first
    relevance_captured: float = 1.0  # Σ R of the traced objects / Σ R of the visible candidates
    selection_changes: int = 0  # objects traced now but not in the previous frame, or the reverse
    shadow_only: tuple[str, ...] = ()  # of ``selected``, those traced by their shadow tier (heuristic.candidates)
    #: of ``selected``, the object traced in part with what the budget left, and the quarters of
    #: its pixels traced (1–3; ``selection.py``): "" and 0 where none was
    partial_object: str = ""
    partial_quarters: int = 0
    #: rendered in flight (``frames_in_flight=2``, ``inflight.py``): no synchronization at its end;
    #: ``times_ms`` holds ``total`` (device time, CUDA events), ``gl``, ``denoise`` and ``issue``,
    #: its stages NaN, all of them NaN until the next frame or ``HybridRenderer.finish`` reads them
    in_flight: bool = False
    #: whether ``times_ms`` holds its stages' device times (``stage_times=False``, or in flight:
    #: NaN, and ``raster`` with them; ``gl``, ``denoise`` and ``total`` are timed still)
    stages_timed: bool = True

    @property
    def budget_met(self) -> bool | None:
        """Whether the trace stage took no longer than the budget (True without one); None where
        the frame did not time its stages (``HybridSettings.times_frame``)."""
        if self.budget_ms <= 0:
            return True
        return None if math.isnan(self.times_ms["trace"]) else bool(self.times_ms["trace"] <= self.budget_ms)

    @property
    def secondary_rays(self) -> int:
        return sum(self.rays[k] for k in RAY_KINDS)

    def untimed(self) -> None:
        """No kernel history was read for this frame (``stage_times=False``, or in flight): its
        stages NaN, ``raster`` with them, and ``stages_timed`` false."""
        self.times_ms.update(dict.fromkeys((k for k in STAGES if k != "denoise"), math.nan))
        self.stages_timed = False

    def as_dict(self) -> dict:
        return {**asdict(self), "secondary_rays": self.secondary_rays, "budget_met": self.budget_met}


class HybridResult:
    """A rendered frame: ``image`` as ``mi.render`` returns it, ``composed``: the same before
    temporal accumulation and denoising (the film of the composed layers), the layers (H×W
    numpy, filtered like the image: ``raster``, ``rt``, ``traced`` and any G-buffer AOV asked
    for; read from the device on first access), the frame's statistics, and the film's pixel
    format, which ``image`` and ``composed`` have (``Development``)."""

    def __init__(self, image: mi.TensorXf, stats: FrameStats, layers: mi.TensorXf | None = None,
                 aovs: dict[str, np.ndarray] | None = None, composed: mi.TensorXf | None = None,
                 pixel_format: mi.Bitmap.PixelFormat = mi.Bitmap.PixelFormat.RGB):
        self.image, self.stats, self.pixel_format = image, stats, pixel_format
        self.composed = image if composed is None else composed
        self._layer_sums, self._aovs, self._layers = layers, aovs or {}, None

    @property
    def layers(self) -> dict[str, np.ndarray]:
        if self._layers is None:
            if self._layer_sums is None:
                raise HybridError("this frame was rendered without layers (layers=False)")
            sums = np.array(self._layer_sums)
            weight = np.maximum(sums[..., 7:8], 1e-12)
            self._layers = {"raster": sums[..., 0:3] / weight, "rt": sums[..., 3:6] / weight,
                            "traced": sums[..., 6] / weight[..., 0], **self._aovs}
        return self._layers


@functools.lru_cache(maxsize=16)
def _halton(spp: int) -> tuple[tuple[float, float], ...]:
    return tuple(map(tuple, qmc.Halton(d=2, scramble=False).random(spp + 1)[1:].tolist()))  # the first point is (0, 0)


def subpixel_offsets(spp: int, seed: int) -> list[tuple[float, float]]:
    """``spp`` sub-pixel positions in [0,1)²: the Halton sequence (low discrepancy), shifted
    modulo 1 by a random offset drawn from ``seed`` (a Cranley–Patterson rotation: each seed gives
    another low-discrepancy set, at the cost of two random numbers, not a new scrambling). The sum
    is taken in Python floats (the same values as numpy's): this is a frame's first host work,
    before its raster pass is issued, where numpy's small arrays cost more than the sum."""
    sx, sy = np.random.default_rng(seed).random(2).tolist()
    return [((x + sx) % 1.0, (y + sy) % 1.0) for x, y in _halton(spp)]


class StageClock:
    """Device time per stage, from Dr.Jit's kernel history (``JitFlag.KernelHistory``: CUDA events
    on the GPU, the LLVM backend's own clock on the CPU), read once after the frame.

    Whenever the device pass's Python body runs (unfrozen, or while ``dr.freeze`` records it),
    :meth:`mark` evaluates a stage's outputs and notes which kernels that stage launched; a replay
    launches the same kernels (same hashes, same order) without running the body, so the history
    of any frame can be split by stage. Reductions and copies, which have no kernel hash, belong to
    the stage of the kernel before them."""

    def __init__(self):
        self.stage_of: dict[str, str] = {}
        self._taken: list[tuple[str, dict]] = []
        #: the history's reader: its entries without the kernels' source (``history.py``); set it
        #: to ``drjit.kernel_history`` to keep each JIT kernel's source (``ir``) in :attr:`last`
        self.read = history.reader()
        #: the last frame's kernels, each with its stage (``scripts/frame_profile.py --kernels``)
        self.last: list[tuple[str, dict]] = []

    def mark(self, stage: str, *values) -> None:
        """Evaluate ``values``; the kernels launched for them that no stage has claimed yet are
        ``stage``'s (kernels of earlier stages flushed with them keep their own)."""
        dr.eval(*values)
        for entry in self.read():
            new = entry.get("hash") and entry["hash"] not in self.stage_of
            if new:
                self.stage_of[entry["hash"]] = stage
            self._taken.append((stage if new else None, entry))

    def discard(self) -> None:
        """Forget the kernels taken since the last :meth:`frame_times` (a frame whose history is not read)."""
        self._taken = []

    def frame_times(self, read: Callable[[], list[dict]] | None = None) -> dict[str, float]:
        """The device ms per stage of the kernels since the last call (the frame's); ``read``: what
        gives the history's entries (default :attr:`read`; a read started ahead, :meth:`HybridRenderer._read_ahead`)."""
        times = dict.fromkeys(STAGES[1:], 0.0)
        current = STAGES[1]
        self.last = []
        for stage, entry in self._taken + [(None, e) for e in (read or self.read)()]:
            stage = stage or self.stage_of.get(entry.get("hash"), current)
            current = stage
            times[stage] = times.get(stage, 0.0) + float(entry.get("execution_time", 0.0))
            self.last.append((stage, entry))
        self._taken = []
        return times


@dataclass(frozen=True)
class PassStatic:
    """What the device pass's kernels are made for (a change records them again)."""

    width: int
    height: int
    primary: str
    refine: str  # where the raster's refined pixels are traced: primary or trace (resolve_refine)
    outline: str  # which outline pixels are refined: ties or silhouettes (primary.resolve_outline)
    effects: tuple[str, ...]
    configs: tuple[tuple[str, ...], ...]  # the effect sets the candidates deserve
    max_depth: int
    rr_depth: int
    roulette: RouletteCap
    hide_emitters: bool
    blend: float
    targets: tuple[str, ...]  # G-buffer targets: the lighting's inputs and the AOVs asked for
    aovs: tuple[str, ...]
    layers: bool
    has_alpha: bool
    box_filter: bool
    has_emitters: bool
    background_alpha: bool  # an environment is seen behind the geometry
    n_objects: int
    guides: bool  # splat the denoiser's guides (denoise.py)
    #: the effect sets (indices into ``configs``) that leave out the indirect light the integrator
    #: traces: their pixels add the learnt indirect term instead (the shadow tier, heuristic.py)
    modelled: tuple[int, ...]
    surface: bool  # keep the first pass's surface for the temporal history (temporal.py)
    #: also splat the colour in the film's filter, for the history, where ``box_filter`` splats it
    #: in a box for the denoiser (temporal.py)
    film_copy: bool
    secondary_spp: int  # paths traced from each traced primary hit (trace.py)
    #: launch the glass pixels' paths first (``trace.trace_effects``' ``long``): on the CUDA backend,
    #: where a candidate's BSDF refracts. H100, 1280×720, the default frame's trace stage: the
    #: Armadillo 6.12-6.18 → 5.52-5.57 ms, the showcase 6.05-6.13 → 6.02-6.05; where glass is a
    #: candidate but hardly traced, the partition's second prefix sum costs ~0.07 ms (226 objects,
    #: 50 % budget: 1.81 → 1.88 ms for the same rays; docs/results/gpu/issue10/stop27).
    #: Not on the LLVM backend, whose threads take large blocks of lanes each: pixel order spreads
    #: the long paths over them (the Armadillo at 320×180 on two cores: 21 ms in pixel order, 30 ms
    #: long paths first)
    long_first: bool = False
    #: an object may be traced in part (``HybridSettings.partial_objects`` with a budget): the
    #: selection reads the pixels' quad positions and the left-out ones with a delta lobe are filled
    #: (``selection.py``, ``compose.fill_left_out``); a frame without a budget has neither
    partial: bool = False

    @property
    def kept(self) -> tuple[str, ...]:
        """The G-buffer targets read after the lighting: the albedo, the denoiser's guides, the
        history's surface and the AOVs asked for."""
        return tuple(dict.fromkeys(["albedo", *(("specular", "normal") if self.guides else ()),
                                    *(("position", "normal") if self.surface else ()), *self.aovs]))


@dataclass
class PassData:
    """The device pass's inputs that change from pass to pass, and the scene's tables."""

    triangle_id: mi.UInt32  # the visibility buffer (raster primaries; unused for camera rays)
    camera: mi.Float  # sub-pixel position (x, y), then the eye (x, y, z): one upload per pass
    seed: mi.UInt32  # the pass's random seed (low, high word)
    config: mi.Int32  # per object: index of its effect set in ``configs``, −1 = not traced this pass
    tables: TriangleTables
    lights: LightTable
    constants: ShapeConstants
    ambient: mi.Float  # per object, the learnt ambient irradiance E (3 floats; lighting.py)
    indirect: mi.Float  # per object, the learnt indirect irradiance of its shadow tier (3 floats)


@dataclass
class PassOutput:
    """What one device pass leaves on the device: splats, and its counts packed into one array so
    that reading them back after the frame costs one copy (:class:`PassCounts`)."""

    image: mi.TensorXf  # the image block (film filter, weight channel last)
    layers: object  # the layer block (raster, rt, traced, weight) or None
    #: rays per object of each kind (RAY_KINDS order), traced pixels, then as float bits the
    #: coverage sums (heuristic.coverage_sums, BLOCKS × objects) and the proxy, edge and hidden-emitter refinements
    counts: mi.UInt32
    aovs: dict
    guides: object = None  # the guide block (albedo, normal, weight) or None
    surface: Surface | None = None  # what the pass hit, per pixel (for the history)
    film: object = None  # the colour block in the film's filter (``PassStatic.film_copy``) or None


@dataclass
class PassCounts:
    """A :class:`PassOutput`'s counts on the host."""

    coverage: np.ndarray  # BLOCKS sums per object, one block each (heuristic.coverage_sums)
    rays: np.ndarray  # objects × ray kinds
    pixels: int
    proxy_refined: int
    edge_refined: int
    emitter_refined: int

    @classmethod
    def read(cls, words: np.ndarray, n_objects: int) -> "PassCounts":
        """The counts of one pass from ``words``, its ``counts`` array read to the host."""
        width = max(n_objects, 1)
        end = len(RAY_KINDS) * width
        rays = words[:end].astype(np.int64).reshape(len(RAY_KINDS), width)[:, :n_objects].T
        sums = words[end + 1:].view(np.float32)
        return cls(sums[:BLOCKS * width], rays, int(words[end]), *(int(v) for v in sums[BLOCKS * width:BLOCKS * width + 3]))


@dataclass
class PixelTerms:
    """Stages 2 and 3 at each pixel's primary hit (or at each traced lane's): what the stages after
    them read."""

    object: mi.UInt32
    valid: mi.Bool
    depth: mi.Float  # the hit's distance from the eye (coverage, heuristic.py)
    targets: dict  # the G-buffer targets read later (PassStatic.kept, gbuffer.aov_values), one array per channel
    shaded: mi.Color3f  # the deferred lighting, without the learnt ambient term
    raster: mi.Color3f  # the raster layer: the deferred lighting with the ambient term (Fig. 1g)
    traced: mi.Bool  # the selection (selection.select_pixels)
    config: mi.UInt32
    left_out: mi.Bool | None = None  # left out of an object traced in part (PassStatic.partial)
    filled: mi.Bool | None = None  # those of them filled from their traced neighbours (selection.FILL_LOBES)

    @property
    def albedo(self) -> mi.Color3f:
        return mi.Color3f(*self.targets["albedo"])


def pixel_selection(hits, data: PassData, static: PassStatic, pixel: mi.UInt32 | None = None) -> Selection:
    """Selection (stage 3, §4) at the primary hits ``hits`` (``selection.select_pixels``), of the
    film's pixels in order or, for lanes of other pixels, of ``pixel``."""
    if static.partial and pixel is None:
        pixel = dr.arange(mi.UInt32, dr.width(hits.valid))
    return select_pixels(hits.si, hits.ray, hits.object, hits.valid, data.config, static.configs, static.has_emitters,
                         pixel if static.partial else None, static.width)


def surface_terms(scene: mi.Scene, hits, data: PassData, static: PassStatic, eye: mi.Point3f) -> tuple[PixelTerms, mi.Bool]:
    """Deferred lighting (stage 2, §3.1) and selection (stage 3, §4) at the primary hits ``hits``;
    also whether each hit's paths are expected to be long (``selection.long_paths``)."""
    targets = aov_values(scene, hits, static.targets, data.constants)
    if static.hide_emitters:  # the environment behind the geometry (area emitters: first_hits passed them)
        targets["emission"] = [dr.zeros(mi.Float, dr.width(hits.valid)) for _ in range(3)]
    shaded = shade(targets, hits.valid, -hits.ray.d, data.lights)
    albedo = mi.Color3f(*targets["albedo"])
    selection = pixel_selection(hits, data, static)
    return PixelTerms(object=hits.object, valid=hits.valid, depth=dr.norm(hits.si.p - eye),
                      targets={k: targets[k] for k in static.kept}, shaded=shaded,
                      raster=with_ambient(shaded, albedo, hits.object, hits.valid, data.ambient),
                      traced=selection.traced, config=selection.config, left_out=selection.left_out,
                      filled=selection.filled), selection.long


def refined_lanes(scene: mi.Scene, hits: PrimaryHits, chosen: Selection, data: PassData, static: PassStatic,
                  found: mi.PreliminaryIntersection3f) -> LanePrimary:
    """The trace lanes' primary hits where the raster's refined pixels (``primary.raster_hits``)
    are traced in the trace stage's launch (``refine="trace"``): each refined lane traces its
    camera ray, makes its own selection and keeps what its ray found in ``found`` (per pixel);
    the other lanes read their hits and selection (``chosen``) from the stages before. The
    refined pixels' lighting is made after the launch, from ``found`` (``device_pass``): inside
    it, its code would enlarge the path kernel that every lane runs (on the H200 the dining room's
    trace stage took 16.2 ms so, 12.9 without: ``docs/results/gpu/issue10/stop33``)."""
    def lanes(pixel: mi.UInt32, busy: mi.Bool, first: mi.Bool) -> LaneHits:
        lane = dr.gather(PrimaryHits, hits, pixel, busy)
        again = busy & (lane.refined > 0)
        traced = dr.gather(mi.Bool, chosen.traced, pixel, busy)
        config = dr.gather(mi.UInt32, chosen.config, pixel, busy)

        def refine(lane, traced, config):
            pi = first_hits(scene, lane.ray, again, static.hide_emitters)
            dr.scatter(found, pi, pixel, first)
            lane = resolved(lane, pi, again, data.tables)
            own = pixel_selection(lane, data, static, pixel)
            return lane, own.traced, own.config

        # a branch, not a mask: the other lanes (most of them) skip it
        lane, traced, config = dr.if_stmt((lane, traced, config), again, refine, lambda *state: state,
                                          label="refined pixels")
        return LaneHits(ray=lane.ray, si=lane.si, object=lane.object, config=config, traced=busy & traced)
    return lanes


def device_pass(scene: mi.Scene, sensor: mi.Sensor, data: PassData, static: PassStatic, clock: StageClock) -> PassOutput:
    """Stages 1 (on the device) to 5 of one sample pass, as Dr.Jit kernels (module docstring)."""
    w, h = static.width, static.height
    offset = mi.Point2f(*(dr.gather(mi.Float, data.camera, k) for k in range(2)))
    eye = mi.Point3f(*(dr.gather(mi.Float, data.camera, k) for k in range(2, 5)))
    seed = mi.UInt64(dr.gather(mi.UInt32, data.seed, 0)) | (mi.UInt64(dr.gather(mi.UInt32, data.seed, 1)) << 32)
    # the raster's outline test measures pixels with the rays' differentials (primary.outline_ties)
    ray = camera_rays(sensor, w, h, offset, differentials=static.primary == "raster" and static.outline == "ties")

    def trace(hits: PrimaryHits, traced: mi.Bool, config: mi.UInt32, long: mi.Bool, refined: mi.Bool | None = None,
              primary: LanePrimary | None = None):
        """4. ray tracing (§3.2): one call for every selected object, each with its own ray kinds
        (and the ``refined`` pixels' camera rays, with ``primary``)"""
        return trace_effects(scene, hits.ray, hits.si, traced if refined is None else traced | refined,
                             static.effects, static.max_depth, static.rr_depth, static.hide_emitters,
                             seed=seed, obj=hits.object, n_objects=static.n_objects,
                             first_effects=static.configs, first_config=config,
                             keep_direct=bool(static.modelled), paths=static.secondary_spp,
                             long=long if static.long_first else None, primary=primary, primary_first=refined,
                             roulette=static.roulette)

    def lit(hits: PrimaryHits, *kept) -> tuple[PixelTerms, mi.Bool]:
        """2. deferred lighting: the raster layer (§3.1, Fig. 1g); 3. selection (§4)"""
        terms, long = surface_terms(scene, hits, data, static, eye)
        # every target read later (the denoiser's guides, the history's surface, the AOVs) in this
        # kernel, with the BSDF calls it makes anyway: left to the composition, each would call the
        # BSDF again there (with the guides, a kernel of 1763 operations on the LLVM backend)
        clock.mark("lighting", terms.raster, terms.shaded, list(terms.targets.values()),
                   *(getattr(terms, k) for k in kept))
        return terms, long

    # 1. primary visibility: the raster's triangles (paper §3.1) or camera rays (the baseline, §8);
    # the raster's refined pixels traced here, or in stage 4's launch (``refine="trace"``)
    if static.primary == "raster" and static.refine == "trace":
        hits = raster_hits(scene, ray, data.triangle_id, w, h, data.tables, static.outline, static.hide_emitters)
        clock.mark("raster", hits.ray, hits.si, hits.shape, hits.object, hits.valid, hits.refined)
        # stages 3, 4, then 2: the refined pixels' hits are found in stage 4's launch, first
        chosen = pixel_selection(hits, data, static)
        clock.mark("select", chosen.traced, chosen.config, chosen.long if static.long_first else None)
        refined = hits.refined > 0
        # written by every refined pixel's lane, read by those alone: not cleared (a clear is one
        # operation per field in each replay of the frozen pass)
        found = dr.empty(mi.PreliminaryIntersection3f, w * h)
        rt, direct, counts = trace(hits, chosen.traced, chosen.config, chosen.long, refined,
                                   refined_lanes(scene, hits, chosen, data, static, found))
        clock.mark("trace", rt, direct, counts.per_object)
        # stage 2 once every pixel has its hit (the refined pixels' from what the launch found); what
        # the stages after it read of the refined hits is evaluated with it, not resolved again
        terms, _ = lit(resolved(hits, found, refined, data.tables), "object", "valid", "depth", "traced", "config",
                       *(("left_out", "filled") if static.partial else ()))
    else:
        if static.primary == "raster":
            hits = primary_hits(scene, ray, data.triangle_id, w, h, data.tables, static.outline, static.hide_emitters)
        else:
            hits = traced_hits(scene, ray, data.tables, static.hide_emitters)
        clock.mark("raster", hits.ray, hits.si, hits.shape, hits.object, hits.valid, hits.refined)
        terms, long = lit(hits)
        clock.mark("select", terms.traced, terms.config, long if static.long_first else None, terms.left_out,
                   terms.filled)
        rt, direct, counts = trace(hits, terms.traced, terms.config, long)
    # coverage (eq. 1), then the refined pixels: proxies, silhouettes and misses
    sums = coverage_sums(terms.object, terms.valid, terms.depth, w, h, static.n_objects, extra=3)
    n = max(static.n_objects, 1)
    sums.add(mi.Float(1.0), BLOCKS * n - 1 + hits.refined, hits.refined > 0)
    raster_layer, albedo = terms.raster, terms.albedo
    full, tier = terms.traced, None
    if static.modelled:  # pixels traced without their indirect light take the learnt term for it
        modelled = mi.Bool(False)
        for k in static.modelled:
            modelled |= terms.config == k
        modelled &= terms.traced
        full = terms.traced & ~modelled
        rt = with_ambient(rt, albedo, terms.object, modelled, data.indirect)
        tier = with_ambient(direct, albedo, terms.object, full, data.indirect)  # what a shadow tier would show
    add_error(sums, terms.object, terms.traced, rt, raster_layer, terms.shaded, albedo, static.n_objects, w, full=full,
              direct=direct, tier=tier, skipped=terms.left_out)  # what tracing changed
    clock.mark("trace", rt, counts.per_object, sums.values)
    # 5. composition (§5), splatted like a camera ray through the same film position; an object
    # traced in part first fills its left-out pixels from their traced neighbours
    shown = terms.traced
    if static.partial:
        rt, shown = fill_left_out(rt, terms.traced, terms.filled, terms.object, w, h)
    color = compose(raster_layer, rt, shown, static.blend)
    if static.max_depth == 0:  # as Mitsuba's path: no vertex at all, not even an emitter seen directly
        color = dr.zeros(mi.Color3f, w * h)
    index = dr.arange(mi.UInt32, w * h)
    pixel = mi.Point2f(mi.Float(index % w), mi.Float(index // w))
    pos = pixel if static.box_filter else pixel + offset
    film = sensor.film()
    # the denoiser needs each pixel's own samples (a wider filter correlates the noise of
    # neighbours, which it then keeps as detail): a box filter when denoising
    rfilter = _box_filter(mi.variant()) if static.guides else film.rfilter()
    block = mi.ImageBlock(film.crop_size(), film.crop_offset(), 5 if static.has_alpha else 4, rfilter)
    alpha = dr.select((terms.valid | static.background_alpha) & (static.max_depth != 0), 1.0, 0.0)
    block.put(pos, [color.x, color.y, color.z] + ([alpha] if static.has_alpha else []) + [mi.Float(1.0)])
    layers = None
    if static.layers:
        layer_block = mi.ImageBlock(film.crop_size(), film.crop_offset(), 8, rfilter)
        layer_block.put(pos, [*raster_layer, *rt, dr.select(shown, 1.0, 0.0),
                              mi.Float(1.0)])
        layers = layer_block.tensor()
    guides = surface = film_block = None
    if static.film_copy:
        film_block = mi.ImageBlock(film.crop_size(), film.crop_offset(), 4, film.rfilter())
        film_block.put(pixel + offset, [color.x, color.y, color.z, mi.Float(1.0)])
        film_block = film_block.tensor()
    if static.guides:  # the denoiser's guides (denoise.py), filtered like the colour
        albedo = [dr.clip(a + s, 0.0, 1.0) for a, s in zip(terms.targets["albedo"], terms.targets["specular"])]
        albedo = [dr.select(terms.valid, a, dr.clip(c, 0.0, 1.0)) for a, c in zip(albedo, (color.x, color.y, color.z))]
        guide_block = mi.ImageBlock(film.crop_size(), film.crop_offset(), 7, rfilter)
        guide_block.put(pos, albedo + list(terms.targets["normal"]) + [mi.Float(1.0)])
        guides = guide_block.tensor()
    if static.surface:
        surface = Surface(position=mi.Point3f(*terms.targets["position"]), normal=mi.Vector3f(*terms.targets["normal"]),
                          object=dr.select(terms.valid, terms.object, 0xFFFFFFFF))
    packed = dr.concat([counts.per_object, dr.reinterpret_array(mi.UInt32, sums.total())])
    clock.mark("compose", block.tensor(), layers, packed, guides, surface, film_block)
    return PassOutput(image=block.tensor(), layers=layers, counts=packed, aovs={k: terms.targets[k] for k in static.aovs},
                      guides=guides, surface=surface, film=film_block)


@functools.lru_cache(maxsize=None)
def _box_filter(variant: str | None = None) -> mi.ReconstructionFilter:
    """Mitsuba's ``box`` reconstruction filter (one per variant)."""
    return mi.load_dict({"type": "box"})


@dataclass
class DrawnAhead:
    """The next frame's visibility buffer, drawn at the end of a frame for the set-up, camera and
    sub-pixel offset it expects that frame to have (:meth:`HybridRenderer._draw_ahead`)."""

    setup: tuple
    camera: RasterCamera
    offset: tuple[float, float]
    fbo: object  # the rasterizer's target (moderngl.Framebuffer)
    query: object  # the GL timer query of its draw
    draws: int  # ``Rasterizer.draws`` after it: another pass since has drawn over it


@dataclass
class _Frame:
    """One frame's fixed parts: the sensor, its camera, the settings of its passes, its statistics."""

    sensor: mi.Sensor
    camera: RasterCamera
    static: PassStatic
    setup: tuple  # the key of its fixed parts (settings, sensor, size, AOVs, layers): ``_setups``
    active: np.ndarray  # per object and kind, whether it is traced when selected (heuristic.active_kinds)
    candidate_config: np.ndarray  # per object: effect set index, −1 not a candidate
    candidates: mi.Int32  # the same on the device (every candidate traced)
    stats: FrameStats
    development: Development  # how its splats become the image (``_post`` works on its film's sRGB)
    ambient: mi.Float | None = None  # the learnt ambient table this frame shades with
    indirect: mi.Float | None = None  # the learnt indirect table of its shadow tiers
    tiers: np.ndarray | None = None  # per object: it has a shadow tier (heuristic.candidates)
    denoiser: Denoiser | None = None  # the denoiser this frame ran, if any
    queries: list = field(default_factory=list)  # the GL timer queries of its passes' draws
    traces: bool = True  # some object is selected: without one the image is the raster layer, noise-free
    timed: bool = True  # its stages are timed (``HybridSettings.times_frame``)

    def denoised(self, settings: HybridSettings) -> bool:
        """Whether the frame is denoised after its device passes: with ``denoise``, where it traces
        something (the raster layer alone has no noise to remove)."""
        return settings.denoise and self.traces


def _normalized(block: mi.TensorXf, first: int) -> mi.TensorXf:
    """Three channels of a splatted block from ``first`` on, divided by the block's weight (its
    last channel)."""
    weight = block.shape[2] - 1
    return block[..., first:first + 3] / dr.maximum(block[..., weight:weight + 1], 1e-12)


#: the film pixel formats hdrfilm develops from the linear sRGB the frame is made in, and the
#: variant's function that converts the colour so (alpha is kept)
FROM_SRGB = {mi.Bitmap.PixelFormat.XYZ: "srgb_to_xyz", mi.Bitmap.PixelFormat.XYZA: "srgb_to_xyz",
             mi.Bitmap.PixelFormat.Y: "luminance", mi.Bitmap.PixelFormat.YA: "luminance"}
SRGB = (mi.Bitmap.PixelFormat.RGB, mi.Bitmap.PixelFormat.RGBA)


class Development:
    """How the passes' splats become the image ``mi.render`` returns: developed in the sensor's film
    (a few small kernels that Mitsuba's C++ film traces quickly: not worth a frozen function).

    The frame is composed in linear sRGB, as Mitsuba's RGB variants render, and the film converts
    it to its pixel format (hdrfilm's ``xyz`` and ``luminance``, with or without alpha). The
    denoiser and the temporal history work on that colour, so a post-processed frame (``_post``)
    is developed in an sRGB film of the same size and filter, and converted to the sensor film's
    format after (:meth:`finish`), as that film converts (``mi.srgb_to_xyz``, ``mi.luminance``:
    the same values to float precision, tests/test_integrator.py). The film's format is read
    from its first development: a film prepared before the frame's first device pass made that
    pass record once more (tests/test_freeze.py)."""

    def __init__(self, film: mi.Film, post: bool):
        self.film = film  # the film developed in: the sensor's, or its sRGB twin
        self.post = post
        self.convert: Callable | None = None  # sRGB → the sensor film's colour; None: no conversion
        self.pixel_format: mi.Bitmap.PixelFormat | None = None  # the sensor film's, once developed

    def __call__(self, block: mi.TensorXf) -> mi.TensorXf:
        """The splats of ``block`` developed in :attr:`film`."""
        image = self._develop(block)
        if self.pixel_format is None:
            self.pixel_format = pixel_format = self.film.bitmap().pixel_format()
            if self.post and pixel_format not in SRGB:
                if pixel_format not in FROM_SRGB:
                    raise UnsupportedSceneError(f"the film's pixel format {pixel_format.name} is not supported with "
                                                "denoise or temporal: use rgb, rgba, xyz, xyza, luminance or "
                                                "luminance_alpha")
                film = self.film
                self.film = mi.load_dict({"type": "hdrfilm", "width": film.size()[0], "height": film.size()[1],
                                          "pixel_format": "rgba" if mi.has_flag(film.flags(), mi.FilmFlags.Alpha) else "rgb",
                                          "rfilter": film.rfilter(), "sample_border": film.sample_border()})
                self.convert = getattr(mi, FROM_SRGB[pixel_format])
                image = self._develop(block)
        return image

    def _develop(self, block: mi.TensorXf) -> mi.TensorXf:
        self.film.prepare([])
        self.film.put_block(mi.ImageBlock(block, self.film.crop_offset(), self.film.rfilter()))
        return self.film.develop()

    def finish(self, image: mi.TensorXf) -> mi.TensorXf:
        """An image of :attr:`film` in the sensor film's pixel format."""
        if self.convert is None:
            return image
        height, width, channels = image.shape
        colour = self.convert(mi.Color3f(*(image[..., k].array for k in range(3))))
        colour = mi.TensorXf(dr.ravel(colour), (height, width, 3 if dr.size_v(colour) == 3 else 1))
        return colour if channels == 3 else dr.concat([colour, image[..., 3:]], axis=2)


class HybridRenderer:
    """The GPU-side state of one scene: its rasterizer (geometry uploaded once), lights and tables,
    and its device pass (recorded once per configuration)."""

    def __init__(self, scene: mi.Scene, rasterizer: Rasterizer):
        if not scene.shapes():
            # the device pass's tables would be empty, which Dr.Jit cannot freeze (it aborts)
            raise UnsupportedSceneError("the scene has no shapes: there is nothing to rasterize or trace")
        self.scene = scene
        self.objects = scene_objects(scene)
        self.raster = rasterizer
        self.lighting = DeferredLighting(scene)
        self.constants = shape_constants(scene)
        self.clock = StageClock()
        # the device pass frozen with the scene's variables in the scene's place (frozen.py); one
        # per PassStatic: Dr.Jit 1.5 was seen to replay a recording made for other static
        # settings (a pass without the denoiser's guides for one with them)
        self.frozen = FrozenScene(scene)
        self._frozen: dict[PassStatic, FrozenFunction] = {}
        self._gl_queries: list = []  # GL timer queries no pass holds
        self._ahead: DrawnAhead | None = None  # the next frame's first pass, drawn by the last frame
        self._cameras: dict[tuple, RasterCamera] = {}  # per set-up, the last frame's camera
        self._setups: dict = {}
        self._denoisers: dict[str, Denoiser] = {}
        self._accumulators: dict[bool, Accumulator] = {}
        #: on the GPU, each frame's counts reach the host without waiting for the rest of its work;
        #: two copies, frames taking turns, so that a frame in flight keeps its own until it is read
        self._counts = [HostCopy(), HostCopy()] if mi.variant().startswith("cuda") else []
        #: the sub-pixel offsets of the next seed, made while the GPU traced the last frame
        self._next_offsets: dict[tuple[int, int], list[tuple[float, float]]] = {}
        #: the last frame, while it is in flight (``frames_in_flight=2``: inflight.py), and the
        #: device time spans of frames no longer in flight, for reuse
        self._in_flight: InFlight | None = None
        self._spans: list[FrameSpan] = []

    def render(self, settings: HybridSettings, sensor: int | mi.Sensor = 0, spp: int = 0, seed: int = 0,
               aovs=(), state: FrameState | None = None, layers: bool = True, next_camera=None) -> HybridResult:
        """One frame (paper Fig. 4). ``state`` carries the previous frame's selection, coverage and
        the cost model into this one (a fresh state: the first frame of a sequence).
        ``next_camera``: the sensor's ``to_world`` in the next frame, where it is known (a camera
        path): the frame draws that frame's raster pass ahead (:meth:`_draw_ahead`).
        With ``settings.frames_in_flight=2`` and no budget, the frame returns without waiting for
        the GPU to finish it, and its times are read later (``inflight.py``, :meth:`finish`)."""
        state = state if state is not None else FrameState()
        next_pose = None if next_camera is None else camera_pose(next_camera)  # checked before any work
        spp, seed = check_frame_numbers(spp, seed)
        timed = settings.times_frame(state.frames, state.cost_model.calibrated, state.jumped)
        with dr.scoped_set_flag(dr.JitFlag.KernelHistory, timed):
            dr.kernel_history_clear()
            clock = _HostClock()
            span, after = self._begin(settings)
            frame = self._frame(settings, resolve_sensor(self.scene, sensor), check_aovs(aovs), spp, layers)
            frame.timed = timed
            # a sequence's frames take seeds seed, seed + 1, ...: the previous frame made these
            offsets = self._next_offsets.pop((frame.stats.spp, seed), None) or subpixel_offsets(frame.stats.spp, seed)
            clock.lap("setup")
            # every pass's visibility buffer first (1): OpenGL draws while the host sets up and
            # plans the frame (a budget's selection: 0.3-0.4 ms on the H100's host), and OpenGL's and CUDA's work
            # take turns on the GPU, so a draw issued after a pass's device work would wait for all of it
            ids = [self._visibility(settings, frame, offset, clock) for offset in offsets]
            tables = [t if settings.learn_ambient else t[:0] for t in (state.ambient, state.indirect)]
            frame.ambient, frame.indirect = (device_array(mi.Float, ambient_table(t, len(self.objects)).ravel())
                                                 for t in tables)
            clock.lap("setup")
            plan, config = self._select(settings, frame, state, seed)  # 3. selection, on the host
            clock.lap("select")
            outputs = [self._device(settings, frame, config, seed, sample, offset, ids[sample], clock)  # 1, 2, 4, 5
                       for sample, offset in enumerate(offsets)]
            # where the GPU denoises the frame after its device passes, their history is read
            # meanwhile (_read_ahead), once their counts are on the host: the launches after them
            # go unrecorded, so that the history is complete then (their stages are the ones timed
            # but temporal accumulation's, a stage of its own, read after the synchronization)
            ahead = timed and frame.denoised(settings) and not settings.temporal
            if ahead:
                dr.set_flag(dr.JitFlag.KernelHistory, False)
            copy = self._counts[0] if self._counts else None
            self._counts.reverse()
            if copy:  # the counts to the host as soon as the device passes are done
                copy.start([o.counts for o in outputs])
            if span is not None:
                # the frame before is done before the GPU starts these passes: its times and what it
                # teaches now, while the GPU traces, before this frame's denoiser records its events again
                self.finish(clock, keep=after is not None)
            composed = frame.development(sum_tensors([o.image for o in outputs]))
            clock.lap("develop")
            image = frame.development.finish(self._post(settings, frame, state, composed, outputs))
            composed = frame.development.finish(composed)
            clock.lap("post")
            self._end_frame(settings, frame, state, plan, copy, [o.counts for o in outputs], image, clock,
                            span, after, seed, next_pose, ahead)
        layer_sums = sum_tensors([o.layers for o in outputs]) if layers else None
        aov_images = {k: _image(v, frame.camera) for k, v in outputs[0].aovs.items()}
        return HybridResult(image=image, stats=frame.stats, layers=layer_sums, aovs=aov_images, composed=composed,
                            pixel_format=frame.development.pixel_format)

    def _begin(self, settings: HybridSettings) -> tuple[FrameSpan | None, FrameSpan | None]:
        """The frame's start: in flight (``frames_in_flight=2``, no budget: a budget learns from the
        trace's time, which only a synchronization gives; ``inflight.py``) its device time span,
        started, and the span of the frame before if that is still in flight; else (None, None),
        once the frame before, if in flight, is finished: what it teaches, before this frame plans
        (on a clock of its own: not this frame's time)."""
        if settings.in_flight:
            span = self._spans.pop() if self._spans else FrameSpan()
            span.start()
            return span, self._in_flight.span if self._in_flight is not None else None
        self.finish()
        return None, None

    def _end_frame(self, settings: HybridSettings, frame: _Frame, state: FrameState, plan: FramePlan | None,
                   copy: HostCopy | None, counts: list, image: mi.TensorXf, clock: "_HostClock",
                   span: FrameSpan | None, after: FrameSpan | None, seed: int, next_pose: np.ndarray | None,
                   read_ahead: bool = False) -> None:
        """The frame's end, once its work is issued: the image evaluated; what the next frame learns
        from this one's ``counts`` (:meth:`_lesson`; in flight: read by the next frame); the
        visibility targets back to OpenGL and the next frame's raster pass drawn ahead
        (:meth:`_draw_ahead`); then the frame's one synchronization and its times, or, in flight,
        the record the next frame finishes it from (``inflight.InFlight``)."""
        # (less the frame before's, where it was finished in this one)
        frame.stats.times_ms["issue"] = clock.elapsed() - sum(clock.phases.get(k, 0.0) for k in ("timing", "readback", "sync"))
        dr.eval(image)
        if span is not None:
            span.stop()
        # the cost model refitted to the last frame's trace (observed after its synchronization)
        # now, while the GPU traces this frame, not before the next frame's plan (made below with a
        # still camera, else once the counts are in, where the frame would wait for the refit)
        state.cost_model.current()
        # the next seed's sub-pixel offsets (~0.1 ms of host time on the H100's host, numpy's
        # generator) now too, not before the next frame's raster pass: the same numbers
        self._next_offsets = {(frame.stats.spp, seed + 1): subpixel_offsets(frame.stats.spp, seed + 1)}
        # and, with a still camera, the next frame's plan, while the GPU traces this one (:meth:`_plan_ahead`)
        self._plan_ahead(settings, frame, state, plan, next_pose)
        learnt = read = None
        if span is None:
            # the counts, then what the next frame learns from them: on the GPU while it develops
            # and denoises this frame (the counts' copy waits for the device passes alone)
            learnt = self._lesson(settings, frame, plan, state, copy, counts, clock)
            read = self._read_ahead() if read_ahead else None
        elif copy and settings.primary == "raster":  # in flight: learnt from in the next frame
            copy.sync()  # this frame's trace done, before OpenGL gets work again (below)
            clock.lap("sync")
        # the visibility targets back to OpenGL (interop's unmap, on Dr.Jit's stream behind this
        # frame's work) now, where the host waits for the GPU, not in the next frame's raster
        # pass; nor earlier, while the GPU traces: OpenGL's side of the unmap, pending there,
        # made the GPU switch contexts during the trace, 0.22-0.46 ms longer on every bench
        # scene (docs/results, issue 10, stop 42)
        self.raster.release()
        # then the next frame's raster pass, which OpenGL runs once this frame's work is done
        self._draw_ahead(settings, frame, self._next_offsets[frame.stats.spp, seed + 1][0], next_pose)
        clock.lap("ahead")
        if span is None:
            # the history read ahead, parsed and split by stage while the GPU still denoises
            stage_ms = self.clock.frame_times(read) if read is not None else None
            clock.lap("timing")
            dr.sync_thread()  # the frame's one synchronization
            clock.lap("sync")
            self._account_times(settings, frame, state, learnt, clock, stage_ms)
            frame.stats.times_ms["total"] = clock.elapsed()
            if settings.budget_ms > 0:
                state.watch(frame.stats.times_ms["total"], settings.budget_ms, frame.timed)
        else:  # its times and its lesson once the GPU is done with it
            self._in_flight = InFlight(frame=frame, span=span, after=after, settings=settings, state=state, copy=copy, counts=counts)
            frame.stats.in_flight = True
            frame.stats.untimed()
            unread = ["total"] + ["denoise"] * (frame.denoiser is not None) + ["gl"] * (settings.primary == "raster")
            frame.stats.times_ms.update(dict.fromkeys(unread, math.nan))
            self.clock.discard()  # no kernel history is read for it
        frame.stats.host_ms = {k: clock.phases.get(k, 0.0) for k in HOST_PHASES}

    def _frame(self, settings: HybridSettings, sensor: mi.Sensor, aovs: tuple[str, ...], spp: int, layers: bool) -> _Frame:
        """The frame's fixed parts; what depends only on the settings is made once and kept."""
        camera = RasterCamera.from_sensor(sensor)
        key = (repr(settings), id(sensor), camera.width, camera.height, aovs, layers)
        if key not in self._setups:
            self._setups[key] = self._setup(settings, sensor, camera, aovs, layers)
        static, active, candidate_config, every, tiers, development = self._setups[key]
        stats = FrameStats(width=camera.width, height=camera.height, spp=int(spp) or sensor.sampler().sample_count(),
                           primary=settings.primary, lights_left_out=self.lighting.lights.approximated,
                           budget_ms=settings.budget_ms)
        return _Frame(sensor=sensor, camera=camera, static=static, setup=key, active=active, stats=stats,
                      development=development,
                      candidate_config=candidate_config, candidates=every, tiers=tiers)

    def _setup(self, settings: HybridSettings, sensor: mi.Sensor, camera: RasterCamera, aovs: tuple[str, ...],
               layers: bool) -> tuple[PassStatic, np.ndarray, np.ndarray, mi.Int32, np.ndarray, Development]:
        kinds = candidate_kinds(settings.candidates, self.scene)
        # the distinct effect sets the candidates deserve, and each object's (-1: not a candidate):
        # fixed for the frame, so that one traced kernel serves every selection. An object that
        # deserves every kind its material has is traced with all the integrator's effects: the
        # lobes it lacks change nothing, and one effect set for all such objects saves the
        # trace a BSDF evaluation per set at the first vertex
        material = default_kinds(self.scene)
        full = [set(ks) >= set(d) for ks, d in zip(kinds, material)]
        active = [settings.effects if ks and f else tuple(k for k in ks if k in settings.effects)
                  for ks, f in zip(kinds, full)]
        # with a budget, an object with diffuse lobes traced with shadows and indirect light may
        # also be traced with its shadow rays alone, its indirect light from the learnt term
        # (heuristic.candidates)
        tiered = settings.budget_ms > 0 and settings.shadow_tier and settings.relevance == "error"
        tiers = np.array([tiered and {"shadow", "indirect"} <= set(a) and "indirect" in d
                          for a, d in zip(active, material)], dtype=bool)
        configs = tuple(sorted({a for a in active if a} | ({SHADOW_ONLY} if tiers.any() else set())))
        modelled = tuple(k for k, c in enumerate(configs) if "indirect" not in c) if "indirect" in settings.effects else ()
        film = sensor.film()
        glass = refracts(self.objects.bsdf(k, self.scene) for k, a in enumerate(active) if a)
        static = PassStatic(
            width=camera.width, height=camera.height, primary=settings.primary, refine=resolve_refine(settings.refine, bool(configs)),
            outline=resolve_outline(settings.outline, resolve_method(settings.raster)),
            effects=settings.effects,
            configs=configs, max_depth=settings.max_depth, rr_depth=settings.rr_depth,
            roulette=settings.roulette,
            hide_emitters=settings.hide_emitters, blend=float(settings.blend),
            targets=tuple(dict.fromkeys(tuple(INPUTS) + aovs)), aovs=aovs, layers=layers,
            has_alpha=mi.has_flag(film.flags(), mi.FilmFlags.Alpha),
            box_filter=settings.denoise or film.rfilter().is_box_filter(),
            has_emitters=len(self.scene.emitters()) > 0,
            background_alpha=self.scene.environment() is not None and not settings.hide_emitters,
            n_objects=len(self.objects), guides=settings.denoise, surface=settings.temporal, modelled=modelled,
            film_copy=settings.temporal and settings.denoise and not film.rfilter().is_box_filter(),
            secondary_spp=settings.secondary_spp, long_first=glass and mi.variant().startswith("cuda"),
            partial=settings.partial_objects and settings.budget_ms > 0)
        config = np.array([configs.index(a) if a else -1 for a in active], dtype=np.int32)
        return (static, active_kinds(kinds, settings.effects), config, mi.Int32(config), tiers,
                Development(film, settings.temporal or settings.denoise))

    def _post(self, settings: HybridSettings, frame: _Frame, state: FrameState, image: mi.TensorXf,
              outputs: list[PassOutput]) -> mi.TensorXf:
        """After the film: the frame blended with its reprojected history (``temporal.py``), then
        denoised with the G-buffer's guides (``denoise.py``) if it traced anything (the raster
        layer alone is noise-free), and the denoised history resolved against the history's
        film-filtered mean; alpha, if the film has it, is kept."""
        if not (settings.temporal or settings.denoise):
            state.history = None
            return image
        rgb = image if image.shape[2] == 3 else image[..., 0:3]
        if settings.temporal:
            if settings.freeze not in self._accumulators:
                self._accumulators[settings.freeze] = Accumulator(settings.freeze,
                                                                  lambda *out: self.clock.mark("temporal", *out))
            accumulate = self._accumulators[settings.freeze]
            film = None if outputs[0].film is None else _normalized(sum_tensors([o.film for o in outputs]), 0)
            rgb, state.history = accumulate(rgb, film, outputs[0].surface, frame.camera, state.history)
        else:
            state.history = None
        if frame.denoised(settings):
            sums = sum_tensors([o.guides for o in outputs])
            guide = [_normalized(sums, k) for k in (0, 3)]
            if settings.denoise_quality not in self._denoisers:
                self._denoisers[settings.denoise_quality] = Denoiser(settings.denoise_quality)
            denoiser = self._denoisers[settings.denoise_quality]
            rgb = denoiser(rgb, Guides(albedo=guide[0], normal=guide[1]))
            frame.denoiser = denoiser
            if settings.temporal:
                rgb = self._accumulators[settings.freeze].resolve(rgb, state.history)
        return rgb if image.shape[2] == 3 else dr.concat([rgb, image[..., 3:]], axis=2)

    def _select(self, settings: HybridSettings, frame: _Frame, state: FrameState, seed: int) -> tuple[FramePlan | None, mi.Int32]:
        """Stage 3 on the host (§4): every visible candidate without a budget; with one, the plan
        of ``budget.plan_frame`` from the last frame's coverage (measured first, with nothing
        traced, if this frame is the first of its size). Once the cost model is calibrated, the
        last frame made that plan already, once its counts were in (:meth:`_account`) or, with a
        still camera, while its GPU traced (:meth:`_plan_ahead`), with the cost model as it stood
        before the last trace's time was known (one observation of up to 48 behind); it is used if
        this frame's settings are the same and the last trace took no longer than the model
        predicted (:meth:`_account_times`). Returns
        the plan and each object's effect set for the device pass."""
        if settings.budget_ms <= 0:
            frame.traces = bool((frame.candidate_config >= 0).any())
            return None, frame.candidates
        cov = state.coverage
        if not isinstance(cov, Coverage) or (cov.width, cov.height) != (frame.camera.width, frame.camera.height):
            probe = self._pass(settings, frame, device_array(mi.Int32, np.full(len(self.objects), -1, np.int32)), seed, 0,
                               (0.5, 0.5))
            cov = self._coverage(frame, PassCounts.read(np.array(probe.counts), len(self.objects)))
            self.clock.frame_times()  # not this frame's work
        ahead, state.next_plan = state.next_plan, None
        made_for = (frame.setup, frame.stats.spp, state.frames)
        plan = ahead[1] if ahead is not None and ahead[0] == made_for else self._plan(settings, frame, state, cov)
        config = np.full(len(self.objects), -1, dtype=np.int32)
        c = plan.candidates
        tier, whole = (c.index[plan.picked][mask] for mask in (c.tier[plan.picked], ~c.tier[plan.picked]))
        if len(tier):
            config[tier] = frame.static.configs.index(SHADOW_ONLY)
        config[whole] = frame.candidate_config[whole]
        if plan.partial is not None:  # the budget's last object, on part of its pixels
            row, quarters = plan.partial
            k = c.index[row]
            config[k] = part_config(int(frame.candidate_config[k]), quarters)
        frame.traces = bool((config >= 0).any())
        return plan, device_array(mi.Int32, config)

    def _plan(self, settings: HybridSettings, frame: _Frame, state: FrameState, cov: Coverage,
              selected: set[int] | None = None) -> FramePlan:
        """Eq. 1–3 from a coverage, then the selection within the budget, for a frame after one that
        selected ``selected`` (default: the state's)."""
        start = time.perf_counter()
        growth = state.growth if cov is state.coverage else None  # the growth that led to ``cov``
        c = candidates(cov, frame.active, state.selected if selected is None else selected, settings.importance,
                       state.rays_per_pixel, self._errors(settings, state), frame.tiers, growth)
        plan = plan_frame(c, settings.selection, settings.budget_ms, frame.stats.spp, state.cost_model,
                          partial=settings.partial_objects)
        plan.host_ms = (time.perf_counter() - start) * 1e3
        return plan

    def _plan_ahead(self, settings: HybridSettings, frame: _Frame, state: FrameState, plan: FramePlan | None,
                    next_pose: np.ndarray | None) -> None:
        """With a still camera and a trace long enough, the next frame's plan, made while the GPU
        traces this frame: from the coverage this frame's plan was made from (the last frame's: the
        same view, at another sub-pixel offset), what was learnt until the last frame, and this
        frame's selection (S of eq. 3). So the host plans where it waits for the trace anyway, not
        once this frame's counts are on the host, where the frame waits for it: on the H200 the
        host's work there (learning, planning, the next raster pass) takes longer than the 1.1 ms
        denoiser, and host work added there was 0.5-1.4 times in the frame, hidden where added while
        the GPU traced (docs/results/gpu/issue10/stop53: frames 0.40-0.69 ms shorter so on the
        showcase, Sponza and the dining room, in turn in one process). A moving camera plans once the counts are in
        (:meth:`_account`): planned from the coverage before the last, its frames on the 226
        objects' camera path captured 6-13 % less relevance, for 0.4-0.8 ms less per frame
        (stop 53). The next frame uses the plan if its settings are the same and this frame's
        trace took no longer than the model predicted (:meth:`_account_times`)."""
        cov = state.coverage  # the last frame's, of this state (whose set-up may have been another)
        if (plan is None or not state.cost_model.calibrated or not isinstance(cov, Coverage)
                or (cov.width, cov.height) != (frame.camera.width, frame.camera.height)):
            return
        # still: the last frame of this set-up (``_draw_ahead`` keeps its camera) drew as this one,
        # and so will the next
        last = self._cameras.get(frame.setup)
        if not (last is not None and last.draws_as(frame.camera)
                and (next_pose is None or frame.camera.at(next_pose).draws_as(frame.camera))):
            return
        # and where the trace leaves the host the time to plan: a trace predicted to take less than
        # twice the last plan's host time is over before the plan, whose time then delays the
        # frame's end either way, and the next raster pass's issue with it (a trace of the
        # Armadillo's floor alone, 0.55 ms: frames 0.13-0.21 ms longer so, stop 53)
        if state.cost_model.predict(plan.rays) * frame.stats.spp >= 2.0 * plan.host_ms:
            state.next_plan = ((frame.setup, frame.stats.spp, state.frames + 1),
                               self._plan(settings, frame, state, cov, selected=plan.traced))

    def _pass(self, settings: HybridSettings, frame: _Frame, config: mi.Int32, seed: int, sample: int, offset,
              clock: "_HostClock | None" = None) -> PassOutput:
        """One sample pass: the visibility buffer (stage 1, OpenGL), then the device pass."""
        clock = clock or _HostClock()
        triangle_id = self._visibility(settings, frame, offset, clock, timed=False)
        return self._device(settings, frame, config, seed, sample, offset, triangle_id, clock)

    def _visibility(self, settings: HybridSettings, frame: _Frame, offset, clock: "_HostClock",
                    timed: bool = True) -> mi.UInt32:
        """Stage 1 of one sample pass: the visibility buffer drawn by OpenGL, as a Dr.Jit array
        (camera rays need none: zeros), or drawn already by the frame before (:meth:`_draw_ahead`).
        ``timed``: the draw's GL time is the frame's (a timer query per sample pass; a probe's
        draw is not timed, nor drawn ahead)."""
        camera = frame.camera
        if settings.primary == "raster":
            fbo = self._drawn_ahead(frame, offset) if timed else None
            if fbo is None:
                fbo = self._draw(settings, camera, offset, frame.queries if timed else None)
            triangle_id = self.raster.device_ids(fbo)
        else:
            triangle_id = dr.zeros(mi.UInt32, camera.width * camera.height)
        clock.lap("raster")
        return triangle_id

    def _draw(self, settings: HybridSettings, camera: RasterCamera, offset, queries: list | None):
        """OpenGL's raster pass, handed to the GPU, timed by a GL timer query appended to
        ``queries`` (None: not timed); returns its target."""
        query = None
        if queries is not None:
            query = self._gl_queries.pop() if self._gl_queries else self.raster.ctx.query(time=True)
            queries.append(query)
        with query or contextlib.nullcontext():  # the draw alone: the query's end waits for nothing of CUDA's
            fbo = self.raster.render(camera, offset, settings.raster)
        gl_flush()  # the draw and the query's end to the GPU now
        return fbo

    def _draw_ahead(self, settings: HybridSettings, frame: _Frame, offset, next_pose: np.ndarray | None = None) -> None:
        """The next frame's raster pass (its first sample pass, at the next seed's first sub-pixel
        ``offset``), issued at the end of this frame where ``raster_ahead`` allows it and the next
        frame's camera can be foreseen: ``next_pose`` (its ``to_world``, given by a camera path:
        ``api.render_sequence``; ``raster.camera.camera_pose``), or this frame's where the camera stands still (the same camera
        as the frame before, for the same set-up).

        It is issued after the frame's targets are handed back to OpenGL (``Rasterizer.release``:
        on the GPU, interop's unmap on Dr.Jit's stream, which orders OpenGL's later work on the
        target after all of this frame's CUDA work), so OpenGL runs it once the GPU is done with
        this frame: the host issues it while the GPU still develops and denoises, and the next
        frame starts from its interop copy, with OpenGL's host issue and the switch between the
        two APIs' contexts behind it (docs/results, issue 10, stop 37). Stop 31 drew ahead while
        the GPU traced, into another target, which OpenGL then ran in turns with the trace: slower;
        stop 42 issued the unmap and this pass (or its commands, flushed later, or the unmap alone)
        while the GPU traced, to take their host time off the frame's end: the trace grew by
        0.22-0.46 ms each time.
        Without ``next_pose``, a camera that moved since the last frame draws nothing ahead (the
        next one would likely move again); a next frame that does not match discards what was
        drawn (``FrameStats.raster_discarded``)."""
        still = self._cameras.get(frame.setup) is frame.camera
        self._cameras[frame.setup] = frame.camera
        on = settings.raster_ahead == "on" or (settings.raster_ahead == "auto"
                                                and self.raster.readback == "cuda-gl-interop")
        if settings.primary != "raster" or not on or not (still or next_pose is not None):
            return
        camera = frame.camera if next_pose is None else frame.camera.at(next_pose)
        if self._ahead is not None:  # drawn for a frame that did not come: its query back
            self._gl_queries.append(self._ahead.query)
        queries: list = []
        fbo = self._draw(settings, camera, offset, queries)
        self._ahead = DrawnAhead(setup=frame.setup, camera=camera, offset=tuple(offset), fbo=fbo,
                                 query=queries[0], draws=self.raster.draws)

    def _drawn_ahead(self, frame: _Frame, offset) -> object | None:
        """The target drawn ahead for this frame's pass at ``offset`` (its query now the frame's),
        or None; a buffer drawn ahead for another frame is discarded and counted."""
        ahead, self._ahead = self._ahead, None
        if ahead is None:
            return None
        if (ahead.setup == frame.setup and ahead.offset == tuple(offset) and ahead.draws == self.raster.draws
                and ahead.camera.draws_as(frame.camera)):
            frame.queries.append(ahead.query)
            frame.stats.raster_ahead += 1
            return ahead.fbo
        self._gl_queries.append(ahead.query)
        frame.stats.raster_discarded += 1
        return None

    def _device(self, settings: HybridSettings, frame: _Frame, config: mi.Int32, seed: int, sample: int, offset,
                triangle_id: mi.UInt32, clock: "_HostClock") -> PassOutput:
        """Stages 1 (on the device) to 5 of one sample pass: the frozen device pass."""
        camera = frame.camera
        data = PassData(triangle_id=triangle_id, camera=device_array(mi.Float, np.r_[offset, camera.eye].astype(np.float32)),
                        seed=device_array(mi.UInt32, np.array([sample, int(seed) & 0xFFFFFFFF], dtype=np.uint32)),
                        config=config,
                        tables=self.raster.tables, lights=self.lighting.table, constants=self.constants,
                        ambient=frame.ambient, indirect=frame.indirect)
        # Mitsuba 3.9's orthographic sensor holds a Dr.Jit variable its traversal does not expose,
        # which a frozen function cannot capture ("created before recording was started"): its
        # frames run unfrozen
        frozen = settings.freeze and not camera.orthographic
        if frozen and frame.static not in self._frozen:  # made once: a new dr.freeze per pass would be waste
            self._frozen[frame.static] = self.frozen.freeze(functools.partial(device_pass, static=frame.static,
                                                                              clock=self.clock))
        if frozen:
            function = self._frozen[frame.static]
            output = function(frame.sensor, data)
            frame.stats.frozen_inputs = function.inputs
        else:
            output = device_pass(self.scene, frame.sensor, data, frame.static, self.clock)
        clock.lap("replay")
        return output

    @staticmethod
    def _errors(settings: HybridSettings, state: FrameState) -> np.ndarray | None:
        return state.error_per_pixel if settings.relevance == "error" else None

    def _coverage(self, frame: _Frame, counts: PassCounts) -> Coverage:
        return Coverage.of(counts.coverage, frame.camera.width, frame.camera.height, len(self.objects))

    def _account(self, settings: HybridSettings, frame: _Frame, plan: FramePlan | None, state: FrameState,
                 passes: list[PassCounts], clock: "_HostClock") -> tuple | None:
        """Once the device passes are done (the GPU may still develop and denoise the frame): the
        frame's counts in its statistics, and what the next frame learns from them. Returns what
        :meth:`_account_times` needs: the rays per object and kind of the frame's passes, with
        the number of passes, when the cost model learns from this frame (else ``None``)."""
        stats = frame.stats
        learnt = None
        stats.geometry_reloads = self.raster.reloads
        if settings.primary == "raster":
            stats.readback = self.raster.readback
            stats.raster_method = resolve_method(settings.raster)
        else:
            stats.rays["camera"] = len(passes) * frame.camera.width * frame.camera.height
        per_object = sum(p.rays for p in passes)  # objects × kinds
        stats.rays.update(zip(RAY_KINDS, (int(v) for v in by_kind(per_object))))
        stats.pixels_traced = sum(p.pixels for p in passes)
        stats.proxy_refinements = sum(p.proxy_refined for p in passes)
        stats.edge_refinements = sum(p.edge_refined for p in passes)
        stats.emitter_refinements = sum(p.emitter_refined for p in passes)
        covs = [self._coverage(frame, p) for p in passes]
        cov = covs[0]
        if plan is None and not frame.traces:  # no candidate at all: nothing traced, nothing to order
            ordered, planned = np.zeros(0, dtype=np.int64), set()
            keys, part = ordered, np.ones(0)
        elif plan is None:  # no budget: every visible candidate was traced; most relevant first
            terms = visibility_terms(cov, frame.active, state.selected, settings.importance, self._errors(settings, state))
            visible = np.nonzero(terms.candidate)[0]
            ordered = visible[np.argsort(-terms.relevance[visible], kind="stable")]
            keys, part = ordered, np.ones(len(ordered))
            planned = set(ordered.tolist())
            stats.candidates_visible = len(ordered)
        else:
            c = plan.candidates
            share = np.zeros(len(c))  # the part of each row's pixels traced
            share[plan.picked] = 1.0
            if plan.partial is not None:
                share[plan.partial[0]] = plan.partial[1] / 4
                stats.partial_object = self.objects.names[int(c.index[plan.partial[0]])]
                stats.partial_quarters = plan.partial[1]
            traced = (share > 0) & (cov.pixels[c.index] > 0)
            rows = np.nonzero(traced)[0][np.argsort(-c.relevance[traced], kind="stable")]
            ordered, keys, part = c.index[rows], c.keys(len(self.objects))[rows], share[rows]
            stats.shadow_only = tuple(self.objects.names[k] for k in c.index[rows[c.tier[rows]]].tolist())
            planned = plan.traced
            total = float(c.relevance[~c.tier].sum())  # every object whole: all there is to capture
            stats.candidates_visible = len(c)
            stats.relevance_captured = float((c.relevance * share)[traced].sum() / total) if total > 0 else 1.0
            stats.predicted_trace_ms = float(state.cost_model.predict(plan.rays)) * len(passes) if planned else 0.0
            stats.predicted_rays = int(sum(plan.rays.values()) * len(passes))
            stats.plan_ms = plan.host_ms
            if planned or len(c):  # the trace's time is known after the synchronization
                # a frame that traces nothing still runs its trace stage: its time is the fixed
                # part t0 measured alone (zero rays), which the model could otherwise only
                # extrapolate, too high after probes whose times hardly grew with their rays
                # a probe's rays were not a prediction (budget.FramePlan.probe): it is observed as
                # expecting what it traced, so that the margin holds the planner's errors alone
                learnt = (per_object, len(passes), None if plan.probe else plan.rays)
            if len(c) and not planned:
                state.cost_model.forget_slowest()
        if len(ordered):
            errors, pairs, residual, albedo, indirect, tier_errors = (
                sum(getattr(c, name) for c in covs)
                for name in ("error_sum", "pairs", "residual_sum", "albedo_sum", "indirect_sum", "tier_error_sum"))
            pixels = cov.pixels[ordered] * len(passes) * part  # those traced: an object in part, its share
            state.learn_rays(keys, pixels, per_object[ordered])
            n = len(self.objects)
            whole = ordered[keys < n]  # errors are learnt where an object is traced whole (heuristic.py)
            state.learn_errors(whole, errors[whole], pairs[whole])
            tiered = whole[frame.tiers[whole]]
            state.learn_errors(n + tiered, errors[tiered] - tier_errors[tiered], pairs[tiered])
            if settings.learn_ambient:  # both terms from the pixels traced with every effect alone
                state.ambient = learn_ambient(state.ambient, ordered, residual[:, ordered].T, albedo[:, ordered].T, pixels)
                if frame.static.modelled:  # the trace returned each path's first vertex apart
                    state.indirect = learn_ambient(state.indirect, ordered, indirect[:, ordered].T, albedo[:, ordered].T, pixels)
        stats.selected = tuple(self.objects.names[k] for k in ordered.tolist())
        stats.selection_changes = len(planned ^ state.selected)
        state.selected = set(planned)
        state.growth = pixel_growth(state.coverage, cov)
        state.coverage = cov
        state.frames += 1
        # the next frame's plan from what this one taught, while the GPU still denoises it (once the
        # cost model has passed its probe frames, whose sizes follow its observations one by one),
        # unless a still camera's was made already (:meth:`_plan_ahead`)
        if plan is not None and state.cost_model.calibrated and state.next_plan is None:
            state.next_plan = ((frame.setup, frame.stats.spp, state.frames), self._plan(settings, frame, state, cov))
        clock.lap("readback")
        return learnt

    def finish(self, clock: "_HostClock | None" = None, keep: bool = False) -> None:
        """Wait until the GPU is done with the frame in flight, if there is one; then what the
        next frames learn from its counts (:meth:`_account`: its statistics too) and its times:
        ``total``, the device time of its span (inflight.py), ``gl`` and ``denoise``. ``clock``:
        the host clock of the frame that does it (``timing``, ``readback``); ``keep``: that frame
        measures its span from this one's end (which is not reused until it is finished)."""
        pending, self._in_flight = self._in_flight, None
        if pending is None:
            return
        clock = clock or _HostClock()
        pending.span.wait()
        clock.lap("timing")
        self._lesson(pending.settings, pending.frame, None, pending.state, pending.copy, pending.counts, clock)
        pending.frame.stats.times_ms["total"] = pending.span.elapsed_ms(pending.after)
        self._timers(pending.frame)
        self._spans += [s for s in (pending.after, None if keep else pending.span) if s is not None]
        clock.lap("timing")

    def _lesson(self, settings: HybridSettings, frame: _Frame, plan: FramePlan | None, state: FrameState,
                copy: HostCopy | None, counts: list, clock: "_HostClock") -> tuple | None:
        """The frame's counts (``copy``'s on the GPU; on the CPU read from the ``counts`` arrays),
        once its device passes are done, and what they teach (:meth:`_account`)."""
        words = copy.wait() if copy else [np.array(c) for c in counts]
        clock.lap("sync")
        return self._account(settings, frame, plan, state, [PassCounts.read(w, len(self.objects)) for w in words], clock)

    def _timers(self, frame: _Frame) -> None:
        """The frame's device times that are not Dr.Jit's kernels: the denoiser's (CUDA events) and
        the raster pass's draws (GL timer queries, then free for other draws)."""
        stats = frame.stats
        if frame.denoiser is not None:
            stats.times_ms["denoise"] = frame.denoiser.elapsed_ms()
        if stats.primary == "raster":
            stats.times_ms["gl"] = sum(gl_elapsed_ms(q) for q in frame.queries)
            self._gl_queries.extend(frame.queries)

    def _read_ahead(self) -> Callable[[], list[dict]]:
        """The kernel history of the frame's device passes, once they are done (their counts on
        the host) and nothing is recorded after them: on the GPU read on a worker thread
        (``history.read_ahead``) while the GPU denoises the frame and this thread learns from its
        counts and issues the next raster pass, not after the synchronization, where the GPU has
        nothing left to do (docs/results/gpu/issue10/stop51: with the entries also parsed before
        the synchronization, the stage times cost a denoised frame -0.08 to +0.03 ms on the H200,
        against +0.14 to +0.22 read after it; a frame without a denoiser, whose GPU is done with it
        soon after, reads after the synchronization: the worker's hand-over cost the DR frame
        ~0.05 ms); on the CPU, whose counts were read with every task done (``inflight.py``), the
        usual reader. Returns what gives the entries (called by the frame's thread before its
        synchronization, while the GPU still denoises)."""
        return history.read_ahead() if self._counts else self.clock.read

    def _account_times(self, settings: HybridSettings, frame: _Frame, state: FrameState, learnt, clock: "_HostClock",
                       stage_ms: dict[str, float] | None = None) -> None:
        """After the frame's synchronization: the device time of its stages (``stage_ms``, from the
        history read ahead, :meth:`_read_ahead`; else read now), and the cost model taught the
        trace's time (:meth:`_account`'s ``learnt``)."""
        stats = frame.stats
        if frame.timed:
            stats.times_ms.update(stage_ms if stage_ms is not None else self.clock.frame_times())
        else:  # no history was kept (``HybridSettings.times_frame``): nothing to read, nothing learnt
            stats.untimed()
        self._timers(frame)
        if settings.primary == "raster" and math.isfinite(stats.times_ms["gl"]):  # NaN: the driver timed no draw (gl_elapsed_ms)
            stats.times_ms["raster"] += stats.times_ms["gl"]
        clock.lap("timing")
        if learnt is not None and frame.timed:
            # the refit waits for the next prediction: the next frame's plan, made ahead (_plan_ahead,
            # _account), or in its _select if that plan is dropped here
            per_object, passes, expected = learnt
            state.cost_model.observe(dict(zip(RAY_KINDS, by_kind(per_object) / passes)),
                                     stats.times_ms["trace"] / passes, expected=expected, fit=False)
            if state.next_plan and stats.times_ms["trace"] > stats.predicted_trace_ms:
                # made ahead by a model that this trace has just shown too optimistic: the next
                # frame plans again, with the model refitted to this trace
                state.next_plan = None
            clock.lap("readback")


class _HostClock:
    """Host time by phase (``FrameStats.host_ms``), with ``time.perf_counter``."""

    def __init__(self):
        self.start = self.last = time.perf_counter()
        self.phases: dict[str, float] = {}

    def lap(self, phase: str) -> None:
        now = time.perf_counter()
        self.phases[phase] = self.phases.get(phase, 0.0) + (now - self.last) * 1e3
        self.last = now

    def elapsed(self) -> float:
        return (self.last - self.start) * 1e3


def sum_tensors(tensors: list):
    """The sum of the passes' tensors (one pass: itself)."""
    out = tensors[0]
    for t in tensors[1:]:
        out = out + t
    return out


def _image(channels: list[mi.Float], camera: RasterCamera) -> np.ndarray:
    """A G-buffer target of the first pass as an (H, W, C) float32 image."""
    return np.stack([np.array(c, dtype=np.float32) for c in channels], axis=-1).reshape(camera.height, camera.width, -1)
