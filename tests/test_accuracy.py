"""Accuracy per millisecond (issue 11): the denoiser, temporal accumulation, relevance by the
error tracing removes, and nested budgets, against Mitsuba's ``path`` on the CPU."""
from __future__ import annotations

import copy
import itertools

import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.api import renderer
from hybrid_integrator.budget import FrameState
from hybrid_integrator.metrics import image_error
from hybrid_integrator.pipeline import HybridSettings
from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix
from hybrid_integrator.selection_graph import Node, select
from conftest import DEFAULT_SCENE, ROOT, SHARED_SCENES, load

SIZE = dict(resx=160, resy=120)


def flip(image, reference) -> float:
    return image_error(np.array(image)[..., :3], reference)[0].flip


def reference(scene, spp=256, seed=99):
    return np.array(mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=spp, seed=seed))


def camera_of(scene):
    return sensor_to_world(scene.sensors()[0])


def test_denoiser_with_gbuffer_guides_beats_noisy_frame_and_path():
    scene = load(DEFAULT_SCENE, **SIZE)
    truth = reference(scene)
    noisy = hi.render(scene, spp=1, seed=4, denoise=False)
    denoised = hi.render(scene, spp=1, seed=4)
    assert denoised.stats.times_ms["denoise"] > 0 and noisy.stats.times_ms["denoise"] == 0
    # against the same frame before the denoiser (splatted with a box filter, as the denoiser needs),
    # the frame without it (the film's filter) and path at the same spp
    path = mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=1, seed=4)
    before = [flip(x, truth) for x in (denoised.composed, noisy.image, path)]
    assert flip(denoised.image, truth) < 0.8 * min(before), before
    with pytest.raises(Exception, match="denoise_quality='best' is not one of"):
        hi.render(scene, spp=1, denoise_quality="best")


def test_frame_that_traces_nothing_is_not_denoised():
    """No candidate: the image is the raster layer, which has no noise, so the denoiser does not
    run (it would cost its full time for nothing): the image is the composed film itself."""
    scene = load(DEFAULT_SCENE, **SIZE)
    raster = hi.render(scene, spp=1, seed=4, candidates="")
    assert raster.stats.pixels_traced == 0 and raster.stats.times_ms["denoise"] == 0
    assert np.array_equal(np.array(raster.image), np.array(raster.composed))
    assert hi.render(scene, spp=1, seed=4).stats.times_ms["denoise"] > 0  # the same scene traced: denoised


@pytest.mark.parametrize("spp", [1, 2])
def test_path_denoised_baseline_guides_are_its_paths_first_hits(spp):
    """The bench's ``path`` + denoiser renders ``path`` and, apart, the guides of an ``aov``
    integrator without a nested one, both replayed from a recording (compare.timed_path_denoised):
    at the same seed the two take the same camera rays, so its image is the one whose guides come
    from the path's own samples (Mitsuba's ``aov`` with ``path`` nested, which traces the paths
    twice)."""
    from hybrid_integrator.compare import timed_path_denoised
    from hybrid_integrator.denoise import Denoiser, Guides
    from hybrid_integrator.raster.camera import sensor_like

    scene = load(DEFAULT_SCENE, resx=80, resy=60)
    image, times = timed_path_denoised(scene, spp, -1, seed=3, repeats=1)
    sensor = sensor_like(scene.sensors()[0], 80, 60, rfilter="box")
    nested = mi.load_dict({"type": "aov", "aovs": "albedo:albedo,nn:sh_normal", "integrator": {"type": "path"}})
    out = mi.render(scene, integrator=nested, sensor=sensor, spp=spp, seed=3)
    expected = Denoiser("high")(out[..., 0:3], Guides(albedo=out[..., 3:6], normal=out[..., 6:9]))
    # (replayed from a recording, the same to the order of the film's atomic sums)
    assert len(times) == 1 and np.allclose(image, np.array(expected, dtype=np.float32)[..., :3], atol=1e-4)


def test_still_camera_history_is_the_mean_of_its_frames():
    """With a still camera every pixel reprojects onto itself: the history is the plain mean of the
    composed frames, and it converges (each frame another sub-pixel offset and seed)."""
    scene = load(DEFAULT_SCENE, **SIZE)
    truth = reference(scene)
    clock = renderer(scene).clock
    marks = []  # the stage clock reads Dr.Jit's kernel history, which waits for the device
    original = clock.mark
    clock.mark = lambda stage, *values: (marks.append(stage), original(stage, *values))
    try:
        frames = hi.render_sequence(scene, [camera_of(scene)] * 8, spp=1, seed=1, denoise=False, temporal=True)
    finally:
        del clock.mark
    # every frame with a history is timed, but only the update's recordings read the kernel
    # history: a replayed update adds no synchronization to the frame
    assert all(f.stats.times_ms["temporal"] > 0 for f in frames[1:])
    update = renderer(scene)._accumulators[True]._update
    assert marks.count("temporal") == update.n_recordings < len(frames) - 1, marks
    mean = np.mean([np.array(f.composed) for f in frames], axis=0)
    assert np.allclose(np.array(frames[-1].image), mean, rtol=1e-4, atol=1e-5)
    errors = [flip(f.image, truth) for f in frames]
    assert errors[-1] < 0.75 * errors[0], errors


@pytest.mark.parametrize("denoise, size, seed", [(False, (80, 60), 3), (False, (80, 60), 5), (False, (80, 60), 7),
                                                (True, (160, 120), 3), (True, (160, 120), 7)],
                         ids=["raw-3", "raw-5", "raw-7", "denoised-3", "denoised-7"])
def test_moving_camera_history_never_worse_than_no_history(denoise, size, seed):
    """A 30-frame camera path: each frame, blended with its reprojected history (same object, same
    surface), is no further from its own reference than the same frame without history;
    disoccluded pixels restart, so nothing ghosts. Denoised: the history's frames are resolved
    against their film-filtered mean (temporal.py), the frames without history are not; at 80×60
    a denoised frame's FLIP varies too much from frame to frame for this comparison (two frames of
    this path are worse than the tolerance with history, before the resolve too), at 160×120 none is.
    Several seeds: with a history of 16 frames the path's last frames passed for seed 3 and failed
    for seeds 4-7 (``temporal.MOTION_FRAMES``)."""
    scene = load(DEFAULT_SCENE, resx=size[0], resy=size[1])
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    origin = start[:3, 3]
    target = origin + start[:3, 2]
    cameras = hi.camera_path([(origin, target), (origin + [0.6, 0.2, 0.0], target + [0.2, 0.0, 0.0])], 30)
    common = dict(spp=1, seed=seed, denoise=denoise, layers=False)
    plain = hi.render_sequence(scene, cameras, **common)
    history = hi.render_sequence(scene, cameras, temporal=True, **common)
    params = mi.traverse(scene.sensors()[0])
    errors = []  # per frame: (with history, without)
    try:
        for k, camera in enumerate(cameras):
            params["to_world"] = camera
            params.update()
            truth = reference(scene, spp=64)
            errors.append((flip(history[k].image, truth), flip(plain[k].image, truth)))
            assert errors[-1][0] <= errors[-1][1] + 0.005, k
            if k == 0:  # no history yet: the same frame
                assert np.allclose(np.array(history[0].image), np.array(plain[0].image), rtol=1e-4, atol=1e-5)
        mean = np.mean(errors, axis=0)
        # better on the whole path; raw, the last frame too (denoised, it is level: 0.139 against 0.138)
        assert mean[0] < mean[1] and (denoise or errors[-1][0] < errors[-1][1]), (mean, errors[-1])
    finally:
        params["to_world"] = mi.ScalarTransform4f(start)
        params.update()


def test_nested_selection_only_adds_objects():
    """From the cost of the first node (by R/C) up, more budget only adds nodes; below it, a budget
    that affords some node selects one (never nothing while a node fits)."""
    rng = np.random.default_rng(0)
    for _ in range(50):
        nodes = [Node(k, float(c), float(r)) for k, (c, r) in enumerate(rng.random((12, 2)))]
        first = max(nodes, key=lambda n: n.relevance / n.cost).cost
        budgets = np.linspace(0, 6, 13)
        chosen = [{n.key for n in select("nested", nodes, budget)} for budget in budgets]
        nested = [c for c, budget in zip(chosen, budgets) if budget >= first]
        assert all(a <= b for a, b in zip(nested, nested[1:]))
        assert all(bool(c) == (budget >= min(n.cost for n in nodes)) for c, budget in zip(chosen, budgets))
    with pytest.raises(Exception, match="relevance=.size. is not one of"):
        hi.render(load(DEFAULT_SCENE, **SIZE), spp=1, relevance="size")


def test_shadow_tier_traces_shadows_alone_with_the_learnt_indirect_light():
    """With a budget, a diffuse object may be traced by its shadow tier: its shadow rays alone,
    its indirect light from the term learnt where it was traced whole. In Sponza (a sun, large
    diffuse walls: the raster layer's error is mostly their missing shadows), three quarters of
    the trace time spent with tiers gives frames far better than the raster layer and about as
    good as the same time spent on whole objects only; the tiers spawn shadow rays alone, and the
    indirect term is learnt. What each run picks depends on its cost model, calibrated on this
    machine's timings: this test's steps run four times in one process
    (docs/results/gpu/issue10/stop46/shadow_tier_cpu.py), the tiers' mean FLIP over four frames
    was 0.029, 0.127 and 0.096 lower and 0.007 higher than without, and a single frame up to 0.016
    higher. So the test compares the mean of four frames, within 0.02; one frame within 0.005, as
    before, failed once in seven runs of the suite. Both sides trace whole objects only
    (``partial_objects=False``): a part, on by default since stop 75, may be bought by either side
    with what its selection leaves, and with parts one suite run scored the side without tiers 0.297
    against the tiers' 0.325 (the script above, ``--partial-objects``: the tiers 0.028-0.091 better
    in four runs of four; docs/results/gpu/issue10/stop75)."""
    scene = load(ROOT / "scenes" / "sponza_mirror.xml", resx=128, resy=72, sponza_dir=str(SHARED_SCENES / "sponza-dabrovic"))
    truth = reference(scene, spp=128)
    camera = camera_of(scene)
    warm = hi.render_sequence(scene, [camera] * 6, spp=1, seed=2)[3:]
    # three quarters: on the CPU the cost model's fixed part alone is 4-14 ms of a ~35 ms trace
    budget = 0.75 * float(np.median([f.stats.times_ms["trace"] for f in warm]))
    n = len(renderer(scene).objects)
    errors = {}
    for tier in (False, True):  # greedy: rows that do not fit are passed over, not the end of the selection
        settings = HybridSettings(budget_ms=budget, shadow_tier=tier, selection="greedy", partial_objects=False)
        state = FrameState()
        for seed in range(8):
            renderer(scene).render(settings, seed=seed, spp=1, state=state, layers=False)
        # the first four of the next frames that trace something: a frame whose cost model was
        # calibrated while the machine was busy may trace nothing at all, and each such frame
        # teaches the model its fixed part (a trace of zero rays) and drops one outlier from it
        # (budget.CostModel.forget_slowest): four frames were seen not to be enough in about one
        # run in five on the CI machine before the first of these
        frames = (renderer(scene).render(settings, seed=seed, spp=1, state=state, layers=False) for seed in range(9, 21))
        traced = list(itertools.islice((f for f in frames if f.stats.selected), 4))
        assert len(traced) == 4, "fewer than four of twelve budgeted frames traced something"
        errors[tier] = float(np.mean([flip(f.image, truth) for f in traced]))
        frame = traced[-1]  # the last: its lesson is the state's
        assert all(set(f.stats.shadow_only) <= set(f.stats.selected) for f in traced)
        if not tier:
            assert not frame.stats.shadow_only
            continue
        assert frame.stats.shadow_only
        tiers = [n + k for k, name in enumerate(renderer(scene).objects.names) if name in frame.stats.shadow_only]
        learnt = state.rays_per_pixel[tiers]  # the tier rows (heuristic.Candidates.keys), learnt in this frame
        assert np.all(learnt[:, 0] > 0.5) and np.all(learnt[:, 1:] == 0), learnt  # shadow rays only
        assert np.isfinite(state.indirect).all(axis=1).any() and np.nanmax(state.indirect) > 0
    raster = renderer(scene).render(HybridSettings(candidates=""), seed=9, spp=1, state=FrameState(), layers=False)
    errors["raster"] = flip(raster.image, truth)
    assert errors[True] <= errors[False] + 0.02 and errors[True] < errors["raster"] - 0.1, errors


def test_more_budget_never_worsens_the_frame():
    """Budgets 0, 25, 50, 75, 100 % of the all-candidates trace time, planned from the same learnt
    state (cost model, rays and errors per object): the selections are nested and FLIP does not
    rise (tolerance 0.005); the errors learnt rank the objects."""
    scene = load(DEFAULT_SCENE, **SIZE)
    truth = reference(scene)
    camera = camera_of(scene)
    everything = hi.render_sequence(scene, [camera] * 3, spp=1, seed=2)[-1]
    trace_ms = everything.stats.times_ms["trace"]
    integrator = hi.api._integrator({"budget_ms": trace_ms})
    hi.render_sequence(scene, [camera] * 6, spp=1, seed=2)  # warm
    state = FrameState()
    for seed in range(6):  # probes, then calibrated frames: the state a sequence would carry
        renderer(scene).render(integrator.settings, seed=seed, spp=1, state=state, layers=False)
    assert np.nanmax(state.error_per_pixel) > 0
    selected, errors = [], []
    for fraction in (0.0, 0.25, 0.5, 0.75, 1.0):
        settings = HybridSettings(budget_ms=max(fraction * trace_ms, 1e-6)) if fraction < 1 else HybridSettings()
        frame = renderer(scene).render(settings, seed=7, spp=1, state=copy.deepcopy(state), layers=False)
        selected.append(set(frame.stats.selected))
        errors.append(flip(frame.image, truth))
    assert all(a <= b for a, b in zip(selected, selected[1:])), selected
    assert all(b <= a + 0.005 for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < errors[0]


def test_learnt_ambient_brings_untraced_pixels_closer():
    """Frames that trace every object learn each object's ambient irradiance E (traced − raster,
    per albedo); a frame that then traces nothing shows the raster layer plus albedo × E, which
    is closer to the truth than the bare raster layer (and is the layer the image shows)."""
    scene = load(DEFAULT_SCENE, **SIZE)
    truth = reference(scene)
    state = FrameState()
    for seed in range(3):
        renderer(scene).render(HybridSettings(), seed=seed, spp=1, state=state, layers=False)
    assert np.isfinite(state.ambient).all(axis=1).any()
    nothing = HybridSettings(candidates="", denoise=False)
    bare = renderer(scene).render(nothing, seed=9, spp=1, state=FrameState())
    learnt = renderer(scene).render(nothing, seed=9, spp=1, state=copy.deepcopy(state))
    assert np.allclose(np.array(learnt.image), learnt.layers["raster"], rtol=1e-5, atol=1e-6)
    assert flip(learnt.image, truth) < flip(bare.image, truth) - 0.05
    off = renderer(scene).render(HybridSettings(candidates="", denoise=False, learn_ambient=False), seed=9, spp=1,
                                 state=copy.deepcopy(state))
    assert np.allclose(np.array(off.image), np.array(bare.image), rtol=1e-5, atol=1e-6)


def test_objects_never_traced_take_the_typical_learnt_term_never_a_shadow():
    """An object's learnt E is its residual per albedo: huge where its albedo is small, negative
    where it lies in shadows the raster layer lacks. An object never traced takes, per channel,
    the median of the learnt rows, never below zero (``lighting.ambient_table``)."""
    from hybrid_integrator.lighting import ambient_table

    nan = [np.nan] * 3
    learnt = np.array([[244.0, 121.0, 95.0], [0.1, 0.2, 0.1], nan, [0.3, 0.4, -0.1], [-0.6, -0.6, -0.7], nan])
    table = ambient_table(learnt, 6)
    assert np.allclose(table[[0, 1, 3, 4]], learnt[[0, 1, 3, 4]])  # learnt rows: their own
    assert np.allclose(table[[2, 5]], [[0.2, 0.3, 0.0]] * 2)  # medians 0.2, 0.3, -0.05 -> 0
    assert np.allclose(ambient_table(np.array([[-0.3, -0.2, -0.4], nan]), 2)[1], 0.0)  # a shadow alone
    assert np.allclose(ambient_table(np.zeros((0, 3)), 3), 0.0)  # nothing learnt


def test_learnt_ambient_never_darkens_or_floods_the_objects_never_traced():
    """On the 226 objects' camera path, ten objects traced (the floor, boxes, glossy spheres) and
    the rest never: with the learnt term each frame is no further from the truth than without it,
    and closer at one pose. (With the mean of the learnt rows for the objects never traced, as
    before, the glossy spheres' E of up to 512 flooded them at one pose, FLIP 0.204 -> 0.269, and
    the floor's shadows darkened them at the other, 0.306 -> 0.507.)"""
    from hybrid_integrator.bench import path_cameras
    from hybrid_integrator.raster.camera import camera_pose

    scene = load(ROOT / "scenes" / "many_objects.xml", resx=160, resy=90)
    cameras = path_cameras(ROOT / "scenes" / "many_objects.xml", 40)
    traced = "floor,box_7_7,box_6_5,box_8_6,sphere_6_6,sphere_8_7,sphere_2_7,sphere_4_7,sphere_4_5,box_2_9"
    gains = []
    with hi.api.posed(scene.sensors()[0]) as place:
        for at in (10, 19):
            place(camera_pose(cameras[at]))
            truth = reference(scene, spp=64)
            errors = {}
            for on in (False, True):
                integrator = hi.api._integrator({"candidates": traced, "learn_ambient": on, "denoise": False})
                frames = [integrator.render_result(scene, seed=k, spp=1, layers=False) for k in range(4)]
                errors[on] = flip(frames[-1].image, truth)
            assert errors[True] <= errors[False] + 0.005, (at, errors)
            gains.append(errors[False] - errors[True])
    assert max(gains) > 0.01, gains


def test_secondary_spp_traces_more_paths_from_each_raster_hit():
    """``secondary_spp=4``: four paths from each traced pixel's one primary hit, averaged. The
    pixels traced are the same, the rays four times as many, the image converges to the same
    truth (its mean radiance) and is less noisy than a frame of one path per hit."""
    scene = load(DEFAULT_SCENE, **SIZE)
    truth = reference(scene)
    one, four = ([hi.render(scene, spp=1, seed=s, denoise=False, layers=False, secondary_spp=k) for s in range(3)]
                 for k in (1, 4))
    assert all(a.stats.pixels_traced == b.stats.pixels_traced > 0 for a, b in zip(one, four))
    assert all(3.5 * a.stats.secondary_rays < b.stats.secondary_rays < 4.5 * a.stats.secondary_rays
               for a, b in zip(one, four))
    mean = np.mean([np.array(f.image)[..., :3] for f in four], axis=0)
    assert abs(mean.mean() / truth[..., :3].mean() - 1) < 0.03  # 1.5 % here, one path per hit 2.2 %
    assert max(flip(f.image, truth) for f in four) < 0.85 * min(flip(f.image, truth) for f in one)
    with pytest.raises(Exception, match="secondary_spp=0 must be >= 1"):
        hi.render(scene, spp=1, secondary_spp=0)


def test_resolve_keeps_the_denoised_image_until_the_history_explains_the_difference():
    """The resolve of a denoised history (temporal.py): the film-filtered mean where the denoiser's
    change is larger than the mean's noise explains, the denoised image where the history is
    noisy or younger than three frames."""
    from hybrid_integrator.temporal import Accumulator, History

    w, h = 8, 4
    n = w * h

    def resolved(frames: float, variance: float) -> np.ndarray:
        mean = mi.Float(np.full(3 * n, 0.5, np.float32))
        history = History(color=mean, square=mi.Float(np.full(3 * n, 0.25 + variance, np.float32)), film=mean,
                          count=mi.Float(np.full(n, frames, np.float32)), surface=None, world_to_clip=np.eye(4),
                          eye=np.zeros(3), width=w, height=h)
        denoised = mi.TensorXf(mi.Float(np.full(3 * n, 0.6, np.float32)), (h, w, 3))
        return np.array(Accumulator(freeze=False).resolve(denoised, history))

    assert np.allclose(resolved(8, 0.0), 0.5)  # a converged history: its mean
    assert np.allclose(resolved(2, 0.0), 0.6)  # two frames: no variance to trust
    assert np.allclose(resolved(8, 1.0), 0.6)  # a noisy history: the denoiser's image
    middle = resolved(64, 0.05)  # in between: a mix of the two
    assert np.all((middle > 0.5) & (middle < 0.6)), middle


def test_resolved_still_history_beats_its_plain_mean_and_its_first_frame():
    """Sixteen still frames, denoised and resolved: closer to the truth than the plain mean of the
    same frames (0.127 against 0.139 here) and than the first frame (0.204), which has no
    history and is the denoised frame itself."""
    scene = load(DEFAULT_SCENE, **SIZE)
    truth = reference(scene)
    cameras = [camera_of(scene)] * 16
    resolved = hi.render_sequence(scene, cameras, spp=1, seed=1, temporal=True, layers=False)
    mean = hi.render_sequence(scene, cameras, spp=1, seed=1, temporal=True, denoise=False, layers=False)
    single = hi.render(scene, spp=1, seed=1, layers=False)
    # the first frame has no history: the denoised frame itself
    assert np.allclose(np.array(resolved[0].image), np.array(single.image), rtol=1e-4, atol=1e-5)
    errors = [flip(f.image, truth) for f in (resolved[-1], mean[-1], resolved[0])]
    assert errors[0] < errors[1] and errors[0] < 0.7 * errors[2], errors
