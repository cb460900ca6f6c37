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

**Nested** (the default): the longest run of nodes by decreasing R/C that fits; a larger
budget only adds nodes. **Greedy**: take nodes by decreasing R/C while they fit, unless the single most relevant node
that fits is worth more. **Exact**: the 0/1 knapsack optimum
(maximum total R with total C within the budget), solved as a mixed-integer linear program by
SciPy's HiGHS (``scipy.optimize.milp``); meant for small N, as a yardstick.

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
        self.nodes = [n for k, n in enumerate(self.nodes) if k != i and k >= start]
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
    for another; it leaves unused at most the cost of the first node that does not fit."""
    return _rows_of("nested", nodes, budget)


def select_greedy(nodes: list[Node], budget: float) -> list[Node]:
    """Nodes by decreasing R/C while they fit, or the single most relevant node that fits if that
    alone is worth more (which guarantees at least half the optimum: ratio order alone can fill
    the budget with small objects and leave out a large, relevant one)."""
    return _rows_of("greedy", nodes, budget)


def _rows_of(method: str, nodes: list[Node], budget: float) -> list[Node]:
    cost = np.array([n.cost for n in nodes], dtype=np.float64)
    relevance = np.array([n.relevance for n in nodes], dtype=np.float64)
    return [nodes[int(i)] for i in select_rows(method, cost, relevance, budget)]


def select_exact(nodes: list[Node], budget: float) -> list[Node]:
    """The 0/1 knapsack optimum (HiGHS MILP)."""
    from scipy.optimize import Bounds, LinearConstraint, milp

    if not nodes:
        return []
    cost = np.array([n.cost for n in nodes], dtype=np.float64)
    relevance = np.array([n.relevance for n in nodes], dtype=np.float64)
    result = milp(-relevance, constraints=LinearConstraint(cost[None, :], -np.inf, float(budget)),
                  integrality=np.ones(len(nodes)), bounds=Bounds(0, 1))
    if result.x is None:
        return []
    return [n for n, x in zip(nodes, result.x) if x > 0.5]


def select_rows(method: str, cost: np.ndarray, relevance: np.ndarray, budget: float) -> np.ndarray:
    """:func:`select_nested` or :func:`select_greedy` on arrays (a row per node, in any order):
    the rows picked. Thousands of nodes take well under a millisecond."""
    order = np.argsort(-relevance / np.maximum(cost, 1e-12), kind="stable")
    spent = np.cumsum(cost[order])
    if method == "nested":
        return order[:int(np.searchsorted(spent, budget, side="right"))]
    chosen, time_left = [], float(budget)
    for row, c in zip(order.tolist(), cost[order].tolist()):
        if c <= time_left:
            chosen.append(row)
            time_left -= c
    fits = np.nonzero(cost <= budget)[0]
    if len(fits):
        best = int(fits[np.argmax(relevance[fits])])
        if relevance[best] > relevance[chosen].sum():
            return np.array([best])
    return np.array(chosen, dtype=np.int64)


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
