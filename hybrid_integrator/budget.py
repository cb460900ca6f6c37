"""The frame-time budget: predicting what tracing costs, and cutting the work to fit (paper §4).

**Cost model.** The time to trace a batch of pixels is modelled as
``t = margin · (t0 + Σ_kind rate_kind · rays_kind)``: a fixed launch cost plus a throughput per
ray kind (shadow, reflection, refraction, indirect). It is calibrated online: every traced batch
adds (rays counted per kind, milliseconds measured with the backend synchronized) to a window of
the last ``window`` observations, which smooths it across frames, and the model is refitted by
non-negative least squares (``scipy.optimize.nnls``). Successive batches trace similar mixes of
rays, so the per-kind rates are nearly collinear; each is therefore pulled towards the pooled rate
(one rate for every ray, fitted first) with the weight of one observation, and only moves away from
it as far as the data show a difference. A prediction is made before tracing, from the rays each
object is expected to spawn (learnt per object, ``FrameState.rays_per_pixel``), and neither those
nor the time per ray are exact (paths vary in length, the machine is shared), so the ``margin`` is
the 90th percentile, over the window, of measured time / the fit applied to the rays that were
*expected*: the prediction is one that 90 % of recent batches stayed under, both errors included. A frame that traces
nothing while candidates are visible forgets the window's slowest observation relative to the fit
if it is an outlier, so that one stall cannot keep the model too pessimistic to ever trace again;
a budget below the fixed cost of a launch consistently measured traces nothing.

**Batches.** The selected objects are traced in relevance order, in as few batches as the budget
allows: one trace call traces objects with different ray kinds together (``trace.py``: each pixel
spawns the kinds its object deserves), so a batch is just a slice of the relevance order, and each
costs one launch. The budget is split into up to ``MAX_BATCHES`` batches only while their launch
costs stay under a quarter of it: more batches let the frame stop earlier when the machine is
slower than predicted, but each costs a launch. Before each batch the predicted time is checked
against the time left, and tracing stops at the first batch that would overrun. Whatever is not
traced shows the raster layer, so the frame is always complete.
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import nnls

from .heuristic import KINDS, ObjectRelevance
from .selection_graph import Node, select


@dataclass
class CostModel:
    """Milliseconds per traced batch as ``t0 + Σ rate_kind · rays_kind`` (see module docstring)."""

    rates: dict[str, float] = field(default_factory=lambda: dict.fromkeys(KINDS, 1e-4))  # ms per ray
    launch_ms: float = 1.0
    window: int = 48
    margin: float = 1.0
    history: deque = field(default_factory=deque)

    @property
    def calibrated(self) -> bool:
        return len(self.history) >= 3

    def _fitted(self, rays: dict[str, float]) -> float:
        return self.launch_ms + sum(self.rates[k] * v for k, v in rays.items())

    def predict(self, rays: dict[str, float]) -> float:
        """Predicted milliseconds of one batch tracing ``rays``."""
        return self.margin * self._fitted(rays)

    def extra(self, rays: dict[str, float]) -> float:
        """Predicted milliseconds ``rays`` add to a batch (without its launch cost)."""
        return self.predict(rays) - self.launch()

    def launch(self) -> float:
        """Predicted fixed cost of one batch."""
        return self.margin * self.launch_ms

    def observe(self, rays: dict[str, float], measured_ms: float, expected: dict[str, float] | None = None) -> None:
        """Add a traced batch: the ``rays`` it traced, its time, and the rays it was ``expected``
        to trace when planned (default: ``rays``)."""
        expected = rays if expected is None else expected
        self.history.append(([float(rays.get(k, 0.0)) for k in KINDS], float(measured_ms),
                             [float(expected.get(k, 0.0)) for k in KINDS]))
        while len(self.history) > self.window:
            self.history.popleft()
        self._fit()

    def forget_slowest(self) -> None:
        """Drop the observation that most exceeds the fit, if it is an outlier (over 1.5 times the
        median measured/fitted ratio), and refit (see module docstring)."""
        if len(self.history) > 3:  # keep three: the model stays calibrated
            ratios = np.array([t / max(self._fitted(dict(zip(KINDS, row))), 1e-9) for row, t, _ in self.history])
            if ratios.max() > 1.5 * np.median(ratios):
                del self.history[int(np.argmax(ratios))]
                self._fit()

    def _fit(self) -> None:
        rays = np.array([row for row, _, _ in self.history])
        ms = np.array([t for _, t, _ in self.history])
        if len(ms) < 2:  # one observation: scale the prior to it
            scale = ms[0] / max(self._fitted(dict(zip(KINDS, rays[0]))), 1e-9)
            self.rates = {k: v * scale for k, v in self.rates.items()}
            self.launch_ms *= scale
            return
        ones = np.ones((len(ms), 1))
        (pooled, launch), _ = nnls(np.hstack([rays.sum(axis=1, keepdims=True), ones]), ms)
        seen = np.nonzero(rays.sum(axis=0) > 0)[0]
        # per-kind rates, each pulled towards the pooled one, as strongly as one observation over
        # the window's length: firmly while there are few observations, hardly once it is full
        weight = np.nanmedian(np.where(rays[:, seen] > 0, rays[:, seen], np.nan), axis=0) / len(ms)
        prior = np.hstack([np.diag(weight), np.zeros((len(seen), 1))])
        solution, _ = nnls(np.vstack([np.hstack([rays[:, seen], ones]), prior]), np.r_[ms, weight * pooled])
        self.rates = dict.fromkeys(KINDS, pooled) | {KINDS[c]: float(x) for c, x in zip(seen, solution[:-1])}
        self.launch_ms = float(solution[-1])
        fitted = np.array([self._fitted(dict(zip(KINDS, row))) for _, _, row in self.history])
        self.margin = float(np.clip(np.quantile(ms / np.maximum(fitted, 1e-9), 0.9), 1.0, 4.0))


@dataclass
class FrameState:
    """What a frame hands to the next (§4.3): the objects selected (S of eq. 3), the cost model and
    the learnt rays per pixel of each object."""

    selected: set[int] = field(default_factory=set)
    cost_model: CostModel = field(default_factory=CostModel)
    rays_per_pixel: dict[int, dict[str, float]] = field(default_factory=dict)
    #: time of the ray-tracing stage outside its batches (set-up, accumulation), smoothed
    overhead_ms: float = 0.0

    def learn_overhead(self, stage_ms: float, batches_ms: float, smoothing: float = 0.5) -> None:
        self.overhead_ms = smoothing * self.overhead_ms + (1 - smoothing) * max(stage_ms - batches_ms, 0.0)

    def learn_rays(self, index: int, pixels: int, rays: dict[str, int], smoothing: float = 0.5) -> None:
        if pixels <= 0:
            return
        old = self.rays_per_pixel.get(index, {})
        self.rays_per_pixel[index] = {k: smoothing * old[k] + (1 - smoothing) * v / pixels if k in old else v / pixels
                                      for k, v in rays.items()}


MAX_BATCHES = 4


@dataclass
class Batch:
    """Objects traced together: one ``trace_effects`` call."""

    objects: list[int]
    mask: np.ndarray  # bool per scene shape: pixels of these objects are traced
    rays: dict[str, float]  # predicted rays per kind
    pixels: dict[int, int]  # visible pixels per object


@dataclass
class FramePlan:
    """The selection of one frame: what is traced, in which batches, against which budget."""

    objects: list[ObjectRelevance]  # every visible candidate, most relevant first
    batches: list[Batch]
    pass_budget_ms: float  # the trace time allowed per sample pass (inf: unlimited)

    def cut(self, first_dropped: int) -> None:
        """Drop the batches from ``first_dropped`` on: they would overrun the budget."""
        del self.batches[first_dropped:]

    @property
    def traced(self) -> set[int]:
        return {k for b in self.batches for k in b.objects}


def _batch(objects: list[ObjectRelevance], n_shapes: int) -> Batch:
    mask = np.zeros(n_shapes, dtype=bool)
    mask[[o.index for o in objects]] = True
    rays: dict[str, float] = {}
    for o in objects:
        for kind, v in o.rays.items():
            rays[kind] = rays.get(kind, 0.0) + v
    return Batch(objects=[o.index for o in objects], mask=mask, rays=rays, pixels={o.index: o.pixels for o in objects})


def plan_frame(objects: list[ObjectRelevance], n_shapes: int, method: str, budget_ms: float, spp: int,
               model: CostModel, pointers: int = 4, overhead_ms: float = 0.0) -> FramePlan:
    """Select the objects to trace (``selection_graph.select``) and slice them into batches.

    Unlimited budget: every visible candidate, in one batch. With a budget: the selector picks
    within the per-pass budget less the stage's own overhead and the launch cost of the batches,
    except while the cost model is not yet calibrated, when the 1, 2, then 4 most relevant objects
    are traced, whatever the budget (probes that measure the machine). The picked objects are sliced, in relevance order, into
    ``n`` batches of about equal predicted cost (module docstring)."""
    order = sorted(objects, key=lambda o: -o.relevance)
    if budget_ms <= 0:
        return FramePlan(order, [_batch(order, n_shapes)] if order else [], float("inf"))
    pass_budget = budget_ms / max(spp, 1) - overhead_ms  # what the batches themselves may take
    if not model.calibrated:  # probes of 1, 2, 4 objects: different ray counts separate t0 from the rates
        probe = order[:2 ** len(model.history)]
        return FramePlan(order, [_batch(probe, n_shapes)] if probe else [], pass_budget)
    launch = model.launch()
    n = int(np.clip(0.25 * pass_budget // max(launch, 1e-9), 1, MAX_BATCHES))
    room = pass_budget - n * launch
    nodes = [Node(o.index, model.extra(o.rays), o.relevance) for o in order]
    picked = {node.key for node in select(method, nodes, room, pointers)} if room > 0 else set()
    return FramePlan(order, _slices([o for o in order if o.index in picked], n, n_shapes, model), pass_budget)


def _slices(order: list[ObjectRelevance], n: int, n_shapes: int, model: CostModel) -> list[Batch]:
    """``order`` cut into at most ``n`` consecutive batches of about equal predicted cost."""
    if not order:
        return []
    cost = np.cumsum([model.extra(o.rays) for o in order])
    edges = np.searchsorted(cost, cost[-1] * np.arange(1, n) / n, side="right")
    bounds = [0, *sorted(set(int(e) for e in edges if 0 < e < len(order))), len(order)]
    return [_batch(order[a:b], n_shapes) for a, b in zip(bounds[:-1], bounds[1:])]
