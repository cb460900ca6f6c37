"""The frame-time budget: predicting what tracing costs, and cutting the work to fit (paper §4).

**Cost model.** The time to trace a batch of pixels is modelled as
``t = t0 + Σ_kind rate_kind · rays_kind``: a fixed launch cost plus a throughput per ray kind
(shadow, reflection, refraction, indirect). It is calibrated online: every traced batch adds
(rays counted per kind, milliseconds measured with the backend synchronized) to a window of
recent observations, the rates are refitted by non-negative least squares
(``scipy.optimize.nnls``) and blended with the previous fit (``smoothing``), so they follow the
machine and the scene across frames without jumping on one noisy batch.

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
    history: deque = field(default_factory=deque)

    def predict(self, rays: dict[str, float]) -> float:
        return self.launch_ms + sum(self.rates[k] * v for k, v in rays.items())

    def observe(self, rays: dict[str, float], measured_ms: float) -> None:
        self.history.append(([float(rays.get(k, 0.0)) for k in KINDS], float(measured_ms)))
        while len(self.history) > self.window:
            self.history.popleft()
        a = np.array([row + [1.0] for row, _ in self.history])
        b = np.array([t for _, t in self.history])
        seen = a[:, :-1].sum(axis=0) > 0
        if len(self.history) < 2:  # one observation: scale the prior to it
            predicted = self.predict(rays)
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


@dataclass
class FrameState:
    """What a frame hands to the next (§4.3): the objects selected (S of eq. 3), the cost model and
    the learnt rays per pixel of each object."""

    selected: set[int] = field(default_factory=set)
    cost_model: CostModel = field(default_factory=CostModel)
    rays_per_pixel: dict[int, dict[str, float]] = field(default_factory=dict)

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
    return Batch(objects=[o.index for o in objects], effects=objects[0].kinds, mask=mask, rays=rays,
                 pixels={o.index: o.pixels for o in objects})


def plan_frame(objects: list[ObjectRelevance], n_shapes: int, method: str, budget_ms: float, spp: int,
               model: CostModel, pointers: int = 4) -> FramePlan:
    """Select the objects to trace (``selection_graph.select``) and group them into batches.

    Unlimited budget: every visible candidate, one batch per set of effects. With a budget: the
    selector picks within the per-pass budget (minus the launch cost of the expected batches),
    and the picked objects are grouped, in relevance order, into batches of at most a quarter of
    the budget each, so that the cut before an overrunning batch can act."""
    order = sorted(objects, key=lambda o: -o.relevance)
    if budget_ms <= 0:
        groups: dict[tuple[str, ...], list[ObjectRelevance]] = {}
        for o in order:
            groups.setdefault(o.kinds, []).append(o)
        return FramePlan(order, [_batch(g, n_shapes) for g in groups.values()], float("inf"))
    pass_budget = budget_ms / max(spp, 1)
    nodes = [Node(o.index, model.predict(o.rays) - model.launch_ms, o.relevance) for o in order]
    room = max(pass_budget - model.launch_ms * min(4, len(nodes)), 0.0)
    picked = {n.key for n in select(method, nodes, room, pointers)}
    batches, current, current_ms = [], [], 0.0
    for o in (o for o in order if o.index in picked):
        cost = model.predict(o.rays) - model.launch_ms
        if current and (o.kinds != current[0].kinds or current_ms + cost > pass_budget / 4):
            batches.append(_batch(current, n_shapes))
            current, current_ms = [], 0.0
        current.append(o)
        current_ms += cost
    if current:
        batches.append(_batch(current, n_shapes))
    return FramePlan(order, batches, pass_budget)
