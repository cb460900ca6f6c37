"""One frame of the hybrid pipeline (paper §6, Fig. 4): raster → lighting → selection → ray
tracing → composition, repeated once per sample at a jittered sub-pixel offset and splatted into
the film.

Each sample pass rasterizes the whole frame at one sub-pixel offset (a scrambled Halton sequence,
one point per pass), so all pixels of a pass share the offset, and ``spp`` passes give
anti-aliasing. Every pass is splatted with the film's reconstruction filter at
``pixel + offset``, exactly where Mitsuba would splat a camera ray through that film position, so
the image converges to what Mitsuba computes. ``primary="raytrace"`` replaces the raster pass by
Mitsuba's camera rays and changes nothing else: the paper's pure ray-tracing baseline (§8).
"""
from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field

import drjit as dr
import mitsuba as mi
import numpy as np
from scipy.stats import qmc

from .compose import compose
from .errors import HybridError
from .primary import PrimaryHits, camera_rays, primary_hits, shape_indices
from .raster.camera import RasterCamera, resolve_sensor
from .raster.gbuffer import aov_values, check_aovs, to_numpy
from .raster.lighting import INPUTS, DeferredLighting
from .raster.visibility import Rasterizer
from .budget import FramePlan, FrameState, plan_frame
from .heuristic import candidate_kinds, coverage, object_relevance
from .selection import DEFAULT_EFFECTS, parse_effects, select_pixels
from .selection_graph import SELECTORS
from .trace import RAY_KINDS, TraceCounts, trace_effects

PRIMARY_SOURCES = ("raster", "raytrace")
STAGES = ("raster", "lighting", "select", "trace", "compose", "total")


@dataclass(frozen=True)
class HybridSettings:
    """The ``hybrid`` integrator's properties (see ``plugins/hybrid.py`` for their meaning)."""

    max_depth: int = -1
    rr_depth: int = 5
    hide_emitters: bool = False
    primary: str = "raster"
    effects: tuple[str, ...] = DEFAULT_EFFECTS
    candidates: object = None  # None: every shape; "id[:kind|kind], ..." or {id: kinds} (heuristic.py)
    blend: float = 1.0
    budget_ms: float = 0.0
    selection: str = "greedy"
    importance: float = 0.0
    freeze: bool = False

    def __post_init__(self):
        if self.primary not in PRIMARY_SOURCES:
            raise HybridError(f"primary='{self.primary}' is not one of {list(PRIMARY_SOURCES)}")
        object.__setattr__(self, "effects", parse_effects(self.effects))
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


@dataclass
class FrameStats:
    """What one frame cost and did. Times are milliseconds with the backend synchronized,
    summed over the frame's sample passes."""

    width: int
    height: int
    spp: int
    primary: str
    times_ms: dict[str, float] = field(default_factory=lambda: dict.fromkeys(STAGES, 0.0))
    rays: dict[str, int] = field(default_factory=lambda: dict.fromkeys(("camera",) + RAY_KINDS, 0))
    pixels_traced: int = 0  # traced pixel-samples, summed over passes
    proxy_refinements: int = 0  # pixel-samples of analytic-shape proxies refined by a ray
    edge_refinements: int = 0  # silhouette pixel-samples whose raster hit was re-traced (primary.py)
    lights_left_out: tuple[str, ...] = ()  # emitters the raster layer cannot show
    readback: str = ""  # how the raster targets reached Dr.Jit: cuda-gl-interop, or host (reason)
    budget_ms: float = 0.0  # 0: unlimited
    predicted_trace_ms: float = 0.0  # what the cost model expected for the batches traced
    predicted_rays: int = 0  # the secondary rays it expected them to trace (``secondary_rays``: traced)
    candidates_visible: int = 0
    selected: tuple[str, ...] = ()  # objects traced this frame, most relevant first
    relevance_captured: float = 1.0  # Σ R of the traced objects / Σ R of the visible candidates
    selection_changes: int = 0  # objects traced now but not in the previous frame, or the reverse
    batches: int = 0

    @property
    def budget_met(self) -> bool:
        return self.budget_ms <= 0 or self.times_ms["trace"] <= self.budget_ms

    @property
    def secondary_rays(self) -> int:
        return sum(self.rays[k] for k in RAY_KINDS)

    def as_dict(self) -> dict:
        return {**asdict(self), "secondary_rays": self.secondary_rays, "budget_met": self.budget_met}


@dataclass
class HybridResult:
    """A rendered frame: ``image`` as ``mi.render`` returns it, the layers (H×W numpy, filtered
    like the image) and the frame's statistics."""

    image: mi.TensorXf
    layers: dict[str, np.ndarray]
    stats: FrameStats


def subpixel_offsets(spp: int, seed: int) -> np.ndarray:
    """``spp`` sub-pixel positions in [0,1)²: a scrambled Halton sequence (low discrepancy)."""
    return qmc.Halton(d=2, scramble=True, seed=seed).random(spp)


class _Clock:
    """Accumulates synchronized stage times into ``FrameStats.times_ms``."""

    def __init__(self, times: dict[str, float]):
        self.times = times
        self.last = time.perf_counter()

    def lap(self, stage: str, *values) -> None:
        if values:
            dr.eval(*values)
        dr.sync_thread()
        now = time.perf_counter()
        self.times[stage] += (now - self.last) * 1e3
        self.last = now


class HybridRenderer:
    """The GPU-side state of one scene: its rasterizer (geometry uploaded once) and lights."""

    def __init__(self, scene: mi.Scene, rasterizer: Rasterizer):
        self.scene = scene
        self.raster = rasterizer
        self.lighting = DeferredLighting(scene)

    def render(self, settings: HybridSettings, sensor: int | mi.Sensor = 0, spp: int = 0, seed: int = 0,
               aovs=(), state: FrameState | None = None) -> HybridResult:
        """One frame. ``state`` carries the previous frame's selection and the cost model into this
        one (a fresh state: the first frame of a sequence)."""
        scene = self.scene
        sensor = resolve_sensor(scene, sensor)
        camera = RasterCamera.from_sensor(sensor)
        aovs = check_aovs(aovs)
        spp = int(spp) or sensor.sampler().sample_count()
        state = state if state is not None else FrameState()
        kinds = candidate_kinds(settings.candidates, scene)
        # the distinct effect sets the candidates deserve, and each shape's (-1: not a candidate):
        # fixed for the frame, so that one traced kernel serves every selection
        active = [tuple(k for k in ks if k in settings.effects) for ks in kinds]
        configs = tuple(sorted({a for a in active if a}))
        shape_config = np.array([configs.index(a) if a else -1 for a in active], dtype=np.int64)
        names = [shape.id() for shape in scene.shapes()]
        has_emitters = len(scene.emitters()) > 0
        w, h = camera.width, camera.height
        stats = FrameStats(width=w, height=h, spp=spp, primary=settings.primary,
                           lights_left_out=self.lighting.lights.approximated, budget_ms=settings.budget_ms)

        film = sensor.film()
        film.prepare([])
        image_block = film.create_block()
        has_alpha = mi.has_flag(film.flags(), mi.FilmFlags.Alpha)
        layer_block = mi.ImageBlock(film.crop_size(), film.crop_offset(), 8, film.rfilter())
        index = dr.arange(mi.UInt32, w * h)
        pixel = mi.Point2f(mi.Float(index % w), mi.Float(index // w))
        box = film.rfilter().is_box_filter()
        counts = TraceCounts()
        first_targets: dict[str, np.ndarray] = {}
        start = time.perf_counter()
        clock = _Clock(stats.times_ms)

        for sample, offset in enumerate(subpixel_offsets(spp, seed)):
            offset = (float(offset[0]), float(offset[1]))
            # 1. primary visibility: the raster (paper §3.1) or camera rays (the baseline, §8)
            if settings.primary == "raster":
                words, distance = self.raster.device_targets(self.raster.render(camera, offset))
                hits = primary_hits(scene, sensor, camera, words, distance, offset, self.raster.is_proxy)
                stats.readback = self.raster.readback
                stats.proxy_refinements += hits.proxy_refined
                stats.edge_refinements += hits.edge_refined
            else:
                ray = camera_rays(sensor, camera, offset)
                si = scene.ray_intersect(ray)
                valid = si.is_valid()
                hits = PrimaryHits(ray=ray, si=si, shape_index=shape_indices(scene, si.shape, valid), valid=valid)
                stats.rays["camera"] += w * h
            clock.lap("raster", hits.ray, hits.si, hits.shape_index, hits.valid)  # all of it: Dr.Jit is lazy

            # 2. deferred lighting: the raster layer (§3.1, Fig. 1g)
            targets = aov_values(scene, hits, tuple(dict.fromkeys(tuple(INPUTS) + aovs)))
            if settings.hide_emitters:
                targets["emission"] = [dr.zeros(mi.Float, w * h) for _ in range(3)]
            raster = self.lighting.shade(targets, hits.valid, camera.eye)
            if sample == 0 and aovs:
                first_targets = to_numpy({k: targets[k] for k in aovs}, (h, w))
            clock.lap("lighting", raster)

            # 3. selection (§4): planned once per frame, from its first pass's primary hits
            if sample == 0:
                plan = self._plan(hits, camera, kinds, names, settings, state, spp)
            clock.lap("select")

            # 4. ray tracing (§3.2): batch by batch, most relevant first, within the budget
            stage_start = time.perf_counter()
            rt, traced = dr.zeros(mi.Color3f, w * h), dr.zeros(mi.Bool, w * h)
            batches_ms = 0.0
            for i, batch in enumerate(list(plan.batches)):
                predicted = state.cost_model.predict(batch.rays)
                elapsed = (time.perf_counter() - stage_start) * 1e3
                if sample == 0 and i > 0 and elapsed + predicted > plan.pass_budget_ms:
                    # the batches before ran slower than predicted, and this one would overrun:
                    # it and the less relevant ones show the raster layer (the first was planned to fit)
                    plan.cut(i)
                    break
                batch_start = time.perf_counter()  # the whole batch: selecting its pixels, tracing, accumulating
                selection = select_pixels(hits.si, hits.ray, hits.shape_index, hits.valid,
                                          np.where(batch.mask, shape_config, -1), configs, has_emitters)
                batch_rt, batch_counts = trace_effects(scene, hits.ray, hits.si, selection.traced, settings.effects,
                                                       settings.max_depth, settings.rr_depth, settings.hide_emitters,
                                                       seed=(int(seed) << 32) + sample, first_effects=configs,
                                                       first_config=selection.config, freeze=settings.freeze,
                                                       shape_index=hits.shape_index, n_shapes=len(names))
                rt += batch_rt
                traced |= selection.traced
                dr.eval(rt, traced)
                dr.sync_thread()
                batch_ms = (time.perf_counter() - batch_start) * 1e3
                if not batch_counts.recorded:  # a recording's time is a one-off, not the tracing cost
                    state.cost_model.observe(batch_counts.rays, batch_ms, expected=batch.rays)
                for k, n in batch.pixels.items():
                    state.learn_rays(k, n, batch_counts.per_object.get(k, dict.fromkeys(RAY_KINDS, 0)))
                counts.add(batch_counts)
                stats.pixels_traced += selection.count
                stats.predicted_trace_ms += float(predicted)
                stats.predicted_rays += int(sum(batch.rays.values()))
                batches_ms += batch_ms
            clock.lap("trace", rt, traced)
            state.learn_overhead((time.perf_counter() - stage_start) * 1e3, batches_ms)

            # 5. composition (§5), splatted like a camera ray through the same film position
            color = compose(raster, rt, traced, settings.blend)
            alpha = dr.select(hits.valid | (scene.environment() is not None and not settings.hide_emitters), 1.0, 0.0)
            pos = pixel if box else pixel + mi.Vector2f(*(dr.opaque(mi.Float, o) for o in offset))
            image_block.put(pos, [color.x, color.y, color.z] + ([alpha] if has_alpha else []) + [mi.Float(1.0)])
            layer_block.put(pos, [raster.x, raster.y, raster.z, rt.x, rt.y, rt.z, dr.select(traced, 1.0, 0.0), mi.Float(1.0)])
            clock.lap("compose", image_block.tensor(), layer_block.tensor())  # the splats are lazy too

        film.put_block(image_block)
        image = film.develop()
        dr.eval(image)
        dr.sync_thread()
        stats.times_ms["total"] = (time.perf_counter() - start) * 1e3
        stats.rays.update(counts.rays)
        self._record_selection(plan, state, stats, names)
        sums = np.array(layer_block.tensor())
        weight = np.maximum(sums[..., 7:8], 1e-12)
        layers = {"raster": sums[..., 0:3] / weight, "rt": sums[..., 3:6] / weight, "traced": sums[..., 6] / weight[..., 0],
                  **first_targets}
        return HybridResult(image=image, layers=layers, stats=stats)

    def _plan(self, hits: PrimaryHits, camera: RasterCamera, kinds, names, settings: HybridSettings,
              state: FrameState, spp: int) -> FramePlan:
        """Eq. 1–3 from this pass's primary hits, then the selection within the budget."""
        depth = dr.norm(hits.si.p - mi.Point3f(*(float(c) for c in camera.eye)))
        cov = coverage(hits.shape_index, hits.valid, depth, camera.width, camera.height, len(names))
        objects = object_relevance(cov, kinds, names, settings.effects, state.selected, settings.importance,
                                   state.rays_per_pixel)
        return plan_frame(objects, len(names), settings.selection, settings.budget_ms, spp, state.cost_model,
                          overhead_ms=state.overhead_ms)

    @staticmethod
    def _record_selection(plan: FramePlan, state: FrameState, stats: FrameStats, names) -> None:
        traced = plan.traced
        ordered = [o for o in plan.objects if o.index in traced]
        total = sum(o.relevance for o in plan.objects)
        stats.candidates_visible = len(plan.objects)
        stats.selected = tuple(names[o.index] for o in ordered)
        stats.relevance_captured = float(sum(o.relevance for o in ordered) / total) if total > 0 else 1.0
        stats.selection_changes = len(traced ^ state.selected)
        stats.batches = len(plan.batches)
        state.selected = traced
        if plan.objects and not traced and plan.pass_budget_ms < float("inf"):
            state.cost_model.forget_slowest()
