"""The frame-time budget: predicting what tracing costs, and cutting the work to fit (paper §4).

**Cost model.** The time to trace the selected pixels of a pass is modelled as
``t = margin · (t0 + Σ_kind rate_kind · rays_kind)``: a fixed launch cost plus a throughput per
ray kind (shadow, reflection, refraction, indirect). It is calibrated online: every traced pass
adds (rays counted per kind, the trace stage's device time, measured with CUDA events or the LLVM
backend's clock: ``kernel_history``) to a window of
the last ``window`` observations, which smooths it across frames, and the model is refitted by
non-negative least squares (``scipy.optimize.nnls``). Successive passes trace similar mixes of
rays, so the per-kind rates are nearly collinear; each is therefore pulled towards the pooled rate
(one rate for every ray, fitted first) with the weight of one observation, and only moves away from
it as far as the data show a difference. A prediction is made before tracing, from the rays each
object is expected to spawn (learnt per object, ``FrameState.rays_per_pixel``), and neither those
nor the time per ray are exact (paths vary in length, the machine is shared), so the ``margin`` is
the 90th percentile, over the window, of measured time / the fit applied to the rays that were
*expected*: the prediction is one that 90 % of recent passes stayed under, both errors included. A frame that traces
nothing while candidates are visible forgets the window's slowest observation relative to the fit
if it is an outlier, so that one stall cannot keep the model too pessimistic to ever trace again;
a budget below the fixed cost of a launch consistently measured traces nothing.

**One trace call per pass.** The selected objects are traced together: one trace call traces
objects with different ray kinds (``trace.py``: each pixel spawns the kinds its object deserves),
and the selection is data (an effect set per object) of the frame's frozen device pass, so the
frame needs no host round trip between selecting and tracing. It is planned from the objects'
coverage of the *previous* frame (§4.3's frame-to-frame coherence; the first frame of a sequence
measures its coverage first). Whatever is not traced shows the raster layer, so the frame is always
complete.
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
    """Milliseconds per traced pass as ``t0 + Σ rate_kind · rays_kind`` (see module docstring)."""

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
        """Predicted milliseconds of a trace call tracing ``rays``."""
        return self.margin * self._fitted(rays)

    def extra(self, rays: dict[str, float]) -> float:
        """Predicted milliseconds ``rays`` add to a trace call (without its launch cost)."""
        return self.predict(rays) - self.launch()

    def launch(self) -> float:
        """Predicted fixed cost of a trace call."""
        return self.margin * self.launch_ms

    def observe(self, rays: dict[str, float], measured_ms: float, expected: dict[str, float] | None = None) -> None:
        """Add a traced pass: the ``rays`` it traced, its time, and the rays it was ``expected``
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
    #: the objects' coverage in the last frame (``heuristic.Coverage``): what the next frame plans from
    coverage: object | None = None
    #: the accumulated frames (``temporal.History``), with ``temporal`` on
    history: object | None = None

    #: per object, the error per traced pixel that tracing removed (heuristic.py, relevance="error")
    error_per_pixel: dict[int, float] = field(default_factory=dict)
    #: per object, the learnt ambient irradiance E (lighting.learn_ambient), RGB
    ambient: dict[int, np.ndarray] = field(default_factory=dict)

    def learn_error(self, index: int, pixels: int, error_sum: float, smoothing: float = 0.5) -> None:
        if pixels <= 0:
            return
        value = error_sum / pixels
        old = self.error_per_pixel.get(index)
        self.error_per_pixel[index] = value if old is None else smoothing * old + (1 - smoothing) * value

    def learn_rays(self, index: int, pixels: int, rays: dict[str, int], smoothing: float = 0.5) -> None:
        if pixels <= 0:
            return
        old = self.rays_per_pixel.get(index, {})
        self.rays_per_pixel[index] = {k: smoothing * old[k] + (1 - smoothing) * v / pixels if k in old else v / pixels
                                      for k, v in rays.items()}


@dataclass
class FramePlan:
    """The selection of one frame: what is traced, against which budget."""

    objects: list[ObjectRelevance]  # every visible candidate, most relevant first
    traced: set[int]  # the objects traced (their pixels, in one trace call per pass)
    rays: dict[str, float]  # the secondary rays per kind they are expected to spawn, per pass
    pass_budget_ms: float  # the trace time allowed per sample pass (inf: unlimited)


def _plan(order: list[ObjectRelevance], picked: set[int], budget: float) -> FramePlan:
    rays: dict[str, float] = {}
    for o in order:
        if o.index in picked:
            for kind, v in o.rays.items():
                rays[kind] = rays.get(kind, 0.0) + v
    return FramePlan(order, picked, rays, budget)


def plan_frame(objects: list[ObjectRelevance], method: str, budget_ms: float, spp: int, model: CostModel,
               pointers: int = 4) -> FramePlan:
    """Select the objects to trace (``selection_graph.select``).

    Unlimited budget: every visible candidate. With a budget: the selector picks within the
    per-pass budget less the launch cost of the trace call, except while the cost model is not
    yet calibrated, when the 1, 2, then 4 most relevant objects are traced, whatever the budget
    (probes that measure the machine)."""
    order = sorted(objects, key=lambda o: -o.relevance)
    if budget_ms <= 0:
        return _plan(order, {o.index for o in order}, float("inf"))
    pass_budget = budget_ms / max(spp, 1)
    if not model.calibrated:  # probes of 1, 2, 4 objects: different ray counts separate t0 from the rates
        return _plan(order, {o.index for o in order[:2 ** len(model.history)]}, pass_budget)
    room = pass_budget - model.launch()
    nodes = [Node(o.index, model.extra(o.rays), o.relevance) for o in order]
    picked = {node.key for node in select(method, nodes, room, pointers)} if room > 0 else set()
    return _plan(order, picked, pass_budget)
