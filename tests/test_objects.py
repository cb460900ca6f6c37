"""Objects inside a scene batched by material (objects.py), the device-side compaction, and the
frozen device pass where the scene has no table lights (issue 10)."""
from __future__ import annotations

import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.objects import MERGE_PREFIX
from hybrid_integrator.selection import compact
from conftest import DEFAULT_SCENE, ROOT, load

MANY = ROOT / "scenes" / "many_objects.xml"


def test_batching_keeps_every_object_and_the_image():
    """226 objects, 10 materials: 18 Mitsuba shapes; every file id is still an object, and Mitsuba's
    path renders the batched scene as the unbatched one."""
    batched = load(MANY, resx=64, resy=36)
    apart = hi.load_scene(MANY, batch=False, resx=64, resy=36)
    objects = hi.scene_objects(batched)
    assert len(batched.shapes()) == 18 and len(objects) == len(apart.shapes()) == 226
    assert sorted(objects.names) == sorted(s.id() for s in apart.shapes())
    assert any(s.id().startswith(MERGE_PREFIX) for s in batched.shapes())
    assert objects.faces.sum() == sum(s.face_count() for s in apart.shapes())
    integrator = mi.load_dict({"type": "path", "max_depth": 4})
    a = np.array(mi.render(apart, integrator=integrator, spp=8, seed=1))
    b = np.array(mi.render(batched, integrator=integrator, spp=8, seed=1))
    assert np.allclose(a, b, atol=1e-5)


def test_every_pixel_names_the_object_the_ray_tracer_hits():
    """The raster's object per pixel (through the triangle → object table of the merged meshes)
    is the object the unbatched scene's ray tracer hits."""
    batched = load(MANY, resx=160, resy=90)
    apart = hi.load_scene(MANY, batch=False, resx=160, resy=90)
    gb = hi.rasterize(batched)
    sensor = apart.sensors()[0]
    from hybrid_integrator.primary import camera_rays

    pi = apart.ray_intersect_preliminary(camera_rays(sensor, 160, 90, (0.5, 0.5)))
    valid = np.array(pi.is_valid()).reshape(90, 160)
    ids = [s.id() for s in apart.shapes()]
    truth = np.where(valid, np.array(pi.shape_index, dtype=np.int64).reshape(90, 160), -1)
    seen = np.array([gb.shape_ids[i] if i >= 0 else "" for i in gb.shape_index.ravel()]).reshape(90, 160)
    expected = np.array([ids[i] if i >= 0 else "" for i in truth.ravel()]).reshape(90, 160)
    assert np.mean(seen == expected) >= 0.995
    assert len(set(seen[gb.hit].ravel())) > 20


def test_an_object_inside_a_merged_mesh_can_be_the_only_candidate():
    scene = load(MANY, resx=160, resy=90)
    gb = hi.rasterize(scene)
    objects = hi.scene_objects(scene)
    visible = [objects.names[i] for i in np.unique(gb.shape_index[gb.hit])]
    name = next(n for n in visible if n.startswith("box") and np.sum(gb.shape_index == objects.index(n)) > 30)
    frame = hi.render(scene, spp=1, candidates=name, effects="shadow")
    assert frame.stats.selected == (name,)
    traced = frame.layers["traced"] > 0.5
    mine = gb.shape_index == objects.index(name)
    assert traced.sum() > 0 and np.mean(mine[traced]) > 0.9  # the traced layer is filtered: its edges blur


@pytest.mark.parametrize("n, density", [(1, 1.0), (97, 0.3), (1000, 0.0), (4096, 0.05), (5000, 0.5)])
@pytest.mark.parametrize("two_level", [False, True])
def test_compaction_on_the_device(n, density, two_level):
    """One prefix sum (the LLVM backend's) or two levels (CUDA's: blocks of 1024 lanes, then their
    totals; 5000 lanes end in a part block) give the same slots."""
    rng = np.random.default_rng(n)
    mask = rng.random(n) < density
    index, active, slot = compact(mi.Bool(mask), two_level=two_level, regions=1)
    expected = np.nonzero(mask)[0]
    assert np.array_equal(np.array(active), np.arange(n) < len(expected))
    assert np.array_equal(np.array(index)[:len(expected)], expected)
    assert np.array_equal(np.array(slot)[expected], np.arange(len(expected)))  # each set lane's place


@pytest.mark.parametrize("n, density, regions", [(100, 0.5, 2), (130, 0.3, 2), (57600, 0.17, 2), (57600, 1.0, 3),
                                                (5000, 0.02, 4), (64, 1.0, 2)])
def test_compaction_deals_the_set_lanes_over_regions(n, density, regions):
    """On the LLVM backend the packed lanes are dealt over equal parts of the width, a chunk of 64 at
    a time (a block per thread): still one lane per set lane, each set lane's index where its slot
    says; every part holds its share of them (to a chunk); the lanes past the parts keep their place."""
    from hybrid_integrator.selection import SPREAD_CHUNK

    rng = np.random.default_rng(n)
    mask = rng.random(n) < density
    index, active, slot = (np.array(a) for a in compact(mi.Bool(mask), regions=regions))
    expected = np.nonzero(mask)[0]
    assert active.sum() == len(expected) and len(set(slot[expected].tolist())) == len(expected)
    assert active[slot[expected]].all() and np.array_equal(index[slot[expected]], expected)
    part = n // (SPREAD_CHUNK * regions) * SPREAD_CHUNK
    if part:
        busy = [int(active[r * part:(r + 1) * part].sum()) for r in range(regions)]
        assert max(busy) - min(busy) <= SPREAD_CHUNK, busy
        assert np.array_equal(np.nonzero(active[regions * part:])[0] + regions * part,
                              np.arange(regions * part, n)[np.arange(regions * part, n) < len(expected)])


def test_dealt_lanes_trace_the_same_image(monkeypatch):
    """The lanes' order changes no pixel: each pixel's random numbers are its own (unfrozen frames,
    every candidate traced, lanes dealt over two parts or packed). The same to the order of the
    film's atomic sums, which two renders of one configuration differ by too (1.2e-7 here)."""
    import functools
    from hybrid_integrator import trace
    from hybrid_integrator.api import renderer
    from hybrid_integrator.budget import FrameState
    from hybrid_integrator.pipeline import HybridSettings

    scene = load(DEFAULT_SCENE, resx=64, resy=48)
    settings = HybridSettings(denoise=False, freeze=False)
    dealt = renderer(scene).render(settings, seed=3, spp=1, state=FrameState(), layers=False)
    monkeypatch.setattr(trace, "compact", functools.partial(trace.compact, regions=1))
    packed = renderer(scene).render(settings, seed=3, spp=1, state=FrameState(), layers=False)
    assert dealt.stats.pixels_traced == packed.stats.pixels_traced > 0
    assert np.allclose(np.array(dealt.image), np.array(packed.image), rtol=1e-5, atol=1e-6)


def test_frozen_pass_without_table_lights_equals_the_unfrozen_one():
    """Only an environment: the light table is empty, which a frozen function cannot take as an
    input (the renderer passes one unused light)."""
    scene = mi.load_dict({
        "type": "scene", "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.8, 0.9, 1.0]}},
        "floor": {"type": "rectangle", "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(2.0),
                  "bsdf": {"type": "diffuse"}},
        "block": {"type": "cube", "to_world": mi.ScalarTransform4f().translate([0, 0.5, 0]).scale(0.4),
                  "bsdf": {"type": "conductor"}},
        "sensor": {"type": "perspective", "fov": 50, "to_world": mi.ScalarTransform4f().look_at([0, 2, 4], [0, 0, 0], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 48, "height": 32}}})
    frozen = [hi.render(scene, spp=1, seed=s) for s in range(3)]
    plain = hi.render(scene, spp=1, seed=2, freeze=False)
    assert np.allclose(np.array(frozen[-1].image), np.array(plain.image), rtol=1e-5, atol=1e-6)
    assert frozen[-1].stats.rays == plain.stats.rays and plain.stats.secondary_rays > 0


def test_frame_statistics_come_from_one_synchronization():
    frame = hi.render(load(DEFAULT_SCENE), spp=2)
    t = frame.stats.times_ms
    assert all(t[k] >= 0 for k in t) and t["trace"] > 0 and t["lighting"] > 0
    assert t["total"] >= t["issue"] > 0
    assert set(frame.stats.host_ms) == {"setup", "select", "raster", "replay", "develop", "post", "readback", "ahead", "timing"}
    assert frame.stats.host_ms["replay"] > 0 and frame.stats.host_ms["timing"] > 0
    # the wall clock until the statistics are on hand: every host phase, the stage times' readout too
    assert t["total"] >= sum(frame.stats.host_ms.values()) - 1e-6


def test_the_history_reader_gives_drjits_entries_without_their_source():
    """``history.reader`` reads Dr.Jit's kernel history through its C API: the same launches as
    ``drjit.kernel_history`` (type, width, hash, operations), without the kernels' source."""
    import drjit as dr

    from hybrid_integrator import history

    read = history.reader()
    assert history.READER == "C API"  # this machine's Dr.Jit: the layout check passed

    def launches(n: int):
        x = dr.arange(mi.Float, n)
        y = dr.sin(x) * 2 + dr.sqrt(x)
        dr.eval(y, dr.sum(y))

    with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
        got = []
        for reader in (dr.kernel_history, read):
            dr.kernel_history_clear()
            launches(1000)
            launches(37)
            got.append(reader())
    theirs, ours = got
    keys = ("type", "size", "hash", "operation_count")
    assert len(ours) == len(theirs) >= 2
    assert [tuple(e.get(k) for k in keys) for e in ours] == [tuple(e.get(k) for k in keys) for e in theirs]
    assert all("ir" not in e and e["execution_time"] >= 0 for e in ours) and all("ir" in e for e in theirs if "hash" in e)
    with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
        assert read() == []  # read, then cleared


def test_the_history_reader_falls_back_to_drjits_where_the_c_api_is_missing(monkeypatch):
    import drjit as dr

    from hybrid_integrator import history

    monkeypatch.setattr(history, "_READER", None)
    monkeypatch.setattr(history, "READER", history.READER)
    monkeypatch.setattr(history, "_load", lambda: None)  # the symbol not found
    assert history.reader() is dr.kernel_history and history.READER == "drjit.kernel_history"


def test_a_process_first_frame_says_its_draw_was_not_timed():
    """Mesa's llvmpipe answers the timer query of a process's first draw with 2**32 - 1 ns (4295
    ms in the frame's stats until now): that frame's ``gl`` is NaN, its raster stage the kernels'
    time alone, and the next frame's draw is timed (a fresh process: the suite has drawn before)."""
    import subprocess
    import sys

    code = ("import mitsuba as mi; mi.set_variant('llvm_ad_rgb'); import hybrid_integrator as hi\n"
            f"scene = hi.load_scene({str(DEFAULT_SCENE)!r}, resx=32, resy=24)\n"
            "for seed in range(2):\n"
            "    t = hi.render(scene, spp=1, seed=seed, denoise=False, raster='draw').stats.times_ms\n"
            "    print(t['gl'], t['raster'], t['total'])")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    (gl0, raster0, total0), (gl1, raster1, total1) = (map(float, line.split()) for line in done.stdout.split("\n")[-3:-1])
    assert (np.isnan(gl0) or 0 < gl0 < total0) and 0 < raster0 < total0
    assert 0 < gl1 < raster1 < total1


def test_next_seeds_offsets_made_ahead_are_the_same_frame():
    """A frame makes the next seed's sub-pixel offsets while the GPU traces (``pipeline.py``):
    a frame whose offsets were made ahead equals one whose were not."""
    from hybrid_integrator.api import renderer
    from hybrid_integrator.pipeline import subpixel_offsets

    scene = load(DEFAULT_SCENE, resx=64, resy=48)
    props = dict(spp=2, denoise=False, learn_ambient=False)
    hi.render(scene, seed=4, **props)
    assert renderer(scene)._next_offsets == {(2, 5): subpixel_offsets(2, 5)}
    ahead = np.array(hi.render(scene, seed=5, **props).image)  # offsets from the memo
    hi.render(scene, seed=9, **props)
    fresh = np.array(hi.render(scene, seed=5, **props).image)  # not: the memo holds seed 10's
    # equal but for the last bits: the CPU backend's atomic sums (the film's filter) are not
    # bit-reproducible within a process either (docs/results/cpu/reproducibility); other
    # offsets move every edge pixel
    assert np.abs(ahead - fresh).max() <= 1e-6 and ahead.mean() > 0


def test_a_still_camera_draws_the_next_frame_ahead():
    """``raster_ahead="on"`` (``auto`` turns it on where interop orders OpenGL after CUDA: the
    GPU): once the camera has stood still for a frame, each frame draws the next one's visibility
    buffer at its end, and the next frame uses it, with the same image as a frame that draws its
    own. A buffer drawn for a frame that does not come (the camera moved, or another pass drew
    into the target since) is discarded and counted, and the frame draws its own."""
    from hybrid_integrator.api import renderer
    from hybrid_integrator.raster.camera import RasterCamera

    scene = hi.load_scene(DEFAULT_SCENE, resx=64, resy=48)  # its own: the test moves its camera
    props = dict(spp=1, denoise=False, learn_ambient=False)

    def frames(seeds, ahead):
        results = [hi.render(scene, seed=s, raster_ahead=ahead, **props) for s in seeds]
        return [np.array(r.image) for r in results], [(r.stats.raster_ahead, r.stats.raster_discarded) for r in results]

    with pytest.raises(hi.HybridError, match="raster_ahead='maybe' is not one of"):
        hi.render(scene, raster_ahead="maybe", **props)
    own, counts = frames(range(4), "off")
    assert counts == [(0, 0)] * 4
    drawn, counts = frames(range(4), "on")
    assert counts == [(0, 0), (0, 0), (1, 0), (1, 0)]  # the first frame's camera is new: nothing drawn ahead
    # equal but for the last bits (the CPU backend's atomic sums: test above)
    assert all(np.abs(a - b).max() <= 1e-6 for a, b in zip(own, drawn)) and own[3].mean() > 0
    # a frame of another set-up comes instead: it discards the buffer (and draws nothing ahead)
    assert frames([4], "off")[1] == [(0, 1)]
    assert frames([5, 6], "on")[1] == [(0, 0), (1, 0)]
    raster = renderer(scene).raster  # another pass draws into the target: the buffer drawn ahead is stale
    raster.render(RasterCamera.from_sensor(scene.sensors()[0]), (0.25, 0.75))
    assert frames([7], "on")[1] == [(0, 1)]
    params = mi.traverse(scene.sensors()[0])
    params["to_world"] = mi.Transform4f().translate([0.05, 0.0, 0.0]) @ params["to_world"]
    params.update()
    moved, counts = frames([8, 9, 10], "on")
    # the camera moved: seed 8 discards what seed 7 drew; its camera is new, so it draws nothing ahead
    assert counts == [(0, 1), (0, 0), (1, 0)]
    assert np.abs(moved[2] - frames([10], "off")[0][0]).max() <= 1e-6


def test_a_camera_path_draws_each_next_frame_ahead():
    """On a camera path (``render_sequence`` gives each frame the next pose), every frame but the
    first starts from the raster pass the frame before drew for its pose, with the same image as
    frames that draw their own; the sensor's pose is restored after."""
    from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix

    scene = hi.load_scene(DEFAULT_SCENE, resx=64, resy=48)
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    eye, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    cameras = hi.camera_path([(eye, target), (eye + [0.1, 0.05, 0.0], target)], 4)
    props = dict(spp=1, denoise=False, learn_ambient=False, layers=False)
    own = hi.render_sequence(scene, cameras, raster_ahead="off", **props)
    drawn = hi.render_sequence(scene, cameras, raster_ahead="on", **props)
    assert [(r.stats.raster_ahead, r.stats.raster_discarded) for r in drawn] == [(0, 0)] + [(1, 0)] * 3
    images = [(np.array(a.image), np.array(b.image)) for a, b in zip(own, drawn)]
    assert all(np.abs(a - b).max() <= 1e-6 for a, b in images)  # as the test above
    assert np.abs(images[0][0] - images[3][0]).max() > 0.05  # the camera did move
    assert np.array_equal(transform_matrix(sensor_to_world(scene.sensors()[0])), start)
    # a next pose that is no transform is named before the frame does anything
    for bad in (np.zeros((4, 4)), np.full((4, 4), np.nan), [1.0, 2.0]):
        with pytest.raises(hi.HybridError, match="camera pose .* is not a"):
            hi.api._integrator({"raster_ahead": "on"}).render_result(scene, spp=1, next_camera=bad)


@pytest.mark.parametrize("n, density", [(1, 1.0), (97, 0.3), (1000, 0.0), (4096, 0.05), (2**22 + 3, 0.5)])
@pytest.mark.parametrize("groups", [1, 2])
@pytest.mark.parametrize("two_level", [False, True])
def test_compaction_puts_the_first_lanes_first(n, density, groups, two_level):
    """With ``first`` masks, the set lanes of the first come first, then those of the second not
    in the first, then the rest, each part in pixel order (a stable partition: the trace launches
    its re-traced primaries, then its long paths, first). 2²² + 3 lanes: the parts' counts need
    23 bits each, two to a 64-bit prefix sum, so three parts take two."""
    rng = np.random.default_rng(n + 1)
    mask, first = rng.random(n) < density, [rng.random(n) < 0.4 for _ in range(groups)]
    index, active, slot = compact(mi.Bool(mask), *(mi.Bool(f) for f in first), None, two_level=two_level, regions=1)
    taken, expected = np.zeros(n, dtype=bool), []
    for part in [*first, np.ones(n, dtype=bool)]:
        expected.append(np.nonzero(mask & part & ~taken)[0])
        taken |= part
    expected = np.concatenate(expected)
    assert np.array_equal(np.array(active), np.arange(n) < len(expected))
    assert np.array_equal(np.array(index)[:len(expected)], expected)
    assert np.array_equal(np.array(slot)[expected], np.arange(len(expected)))


def test_glass_is_what_the_trace_launches_first():
    """The device pass partitions its traced pixels (glass first) where a candidate refracts:
    dielectrics, rough or smooth; not thin glass (a null lobe: its paths pass straight through),
    diffuse, conductors or plastic."""
    from hybrid_integrator.selection import refracts

    bsdf = lambda kind: mi.load_dict({"type": kind})  # noqa: E731
    for kind in ("dielectric", "roughdielectric"):
        assert refracts([bsdf("diffuse"), bsdf(kind)]), kind
    assert not refracts([bsdf("thindielectric"), bsdf("diffuse"), bsdf("conductor"), bsdf("roughplastic"), None])
    assert not refracts([])
