"""The raster's visibility buffer against Mitsuba's own ray tracer (issue 2 acceptance).

Through the same sub-pixel positions, shape and triangle must agree on >= 99.9 % of pixels,
hit/miss on >= 99.9 %, and the median relative depth error must be <= 1e-4."""
from __future__ import annotations

import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.raster.agreement import visibility_agreement
from conftest import DEFAULT_SCENE, ROOT, SHARED_SCENES, load, make_sensor

SCENES = {
    "default": DEFAULT_SCENE,
    "showcase": SHARED_SCENES / "cbox/showcase_coloured_glass.xml",
    "armadillo": SHARED_SCENES / "models/armadillo.xml",
    "sponza": SHARED_SCENES / "sponza-dabrovic/scene.xml",
}

# (label, width, height, fov_axis, principal point offset, sub-pixel offset); None = the scene's own sensor
CONFIGS = [
    ("1280x720 own sensor", 1280, 720, None, (0.0, 0.0), (0.5, 0.5)),
    ("1280x720 jittered offset", 1280, 720, None, (0.0, 0.0), (0.13, 0.77)),
    ("square fov x", 512, 512, "x", (0.0, 0.0), (0.5, 0.5)),
    ("portrait fov y", 360, 640, "y", (0.0, 0.0), (0.9, 0.05)),
    ("1280x720 principal point", 1280, 720, "x", (0.04, -0.03), (0.5, 0.5)),
]


def check(scene, sensor, offset, method="auto"):
    gb = hi.rasterize(scene, sensor=sensor, offset=offset, method=method)
    a = visibility_agreement(scene, sensor if not isinstance(sensor, int) else scene.sensors()[sensor], gb)
    assert gb.shape_index.shape == (a.pixels // gb.shape_index.shape[1], gb.shape_index.shape[1])
    assert gb.hit.mean() > 0.05, "the view must show some geometry for the check to mean anything"
    assert a.hit_miss >= 0.999, a
    assert a.shape_and_triangle >= 0.999, a
    assert a.median_relative_depth_error <= 1e-4, a
    return gb


@pytest.mark.parametrize("config", CONFIGS, ids=[c[0] for c in CONFIGS])
@pytest.mark.parametrize("name", list(SCENES))
def test_agreement_with_ray_tracer(name, config):
    label, width, height, fov_axis, ppo, offset = config
    scene = load(SCENES[name], resx=1280, resy=720)
    sensor = 0 if fov_axis is None else make_sensor(scene, width, height, fov_axis, ppo)
    gb = check(scene, sensor, offset)
    assert gb.depth.shape == (height, width)


@pytest.mark.parametrize("config", [CONFIGS[1], CONFIGS[3]], ids=[CONFIGS[1][0], CONFIGS[3][0]])
@pytest.mark.parametrize("name", list(SCENES))
def test_compute_pass_agrees_with_ray_tracer(name, config):
    """The visibility pass in compute shaders (raster/compute.py) meets the draw's bar."""
    label, width, height, fov_axis, ppo, offset = config
    scene = load(SCENES[name], resx=1280, resy=720)
    sensor = 0 if fov_axis is None else make_sensor(scene, width, height, fov_axis, ppo)
    check(scene, sensor, offset, method="compute")


def test_compute_pass_keeps_thin_parts_in_order():
    """The glass Armadillo's 400k triangles are about a pixel each, and its fingers and ears are
    thin: a depth computed with too little precision puts their far side in front. The compute
    pass must agree with the camera rays as well as the draw does (both 99.97 % here)."""
    scene = load(ROOT / "scenes/armadillo_glass.xml", resx=1280, resy=720, models_dir=str(SHARED_SCENES / "models"))
    for method in ("draw", "compute"):
        gb = hi.rasterize(scene, offset=(0.13, 0.77), method=method)
        assert visibility_agreement(scene, scene.sensors()[0], gb).shape_and_triangle >= 0.9996, method


def test_compute_pass_is_the_draw_but_for_ties():
    """Inside Sponza every tier of the compute pass is used (small triangles one per invocation,
    medium ones by 64 invocations each, large ones and those crossing the eye's plane by tiles); the
    visibility buffer is the draw's but where a pixel centre lies on a shared edge or two faces
    are at one depth, and the frame rendered from it is the same."""
    from hybrid_integrator.raster.camera import RasterCamera

    scene = load(SCENES["sponza"], resx=192, resy=108)
    raster = hi.rasterizer(scene)
    camera = RasterCamera.from_sensor(scene.sensors()[0])
    drawn = raster.read_ids(raster.render(camera, (0.3, 0.6), "draw")).copy()
    computed = raster.read_ids(raster.render(camera, (0.3, 0.6), "compute"))
    large, medium = raster.compute_tiers()
    assert large > 0 and medium > 0 and (computed > 0).mean() > 0.99
    assert np.mean(drawn == computed) >= 0.995
    assert np.array_equal(drawn == 0, computed == 0)
    results = {m: hi.render(scene, spp=1, seed=4, raster=m, denoise=False) for m in ("draw", "compute")}
    assert [results[m].stats.raster_method for m in ("draw", "compute")] == ["draw", "compute"]
    assert np.abs(results["draw"].image - results["compute"].image).max(axis=-1).mean() < 1e-3


def test_compute_passes_of_two_scenes_and_sizes_take_turns():
    """A compute pass binds its buffers and target only when its film size changes or another
    pass bound its own (``raster/compute.py``): passes of two scenes at two sizes, in turn, each
    give what they gave alone."""
    from hybrid_integrator.raster.camera import RasterCamera

    scenes = [load(SCENES["sponza"], resx=96, resy=54), load(DEFAULT_SCENE, resx=64, resy=48)]
    cameras = [RasterCamera.from_sensor(s.sensors()[0]) for s in scenes]
    small = make_sensor(scenes[0], 48, 40, "x", (0.0, 0.0))

    def ids(k, camera):
        raster = hi.rasterizer(scenes[k])
        return raster.read_ids(raster.render(camera, (0.3, 0.6), "compute")).copy()

    alone = [ids(0, cameras[0]), ids(1, cameras[1]), ids(0, RasterCamera.from_sensor(small))]
    turns = [ids(1, cameras[1]), ids(0, cameras[0]), ids(0, RasterCamera.from_sensor(small)), ids(0, cameras[0]),
             ids(1, cameras[1])]
    for got, expected in zip(turns, [alone[1], alone[0], alone[2], alone[0], alone[1]]):
        assert got.shape == expected.shape and np.array_equal(got, expected)
    assert all((a > 0).mean() > 0.3 for a in alone)


def test_one_pass_compute_is_the_two_pass_bit_for_bit_or_names_what_it_needs():
    """With 64-bit atomics (NVIDIA's GL) the compute pass resolves depth and number in one pass:
    it must give the two-pass visibility buffer exactly, on every tier (Sponza). Mesa's llvmpipe
    (CI) has no 64-bit atomics: the one-pass pass, asked for, says which extension it needs, and the
    pass the rasterizer picks is the two-pass one."""
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.raster.compute import ATOMIC64, ComputeVisibility

    scene = load(SCENES["sponza"], resx=192, resy=108)
    raster = hi.rasterizer(scene)
    camera = RasterCamera.from_sensor(scene.sensors()[0])
    fbo = raster.target(camera.width, camera.height)
    passes = {}
    for one_pass in (False, True):
        if one_pass and ATOMIC64 not in raster.ctx.extensions:
            with pytest.raises(RuntimeError, match=ATOMIC64):
                ComputeVisibility(raster.ctx, raster.vertices, raster.faces, len(raster.geometry.faces), one_pass=True)
            assert not ComputeVisibility(raster.ctx, raster.vertices, raster.faces, len(raster.geometry.faces)).one_pass
            continue
        visibility = ComputeVisibility(raster.ctx, raster.vertices, raster.faces, len(raster.geometry.faces), one_pass)
        passes[one_pass] = raster.read_ids(visibility.render(camera, (0.3, 0.6), fbo)).copy()
        assert visibility.tiers()[0] > 0 and visibility.tiers()[1] > 0 and (passes[one_pass] > 0).mean() > 0.99
    if True in passes:
        assert np.array_equal(passes[True], passes[False])


@pytest.mark.parametrize("fov_axis", ["smaller", "larger", "diagonal"])
def test_fov_axis_conventions(fov_axis):
    scene = load(DEFAULT_SCENE)
    for width, height in ((400, 240), (240, 400)):
        check(scene, make_sensor(scene, width, height, fov_axis, (0.02, 0.01)), (0.25, 0.6))


def test_gbuffer_layout_and_background():
    scene = load(DEFAULT_SCENE)
    gb = hi.rasterize(scene)
    h, w = 240, 320
    assert gb.shape_index.shape == (h, w) and gb.shape_index.dtype == np.int32
    assert gb.prim_index.dtype == np.uint32 and gb.bary.shape == (h, w, 2) and gb.bary.dtype == np.float32
    assert gb.depth.dtype == np.float32 and gb.proxy.dtype == bool
    assert not gb.proxy.any()
    ids = [gb.shape_ids[i] for i in np.unique(gb.shape_index[gb.hit])]
    assert {"floor", "ceiling", "back", "redwall", "greenwall", "glass_sphere", "mirror_sphere"} <= set(ids)
    # row 0 is the top of the image: the ceiling is above the floor
    def seen(row, col):
        return gb.shape_ids[gb.shape_index[row, col]] if gb.shape_index[row, col] >= 0 else None

    assert (seen(h // 10, w // 2), seen(h - h // 10, w // 2)) == ("ceiling", "floor")
    # the red wall (x = -1) is on the image's left, as Mitsuba renders it
    assert (seen(h // 2, w // 5), seen(h // 2, w - w // 5)) == ("redwall", "greenwall")
    # the 4:3 film is wider than the box: its left and right edges see the background
    assert seen(h // 2, 0) is None and seen(h // 2, w - 1) is None
    # barycentrics are clamped into the triangle
    b = gb.bary[gb.hit]
    assert (b >= 0).all() and (b.sum(axis=1) <= 1 + 1e-6).all()
    assert np.isinf(gb.depth[~gb.hit]).all() and (gb.shape_index[~gb.hit] == -1).all()


def test_background_pixels_are_misses():
    """A camera that looks past the scene: background is -1 / inf and agrees with the ray tracer."""
    scene = load(SHARED_SCENES / "models/armadillo.xml", resx=320, resy=180)
    gb = check(scene, 0, (0.5, 0.5))
    assert (~gb.hit).any()


def test_geometry_is_uploaded_once_and_reused():
    scene = load(DEFAULT_SCENE)
    first = hi.rasterizer(scene)
    a = hi.rasterize(scene, offset=(0.1, 0.1))
    b = hi.rasterize(scene, offset=(0.9, 0.9))
    assert hi.rasterizer(scene) is first
    # a different sub-pixel position sees different barycentrics on the same triangles
    same = a.hit & b.hit & (a.prim_index == b.prim_index) & (a.shape_index == b.shape_index)
    assert same.sum() > 0.5 * a.hit.sum() and not np.allclose(a.bary[same], b.bary[same])


def test_drawn_vertices_are_numbered_in_order_of_first_use():
    """The rasterizer draws the scene's triangles with their vertices renumbered (a faster
    geometry-bound draw): every triangle keeps its number and its corners, the first triangles
    use the first vertices, and vertices no triangle uses are gone."""
    from hybrid_integrator.raster.geometry import SceneGeometry, scene_geometry

    scene = load(SHARED_SCENES / "models/armadillo.xml", resx=64, resy=36)
    loaded = scene_geometry(scene)
    extra = SceneGeometry(np.concatenate([loaded.positions, [[9.0, 9.0, 9.0]]]).astype(np.float32),
                          loaded.faces, loaded.first_triangle, loaded.proxy)  # one unused vertex
    drawn = extra.renumbered()
    assert np.array_equal(drawn.positions[drawn.faces], loaded.positions[loaded.faces])
    assert len(drawn.positions) == len(np.unique(loaded.faces))
    first_seen = drawn.faces.ravel()[np.sort(np.unique(drawn.faces.ravel(), return_index=True)[1])]
    assert np.array_equal(first_seen, np.arange(len(drawn.positions)))
    # the order depends on the triangles alone, not on how the file numbered its vertices
    order = np.random.default_rng(0).permutation(len(loaded.positions))
    position_of = np.empty_like(order)
    position_of[order] = np.arange(len(order))
    shuffled = SceneGeometry(loaded.positions[order], position_of[loaded.faces].astype(np.uint32),
                             loaded.first_triangle, loaded.proxy).renumbered()
    assert np.array_equal(shuffled.faces, drawn.faces) and np.array_equal(shuffled.positions, drawn.positions)
    assert np.array_equal(hi.rasterizer(scene).geometry.faces, loaded.renumbered().faces)


def test_float_depth_keeps_precision_far_away():
    """A distant camera (1 km): a 24-bit 1/z depth buffer would lose the triangles; reversed-Z
    float depth (context.DepthPrecision) does not.
    (Sub-pixel offset and aim are off-axis so that no rectangle diagonal runs through pixel centres,
    where either triangle is a right answer.)"""
    import mitsuba as mi

    scene = load(DEFAULT_SCENE)
    sensor = mi.load_dict({"type": "perspective", "fov": 0.12, "near_clip": 0.01, "far_clip": 5000.0,
                           "to_world": mi.ScalarTransform4f().look_at(origin=[3, 2, 1000], target=[0.01, 0.02, 0], up=[0, 1, 0]),
                           "film": {"type": "hdrfilm", "width": 320, "height": 240}})
    check(scene, sensor, (0.3, 0.6))


def test_shape_indices_from_pointers_match_mitsuba():
    """The pointer → index map (needed where OptiX leaves shape_index unset) agrees with Embree's."""
    import drjit as dr
    from hybrid_integrator.primary import camera_rays, shape_indices, shape_table

    scene = load(SHARED_SCENES / "cbox/showcase_coloured_glass.xml", resx=1280, resy=720)
    pi = scene.ray_intersect_preliminary(camera_rays(scene.sensors()[0], 1280, 720, (0.5, 0.5)))
    valid = pi.is_valid()
    mapped = np.array(shape_indices(shape_table(scene), pi.shape, valid))[np.array(valid)]
    assert len(np.unique(mapped)) == len(scene.shapes())
    assert np.array_equal(mapped, np.array(pi.shape_index)[np.array(valid)])
    assert dr.width(valid) == 1280 * 720


def test_frame_says_how_the_raster_targets_reached_drjit():
    """CUDA–OpenGL interop needs a CUDA variant; on the CPU the targets go through the host, and
    the frame's statistics say so and why."""
    scene = load(DEFAULT_SCENE)
    frame = hi.render(scene, spp=1)
    assert frame.stats.readback == "host (llvm_ad_rgb is not a CUDA variant)"


def test_raster_camera_follows_a_path_set_from_matrices():
    """``render_frames`` sets the sensor's ``to_world`` from 4×4 matrices. ``traverse`` hands out the
    sensor's own objects, which an update changes in place: the raster camera's cache must not
    mistake a new camera for an old one whose variable indices were freed and reused (it once
    did, and the raster drew frames from stale cameras)."""
    import hybrid_integrator as hi
    from hybrid_integrator.raster import camera as cam

    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    sensor = scene.sensors()[0]
    params = mi.traverse(sensor)
    start = np.array(params["to_world"].matrix).reshape(4, 4)
    origin, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    path = hi.camera_path([(origin, target), (origin + [0.5, 0.2, 0.0], target)], 80)
    stale = 0
    for k, c in enumerate(path):
        params["to_world"] = mi.ScalarTransform4f(cam.transform_matrix(c))
        params.update()
        used = cam.RasterCamera.from_sensor(sensor)
        hi.render(scene, spp=1, seed=k, layers=False, denoise=False)  # the frame's own Dr.Jit work
        kept = dict(cam._CAMERAS)
        cam._CAMERAS.clear()
        fresh = cam.RasterCamera.from_sensor(sensor)
        cam._CAMERAS.clear()
        cam._CAMERAS.update(kept)
        stale += not np.allclose(used.world_to_clip, fresh.world_to_clip)
    assert stale == 0


def test_raster_camera_sees_parameters_changed_through_another_traversal():
    """The raster camera traverses a sensor once and keeps what ``mi.traverse`` returned (the
    sensor's own members): a field of view, principal point and pose set through another
    traversal and ``update()`` must reach it, as a camera built from scratch sees them."""
    import hybrid_integrator as hi
    from hybrid_integrator.raster import camera as cam

    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    sensor = scene.sensors()[0]
    first = cam.RasterCamera.from_sensor(sensor)
    params = mi.traverse(sensor)
    params["x_fov"] = 25.0
    params["principal_point_offset_x"] = 0.1
    params["to_world"] = mi.ScalarTransform4f().look_at([0.3, 1.0, 4.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0])
    params.update()
    seen = cam.RasterCamera.from_sensor(sensor)
    cam._CAMERAS.clear()
    fresh = cam.RasterCamera.from_sensor(sensor)
    assert not np.allclose(seen.world_to_clip, first.world_to_clip)
    assert np.allclose(seen.world_to_clip, fresh.world_to_clip) and np.allclose(seen.eye, [0.3, 1.0, 4.0])
    # the projection is kept apart from the pose: a zoom alone (the same pose) must reach it too
    params["x_fov"] = 40.0
    params.update()
    zoomed = cam.RasterCamera.from_sensor(sensor)
    cam._CAMERAS.clear()
    assert np.allclose(zoomed.world_to_clip, cam.RasterCamera.from_sensor(sensor).world_to_clip)
    assert not np.allclose(zoomed.world_to_clip, fresh.world_to_clip)


def test_relative_clip_is_the_shifted_projection_around_the_eye():
    """The raster pass's matrix (``RasterCamera.relative_clip``, made once per camera and shifted
    per sample by row operations) is the sample's shift times world → clip, with the depth row of
    reversed-Z (or orthographic) depth, taken around the eye: in float32 the very matrix of that
    product, for perspective and orthographic cameras far from the origin."""
    from hybrid_integrator.raster.camera import RasterCamera

    rng = np.random.default_rng(0)
    for orthographic in (False, True):
        for _ in range(20):
            camera = RasterCamera(width=1280, height=720, world_to_clip=rng.normal(size=(4, 4)),
                                  eye=rng.normal(size=3) * 10 ** rng.uniform(0, 6), near_clip=0.01, far_clip=100.0,
                                  orthographic=orthographic, depth_row=rng.normal(size=4))
            ox, oy = rng.random(2)
            shift = np.eye(4)
            shift[0, 3], shift[1, 3] = (1 - 2 * ox) / 1280, (1 - 2 * oy) / 720
            clip = shift @ camera.world_to_clip
            clip[2] = ((np.array([0.0, 0.0, 0.0, 100.0]) - camera.depth_row) / (100.0 - 0.01) if orthographic
                       else (0.0, 0.0, 0.0, 0.01))
            relative, origin = camera.relative_clip((ox, oy))
            expected = clip.copy()
            expected[:, 3] = clip @ np.r_[origin.astype(np.float64), 1.0]
            assert np.array_equal(camera.clip_matrix((ox, oy)).astype(np.float32), clip.astype(np.float32))
            assert np.array_equal(relative.astype(np.float32), expected.astype(np.float32))


def test_place_sensor_moves_the_camera_as_params_update_does_without_reading_back():
    """``raster.camera.place_sensor`` (``api.posed``'s move, stop 56) sets a perspective sensor's
    ``to_world`` without Mitsuba's ``parameters_changed``, whose read-back of the transform waits
    for the device: the sensor then samples the camera rays it samples after ``params.update()``
    (bit for bit), the raster camera built from it equals one built
    from scratch (which reads the transform back), a pose that scales is refused as Mitsuba
    refuses it, and ``posed`` leaves the sensor at its own pose, its host copy refreshed."""
    import hybrid_integrator as hi
    from hybrid_integrator.api import posed
    from hybrid_integrator.raster import camera as cam

    scene = hi.load_scene(DEFAULT_SCENE, resx=32, resy=24)
    sensor = scene.sensors()[0]
    params = mi.traverse(sensor)
    start = cam.transform_matrix(params["to_world"])
    bbox = sensor.bbox()
    origin, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    poses = [cam.camera_pose(c) for c in hi.camera_path([(origin, target), (origin + [0.5, 0.2, 0.0], target)], 5)]
    samples = mi.Point2f(np.linspace(0.0, 1.0, 7, dtype=np.float32), np.linspace(1.0, 0.0, 7, dtype=np.float32))

    def rays() -> np.ndarray:  # the sensor's camera rays through fixed film positions
        ray, _ = sensor.sample_ray(0.0, 0.5, samples, mi.Point2f(0.5))
        return np.concatenate([np.array(ray.o), np.array(ray.d), np.array(ray.maxt)[None]])

    with posed(sensor) as place:
        for pose in poses[1:]:
            place(pose)
            placed = cam.RasterCamera.from_sensor(sensor)
            moved = rays()
            kept = dict(cam._CAMERAS)
            cam._CAMERAS.clear()
            fresh = cam.RasterCamera.from_sensor(sensor)
            cam._CAMERAS.update(kept)
            assert np.array_equal(placed.world_to_clip, fresh.world_to_clip) and np.array_equal(placed.eye, fresh.eye)
            assert np.allclose(cam.transform_matrix(mi.traverse(sensor)["to_world"]), pose)
            other = mi.traverse(sensor)
            other["to_world"] = mi.ScalarTransform4f(pose)
            other.update()
            assert np.array_equal(moved, rays())
        with pytest.raises(hi.HybridError, match="scale"):
            place(poses[1] @ np.diag([2.0, 2.0, 2.0, 1.0]))
    assert np.array_equal(cam.transform_matrix(mi.traverse(sensor)["to_world"]), start)
    assert np.allclose(np.array(sensor.bbox().min), np.array(bbox.min))
