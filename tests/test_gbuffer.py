"""G-buffer targets (paper Table 2) derived from Mitsuba's BSDFs, analytic-shape proxies, EXR output."""
from __future__ import annotations

import json

import drjit as dr
import mitsuba as mi
import numpy as np

import hybrid_integrator as hi
from hybrid_integrator.cli import main as cli
from hybrid_integrator.io import read_exr
from hybrid_integrator.primary import camera_rays, silhouettes
from hybrid_integrator.raster.camera import RasterCamera
from conftest import DEFAULT_SCENE, SHARED_SCENES, load


def pixels_of(gb, name):
    return gb.shape_index == gb.shape_ids.index(name)


def test_analytic_spheres_are_flagged_as_proxies():
    scene = load(SHARED_SCENES / "cbox/cbox_spheres_analytic.xml", res=256, integrator="path")
    gb = hi.rasterize(scene, aovs=("position",))
    objects = hi.scene_objects(scene)
    shapes = [i for i, s in enumerate(scene.shapes()) if s.class_name() == "Sphere"]
    spheres = [int(objects.first_object[i]) for i in shapes]  # an analytic shape is one object
    assert len(spheres) == 2
    # every pixel whose camera ray hits an exact sphere is flagged (the proxy encloses the sphere)
    sensor = scene.sensors()[0]
    h, w = gb.depth.shape
    pi = scene.ray_intersect_preliminary(camera_rays(sensor, w, h, (0.5, 0.5)))
    exact = np.isin(np.where(np.array(pi.is_valid()), np.array(pi.shape_index, dtype=np.int64), -1), shapes).reshape(gb.depth.shape)
    assert exact.sum() > 1000
    assert gb.proxy[exact].all()
    assert np.isin(gb.shape_index[gb.proxy], spheres).all()
    assert not gb.proxy[gb.hit & ~np.isin(gb.shape_index, spheres)].any()
    # proxy pixels were refined by a real ray: the position AOV lies on the exact sphere surface
    for index in shapes:
        to_world = np.array(mi.traverse(scene.shapes()[index])["to_world"].matrix).reshape(4, 4)
        centre, radius = to_world[:3, 3], np.linalg.norm(to_world[:3, 0])
        on = exact & (np.array(pi.shape_index).reshape(exact.shape) == index)
        r = np.linalg.norm(gb.position[on] - centre, axis=1)
        assert np.allclose(r, radius, rtol=1e-4)


def test_aovs_match_mitsuba_materials():
    scene = load(DEFAULT_SCENE)
    gb = hi.rasterize(scene, aovs=("all",))
    assert set(gb.aovs) == {"position", "normal", "albedo", "specular", "optical", "emission"}
    hit = gb.hit
    # position: on the camera ray at the visibility buffer's depth
    sensor = scene.sensors()[0]
    camera = RasterCamera.from_sensor(sensor)
    ray = camera_rays(sensor, camera.width, camera.height, (0.5, 0.5))
    d = np.stack([np.array(ray.d[k]) for k in range(3)], -1).reshape(gb.position.shape)
    expected = camera.eye + d * gb.depth[..., None]
    h, w = gb.shape_index.shape
    labels = mi.UInt32((gb.shape_index + 1).ravel().astype(np.uint32))
    edge = np.array(silhouettes(lambda j, active: dr.gather(mi.UInt32, labels, j, active), w, h)).reshape(h, w)
    inner = hit & ~edge  # silhouette pixels are re-traced (primary.py)
    assert np.allclose(gb.position[inner], expected[inner], atol=1e-4)
    # normal: unit shading normals; the floor's points up, the red wall's points +x
    assert np.allclose(np.linalg.norm(gb.normal[inner], axis=1), 1.0, atol=1e-4)
    assert np.allclose(gb.normal[pixels_of(gb, "floor")], [0, 1, 0], atol=1e-5)
    assert np.allclose(gb.normal[pixels_of(gb, "redwall")], [1, 0, 0], atol=1e-5)
    # albedo: the diffuse reflectance of each wall; zero on the mirror and the glass
    assert np.allclose(gb.albedo[pixels_of(gb, "redwall")], [0.570068, 0.0430135, 0.0443706], atol=1e-5)
    assert np.allclose(gb.albedo[pixels_of(gb, "glass_sphere") | pixels_of(gb, "mirror_sphere")], 0)
    # specular: silver reflects most light, diffuse walls none, glass a Fresnel fraction
    assert gb.specular[pixels_of(gb, "mirror_sphere")].mean() > 0.9
    assert np.all(gb.specular[pixels_of(gb, "back")] == 0)
    glass = gb.optical[pixels_of(gb, "glass_sphere")]
    assert 0.03 < np.median(glass[:, 0]) < 0.1  # reflectivity ~ Fresnel at near-normal incidence
    assert np.allclose(glass[:, 1], 1.5, atol=1e-5)  # index of refraction
    assert np.median(glass[:, 2]) < 0.1  # clear glass: nearly transparent
    assert np.allclose(glass[:, 3], 0)  # smooth
    walls = gb.optical[pixels_of(gb, "back")]
    assert np.allclose(walls, [0, 1, 1, 1])  # diffuse: not reflective, ior 1, opaque, rough
    assert np.all(gb.position[~hit] == 0)
    # emission: the area light's radiance where it is seen, nothing on the walls or the background
    assert np.allclose(gb.emission[pixels_of(gb, "light")], [18.387, 13.9873, 6.75357], rtol=1e-5)
    assert np.all(gb.emission[pixels_of(gb, "back")] == 0) and np.all(gb.emission[~hit] == 0)


def test_a_surface_without_a_diffuse_lobe_has_no_albedo_and_its_raster_layer_does_not_glare():
    """Mitsuba's ``eval_diffuse_reflectance`` is π·f(wi, n) for a BSDF that does not define it (a
    rough conductor, a rough dielectric): seen head-on, 5.9 on rough copper. Such a surface has no
    diffuse lobe, so its albedo is 0, and the raster layer (nothing traced) shades it with its
    specular lobe alone: its pixels' mean 0.35 against the path tracer's 0.32. With the albedo
    Mitsuba gave (up to 5.9 here), they were 0.68."""
    scene = mi.load_dict({
        "type": "scene",
        "sensor": {"type": "perspective", "fov": 40, "to_world": mi.ScalarTransform4f().look_at([0, 0, 5], [0, 0, 0], [0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 64, "height": 64, "rfilter": {"type": "box"}}},
        "copper": {"type": "sphere", "bsdf": {"type": "roughconductor", "material": "Cu", "alpha": 0.2}},
        "glass": {"type": "sphere", "center": [1.6, 0, 0], "radius": 0.5, "bsdf": {"type": "roughdielectric", "alpha": 0.2}},
        "floor": {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, 0, -2]).scale(4),
                  "bsdf": {"type": "diffuse"}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.5}}})
    gb = hi.rasterize(scene, aovs=("albedo",))
    # (an outline pixel of the glass may show the floor: its hit is re-traced, primary.py)
    assert np.mean(np.all(gb.albedo[pixels_of(gb, "copper") | pixels_of(gb, "glass")] == 0, axis=-1)) > 0.95
    assert np.allclose(gb.albedo[pixels_of(gb, "floor")], 0.5)
    assert 0 <= gb.albedo.min() and gb.albedo.max() <= 1
    copper = pixels_of(gb, "copper")
    raster = np.array(hi.render(scene, spp=1, candidates="", denoise=False, learn_ambient=False).image)[..., :3]
    truth = np.array(mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=256))[..., :3]
    assert raster[copper].mean() < 1.5 * truth[copper].mean(), (raster[copper].mean(), truth[copper].mean())


def test_textured_albedo_comes_from_the_texture():
    scene = load(SHARED_SCENES / "sponza-dabrovic/scene.xml", resx=320, resy=180)
    gb = hi.rasterize(scene, aovs=("albedo",))
    objects = hi.scene_objects(scene)
    textured = [k for k in range(len(objects)) if "data" in " ".join(mi.traverse(objects.bsdf(k, scene)).keys())]
    assert textured
    mask = np.isin(gb.shape_index, textured)
    # a bitmap varies across a shape's pixels; a constant reflectance would not
    per_shape_std = [gb.albedo[gb.shape_index == i].std(axis=0).max() for i in textured if (gb.shape_index == i).sum() > 100]
    assert mask.sum() > 1000 and max(per_shape_std) > 0.02


def test_cli_writes_multilayer_exr_and_contact_sheet(tmp_path, capsys):
    out = tmp_path / "gb" / "default.exr"
    assert cli(["gbuffer", str(DEFAULT_SCENE), "-o", str(out), "-D", "resx=96", "-D", "resy=64"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["width"] == 96 and report["height"] == 64 and report["raster_ms"] > 0
    channels, header = read_exr(out)
    expected = {"shape_index", "prim_index", "bary.u", "bary.v", "depth.Z", "proxy"}
    for name, names in hi.AOV_CHANNELS.items():
        expected |= {f"{name}.{c}" for c in names}
    assert set(channels) == expected
    scene = load(DEFAULT_SCENE, resx=96, resy=64)
    gb = hi.rasterize(scene, aovs=("all",))
    assert header["shape_ids"].split(",") == list(gb.shape_ids)
    assert np.array_equal(channels["shape_index"], gb.shape_index.astype(np.float32))
    assert np.array_equal(channels["prim_index"], gb.prim_index)
    assert np.array_equal(channels["depth.Z"], gb.depth)
    assert np.array_equal(channels["optical.ior"], gb.optical[..., 1])
    png = mi.Bitmap(str(out.with_suffix(".png")))
    assert png.width() > 400 and png.height() > 100


def test_offset_moves_the_sample_like_mitsuba():
    """The raster at offset o sees what Mitsuba's camera ray through (i + o) / W sees."""
    scene = load(DEFAULT_SCENE)
    for offset in ((0.0, 0.0), (0.99, 0.01)):
        gb = hi.rasterize(scene, offset=offset)
        sensor = scene.sensors()[0]
        h, w = gb.depth.shape
        ray = camera_rays(sensor, w, h, offset)
        t = np.array(scene.ray_intersect(ray).t + dr.norm(ray.o - mi.Point3f(0, 0, 3.9))).reshape(gb.depth.shape)
        both = gb.hit & np.isfinite(t)
        assert np.median(np.abs(gb.depth[both] - t[both]) / t[both]) < 1e-5


def test_the_light_table_lies_in_aligned_memory():
    """The LLVM backend maps a NumPy array's memory; the light rows lie on 64-byte boundaries
    (interop.device_array), so that the lighting kernel reads a light as one packet gather in every
    process: mapped where NumPy put them, it read them in 4 scalar gathers in some processes, at
    1.6× the lighting stage's time (stop 66)."""
    from hybrid_integrator.lighting import DeferredLighting

    rows = DeferredLighting(load(DEFAULT_SCENE, resx=32, resy=24)).table.rows
    assert len(rows) == 3
    for row in rows:
        assert np.asarray(row).ctypes.data % 64 == 0
