"""Bad input gets a clear error that names the problem."""
from __future__ import annotations

import mitsuba as mi
import numpy as np
import pytest

import hybrid_integrator as hi
from hybrid_integrator.cli import main as cli
from hybrid_integrator.scene import load_scene
from conftest import DEFAULT_SCENE, load


def test_non_jit_variant(capsys):
    mi.set_variant("scalar_rgb")
    try:
        scene = mi.load_dict({"type": "scene", "sensor": {"type": "perspective"}, "s": {"type": "cube"}})
        with pytest.raises(hi.UnsupportedVariantError, match="'scalar_rgb' is not supported.*llvm_ad_rgb"):
            hi.rasterize(scene)
    finally:
        mi.set_variant("llvm_ad_rgb")
    assert cli(["gbuffer", str(DEFAULT_SCENE), "--variant", "scalar_rgb"]) == 2
    assert "'scalar_rgb' is not supported" in capsys.readouterr().err


def test_unsupported_shape_type(tmp_path):
    curve = tmp_path / "curve.txt"
    curve.write_text("0 0 0 0.1\n0 1 0 0.1\n")
    scene = mi.load_dict({"type": "scene", "sensor": {"type": "perspective"},
                          "hair": {"type": "linearcurve", "filename": str(curve)}})
    with pytest.raises(hi.UnsupportedSceneError, match="shape 'hair' has type 'LinearCurve'"):
        hi.rasterize(scene)


def test_thin_lens_sensor_says_what_to_do():
    """Orthographic sensors are rasterized (the stability catalog checks them against camera rays);
    a thin lens has no single centre of projection: the error says to use camera rays."""
    scene = mi.load_dict({"type": "scene", "s": {"type": "cube"},
                          "sensor": {"type": "thinlens", "aperture_radius": 0.1, "focus_distance": 4}})
    with pytest.raises(hi.UnsupportedSceneError, match="sensor type 'ThinLensCamera' is not supported.*primary='raytrace'"):
        hi.rasterize(scene)
    gb = hi.rasterize(mi.load_dict({"type": "scene", "sensor": {"type": "orthographic"}, "s": {"type": "cube"}}))
    assert gb.hit.any()


def test_crop_window():
    scene = mi.load_dict({"type": "scene", "s": {"type": "cube"}, "sensor": {
        "type": "perspective", "film": {"type": "hdrfilm", "width": 64, "height": 64,
                                        "crop_width": 32, "crop_height": 32, "crop_offset_x": 8}}})
    with pytest.raises(hi.UnsupportedSceneError, match="crop window"):
        hi.rasterize(scene)


def _film_scene(width: int, height: int) -> mi.Scene:
    return mi.load_dict({"type": "scene", "s": {"type": "cube"}, "e": {"type": "constant"}, "sensor": {
        "type": "perspective", "fov_axis": "smaller", "fov": 40, "to_world": mi.ScalarTransform4f().look_at([0, 0, 5], [0, 0, 0], [0, 1, 0]),
        "film": {"type": "hdrfilm", "width": width, "height": height}}})


def test_film_without_pixels():
    """Mitsuba loads a film of width 0; the frame's empty arrays made Dr.Jit abort the process
    (camera rays) or OpenGL refuse its target (the raster)."""
    scene = _film_scene(0, 4)
    with pytest.raises(hi.UnsupportedSceneError, match="film size 0×4 has no pixels"):
        hi.rasterize(scene)
    for primary in ("raster", "raytrace"):
        with pytest.raises(hi.UnsupportedSceneError, match="film size 0×4 has no pixels"):
            hi.render(scene, spp=1, primary=primary)


def test_film_larger_than_the_gl_context_draws():
    """A side past the context's limit (16384 on llvmpipe) names the limit and the way out, camera
    rays, which render it."""
    from hybrid_integrator.raster.context import gl_context, max_target_side

    limit = max_target_side(gl_context())
    scene = _film_scene(limit + 1, 1)
    with pytest.raises(hi.UnsupportedSceneError, match=f"film size {limit + 1}×1 is too large to rasterize.*"
                                                        f"at most {limit} pixels per side.*primary='raytrace'"):
        hi.render(scene, spp=1)
    image = np.array(hi.render(scene, spp=1, primary="raytrace", denoise=False, layers=False).image)
    assert image.shape[:2] == (1, limit + 1) and np.isfinite(image).all() and image.max() > 0


@pytest.mark.parametrize("counts, message", [(["--spp", "0"], "compare: spp=0 must be >= 1"),
                                             (["--gt-spp", "-3"], "compare: gt_spp=-3 must be >= 1")])
def test_compare_sample_counts(tmp_path, capsys, counts, message):
    """A ground truth of 0 samples was rendered with the sampler's count and reported as "0 spp";
    a negative one failed inside Mitsuba's render with a traceback."""
    assert cli(["compare", str(DEFAULT_SCENE), *counts, "-o", str(tmp_path / "c")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "c").exists()


def test_missing_scene_file(tmp_path, capsys):
    with pytest.raises(hi.HybridError, match="scene file not found: .*nowhere.xml"):
        load_scene(tmp_path / "nowhere.xml")
    assert cli(["gbuffer", str(tmp_path / "nowhere.xml")]) == 2
    assert "scene file not found" in capsys.readouterr().err


def test_malformed_scene_file(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text("<scene version='3.0.0'><shape type='cube'>")
    with pytest.raises(hi.HybridError, match="cannot load scene .*bad.xml"):
        load_scene(bad)


def test_nan_geometry():
    mesh = mi.Mesh("broken", 3, 1)
    params = mi.traverse(mesh)
    params["vertex_positions"] = [0, 0, 0, 1, 0, float("nan"), 0, 1, 0]
    params["faces"] = [0, 1, 2]
    params.update()
    scene = mi.load_dict({"type": "scene", "sensor": {"type": "perspective"}, "broken": mesh})
    with pytest.raises(hi.UnsupportedSceneError, match="shape 'broken' has 1 vertices with NaN"):
        hi.rasterize(scene)


def test_bad_aov_and_offset():
    scene = load(DEFAULT_SCENE)
    with pytest.raises(hi.HybridError, match=r"unknown G-buffer AOV\(s\) \['colour'\]"):
        hi.rasterize(scene, aovs=("colour",))
    with pytest.raises(hi.HybridError, match=r"offset \(1.0, 0.5\) must lie in \[0, 1\)"):
        hi.rasterize(scene, offset=(1.0, 0.5))


def test_bad_spp_and_seed():
    """A frame's spp and seed are whole numbers >= 0: 2.5 samples are not truncated to 2, a negative
    seed is not left to NumPy's generator to refuse, ``True`` is no count; the background path of
    a scene without shapes checks them too."""
    scene = load(DEFAULT_SCENE)
    for kwargs, message in (({"spp": 2.5}, r"spp=2.5 is impossible"), ({"spp": -1}, r"spp=-1 is impossible"),
                            ({"spp": True}, r"spp=True is impossible"), ({"spp": "2"}, r"spp='2' is impossible"),
                            ({"seed": -1}, r"seed=-1 is impossible: give a whole number >= 0"),
                            ({"seed": 2.5}, r"seed=2.5 is impossible")):
        with pytest.raises(hi.HybridError, match=message):
            hi.render(scene, **kwargs)
    with pytest.raises(hi.HybridError, match=r"seed=-3 is impossible"):
        hi.render(mi.load_dict({"type": "scene", "sensor": {"type": "perspective"}}), seed=-3)
    assert hi.render(scene, spp=np.int64(1), seed=np.uint32(4)).stats.spp == 1  # NumPy's integers are whole numbers


def test_bad_camera_path(tmp_path):
    """A camera path's poses are checked before any frame: one that is not a 4×4 transform, or not
    finite, is a clear error in ``render_sequence`` and in ``render_frames`` (before a worker
    starts, and nothing written)."""
    scene = load(DEFAULT_SCENE)
    nan = np.full((4, 4), np.nan)
    for cameras, message in (([np.eye(4), None], r"camera pose None is not a 4×4 transform"),
                             ([np.eye(3)], r"is not a 4×4 transform"),
                             ([np.eye(4), nan], r"is not a finite, invertible transform")):
        with pytest.raises(hi.HybridError, match=message):
            hi.render_sequence(scene, cameras, spp=1)
    with pytest.raises(hi.HybridError, match=r"is not a finite, invertible transform"):
        hi.render_frames(DEFAULT_SCENE, [np.eye(4), nan], tmp_path / "frames", spp=1)
    assert not (tmp_path / "frames").exists()


def test_sensor_index_out_of_range():
    with pytest.raises(hi.UnsupportedSceneError, match="sensor index 3 is out of range"):
        hi.rasterize(load(DEFAULT_SCENE), sensor=3)


@pytest.mark.parametrize("lights", [{}, {"sky": {"type": "constant"}}], ids=["empty", "only an emitter"])
def test_scene_without_shapes(lights):
    """Nothing to draw or trace: the frame is Mitsuba's own render of the background (black, or the
    environment), recorded as a fallback; the raster stage alone says there is nothing to draw."""
    scene = mi.load_dict({"type": "scene", **lights,
                          "sensor": {"type": "perspective", "film": {"type": "hdrfilm", "width": 16, "height": 8}}})
    result = hi.render(scene, spp=1)
    path = mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=1)
    assert np.allclose(np.array(result.image), np.array(path)) and np.isfinite(np.array(result.image)).all()
    assert np.array(result.image).mean() == (1.0 if lights else 0.0)
    assert "no shapes" in result.stats.fallback
    with pytest.raises(hi.UnsupportedSceneError, match="the scene has no shapes"):
        hi.api.renderer(scene)
