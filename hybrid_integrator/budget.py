"""The frame-time budget: predicting what tracing costs, and cutting the work to fit (paper §4).

**Cost model.** The time to trace the selected pixels of a pass is modelled as
``t = margin · (t0 + Σ_kind rate_kind · rays_kind)``: a fixed launch cost plus a throughput per
ray kind (shadow, reflection, refraction, indirect). It is calibrated online: every traced pass
adds (rays counted per kind, the trace stage's device time, measured with CUDA events or the LLVM
backend's clock: ``kernel_history``) to a window of
the last ``window`` observations, which smooths it across frames, and the model is refitted by
non-negative least squares (``scipy.optimize.nnls``) before its next prediction (a frame learns its
trace's time after its synchronization; the refit waits for the next plan, which is made while the
GPU traces or denoises the next frame). Successive passes trace similar mixes of
rays, so the per-kind rates are nearly collinear; each is therefore pulled towards the pooled rate
(one rate for every ray, fitted first) with the weight of one observation, and only moves away from
it as far as the data show a difference. A prediction is made before tracing, from the rays each
object is expected to spawn (learnt per object, ``FrameState.rays_per_pixel``), and neither those
nor the time per ray are exact (paths vary in length, the machine is shared), so the ``margin`` is
the 95th percentile (``quantile``), over the window, of measured time / the fit applied to the rays
that were *expected*: the prediction is one that 95 % of recent passes stayed under, both errors
included. (A 90th percentile over a window of 48 left 87–89 % of the GPU frames within budget +
10 %: the quantile of a short window is itself uncertain, so the target needs a margin above it.) A frame that traces
nothing while candidates are visible still runs its trace stage: it is observed as a pass of zero
rays, the fixed part t0 measured alone (probes whose times hardly grow with their rays, on a busy
machine, otherwise extrapolate a t0 above a small budget, and nothing is ever traced again; a
window of such passes alone refits t0 and keeps the rates learnt before them); it
also forgets the window's slowest observation relative to the fit if it is an outlier, so that one
stall cannot keep the model too pessimistic. A budget below the fixed cost of a launch
consistently measured traces nothing.

**One trace call per pass.** The selected objects are traced together: one trace call traces
objects with different ray kinds (``trace.py``: each pixel spawns the kinds its object deserves),
and the selection is data (an effect set per object) of the frame's frozen device pass, so the
frame needs no host round trip between selecting and tracing. It is planned from the objects'
coverage of the *previous* frame (§4.3's frame-to-frame coherence; the first frame of a sequence
measures its coverage first). Whatever is not traced shows the raster layer, so the frame is always
complete.
"""
from __future__ import annotations

import statistics
from collections import deque
from fractions import Fraction
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import nnls

from .heuristic import KINDS, Candidates, ObjectRelevance
from .selection_graph import Node, select, select_rows


@dataclass
class CostModel:
    """Milliseconds per traced pass as ``t0 + Σ rate_kind · rays_kind`` (see module docstring)."""

    rates: dict[str, float] = field(default_factory=lambda: dict.fromkeys(KINDS, 1e-4))  # ms per ray
    launch_ms: float = 1.0
    window: int = 48
    quantile: float = 0.95  # of measured / predicted time: the margin (module docstring)
    margin: float = 1.0
    history: deque = field(default_factory=deque)
    stale: bool = False  # observed since the last fit (``observe(fit=False)``): refitted before the next prediction

    @property
    def calibrated(self) -> bool:
        return len(self.history) >= 3

    def current(self) -> "CostModel":
        """The model fitted to every observation (refitted now if one was added with
        ``fit=False``)."""
        if self.stale:
            self.stale = False
            self._fit()
        return self

    def _fitted(self, rays: dict[str, float]) -> float:
        return self.launch_ms + sum(self.rates[k] * v for k, v in rays.items())

    def _rate_vector(self) -> np.ndarray:
        """The rates in KINDS order, for rows of rays by kind."""
        return np.array([self.rates[k] for k in KINDS])

    def predict(self, rays: dict[str, float]) -> float:
        """Predicted milliseconds of a trace call tracing ``rays``."""
        return self.current().margin * self._fitted(rays)

    def extra(self, rays: dict[str, float]) -> float:
        """Predicted milliseconds ``rays`` add to a trace call (without its launch cost)."""
        return self.predict(rays) - self.launch()

    def extra_rows(self, rays: np.ndarray) -> np.ndarray:
        """:meth:`extra` of each row of ``rays`` (rays by kind, KINDS order), at once."""
        return self.current().margin * (rays @ self._rate_vector())

    def launch(self) -> float:
        """Predicted fixed cost of a trace call."""
        return self.current().margin * self.launch_ms

    def observe(self, rays: dict[str, float], measured_ms: float, expected: dict[str, float] | None = None,
                fit: bool = True) -> None:
        """Add a traced pass: the ``rays`` it traced, its time, and the rays it was ``expected``
        to trace when planned (default: ``rays``). ``fit=False`` leaves the refit to the next
        prediction (:meth:`current`): a frame learns its trace's time after its synchronization,
        and its next plan is made where the host waits for the GPU anyway."""
        expected = rays if expected is None else expected
        self.history.append(([float(rays.get(k, 0.0)) for k in KINDS], float(measured_ms),
                             [float(expected.get(k, 0.0)) for k in KINDS]))
        while len(self.history) > self.window:
            self.history.popleft()
        self.stale = True
        if fit:
            self.current()

    def forget_slowest(self) -> None:
        """Drop the observation that most exceeds the fit, if it is an outlier (over 1.5 times the
        median measured/fitted ratio), and refit (see module docstring)."""
        self.current()
        if len(self.history) > 3:  # keep three: the model stays calibrated
            ratios = np.array([t / max(self._fitted(dict(zip(KINDS, row))), 1e-9) for row, t, _ in self.history])
            if ratios.max() > 1.5 * statistics.median(ratios.tolist()):
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
        seen = np.nonzero(rays.sum(axis=0) > 0)[0]
        if len(seen):
            self._fit_rates(rays, ms, seen)
        else:  # the window holds traces of nothing alone: they measure t0; the rates stay as learnt
            self.launch_ms = float(ms.mean())
        expected = np.array([row for _, _, row in self.history])
        fitted = self.launch_ms + (expected * self._rate_vector()).sum(axis=1)
        self.margin = float(np.clip(_quantile((ms / np.maximum(fitted, 1e-9)).tolist(), self.quantile), 1.0, 4.0))

    def _fit_rates(self, rays: np.ndarray, ms: np.ndarray, seen: np.ndarray) -> None:
        """t0 and the rates of the kinds ``seen`` in the window (the others: the pooled rate)."""
        ones = np.ones((len(ms), 1))
        (pooled, launch), _ = nnls(np.hstack([rays.sum(axis=1, keepdims=True), ones]), ms)
        # per-kind rates, each pulled towards the pooled one, as strongly as one observation over
        # the window's length: firmly while there are few observations, hardly once it is full
        # (the median of each kind's traced passes; the statistics module's median and quantile,
        # cheaper than numpy's on 48 values: the fit runs once a frame, on the host while the GPU
        # traces; scripts/cost_model_fit.py times it)
        weight = np.array([statistics.median(column[column > 0].tolist()) for column in rays[:, seen].T]) / len(ms)
        prior = np.hstack([np.diag(weight), np.zeros((len(seen), 1))])
        solution, _ = nnls(np.vstack([np.hstack([rays[:, seen], ones]), prior]), np.r_[ms, weight * pooled])
        self.rates = dict.fromkeys(KINDS, pooled) | {KINDS[c]: float(x) for c, x in zip(seen, solution[:-1])}
        self.launch_ms = float(solution[-1])


def _quantile(values: list[float], q: float) -> float:
    """The ``q`` quantile of ``values``, interpolated linearly between order statistics (as
    ``numpy.quantile``'s default), through ``statistics.quantiles`` (``q`` in hundredths), with
    as few cut points as ``q`` needs (0.95: 19 cuts, not 99; a third of the time)."""
    if len(values) < 2:
        return values[0]
    q = Fraction(min(max(round(q * 100), 1), 99), 100)
    return statistics.quantiles(values, n=q.denominator, method="inclusive")[q.numerator - 1]


def grown_table(table: np.ndarray, rows: int) -> np.ndarray:
    """``table`` with at least ``rows`` rows, the new ones NaN (never learnt)."""
    if len(table) >= rows:
        return table
    grown = np.full((rows,) + table.shape[1:], np.nan)
    grown[:len(table)] = table
    return grown


def blend_rows(table: np.ndarray, index: np.ndarray, value: np.ndarray, smoothing: float) -> np.ndarray:
    """Blend ``value`` into the rows ``index`` of ``table`` (a first value is taken as it is)."""
    table = grown_table(table, int(index.max()) + 1 if len(index) else 0)
    old = table[index]
    table[index] = np.where(np.isfinite(old), smoothing * old + (1 - smoothing) * value, value)
    return table


@dataclass
class FrameState:
    """What a frame hands to the next (§4.3): the objects selected (S of eq. 3), the cost model and
    what was learnt per object where it was traced, as arrays indexed by object (NaN: never)."""

    selected: set[int] = field(default_factory=set)
    cost_model: CostModel = field(default_factory=CostModel)
    #: per row (``heuristic.Candidates.keys``: an object, or its shadow tier), the secondary rays
    #: per traced pixel by kind (rows × KINDS)
    rays_per_pixel: np.ndarray = field(default_factory=lambda: np.empty((0, len(KINDS))))
    #: the objects' coverage in the last frame (``heuristic.Coverage``): what the next frame plans from
    coverage: object | None = None
    #: per object, how its pixels grew from the frame before the last to the last
    #: (``heuristic.pixel_growth``; None: no such pair of frames)
    growth: np.ndarray | None = None
    #: the accumulated frames (``temporal.History``), with ``temporal`` on
    history: object | None = None
    #: per row, the mean square of the error tracing removed, per traced pixel (heuristic.py,
    #: relevance="error"); an estimate that may come out below zero where that error is ~0
    error_squared: np.ndarray = field(default_factory=lambda: np.empty(0))
    #: per object, the learnt ambient irradiance E (lighting.learn_ambient), RGB (objects × 3)
    ambient: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    #: per object, the learnt indirect irradiance that its shadow tier adds (lighting.py), RGB
    indirect: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    #: the next frame's plan, made ahead in this one (``pipeline.HybridRenderer._plan_ahead``, ``_account``),
    #: as (what it was made for: the frame's set-up key, spp and number, ``frames``; the ``FramePlan``)
    next_plan: tuple | None = None
    #: the frames that have learnt from their counts into this state
    frames: int = 0
    #: the last few frames' wall times (ms; :meth:`watch`)
    totals: deque = field(default_factory=lambda: deque(maxlen=8))
    #: the last frame took longer than the ones before it by over half its budget: the next frame
    #: times its trace whatever ``timing_interval`` says (``pipeline.HybridSettings.times_frame``)
    jumped: bool = False

    def watch(self, total_ms: float, budget_ms: float, timed: bool) -> None:
        """A budgeted frame's wall time against the untimed frames before it. A frame that does
        not time its trace cannot tell that it overran its budget, and its cost model learns
        nothing from it; a plan that overruns, made by a model that the next timed frame would
        correct, could repeat until then. Such a frame is seen from outside, though: it takes
        longer than the frames before it. So an untimed frame more than half its budget longer
        than the median of the last few untimed ones marks the next frame to be timed
        (``jumped``); the host's own changes of speed (stop 58) mark some more, which costs those
        frames their history's time, nothing else. A timed frame, longer by its history's cost,
        is compared with nothing and clears the mark."""
        if timed:
            self.jumped = False
            return
        self.jumped = len(self.totals) >= 3 and total_ms > statistics.median(self.totals) + 0.5 * budget_ms
        self.totals.append(total_ms)

    @property
    def error_per_pixel(self) -> np.ndarray:
        """Per row, E_k of heuristic.py: the root of the learnt mean square error (NaN: never
        traced)."""
        return np.sqrt(np.maximum(self.error_squared, 0.0))

    def learn_rays(self, keys: np.ndarray, pixels: np.ndarray, rays: np.ndarray, smoothing: float = 0.5) -> None:
        """One frame's traced rows ``keys`` (``heuristic.Candidates.keys``): their traced pixels and
        rays by kind (KINDS order), averaged into what was learnt before (``smoothing``: the weight
        of the past)."""
        seen = pixels > 0
        if seen.any():
            self.rays_per_pixel = blend_rows(self.rays_per_pixel, keys[seen],
                                             rays[seen] / pixels[seen, None].astype(np.float64), smoothing)

    def learn_errors(self, keys: np.ndarray, error_sums: np.ndarray, pairs: np.ndarray, smoothing: float = 0.5) -> None:
        """The rows ``keys``' sums of error products over ``pairs`` adjacent traced pixels
        (``heuristic.add_error``; a mean square error per row), averaged into what was learnt."""
        paired = pairs > 0  # an object one pixel wide has no pair: nothing learnt this frame
        if paired.any():
            self.error_squared = blend_rows(self.error_squared, keys[paired], error_sums[paired] / pairs[paired], smoothing)


@dataclass
class FramePlan:
    """The selection of one frame: what is traced, against which budget."""

    candidates: Candidates  # every visible candidate (heuristic.candidates)
    picked: np.ndarray  # rows of ``candidates`` traced (their pixels, in one trace call per pass)
    rays: dict[str, float]  # the secondary rays per kind they are expected to spawn, per pass
    pass_budget_ms: float  # the trace time allowed per sample pass (inf: unlimited)
    #: a probe of the uncalibrated model (``plan_frame``): its ``rays`` come from the prior's rays
    #: per pixel, no prediction, and it is observed as expecting what it traced
    probe: bool = False
    #: host ms its making took (eq. 1–3 and the selector), wherever the renderer made it: in the
    #: frame's selection phase, or ahead, in the frame before (``pipeline.HybridRenderer._plan``)
    host_ms: float = 0.0
    #: one more object traced in part with what the budget left: (its row of ``candidates``, the
    #: quarters of its pixels traced, 1–3; ``selection.QUAD_KEPT``), or None (:func:`_part`)
    partial: tuple[int, int] | None = None

    @property
    def traced(self) -> set[int]:
        """The object indices traced (in part too)."""
        rows = self.candidates.index[self.picked].tolist()
        return set(rows + ([int(self.candidates.index[self.partial[0]])] if self.partial else []))


def _plan(c: Candidates, picked: np.ndarray, budget: float, probe: bool = False,
          partial: tuple[int, int] | None = None) -> FramePlan:
    picked = np.asarray(picked, dtype=np.int64)
    # an object picked whole and by its shadow tier is traced whole: the tier's rays are part of it
    whole = np.zeros(int(c.index.max()) + 1 if len(c) else 0, dtype=bool)
    whole[c.index[picked][~c.tier[picked]]] = True
    picked = picked[~(c.tier[picked] & whole[c.index[picked]])]
    rays = c.rays_of(picked)
    if partial is not None:  # its share of the object's rays
        row, quarters = partial
        for kind, v in zip(KINDS, c.rays[row] * quarters / 4):
            if v > 0:
                rays[kind] = rays.get(kind, 0.0) + float(v)
    return FramePlan(c, picked, rays, budget, probe, partial=partial)


def _part(c: Candidates, picked: np.ndarray, cost: np.ndarray, room: float) -> tuple[int, int] | None:
    """What the budget left after the selection buys (``selection.py``, "Part of an object"): of
    the objects with no row picked, the one whose affordable part (1, 2 or 3 quarters of its
    pixels, each at a quarter of its whole row's ``cost``) is worth the most relevance (its
    relevance × the part); None where no quarter of any fits. Returns (its row, quarters)."""
    picked = np.asarray(picked, dtype=np.int64)
    left = room - float(cost[picked].sum())
    taken = np.zeros(int(c.index.max()) + 1, dtype=bool)
    taken[c.index[picked]] = True
    rows = np.nonzero(~c.tier & ~taken[c.index] & (cost > 0))[0]
    if left <= 0 or not len(rows):
        return None
    quarters = np.minimum(np.floor(4.0 * left / cost[rows]), 3).astype(np.int64)
    worth = c.relevance[rows] * quarters
    if not (quarters >= 1).any() or worth.max() <= 0:
        return None
    best = int(np.argmax(worth))
    return int(rows[best]), int(quarters[best])


def plan_frame(objects, method: str, budget_ms: float, spp: int, model: CostModel, pointers: int = 4,
               partial: bool = False) -> FramePlan:
    """Select the objects to trace among ``objects`` (``heuristic.candidates``, or a list of
    ``ObjectRelevance``).

    Unlimited budget: every visible candidate. With a budget: the selector picks within the
    per-pass budget less the launch cost of the trace call, except while the cost model is not
    yet calibrated, when the most relevant object, the next two, then the four most relevant are
    traced, whatever the budget (probes that measure the machine, :func:`_probe`; whole objects,
    not shadow tiers). ``nested`` and ``greedy`` run on the arrays; ``graph`` and ``exact``
    (yardsticks) on one node per candidate (``selection_graph``). An object's whole row and its
    shadow tier are two options of one object: it is traced, and charged, once
    (``selection_graph``'s options of one object). With ``partial``, the budget the selection
    leaves buys a part of one more object (:func:`_part`)."""
    c = objects if isinstance(objects, Candidates) else _as_candidates(objects)
    if budget_ms <= 0:
        return _plan(c, np.arange(len(c)), float("inf"))
    pass_budget = budget_ms / max(spp, 1)
    if not model.calibrated:
        whole = np.nonzero(~c.tier)[0]
        return _plan(c, _probe(whole[np.argsort(-c.relevance[whole], kind="stable")], len(model.history)), pass_budget,
                     probe=True)
    room = pass_budget - model.launch()
    if room <= 0 or not len(c):
        return _plan(c, [], pass_budget)
    cost = model.extra_rows(c.rays)
    if method in ("nested", "greedy"):  # an object's whole row upgrades its shadow tier (selection_graph.py)
        picked = select_rows(method, cost, c.relevance, room, _tier_of_whole(c))
    else:
        nodes = [Node(int(i), float(cost[i]), float(c.relevance[i]), group=int(c.index[i])) for i in range(len(c))]
        picked = [node.key for node in select(method, nodes, room, pointers)]
    return _plan(c, picked, pass_budget, partial=_part(c, picked, cost, room) if partial else None)


#: the uncalibrated model's three probes, as slices of the whole rows ranked by relevance
#: (:func:`_probe`): the most relevant, the next two, the first four
PROBES = (slice(0, 1), slice(1, 3), slice(0, 4))


def _probe(ranked: np.ndarray, k: int) -> np.ndarray:
    """The rows the ``k``-th probe traces (``PROBES``; a lone object: it, each time). Their ray
    counts differ, which separates t0 from the rates, and no two probes trace one mix where two
    objects are visible (each alone, then both). A trace is not additive in its objects: one
    kernel runs every path to its end, so an object's long paths overlap the others' work, and
    probes of the 1, 2 and 4 most relevant never traced the second without the first (stop 72:
    the glass Armadillo alone planned at 2.57 ms, 4.21 measured on an H100; stop 73)."""
    return ranked[PROBES[k] if len(ranked) > 1 else PROBES[0]]


def _tier_of_whole(c: Candidates) -> np.ndarray:
    """Per row, the row of its object's shadow tier where the row is the object whole (else -1)."""
    base = np.full(len(c), -1, dtype=np.int64)
    tiers = np.nonzero(c.tier)[0]
    if len(tiers):
        row = np.full(int(c.index.max()) + 1, -1, dtype=np.int64)
        row[c.index[~c.tier]] = np.nonzero(~c.tier)[0]
        base[row[c.index[tiers]]] = tiers
    return base


def _as_candidates(objects: list[ObjectRelevance]) -> Candidates:
    rays = np.array([[o.rays.get(k, 0.0) for k in KINDS] for o in objects]).reshape(-1, len(KINDS))
    arrays = {name: np.array([getattr(o, name) for o in objects]) for name in ("index", "pixels", "visibility", "relevance")}
    return Candidates(rays=rays, terms=None, **arrays)
