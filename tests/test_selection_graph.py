"""The selection graph (paper §4.2–4.3), greedy and exact selection."""
from __future__ import annotations

import numpy as np
import pytest

from hybrid_integrator.selection_graph import Node, SelectionGraph, select, select_exact, select_greedy

# The paper's Table 1: nodes 9..22 with their cost and relevance (Fig. 2)
TABLE_1 = [(20, 22), (19, 21), (18, 18), (17, 30), (16, 31), (15, 32), (14, 28), (14, 27), (13, 9), (12, 29),
           (11, 1), (10, 20), (9, 4), (9, 3)]


def paper_graph(pointers=4):
    return SelectionGraph([Node(f"c{c}r{r}", c, r) for c, r in TABLE_1], pointers=pointers)


def test_paper_example_figure_3():
    """Time left for a cost of 18: the nodes of cost 20 and 19 move to the next graph, and the node of
    cost 15 and relevance 32 is selected rather than the node of cost 18."""
    graph = paper_graph()
    chosen = graph.select_one(18)
    assert (chosen.cost, chosen.relevance) == (15, 32)
    assert [(n.cost, n.relevance) for n in graph.moved[:2]] == [(20, 22), (19, 21)]
    assert (15, 32) not in [(n.cost, n.relevance) for n in graph.nodes]
    # the cost-18 node stays available in this frame's graph
    assert (18, 18) in [(n.cost, n.relevance) for n in graph.nodes]


def test_graph_structure():
    graph = paper_graph(pointers=3)
    costs = [n.cost for n in graph.nodes]
    assert costs == sorted(costs, reverse=True)  # the cost chain
    for i, targets in graph.links.items():
        assert len(targets) <= 3
        assert all(j > i and graph.nodes[j].relevance > graph.nodes[i].relevance for j in targets)
        assert [graph.nodes[j].relevance for j in targets] == sorted((graph.nodes[j].relevance for j in targets), reverse=True)
    # the cost-18 node points first to the most relevant cheaper node
    i18 = next(i for i, n in enumerate(graph.nodes) if n.cost == 18)
    assert graph.nodes[graph.links[i18][0]].relevance == 32


def test_selection_respects_budget_and_moves_everything():
    graph = paper_graph()
    chosen = graph.select(40)
    assert sum(n.cost for n in chosen) <= 40
    assert [(n.cost, n.relevance) for n in chosen][0] == (16, 31) or chosen[0].relevance >= 31
    assert len(graph.nodes) == 0 and len(graph.moved) == len(TABLE_1)  # all carried to the next graph
    assert select("graph", [], 10) == [] and paper_graph().select(5) == []


def test_greedy_and_exact():
    nodes = [Node(k, c, r) for k, (c, r) in enumerate(TABLE_1)]
    exact = select_exact(nodes, 30)
    greedy = select_greedy(nodes, 30)
    for chosen in (exact, greedy):
        assert sum(n.cost for n in chosen) <= 30
    # optimum by brute force
    best = 0
    for mask in range(1 << len(nodes)):
        c = sum(n.cost for k, n in enumerate(nodes) if mask >> k & 1)
        if c <= 30:
            best = max(best, sum(n.relevance for k, n in enumerate(nodes) if mask >> k & 1))
    assert sum(n.relevance for n in exact) == best
    assert sum(n.relevance for n in greedy) <= best


@pytest.mark.parametrize("seed", range(5))
def test_no_selector_beats_the_optimum(seed):
    rng = np.random.default_rng(seed)
    nodes = [Node(k, float(c), float(r)) for k, (c, r) in enumerate(zip(rng.uniform(1, 10, 12), rng.uniform(0, 5, 12)))]
    budget = 0.4 * sum(n.cost for n in nodes)
    optimum = sum(n.relevance for n in select("exact", nodes, budget))
    for method in ("graph", "greedy"):
        chosen = select(method, nodes, budget)
        assert sum(n.cost for n in chosen) <= budget + 1e-9
        assert sum(n.relevance for n in chosen) <= optimum + 1e-9
    with pytest.raises(ValueError, match="selection='best'"):
        select("best", nodes, budget)


def test_greedy_keeps_a_large_relevant_object_that_ratio_order_leaves_out():
    small, large = Node("small", 1.0, 2.0), Node("large", 10.0, 10.0)
    assert [n.key for n in select_greedy([small, large], 10.0)] == ["large"]
    assert {n.key for n in select_greedy([small, large], 11.0)} == {"small", "large"}


def options(tier=(1.0, 0.3), whole=(4.0, 0.4), other=(3.0, 0.2)):
    """One object with two options (its shadow tier and the object whole: group "a") and another
    object: (cost, relevance) each."""
    return [Node("a tier", *tier, group="a"), Node("a whole", *whole, group="a"), Node("b", *other, group="b")]


@pytest.mark.parametrize("budget, nested", [(4.5, {"a tier", "b"}), (7.5, {"a whole", "b"}), (3.5, {"a tier"})])
def test_an_objects_options_are_not_counted_twice(budget, nested):
    """Tracing an object whole costs its whole row, not that plus its tier's: the whole row is the
    tier's upgrade (what it adds: 3 ms, 0.1), taken after the tier. Counted as two objects, nested
    selection stopped at the whole row (1 + 4 ms) with budget left for b; and no selector returns
    both options of one object."""
    for method in ("nested", "greedy", "graph", "exact"):
        chosen = select(method, options(), budget)
        keys = {n.key for n in chosen}
        assert not {"a tier", "a whole"} <= keys, (method, keys)
        assert sum(n.cost for n in chosen) <= budget + 1e-9
    assert {n.key for n in select("nested", options(), budget)} == nested
    assert sum(n.relevance for n in select("exact", options(), budget)) == pytest.approx(
        sum(n.relevance for n in options() if n.key in nested))


def test_a_dominated_tier_is_passed_over():
    """A whole row whose upgrade adds more per millisecond than its tier gives (0.3 for 2 ms over a
    tier of 0.1 for 1 ms) stands alone: nested takes it before b, not the tier first."""
    nodes = options(tier=(1.0, 0.1), whole=(3.0, 0.4), other=(2.0, 0.15))
    assert {n.key for n in select("nested", nodes, 3.5)} == {"a whole"}
    assert {n.key for n in select("nested", nodes, 5.0)} == {"a whole", "b"}


def test_nested_starts_at_the_first_node_that_fits():
    """Where the first node by R/C (a's tier, 5 ms) is over the budget, nested selects the run
    from the first node that fits alone (b) rather than nothing; a's upgrade (1 ms more than its
    tier), which would fit by what it adds, is passed over with the tier it upgrades."""
    nodes = options(tier=(5.0, 1.0), whole=(6.0, 1.05), other=(1.0, 0.1))
    assert {n.key for n in select("nested", nodes, 2.0)} == {"b"}
    assert {n.key for n in select("nested", nodes, 0.5)} == set()  # nothing fits
    assert {n.key for n in select("nested", nodes, 5.0)} == {"a tier"}  # the first fits: the run from it
    assert {n.key for n in select("nested", nodes, 7.0)} == {"a whole", "b"}


def test_nested_budgets_only_upgrade():
    """With options, more budget still only adds: an object goes from nothing to its tier to whole."""
    rng = np.random.default_rng(3)
    nodes = []
    for k in range(8):
        tier_cost, tier_r = rng.uniform(0.2, 1.0), rng.uniform(0.1, 1.0)
        nodes += [Node((k, "tier"), tier_cost, tier_r, group=k),
                  Node((k, "whole"), tier_cost + rng.uniform(0.5, 4.0), tier_r + rng.uniform(0.0, 0.5), group=k)]
    level = {}
    for budget in np.linspace(0.0, 30.0, 31):
        now = {key[0]: 2 if key[1] == "whole" else 1 for key in (n.key for n in select("nested", nodes, budget))}
        assert all(now.get(k, 0) >= v for k, v in level.items()), budget
        level = now
    with pytest.raises(ValueError, match="up to two"):
        select("nested", nodes[:2] + [Node("third", 9.0, 1.0, group=0)], 5.0)
