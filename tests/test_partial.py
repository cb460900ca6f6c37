"""Part of an object (``selection.py``): the budget a selection leaves buys 1–3 of each 2×2 pixel
quad's positions of one more object, whose left-out pixels with a delta lobe are filled from
their traced neighbours (``compose.fill_left_out``)."""
from __future__ import annotations

import copy

import drjit as dr
import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.api import renderer
from hybrid_integrator.budget import CostModel, FrameState, plan_frame
from hybrid_integrator.compose import fill_left_out
from hybrid_integrator.heuristic import BLOCKS, KINDS, Candidates, Coverage, DeviceSums, add_error
from hybrid_integrator.pipeline import HybridSettings
from hybrid_integrator.primary import camera_rays
from hybrid_integrator.selection import FILL_LOBES, QUAD_KEPT, part_config, select_pixels
from conftest import DEFAULT_SCENE, ROOT, SHARED_SCENES, load
from test_accuracy import camera_of, flip, reference


def _calibrated() -> CostModel:
    model = CostModel(rates=dict.fromkeys(KINDS, 1.0), launch_ms=0.5)
    model.history.extend([([0.0] * 4, 0.5, [0.0] * 4)] * 3)  # as if three passes had been measured
    return model


def _candidates(tier: bool = False) -> Candidates:
    """Object 0: a glass object, 8 refraction rays (8 ms) and the most relevant; object 1: a
    shadow and an indirect ray (2 ms), with ``tier`` also its shadow tier (row 2: 1 ms)."""
    rays = np.zeros((3, len(KINDS)))
    rays[0, KINDS.index("refraction")] = 8.0
    rays[1, KINDS.index("shadow")], rays[1, KINDS.index("indirect")] = 1.0, 1.0
    rays[2, KINDS.index("shadow")] = 1.0
    rows = 3 if tier else 2
    return Candidates(index=np.array([0, 1, 1][:rows]), pixels=np.full(rows, 100), visibility=np.ones(rows),
                      relevance=np.array([0.7, 0.2, 0.15][:rows]), rays=rays[:rows], terms=None,
                      tier=np.array([False, False, True][:rows]))


@pytest.mark.parametrize("method", ["nested", "greedy", "graph", "exact"])
def test_the_budget_left_buys_part_of_one_more_object(method):
    """7.5 ms of room (8 ms less the 0.5 ms launch): object 1 whole (2 ms) is picked, object 0
    (8 ms) does not fit; the 5.5 ms left buy 2 of its 4 quarters (4 ms), charged in the plan's
    rays and its prediction, and the object counts as traced. Without ``partial``, nothing of it."""
    c, model = _candidates(), _calibrated()
    plan = plan_frame(c, method, 8.0, 1, model, partial=True)
    assert plan.picked.tolist() == [1] and plan.partial == (0, 2)
    assert plan.rays == {"shadow": 1.0, "refraction": 4.0, "indirect": 1.0}
    assert plan.traced == {0, 1} and model.predict(plan.rays) <= plan.pass_budget_ms
    whole = plan_frame(c, method, 8.0, 1, model)
    assert whole.partial is None and whole.traced == {1} and whole.rays == {"shadow": 1.0, "indirect": 1.0}
    # a quarter costs 2 ms: 1.5 ms left after object 1 buys none; alone, 7.5 ms buy 3 quarters,
    # the most (4 would be the object whole, which did not fit)
    assert plan_frame(c, method, 4.0, 1, model, partial=True).partial is None
    alone = Candidates(index=np.array([0]), pixels=np.array([100]), visibility=np.ones(1), relevance=np.array([0.9]),
                       rays=c.rays[:1], terms=None)
    assert plan_frame(alone, method, 8.0, 1, model, partial=True).partial == (0, 3)
    # an unlimited budget traces everything whole; a probe (uncalibrated model) whole objects only
    assert plan_frame(c, method, 0.0, 1, model, partial=True).partial is None
    assert plan_frame(c, method, 8.0, 1, CostModel(), partial=True).partial is None


def test_an_object_with_a_row_picked_is_not_also_traced_in_part():
    """Object 1's shadow tier picked (1 ms of 1.5 ms of room): its whole row is not a part's
    candidate (a quarter of it, 0.5 ms, would fit what is left), and object 0's quarter (2 ms)
    does not fit."""
    c, model = _candidates(tier=True), _calibrated()
    plan = plan_frame(c, "nested", 2.0, 1, model, partial=True)
    assert plan.picked.tolist() == [2] and plan.partial is None


@pytest.mark.parametrize("quarters", [1, 2, 3])
def test_an_objects_part_traces_its_kept_quad_positions_and_fills_its_delta_pixels(quarters):
    """Mitsuba's own hits of the default scene's camera rays, all taken as one object traced with
    shadows, reflections and refractions on ``quarters`` of its pixels: a pixel that needs one is
    traced at the kept positions of its 2×2 quad (x mod 2 + 2 · (y mod 2)) and left out at the
    others; a left-out pixel on the mirror or the glass (a delta lobe) is filled, one on the
    diffuse walls keeps the raster layer."""
    scene = load(DEFAULT_SCENE, resx=32, resy=24)
    ray = camera_rays(scene.sensors()[0], 32, 24, (0.5, 0.5))
    si = scene.ray_intersect(ray)
    pixel = dr.arange(mi.UInt32, 32 * 24)
    obj = dr.zeros(mi.UInt32, 32 * 24)
    config = mi.Int32([part_config(0, quarters)])
    effects = (("shadow", "reflection", "refraction"),)
    whole = select_pixels(si, ray, obj, si.is_valid(), mi.Int32([0]), effects, True)
    part = select_pixels(si, ray, obj, si.is_valid(), config, effects, True, pixel, 32)
    needs = np.array(whole.traced)
    assert needs.sum() > 500 and whole.left_out is None and whole.filled is None
    index = np.arange(32 * 24)
    position = index % 2 + 2 * ((index // 32) % 2)
    kept = np.isin(position, QUAD_KEPT[quarters])
    assert np.array_equal(np.array(part.traced), needs & kept)
    assert np.array_equal(np.array(part.left_out), needs & ~kept)
    delta = (np.array(si.bsdf(ray).flags()) & int(FILL_LOBES)) != 0
    filled = np.array(part.filled)
    assert np.array_equal(filled, needs & ~kept & delta)
    assert 0 < filled.sum() < np.array(part.left_out).sum()  # the mirror and glass, not the walls
    assert np.array_equal(np.array(part.config), np.zeros(32 * 24))  # the effect set, without the part's bits


def test_a_left_out_pixel_takes_the_mean_of_its_traced_neighbours_on_its_object():
    """4 × 3 pixels: traced 0, 2, 8 and 10 (a quarter's positions); pixel 5's eight neighbours
    include all four, pixel 1 has 0 and 2; pixel 3 lies on another object than its traced
    neighbour 2 and keeps the raster layer (not shown as traced)."""
    values = np.arange(12.0) ** 2
    rt = mi.Color3f(mi.Float(values), mi.Float(2 * values), mi.Float(np.ones(12)))
    traced = np.isin(np.arange(12), [0, 2, 8, 10])
    left_out = np.isin(np.arange(12), [1, 3, 5])
    obj = np.zeros(12, dtype=np.uint32)
    obj[3] = 1
    filled, shown = fill_left_out(rt, mi.Bool(traced), mi.Bool(left_out), mi.UInt32(obj), 4, 3)
    x = np.array(filled.x)
    assert x[1] == pytest.approx((0 + 4) / 2) and x[5] == pytest.approx((0 + 4 + 64 + 100) / 4)
    assert x[3] == 9.0 and np.array(filled.y)[5] == pytest.approx(2 * x[5])
    assert np.array_equal(np.array(shown), traced | np.isin(np.arange(12), [1, 5]))
    untouched = ~np.isin(np.arange(12), [1, 5])
    assert np.array_equal(x[untouched], values[untouched])


@pytest.mark.parametrize("quarters", [1, 2, 3])
def test_a_part_is_measured_across_its_left_out_pixels(quarters):
    """The error relevance pairs horizontally adjacent traced pixels (``heuristic.add_error``); a
    part of 1 or 2 quarters has no two side by side, so a traced pixel whose right neighbour was
    left out pairs with the pixel after it. With a bias b on every traced pixel, E = b from every
    part; without ``skipped`` a part of 1 or 2 quarters would have no pair at all."""
    h, w = 8, 12
    y, x = np.mgrid[0:h, 0:w]
    kept = np.isin(x % 2 + 2 * (y % 2), QUAD_KEPT[quarters])
    tone = lambda v: v / (1.0 + v)
    cheap = np.full((h, w), 0.5)
    exact_tone = tone(cheap) + 0.2
    exact = np.where(kept, exact_tone / (1.0 - exact_tone), cheap)
    def color(v):
        return mi.Color3f(*(mi.Float(v.ravel().astype(np.float32)) for _ in range(3)))
    def pairs(skipped):
        sums = DeviceSums(mi.Float, BLOCKS)
        add_error(sums, mi.UInt32(np.zeros(h * w, np.uint32)), mi.Bool(kept.ravel()), color(exact), color(cheap),
                  color(cheap), color(cheap), 1, w, skipped=skipped)
        return Coverage.of(sums.total(), w, h, 1)
    measured = pairs(mi.Bool((~kept).ravel()))
    assert measured.pairs[0] > 0
    assert np.sqrt(measured.error_sum[0] / measured.pairs[0]) == pytest.approx(0.2, abs=1e-5)
    assert (pairs(None).pairs[0] == 0) == (quarters < 3)


def test_a_budget_short_of_the_glass_armadillo_traces_part_of_it():
    """The glass Armadillo is most of the scene's trace time: a budget short of it buys nothing of
    it, at one error for every budget below 100 % (stop 69's CPU probe: FLIP 0.205 at 25, 50 and
    75 %). From the same learnt state, the same budget with ``partial_objects`` (the default since
    stop 75) traces a part of the Armadillo (stats, pixels traced), within the budget the plan predicts, and the frame is far
    closer to ``path``. The Armadillo is the only candidate and the budget is the launch cost plus
    55 % of what the learnt cost model predicts for the Armadillo past it, so the plans do not depend on the
    machine's load: the whole object does not fit, two quarters of it do."""
    scene = load(ROOT / "scenes" / "armadillo_glass.xml", resx=160, resy=90, models_dir=str(SHARED_SCENES / "models"))
    truth = reference(scene, spp=64)
    camera = camera_of(scene)
    only = dict(candidates="armadillo")
    everything = hi.render_sequence(scene, [camera] * 4, spp=1, seed=2, **only)[-1]
    state = FrameState()
    for seed in range(8):  # the probes, then calibrated frames that learn the Armadillo's rays and errors
        settings = HybridSettings(budget_ms=0.6 * everything.stats.times_ms["trace"], partial_objects=False, **only)
        renderer(scene).render(settings, seed=seed, spp=1, state=state, layers=False)
    all_in = renderer(scene).render(HybridSettings(budget_ms=1e6, **only), seed=9, spp=1,
                                    state=copy.deepcopy(state)).stats
    assert all_in.selected == ("armadillo",) and not all_in.partial_object
    launch = state.cost_model.launch()
    budget = launch + 0.55 * (all_in.predicted_trace_ms - launch)
    frames = {}
    for partial, part_setting in ((False, dict(partial_objects=False)), (True, {})):  # {}: as it ships
        settings = HybridSettings(budget_ms=budget, **part_setting, **only)
        frames[partial] = renderer(scene).render(settings, seed=9, spp=1, state=copy.deepcopy(state))
    whole, part = frames[False].stats, frames[True].stats
    assert whole.selected == () and whole.pixels_traced == 0 and not whole.partial_object
    assert part.selected == ("armadillo",) and (part.partial_object, part.partial_quarters) == ("armadillo", 2)
    assert 0 < part.pixels_traced < all_in.pixels_traced
    assert part.predicted_trace_ms <= budget
    assert flip(frames[True].image, truth) < flip(frames[False].image, truth) - 0.05
