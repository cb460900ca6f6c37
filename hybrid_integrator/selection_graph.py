"""The selection graph of Sabino et al. §4.2–4.3, and the two selectors it is measured against.

Every candidate object is a node with a cost C (its predicted ray-tracing time) and a relevance R.
Given the time left in the frame, a selector picks which objects to ray trace.

**The selection graph** (§4.2, Fig. 2). Nodes are chained by decreasing cost (each points to the
next cheaper node), and each node also points to up to ``N`` *cheaper, more relevant, unselected*
nodes, ordered by relevance. Selecting (§4.3, Fig. 3): walk the cost chain from its most expensive
node to the first node whose cost fits the time left; the nodes passed over cannot be afforded
this frame and move to the graph under construction for the next frame. From the node reached,
follow relevance pointers while they lead to a more relevant node; the node where that stops is
selected, ray traced, and moved to the next graph; its cost is taken from the time left and the
walk starts again. When nothing fits, every remaining node moves to the next graph.

**Nested** (the default): the longest run of nodes by decreasing R/C that fits (from the first
node that fits alone, where the first does not); from the first node's cost up, a larger budget
only adds nodes. **Greedy**: take nodes by decreasing R/C while they fit, unless the single most
relevant node that fits is worth more. **Exact**: the 0/1 knapsack optimum
(maximum total R with total C within the budget), solved as a mixed-integer linear program by
SciPy's HiGHS (``scipy.optimize.milp``); meant for small N, as a yardstick.

**Options of one object.** An object may be a candidate twice: traced whole, or only by its
shadow tier (``heuristic.py``). The two are options of one object, not two objects: tracing it
whole costs the whole row's time, not that time plus its tier's. Nodes of one ``group`` exclude
each other (``graph``, ``exact``); the ratio-ordered selectors (``nested``, ``greedy``) take the
whole row as an *upgrade* of the tier instead (:func:`upgrades`): an item of the cost and
relevance it adds to the tier, taken only after it, as for a multiple-choice knapsack's LP
relaxation. Counted as two objects (before issue 10's stop 47), the whole row's cost was spent on
top of its tier's: on the H200 a Sponza frame at 75 % of its trace time stopped at 4.2 ms of
predicted trace with 9.3 ms of room (``docs/results/gpu/issue10/stop47``).

``scripts/selection_benchmark.py`` measures, on random instances, how much of the optimum's
relevance each captures and what it costs; ``docs/results/`` holds the numbers.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

SELECTORS = ("nested", "greedy", "graph", "exact")


@dataclass(frozen=True)
class Node:
    key: object  # the object's identity (its shape index, or a label)
    cost: float
    relevance: float
    group: object = None  # nodes of one group (the options of one object) exclude each other; None: its own


@dataclass
class SelectionGraph:
    """The graph of one frame. ``pointers`` is N, the relevance pointers kept per node."""

    nodes: list[Node]
    pointers: int = 4
    #: nodes moved to the graph of the next frame, in the order they moved
    moved: list[Node] = field(default_factory=list)

    def __post_init__(self):
        self.nodes = sorted(self.nodes, key=lambda n: (-n.cost, -n.relevance))
        self._link()

    def _link(self) -> None:
        """Relevance pointers: for each node, the N cheaper (later in the chain), more relevant
        nodes, most relevant first."""
        self.links: dict[int, list[int]] = {}
        for i, node in enumerate(self.nodes):
            better = [j for j in range(i + 1, len(self.nodes)) if self.nodes[j].relevance > node.relevance]
            better.sort(key=lambda j: -self.nodes[j].relevance)
            self.links[i] = better[: self.pointers]

    def select_one(self, time_left: float) -> Node | None:
        """One step of §4.3: the node to ray trace next, or ``None`` when nothing fits (then every
        remaining node has moved to the next graph)."""
        start = next((i for i, n in enumerate(self.nodes) if n.cost <= time_left), None)
        if start is None:
            self.moved.extend(self.nodes)
            self.nodes = []
            return None
        self.moved.extend(self.nodes[:start])  # too expensive for the time left in this frame
        i = start
        while self.links[i] and self.nodes[self.links[i][0]].relevance > self.nodes[i].relevance:
            i = self.links[i][0]
        chosen = self.nodes[i]
        self.moved.append(chosen)
        # the chosen node's other options (its group) are not traced besides it
        rivals = [k for k, n in enumerate(self.nodes) if k != i and chosen.group is not None and n.group == chosen.group]
        self.moved.extend(self.nodes[k] for k in rivals if k >= start)
        self.nodes = [n for k, n in enumerate(self.nodes) if k != i and k >= start and k not in rivals]
        self._link()
        return chosen

    def select(self, budget: float) -> list[Node]:
        """Select nodes until the budget is spent; returns them in the order selected."""
        chosen, time_left = [], float(budget)
        while (node := self.select_one(time_left)) is not None:
            chosen.append(node)
            time_left -= node.cost
        return chosen


def select_nested(nodes: list[Node], budget: float) -> list[Node]:
    """The longest run of nodes, by decreasing R/C, that fits: *nested* in the budget (what a
    budget B selects, any budget above B selects too), so more budget never swaps a selection
    for another; it leaves unused at most the cost of the first node that does not fit.

    Where the first node alone costs more than the budget, the run starts at the first node that
    fits alone (an upgrade of a node passed over is passed over too), rather than selecting
    nothing: the budget is spent, not held by tracing nothing (issue 10's complaint; on the H200
    the showcase's frames at 25 % traced nothing in most frames: docs/results/gpu/issue10/stop54).
    Budgets from the first node's cost up stay nested."""
    return _rows_of("nested", nodes, budget)


def select_greedy(nodes: list[Node], budget: float) -> list[Node]:
    """Nodes by decreasing R/C while they fit, or the single most relevant node that fits if that
    alone is worth more (which guarantees at least half the optimum: ratio order alone can fill
    the budget with small objects and leave out a large, relevant one)."""
    return _rows_of("greedy", nodes, budget)


def _rows_of(method: str, nodes: list[Node], budget: float) -> list[Node]:
    cost = np.array([n.cost for n in nodes], dtype=np.float64)
    relevance = np.array([n.relevance for n in nodes], dtype=np.float64)
    base = np.full(len(nodes), -1, dtype=np.int64)  # of two options of one object, the costlier upgrades the other
    for members in _groups(nodes):
        if len(members) > 2:
            raise ValueError(f"{method}: an object has {len(members)} options; up to two (whole and shadow tier) are supported")
        if len(members) == 2:
            low, high = sorted(members, key=lambda i: cost[i])
            base[high] = low
    return [nodes[int(i)] for i in select_rows(method, cost, relevance, budget, base)]


def _groups(nodes: list[Node]) -> list[list[int]]:
    """The indices of the nodes of each ``group`` (nodes without one are left out)."""
    groups: dict = {}
    for i, n in enumerate(nodes):
        if n.group is not None:
            groups.setdefault(n.group, []).append(i)
    return list(groups.values())


def select_exact(nodes: list[Node], budget: float) -> list[Node]:
    """The 0/1 knapsack optimum (HiGHS MILP), at most one node per ``group``."""
    from scipy.optimize import Bounds, LinearConstraint, milp

    if not nodes:
        return []
    cost = np.array([n.cost for n in nodes], dtype=np.float64)
    relevance = np.array([n.relevance for n in nodes], dtype=np.float64)
    rows = [cost[None, :]]
    upper = [float(budget)]
    for members in (m for m in _groups(nodes) if len(m) > 1):  # at most one option per object
        row = np.zeros(len(nodes))
        row[members] = 1.0
        rows.append(row[None, :])
        upper.append(1.0)
    result = milp(-relevance, constraints=LinearConstraint(np.vstack(rows), -np.inf, np.array(upper)),
                  integrality=np.ones(len(nodes)), bounds=Bounds(0, 1))
    if result.x is None:
        return []
    return [n for n, x in zip(nodes, result.x) if x > 0.5]


def upgrades(cost: np.ndarray, relevance: np.ndarray, base: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rows as items of the ratio-ordered selectors where a row upgrades another (``base[i]``
    ≥ 0: row ``i`` is an option of the same object as row ``base[i]``, costlier and meant to
    replace it; -1: none). An upgrade becomes the item of what it adds (its cost and relevance
    less its base's), taken only after its base (``requires``). Where that item would be worth
    at least as much per millisecond as its base (or costs nothing more), the base is left out
    (``requires`` -2) and the upgrade stays whole, on its own: the LP relaxation of a
    multiple-choice knapsack takes an object's options in decreasing order of what each adds per
    millisecond, and a dominated base would only delay the upgrade. Returns the items' cost and
    relevance and, per row, the row it requires (-1: none, -2: left out)."""
    cost, relevance = np.array(cost, dtype=np.float64), np.array(relevance, dtype=np.float64)
    requires = np.full(len(cost), -1, dtype=np.int64)
    up = np.nonzero(base >= 0)[0]
    low = base[up]
    added, gained = cost[up] - cost[low], relevance[up] - relevance[low]
    dominated = (added <= 0) | (gained * cost[low] >= relevance[low] * added)
    requires[low[dominated]] = -2
    kept = ~dominated
    cost[up[kept]], relevance[up[kept]], requires[up[kept]] = added[kept], gained[kept], low[kept]
    return cost, relevance, requires


def select_rows(method: str, cost: np.ndarray, relevance: np.ndarray, budget: float,
                base: np.ndarray | None = None) -> np.ndarray:
    """:func:`select_nested` or :func:`select_greedy` on arrays (a row per node, in any order):
    the rows picked. ``base`` (per row, -1: none) marks rows that upgrade another option of the
    same object (:func:`upgrades`); of an object's options the costliest picked is returned.
    3 228 rows (2 000 objects and their shadow tiers) take 0.07 ms on a CPU of the CI machine
    (docs/results/gpu/issue10/stop64/plan_time.py)."""
    row_cost, row_relevance = np.asarray(cost, dtype=np.float64), np.asarray(relevance, dtype=np.float64)
    requires = np.full(len(row_cost), -1, dtype=np.int64)
    cost, relevance = row_cost, row_relevance
    if base is not None and (np.asarray(base) >= 0).any():
        cost, relevance, requires = upgrades(row_cost, row_relevance, np.asarray(base))
    rows = np.nonzero(requires != -2)[0]
    # a base before its upgrades: upgrades() keeps only those adding less per millisecond than it
    order = rows[np.argsort(-relevance[rows] / np.maximum(cost[rows], 1e-12), kind="stable")]
    if method == "nested":
        chosen = _run(order, cost, budget)
        if not len(chosen):  # the first node alone is over the budget: the run starts at the first that fits
            fits = np.nonzero(row_cost[order] <= budget)[0]
            if len(fits):
                passed, rest = order[:fits[0]], order[fits[0]:]
                chosen = _run(rest[~np.isin(requires[rest], passed)], cost, budget)  # no upgrade of a node passed over
    else:
        taken = np.zeros(len(cost), dtype=bool)
        time_left = float(budget)
        for row, c in zip(order.tolist(), cost[order].tolist()):
            if c <= time_left and (requires[row] < 0 or taken[requires[row]]):
                taken[row] = True
                time_left -= c
        chosen = np.nonzero(taken)[0]
        # the single row (an option at its own cost) that fits and alone is worth more
        fits = np.nonzero(row_cost <= budget)[0]
        if len(fits):
            best = int(fits[np.argmax(row_relevance[fits])])
            if row_relevance[best] > relevance[chosen].sum():
                return np.array([best])
    replaced = np.zeros(len(cost), dtype=bool)
    replaced[requires[chosen][requires[chosen] >= 0]] = True
    return chosen[~replaced[chosen]].astype(np.int64)


def _run(order: np.ndarray, cost: np.ndarray, budget: float) -> np.ndarray:
    """The longest run of ``order`` whose costs add up to at most ``budget``."""
    return order[:int(np.searchsorted(np.cumsum(cost[order]), budget, side="right"))]


def select(method: str, nodes: list[Node], budget: float, pointers: int = 4) -> list[Node]:
    """Pick the nodes to ray trace within ``budget`` with ``method`` (one of ``SELECTORS``)."""
    if method == "graph":
        return SelectionGraph(list(nodes), pointers=pointers).select(budget)
    if method == "nested":
        return select_nested(nodes, budget)
    if method == "greedy":
        return select_greedy(nodes, budget)
    if method == "exact":
        return select_exact(nodes, budget)
    raise ValueError(f"selection='{method}' is not one of {list(SELECTORS)}")
