"""The frame-time budget: predicting what tracing costs, and cutting the work to fit (paper §4).

**Cost model.** The time to trace a batch of pixels is modelled as
``t = margin · (t0 + Σ_kind rate_kind · rays_kind)``: a fixed launch cost plus a throughput per
ray kind (shadow, reflection, refraction, indirect). It is calibrated online: every traced batch
adds (rays counted per kind, milliseconds measured with the backend synchronized) to a window of
recent observations, the rates are refitted by non-negative least squares
(``scipy.optimize.nnls``) and blended with the previous fit (``smoothing``), so they follow the
machine and the scene across frames without jumping on one noisy batch. Rays do not explain all
of a batch's time (path lengths vary, a kernel is compiled the first time a set of effects
occurs), so the ``margin`` is the 90th percentile of measured/fitted time over the window: the
prediction is one that 90 % of recent batches stayed under.

**Batches.** The selected objects are traced in relevance order, grouped into batches of objects
that share their ray kinds; before each batch the predicted time is checked against the time left,
and tracing stops at the first batch that would overrun. Whatever is not traced shows the raster
layer, so the frame is always complete.
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
    smoothing: float = 0.5
    margin: float = 1.0
    history: deque = field(default_factory=deque)

    @property
    def calibrated(self) -> bool:
        return len(self.history) >= 2

    def relax(self, factor: float = 0.8) -> None:
        """Lower every prediction a little: after a frame that traced nothing, so that a model made
        pessimistic by one slow batch (a kernel compiled on first use) tries again."""
        self.rates = {k: v * factor for k, v in self.rates.items()}
        self.launch_ms *= factor

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

    def observe(self, rays: dict[str, float], measured_ms: float) -> None:
        self.history.append(([float(rays.get(k, 0.0)) for k in KINDS], float(measured_ms)))
        while len(self.history) > self.window:
            self.history.popleft()
        a = np.array([row + [1.0] for row, _ in self.history])
        b = np.array([t for _, t in self.history])
        seen = a[:, :-1].sum(axis=0) > 0
        if len(self.history) < 2:  # one observation: scale the prior to it
            predicted = self._fitted(rays)
            scale = measured_ms / predicted if predicted > 0 else 1.0
            self.rates = {k: v * scale for k, v in self.rates.items()}
            self.launch_ms *= scale
            return
        columns = np.r_[np.nonzero(seen)[0], len(KINDS)]
        solution, _ = nnls(a[:, columns], b)
        fitted = dict(self.rates)
        for c, x in zip(columns[:-1], solution[:-1]):
            fitted[KINDS[c]] = x
        s = self.smoothing
        self.rates = {k: s * self.rates[k] + (1 - s) * fitted[k] for k in KINDS}
        self.launch_ms = s * self.launch_ms + (1 - s) * solution[-1]
        fitted_ms = np.array([self._fitted(dict(zip(KINDS, row))) for row, _ in self.history])
        self.margin = float(np.clip(np.quantile(b / np.maximum(fitted_ms, 1e-9), 0.9), 1.0, 4.0))


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


@dataclass
class Batch:
    """Objects traced together: one ``trace_effects`` call with one set of effects."""

    objects: list[int]
    effects: tuple[str, ...]
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
    effects = tuple(k for k in KINDS if any(k in o.kinds for o in objects))
    return Batch(objects=[o.index for o in objects], effects=effects, mask=mask, rays=rays,
                 pixels={o.index: o.pixels for o in objects})


def plan_frame(objects: list[ObjectRelevance], n_shapes: int, method: str, budget_ms: float, spp: int,
               model: CostModel, pointers: int = 4, overhead_ms: float = 0.0) -> FramePlan:
    """Select the objects to trace (``selection_graph.select``) and group them into batches.

    Unlimited budget: every visible candidate. With a budget: the selector picks within the
    per-pass budget less the stage's own overhead and the launch cost of the batches, except while the cost model is not yet
    calibrated, when only the most relevant object is traced (a probe that measures the machine).
    The picked objects are grouped, in relevance order, into as few batches as their ray kinds allow
    (each ``trace_effects`` call has a launch cost), and a group is split where it would exceed
    half the budget, so that the cut before an overrunning batch can act."""
    order = sorted(objects, key=lambda o: -o.relevance)
    if budget_ms <= 0:
        return FramePlan(order, _groups(order, n_shapes, float("inf"), model), float("inf"))
    pass_budget = budget_ms / max(spp, 1) - overhead_ms  # what the batches themselves may take
    if not model.calibrated:
        return FramePlan(order, _groups(order[:1], n_shapes, float("inf"), model), pass_budget)
    groups = len({o.batch_key for o in order})
    nodes = [Node(o.index, model.extra(o.rays), o.relevance) for o in order]
    room = max(pass_budget - model.launch() * groups, 0.0)
    picked = {n.key for n in select(method, nodes, room, pointers)}
    return FramePlan(order, _groups([o for o in order if o.index in picked], n_shapes, pass_budget / 2, model), pass_budget)


def _groups(order: list[ObjectRelevance], n_shapes: int, cap_ms: float, model: CostModel) -> list[Batch]:
    """Batches of objects that can share a trace call (``ObjectRelevance.batch_key``), in order of
    their most relevant object, each at most ``cap_ms`` of predicted tracing (beyond the launch
    cost). A shared batch traces the union of its objects' kinds, which for each object adds only
    kinds its material has no lobe for."""
    batches: list[list[ObjectRelevance]] = []
    open_batch: dict[tuple[str, ...], tuple[list[ObjectRelevance], float]] = {}
    for o in order:
        cost = model.extra(o.rays)
        members, total = open_batch.get(o.batch_key, (None, 0.0))
        if members is None or total + cost > cap_ms:
            members, total = [], 0.0
            batches.append(members)
        members.append(o)
        open_batch[o.batch_key] = (members, total + cost)
    return [_batch(members, n_shapes) for members in batches]
