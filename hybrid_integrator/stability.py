"""Where each method fails: the stability catalog (issue 12).

Rasterization, ray tracing and the selection heuristic each break in known places: sub-pixel and
grazing geometry, depth precision far from the origin, near-plane clipping, degenerate meshes,
unusual cameras, emitters and materials the raster layer only approximates, impossible budgets,
misuse. Each :class:`Case` builds a small scene (Mitsuba's own plugins, 48×36 pixels by default)
and names the outcome the hybrid must deliver, one of:

``agree``
    raster primaries ≡ camera rays: the hybrid frame and the pure ray-tracing baseline (same seed,
    the paper's effects, no denoiser) differ by at most 1 % of the image's mean on at least
    ``bound`` of the pixels (the figure). Where the raster cannot resolve a pixel (sub-pixel
    geometry, silhouettes, proxies), the hybrid re-traces it with a camera ray (``primary.py``):
    this is what holds the figure up.
``visibility``
    the raster's visibility buffer against Mitsuba's ``ray_intersect_preliminary`` along the same
    camera rays (``raster.agreement``): the fraction of pixels with the same object and triangle,
    at least ``bound``. (Where shading differs for reasons of ray-tracing precision, this is what
    the raster stage answers for.)
``flip``
    the hybrid (every term traced, 16 spp, no denoiser) against Mitsuba's ``path`` at 256 spp: the
    figure is its FLIP minus that of ``path`` at the same 16 spp, at most ``bound`` (the hybrid is
    as good an estimator as Mitsuba's own on that scene).
``error``
    a :class:`HybridError` whose message matches ``expect``; any other exception fails the case.
``stats``
    the frame renders (finite, not all black unless the case says so) and ``check(result)``
    returns the figure, which must be ≤ ``bound``.

Every render is checked for NaN/Inf. :func:`run_case` returns a :class:`CaseResult` with the
figure and the images of the report strip (reference, raster layer, hybrid, error map);
``tests/stability`` runs the fast cases, ``scripts/stability_report.py`` all of them into
``docs/results/stability.md``.
"""
from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field
from typing import Callable

import mitsuba as mi
import numpy as np

from .errors import HybridError
from .procedural import sphere_mesh
from .raster.camera import sensor_to_world

RES = (48, 36)
PAPER = "shadow,reflection,refraction"


def look_at(origin, target=(0, 0, 0), up=(0, 1, 0)) -> mi.ScalarTransform4f:
    return mi.ScalarTransform4f().look_at(origin=list(origin), target=list(target), up=list(up))


def sensor(origin=(0, 1, 4), target=(0, 0, 0), fov=45.0, res=RES, **extra) -> dict:
    film = {"type": "hdrfilm", "width": int(res[0]), "height": int(res[1]), **extra.pop("film", {})}
    return {"type": extra.pop("type", "perspective"), "fov": fov, "to_world": look_at(origin, target), "film": film,
            **extra}


def diffuse(rgb=(0.6, 0.6, 0.6)) -> dict:
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": list(rgb)}}


def floor(y=-1.0, size=4.0, bsdf=None) -> dict:
    return {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, y, 0]).rotate([1, 0, 0], -90)
            .scale(size), "bsdf": bsdf or diffuse()}


def scene(shapes: dict, cam: dict | None = None, lights: dict | None = None, **extra) -> dict:
    """A scene dict: the shapes, a camera, and (default) a point light and a dim constant sky."""
    lights = lights if lights is not None else {
        "light": {"type": "point", "position": [2.0, 4.0, 3.0], "intensity": {"type": "rgb", "value": [40.0] * 3}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [0.1] * 3}}}
    return {"type": "scene", "sensor": cam or sensor(), **lights, **shapes, **extra}


def mesh(vertices, faces, bsdf=None, **extra) -> dict:
    """A triangle mesh from arrays (Mitsuba's ``mi.Mesh``), as a scene-dict entry."""
    v = np.asarray(vertices, dtype=np.float32)
    f = np.asarray(faces, dtype=np.uint32)
    m = mi.Mesh("mesh", vertex_count=len(v), face_count=len(f), has_vertex_normals=False, has_vertex_texcoords=False)
    params = mi.traverse(m)
    params["vertex_positions"] = mi.Float(v.ravel())
    params["faces"] = mi.UInt32(f.ravel())
    params.update()
    if bsdf is not None:
        m.set_bsdf(mi.load_dict(bsdf))
    return m


def load(scene_dict: dict) -> mi.Scene:
    """A case's scene as ``hi.load_scene`` makes one from a file: its shapes kept apart by Mitsuba
    (``optimize=False``), then batched by material with their object ids kept (``objects.py``)."""
    from .objects import batch_by_material

    return batch_by_material(mi.load_dict(scene_dict, optimize=False))


@dataclass(frozen=True)
class Case:
    name: str
    group: str  # raster | trace | budget | use
    build: Callable[[], dict]  # the scene dict
    outcome: str  # agree | flip | error | stats
    bound: float = 0.0
    props: dict = field(default_factory=dict)  # the hybrid integrator's properties
    expect: str = ""  # error: a regular expression the message must match
    check: Callable | None = None  # stats: result -> figure
    spp: int = 2
    frames: int = 1  # stats: render this many frames and check the last
    orbit: float = 0.0  # ... with the camera turning this many degrees about the scene's y axis over them
    slow: bool = False
    note: str = ""  # what happens, and what should


@dataclass
class CaseResult:
    case: Case
    passed: bool
    figure: float
    detail: str
    seconds: float
    images: dict[str, np.ndarray] = field(default_factory=dict)


def _finite(image: np.ndarray, what: str) -> None:
    if not np.isfinite(image).all():
        raise AssertionError(f"{what} has NaN or Inf pixels")


def _hybrid(scene_obj, case: Case, **props):
    import hybrid_integrator as hi

    return hi.render(scene_obj, spp=case.spp, seed=5, **{**case.props, **props})


def run_case(case: Case) -> CaseResult:
    """Build the case's scene, render what its outcome needs and measure the figure."""
    from .metrics import image_error

    start = time.perf_counter()
    images: dict[str, np.ndarray] = {}
    scene_obj = None
    try:
        if case.outcome == "error":
            try:
                scene_obj = load(case.build())
                _hybrid(scene_obj, case)
            except HybridError as exc:
                ok = re.search(case.expect, str(exc)) is not None
                return CaseResult(case, ok, math.nan, str(exc), time.perf_counter() - start)
            return CaseResult(case, False, math.nan, "no error was raised", time.perf_counter() - start)
        scene_obj = load(case.build())
        if case.outcome == "agree":
            common = dict(effects=PAPER, denoise=False)
            hybrid = _hybrid(scene_obj, case, **common)
            baseline = _hybrid(scene_obj, case, primary="raytrace", **common)
            a, b = np.array(hybrid.image)[..., :3], np.array(baseline.image)[..., :3]
            _finite(a, "the hybrid frame")
            diff = np.abs(a - b).max(axis=-1)
            figure = float(np.mean(diff <= 0.01 * max(float(b.mean()), 1e-6)))
            images = {"reference (camera rays)": b, "raster layer": hybrid.layers["raster"], "hybrid": a, "error": diff}
            return CaseResult(case, figure >= case.bound, figure, f"{figure:.4f} of the pixels agree",
                              time.perf_counter() - start, images)
        if case.outcome == "visibility":
            import hybrid_integrator as hi
            from .raster.agreement import visibility_agreement

            agreement = visibility_agreement(scene_obj, scene_obj.sensors()[0], hi.rasterize(scene_obj))
            figure = agreement.shape_and_triangle
            return CaseResult(case, figure >= case.bound, figure,
                              f"{figure:.4f} same triangle, {agreement.hit_miss:.4f} same hit or miss",
                              time.perf_counter() - start)
        if case.outcome == "flip":
            truth = np.array(mi.render(scene_obj, integrator=mi.load_dict(_path_dict(case)), spp=256, seed=1))[..., :3]
            hybrid = _hybrid(scene_obj, case, denoise=False)
            a = np.array(hybrid.image)[..., :3]
            _finite(a, "the hybrid frame")
            path = np.array(mi.render(scene_obj, integrator=mi.load_dict(_path_dict(case)), spp=case.spp, seed=5))[..., :3]
            err, maps = image_error(a, truth)
            figure = err.flip - image_error(path, truth)[0].flip
            images = {"reference (path 256 spp)": truth, "raster layer": hybrid.layers["raster"], "hybrid": a,
                      "error": maps["flip"]}
            return CaseResult(case, figure <= case.bound, figure, f"FLIP {err.flip:.4f}, path {err.flip - figure:.4f}",
                              time.perf_counter() - start, images)
        if case.frames > 1:
            import hybrid_integrator as hi

            camera = sensor_to_world(scene_obj.sensors()[0])
            cameras = [mi.ScalarTransform4f().rotate([0, 1, 0], case.orbit * k / (case.frames - 1)) @ camera
                       for k in range(case.frames)]
            frames = hi.render_sequence(scene_obj, cameras, spp=case.spp, seed=5, layers=False, **case.props)
            result = frames[-1]
            result.sequence = frames  # for checks over the whole sequence
        else:
            result = _hybrid(scene_obj, case)
        a = np.array(result.image)[..., :3]
        _finite(a, "the frame")
        figure = float(case.check(result))
        images = {"hybrid": a}
        return CaseResult(case, figure <= case.bound, figure, "", time.perf_counter() - start, images)
    except Exception as exc:  # a crash, or an error that is not a HybridError: the case fails
        return CaseResult(case, False, math.nan, f"{type(exc).__name__}: {str(exc)[:300]}", time.perf_counter() - start)
    finally:
        from .cache import forget

        if scene_obj is not None:
            forget(scene_obj)  # its GPU state and Dr.Jit objects are not kept for the next case


def _path_dict(case: Case) -> dict:
    keys = {k: case.props[k] for k in ("max_depth", "rr_depth", "hide_emitters") if k in case.props}
    return {"type": "path", **keys}


# --- the catalog ---------------------------------------------------------------------------------

def _sphere(radius=1.0, center=(0, 0, 0), bsdf=None) -> dict:
    return {"type": "sphere", "radius": radius, "center": list(center), "bsdf": bsdf or diffuse((0.7, 0.3, 0.2))}


def _offset_scene(offset: float, scale: float = 1.0) -> Callable[[], dict]:
    def build():
        o = np.array([offset, offset, offset])
        t = mi.ScalarTransform4f().translate(o.tolist()).scale(scale)
        shapes = {"cube": {"type": "cube", "to_world": t @ mi.ScalarTransform4f().rotate([0, 1, 0], 30).scale(0.6),
                           "bsdf": diffuse((0.2, 0.5, 0.7))},
                  "floor": {**floor(), "to_world": t @ mi.ScalarTransform4f().translate([0, -1, 0]).rotate([1, 0, 0], -90).scale(4)}}
        cam = sensor(origin=(o + scale * np.array([0, 1, 4])).tolist(), target=o.tolist())
        cam["near_clip"], cam["far_clip"] = 0.01 * scale, 100 * scale
        light = {"light": {"type": "point", "position": (o + scale * np.array([2, 4, 3])).tolist(),
                           "intensity": {"type": "rgb", "value": [40.0 * scale * scale] * 3}}}
        return scene(shapes, cam, light)
    return build


def _analytic(kind: str, size: float) -> Callable[[], dict]:
    def build():
        t = mi.ScalarTransform4f().scale(size)
        shape = {"sphere": {"type": "sphere", "radius": size},
                 "cylinder": {"type": "cylinder", "radius": 0.5 * size, "p0": [0, -size, 0], "p1": [0, size, 0]},
                 "disk": {"type": "disk", "to_world": t @ mi.ScalarTransform4f().rotate([1, 0, 0], -60)},
                 "rectangle": {"type": "rectangle", "to_world": t @ mi.ScalarTransform4f().rotate([1, 0, 0], -60)},
                 "cube": {"type": "cube", "to_world": t @ mi.ScalarTransform4f().rotate([1, 1, 0], 35)}}[kind]
        cam = sensor(origin=(0, 1.0 * size, 4 * size))
        cam["near_clip"] = 0.01 * size
        light = {"light": {"type": "point", "position": [2 * size, 4 * size, 3 * size],
                           "intensity": {"type": "rgb", "value": [40.0 * size * size] * 3}}}
        return scene({"obj": {**shape, "bsdf": diffuse((0.7, 0.5, 0.2))}}, cam, light)
    return build


def hidden_emitter_scene(ball: str | None = None) -> dict:
    """An area-emitting sphere (the "lamp") in front of a floor (a mesh: Mitsuba's ``path`` with
    ``hide_emitters`` misplaces an analytic shape behind a hidden emitter), a point light and a dim
    sky; with ``ball`` ("analytic" or "mesh", a fine UV sphere), a small emitting panel in front of
    a sphere as well. The scene of ``hide_emitters``' case, test and probe
    (docs/results/gpu/issue10/stop65/hide_emitters.py)."""
    shapes = {"floor": mesh([[-4, -1, -4], [4, -1, -4], [4, -1, 4], [-4, -1, 4]], [[0, 2, 1], [0, 3, 2]], diffuse()),
              "lamp": _sphere(0.6, (-0.8, 0, 0), diffuse((0.7, 0.3, 0.2))) | {
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [3.0, 2.0, 1.0]}}}}
    if ball is not None:
        place = mi.ScalarTransform4f().translate([1.0, 0.0, 0.0]).scale(0.5)
        shapes["ball"] = ({"type": "sphere", "to_world": place} if ball == "analytic" else
                          {"type": "ply", "filename": str(sphere_mesh(200_000)), "to_world": place}) | {"bsdf": diffuse((0.2, 0.6, 0.3))}
        shapes["panel"] = {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([1.0, 0.1, 1.5]).scale(0.3),
                           "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}}}
    return scene(shapes, sensor(res=(64, 48)))


def _basic(extra_shapes=None, cam=None, lights=None) -> Callable[[], dict]:
    return lambda: scene({"floor": floor(), "ball": _sphere(0.8), **(extra_shapes or {})}, cam, lights)


def _grid(n: int, res=RES) -> Callable[[], dict]:
    """``n`` small cubes on a floor: many objects for the heuristic."""
    def build():
        side = int(math.ceil(math.sqrt(n)))
        shapes = {"floor": floor(size=6)}
        for k in range(n):
            x, z = (k % side) / side * 8 - 4, (k // side) / side * 8 - 4
            shapes[f"c{k}"] = {"type": "cube", "to_world": mi.ScalarTransform4f().translate([x, -0.9, z]).scale(0.08),
                               "bsdf": diffuse((0.5, 0.5, 0.5))}
        return scene(shapes, sensor(origin=(0, 5, 7), res=res))
    return build


def _triangles(vertices, faces) -> Callable[[], dict]:
    return lambda: scene({"floor": floor(), "m": mesh(vertices, faces, diffuse((0.3, 0.6, 0.3)))})


TETRA_V = [[-1, -0.5, -0.5], [1, -0.5, -0.5], [0, -0.5, 1], [0, 1, 0]]
TETRA_F = [[0, 1, 3], [1, 2, 3], [2, 0, 3], [0, 2, 1]]
def _emitters() -> dict[str, dict]:
    return {
        "point": {"l": {"type": "point", "position": [2, 4, 3], "intensity": {"type": "rgb", "value": [40.0] * 3}}},
        "spot": {"l": {"type": "spot", "to_world": look_at((1, 4, 2), (0, -1, 0)), "cutoff_angle": 30,
                       "intensity": {"type": "rgb", "value": [80.0] * 3}}},
        "directional": {"l": {"type": "directional", "direction": [-0.3, -1, -0.4], "irradiance": {"type": "rgb", "value": [3.0] * 3}}},
        "area": {"l": {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, 3, 0]).rotate([1, 0, 0], 90),
                       "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [6.0] * 3}}}},
        "constant": {"l": {"type": "constant", "radiance": {"type": "rgb", "value": [1.0] * 3}}},
        "sunsky": {"l": {"type": "sunsky"}},
    }


def _bsdfs() -> dict[str, object]:
    return {
        "twosided": {"type": "twosided", "material": diffuse((0.7, 0.4, 0.2))},
        "blend": {"type": "blendbsdf", "weight": 0.5, "bsdf_0": diffuse((0.7, 0.2, 0.2)), "bsdf_1": {"type": "conductor"}},
        "mask": {"type": "mask", "opacity": 0.5, "material": diffuse((0.2, 0.7, 0.2))},
        "mask (textured opacity)": {"type": "mask", "material": diffuse((0.2, 0.7, 0.2)),
                                    "opacity": {"type": "checkerboard", "to_uv": mi.ScalarTransform4f().scale(4)}},
        "bump": lambda: {"type": "bumpmap", "arbitrary": {"type": "bitmap", "filename": _texture("bumps"), "raw": True},
                         "scale": 0.5, "bsdf": diffuse((0.6, 0.6, 0.6))},
        "normalmap": lambda: {"type": "normalmap", "normalmap": {"type": "bitmap", "filename": _normal_map(), "raw": True},
                              "bsdf": diffuse((0.6, 0.6, 0.6))},
        "textured": {"type": "diffuse", "reflectance": {"type": "checkerboard", "to_uv": mi.ScalarTransform4f().scale(6)}},
        "roughconductor": {"type": "roughconductor", "alpha": 0.2},
        "plastic": {"type": "plastic", "diffuse_reflectance": {"type": "rgb", "value": [0.2, 0.3, 0.8]}},
    }


def _glass(shapes) -> Callable[[], dict]:
    return lambda: scene({"floor": floor(bsdf={"type": "diffuse", "reflectance": {"type": "checkerboard",
                                                                                    "to_uv": mi.ScalarTransform4f().scale(8)}}),
                          **shapes})


def _selection_ms(result, visible: int) -> float:
    """The median host ms of making a frame's plan (``FrameStats.plan_ms``: eq. 1–3 and the
    selector, wherever the frame's plan was made) over a sequence's frames after the cost model's
    probes, if at least ``visible`` candidates were seen (else inf). (Until stop 63 the ``select``
    phase's host time: since stop 53 a still camera's plan is made while the frame before traces,
    and that phase only picks it up: 0.05 ms at 2 000 objects.)"""
    if result.stats.candidates_visible < visible:
        return math.inf
    return float(np.median([f.stats.plan_ms for f in result.sequence[4:]]))


def _changes_per_frame(result) -> float:
    """Mean ``selection_changes`` over a sequence's frames after the cost model's probes."""
    return float(np.mean([f.stats.selection_changes for f in result.sequence[4:]]))


def catalog() -> list[Case]:
    cases: list[Case] = []
    EMITTERS, BSDFS = _emitters(), _bsdfs()
    add = cases.append
    # --- raster: the visibility buffer against Mitsuba's camera rays ---
    add(Case("sub-pixel sphere (0.1 px)", "raster", _basic({"tiny": _sphere(0.004, (0.5, 0.3, 1.0))}), "agree", 0.99,
             note="smaller than a pixel: the raster may miss it at a pass's offset; the hybrid re-traces silhouettes"))
    add(Case("thin wires", "raster", _basic({f"w{k}": {"type": "cylinder", "radius": 0.004, "p0": [-2, -0.5 + 0.3 * k, 0.5],
                                                          "p1": [2, -0.3 + 0.3 * k, 0.5]} for k in range(4)}), "agree", 0.98))
    add(Case("grazing sliver", "raster", _triangles([[-2, -0.99, -2], [2, -0.99, -2], [0, -0.98, 3]], [[0, 1, 2]]),
             "agree", 0.98))
    add(Case("many triangles per pixel (5M-triangle sphere mesh at 64×64)", "raster",
             lambda: scene({"floor": floor(), "dense": {"type": "ply", "filename": str(sphere_mesh(5_000_000)),
                                                         "to_world": mi.ScalarTransform4f().scale(0.8)}},
                           sensor(res=(64, 64))), "agree", 0.97, slow=True,
             note="about 1 000 triangles per pixel: the raster keeps the nearest, as the ray tracer does"))
    add(Case("geometry crossing the near plane", "raster",
             _basic(cam=sensor(origin=(0, 0, 1.2), target=(0, 0, 0), near_clip=0.5)), "agree", 0.98,
             note="Mitsuba's rays start on the near plane; the raster clips there too (reversed-Z)"))
    add(Case("geometry behind the camera", "raster", _basic({"behind": _sphere(0.5, (0, 1, 6))}), "agree", 0.99))
    add(Case("sphere with a non-uniform scale", "raster",
             _basic({"ball": {"type": "sphere", "to_world": mi.ScalarTransform4f().scale([0.8, 0.3, 0.5]),
                              "bsdf": diffuse((0.7, 0.3, 0.2))}}), "agree", 0.99,
             note="Mitsuba keeps the sphere round (its radius from the x axis; it warns): the proxy is placed by "
                  "the sphere's bounding box, not by to_world, whose ellipsoid missed rows of it"))
    add(Case("camera inside a closed mesh", "raster",
             lambda: scene({"room": {"type": "cube", "to_world": mi.ScalarTransform4f().scale(5), "bsdf": diffuse()},
                            "ball": _sphere(0.8)}, lights={"light": {"type": "point", "position": [1, 2, 1],
                                                                     "intensity": {"type": "rgb", "value": [20.0] * 3}}}),
             "agree", 0.99))
    add(Case("z-fighting (coplanar rectangles)", "raster",
             _basic({"over": {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, -1, 0]).rotate([1, 0, 0], -90)
                              .scale(2), "bsdf": diffuse((0.1, 0.8, 0.1))}}), "agree", 0.5,
             note="two surfaces at one depth: raster and ray tracer may pick different ones; both are 'right'"))
    for offset, bound in ((1e6, 0.99), (1e7, 0.85)):
        add(Case(f"scene and camera offset by {offset:.0e}", "raster", _offset_scene(offset), "visibility", bound,
                 note="vertices drawn relative to the eye (raster/shaders/visibility.vert): at 1e6 the same "
                      "triangle on 99.8 % of the pixels (96.5 % in absolute coordinates); at 1e7 float32 "
                      "positions quantize the scene itself (1 unit), and the shading points of both "
                      "methods differ by a float32 step, which shadow rays amplify (images agree on 82 %)"))
    add(Case("tiny scene (1e-4 units)", "raster", _offset_scene(0.0, 1e-4), "agree", 0.98))
    add(Case("depth range 1e-3 … 1e5", "raster",
             lambda: scene({"near": _sphere(0.002, (0.0, 0.0, 3.99)), "far": _sphere(2e4, (0, 0, -9e4)), "floor": floor()},
                           sensor(origin=(0, 0, 4), near_clip=1e-3, far_clip=1e5)), "agree", 0.97))
    add(Case("far clip inside the scene", "raster", _basic(cam=sensor(far_clip=4.2)), "agree", 0.98,
             note="the far plane cuts the floor and the sphere's back: Mitsuba's camera rays end there (maxt), "
                  "the raster clips there"))
    add(Case("zero-area triangles", "raster", _triangles(TETRA_V + [[0, 0, 0]], TETRA_F + [[4, 4, 4], [0, 0, 1]]), "agree", 0.98))
    add(Case("duplicate vertices", "raster", _triangles(TETRA_V + TETRA_V, TETRA_F + [[f + 4 for f in t] for t in TETRA_F]),
             "agree", 0.97))
    add(Case("flipped normals (reversed winding)", "raster", _triangles(TETRA_V, [t[::-1] for t in TETRA_F]), "agree", 0.98))
    add(Case("non-manifold (three faces on an edge)", "raster",
             _triangles(TETRA_V + [[0, -0.5, -1.5]], TETRA_F + [[0, 1, 4]]), "agree", 0.98))
    add(Case("NaN vertex", "raster", _triangles(TETRA_V[:3] + [[math.nan, 0, 0]], TETRA_F), "error", expect="NaN or infinite positions"))
    add(Case("Inf vertex", "raster", _triangles(TETRA_V[:3] + [[0, math.inf, 0]], TETRA_F), "error",
             expect="NaN or infinite positions"))
    add(Case("instance (shapegroup)", "raster",
             lambda: scene({"g": {"type": "shapegroup", "s": _sphere(0.5)},
                            "i": {"type": "instance", "shapegroup": {"type": "ref", "id": "g"}}, "floor": floor()}),
             "error", expect="type 'Instance'"))
    for kind in ("sphere", "cylinder", "disk", "rectangle", "cube"):
        for size in (1e-3, 1.0, 1e3):
            add(Case(f"analytic {kind}, size {size:g}", "raster", _analytic(kind, size), "agree", 0.98,
                     note="sphere, cylinder, disk are drawn as proxies and refined by a ray"))
    for fov in (1.0, 170.0):
        add(Case(f"fov {fov:g}°", "raster", _basic(cam=sensor(fov=fov)), "agree", 0.98))
    for axis in ("y", "diagonal", "smaller", "larger"):
        add(Case(f"fov_axis {axis}", "raster", _basic(cam=sensor(fov_axis=axis)), "agree", 0.98))
    add(Case("principal point shift", "raster",
             _basic(cam=sensor(principal_point_offset_x=0.2, principal_point_offset_y=-0.1)), "agree", 0.98))
    for extent in (1.0, 3.0):
        add(Case(f"orthographic sensor, extent {extent:g}", "raster",
                 _basic(cam={**{k: v for k, v in sensor().items() if k != "fov"}, "type": "orthographic",
                             "to_world": look_at((0, 1, 4)) @ mi.ScalarTransform4f().scale([extent, extent, 1])}),
                 "agree", 0.98, note="parallel projection: clip w = 1, depth from camera-space z"))
    add(Case("thin lens sensor (depth of field)", "raster",
             _basic(cam={**sensor(), "type": "thinlens", "aperture_radius": 0.1, "focus_distance": 4}), "error",
             expect="sensor type 'ThinLensCamera' is not supported",
             note="a raster has one centre of projection: depth of field needs camera rays (or a blur)"))
    add(Case("crop window", "raster", _basic(cam=sensor(film={"crop_width": 24, "crop_height": 18})), "error",
             expect="crop window"))
    add(Case("film without pixels (0×4)", "raster", _basic(cam=sensor(res=(0, 4), fov_axis="smaller")), "error",
             expect="film size 0×4 has no pixels",
             note="Mitsuba loads it; until stop 63 the frame's empty arrays made Dr.Jit abort the process"))
    for res in ((1, 1), (7, 3), (512, 4)):
        add(Case(f"resolution {res[0]}×{res[1]}", "raster", _basic(cam=sensor(res=res)), "agree", 0.95))
    add(Case("resolution 4096×16", "raster", _basic(cam=sensor(res=(4096, 16))), "agree", 0.95, slow=True))
    add(Case("empty scene", "raster", lambda: {"type": "scene", "sensor": sensor()}, "stats", 0.0,
             check=lambda r: float(np.array(r.image).max()) + (0.0 if "no shapes" in r.stats.fallback else 1.0),
             note="black, as Mitsuba renders it; recorded as a fallback"))
    add(Case("only an environment emitter", "raster", lambda: scene({}, lights=EMITTERS["constant"]), "stats", 0.0,
             check=lambda r: abs(float(np.array(r.image).mean()) - 1.0) + (0.0 if r.stats.fallback else 1.0)))
    # --- ray tracing from the G-buffer ---
    add(Case("total internal reflection (glass cube)", "trace",
             _glass({"glass": {"type": "cube", "to_world": mi.ScalarTransform4f().rotate([1, 1, 0], 40).scale(0.7),
                               "bsdf": {"type": "dielectric"}}}), "flip", 0.03, spp=16))
    add(Case("nested dielectrics", "trace",
             _glass({"outer": _sphere(0.9, bsdf={"type": "dielectric", "int_ior": 1.5}),
                     "inner": _sphere(0.4, bsdf={"type": "dielectric", "int_ior": 1.33, "ext_ior": 1.5})}), "flip", 0.03, spp=16))
    add(Case("thin dielectric", "trace", _glass({"sheet": {"type": "rectangle", "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 30),
                                                           "bsdf": {"type": "thindielectric"}}}), "flip", 0.03, spp=16))
    for depth in (0, 1, 2, -1):
        add(Case(f"max_depth {depth}", "trace", _glass({"ball": _sphere(0.8, bsdf={"type": "dielectric"})}), "flip", 0.03,
                 props={"max_depth": depth}, spp=16,
                 note="max_depth 0: black, as path; 1: emitters only (traced pixels)"))
    add(Case("rr_depth 1", "trace", _basic(), "flip", 0.03, props={"rr_depth": 1}, spp=16))
    add(Case("grazing angles: self-intersection on raster hits", "trace",
             _basic(cam=sensor(origin=(0, -0.95, 4), target=(0, -1, 0))), "agree", 0.97))
    add(Case("emitters seen directly and in a mirror", "trace",
             lambda: scene({"floor": floor(), "mirror": _sphere(0.8, bsdf={"type": "conductor"}), **EMITTERS["area"]},
                           lights={}), "flip", 0.03, spp=16))
    add(Case("hide_emitters: an area-emitting sphere seen directly", "trace", hidden_emitter_scene, "flip", 0.03,
             props={"hide_emitters": True}, spp=16,
             note="path's camera rays pass through area emitters (skip_area_emitters): the hybrid showed the sphere's "
                  "surface lit but not emitting, now what lies behind it (primary.first_hits). The floor is a mesh: "
                  "path misplaces an analytic shape behind a hidden emitter"))
    for name, lights in EMITTERS.items():
        add(Case(f"emitter: {name}", "trace", _basic(lights=lights), "flip", 0.03, spp=16))
    add(Case("emitter: envmap", "trace", _basic(lights={"l": {"type": "envmap", "filename": _envmap()}}), "flip", 0.03, spp=16))
    for name, bsdf in BSDFS.items():
        add(Case(f"BSDF: {name}", "trace",
                 lambda bsdf=bsdf: scene({"floor": floor(), "ball": _sphere(0.8, bsdf=bsdf() if callable(bsdf) else bsdf)}),
                 "flip", 0.03, spp=16))
    # --- heuristic and budget ---
    add(Case("budget 1e-9 ms (nothing fits)", "budget", _basic(), "stats", 0.0, props={"budget_ms": 1e-9},
             check=lambda r: 0.0 if r.stats.budget_ms > 0 else 1.0))
    add(Case("budget 1e9 ms (everything fits)", "budget", _basic(), "stats", 0.0, props={"budget_ms": 1e9},
             check=lambda r: 0.0 if r.stats.budget_met and r.stats.secondary_rays > 0 else 1.0,
             note="a first frame probes the machine (the most relevant object only), then all fit"))
    for bad in (-1.0, math.nan, math.inf):
        add(Case(f"budget {bad} ms", "budget", _basic(), "error", props={"budget_ms": bad}, expect="is impossible"))
    add(Case("candidate: unknown id", "budget", _basic(), "error", props={"candidates": "ball,teapot"},
             expect=r"unknown candidate object id\(s\) \['teapot'\]"))
    add(Case("candidates: duplicates", "budget", _basic(), "stats", 0.0, props={"candidates": "ball,ball"},
             check=lambda r: 0.0 if r.stats.selected == ("ball",) else 1.0))
    add(Case("candidates: empty (raster layer only)", "budget", _basic(), "stats", 0.0, props={"candidates": ""},
             check=lambda r: float(r.stats.secondary_rays)))
    add(Case("2 000 objects: selection time", "budget", _grid(2000, (320, 240)), "stats", 1.0, props={"budget_ms": 1e9},
             check=lambda r: _selection_ms(r, 1000), frames=10, spp=1, slow=True,
             note="the figure: median host ms of making a frame's plan (eq. 1-3 and the nested selector) over "
                  "frames 5-10, on arrays (46 ms per frame before, with a Python object per candidate)"))
    add(Case("20 000 objects: selection time", "budget", _grid(20000, (640, 480)), "stats", 10.0, props={"budget_ms": 1e9},
             check=lambda r: _selection_ms(r, 10000), frames=10, spp=1, slow=True,
             note="the figure: median host ms of making a frame's plan over frames 5-10 (827 ms before)"))
    for importance, bound in ((0.0, 15.0), (0.05, 15.0)):
        add(Case(f"selection flicker on a camera orbit, importance {importance:g}", "budget", _grid(60), "stats", bound,
                 props={"budget_ms": 2.0, "importance": importance, "denoise": False}, frames=24, orbit=40.0, spp=1,
                 check=_changes_per_frame, slow=True,
                 note="the figure: objects entering or leaving the selection per frame (after the probes); "
                      "I of eq. 3 is meant as hysteresis, but here the changes come from objects entering and "
                      "leaving the view, which it cannot hold; the selection follows measured times, so the "
                      "figure varies from run to run (4 to 10 on the CPU machine): a report case, not a test"))
    # --- use and misuse ---
    add(Case("unknown effect", "use", _basic(), "error", props={"effects": "glow"}, expect="unknown effect"))
    add(Case("unknown property", "use", _basic(), "error", props={"colour": 1}, expect="has no property 'colour'"))
    add(Case("blend out of range", "use", _basic(), "error", props={"blend": 1.5}, expect="must lie in"))
    add(Case("negative spp", "use", _basic(), "error", spp=-3, expect="spp=-3 is impossible"))
    return cases


def _exr(name: str, make: Callable[[], np.ndarray]) -> str:
    """An EXR of ``make()``'s image in the temporary directory, made once per name."""
    import tempfile
    from pathlib import Path

    path = Path(tempfile.gettempdir()) / f"hybrid_stability_{name}.exr"
    if not path.is_file():
        mi.Bitmap(np.ascontiguousarray(make().astype(np.float32))).write(str(path))
    return str(path)


def _texture(name: str) -> str:
    """A small noise texture: bump heights."""
    return _exr(name, lambda: np.random.default_rng(0).random((64, 64, 1)))


def _normal_map() -> str:
    """A small noise normal map (tangent-space unit normals tilted up to ~40°, stored as (n + 1) / 2)."""
    def make():
        n = np.random.default_rng(1).normal(size=(64, 64, 3)) * [0.4, 0.4, 0.0] + [0.0, 0.0, 1.0]
        return (n / np.linalg.norm(n, axis=-1, keepdims=True) + 1.0) / 2.0
    return _exr("normals", make)


def _envmap() -> str:
    """A small gradient environment map."""
    y = np.linspace(1.0, 0.1, 16)[:, None, None]
    return _exr("envmap", lambda: np.broadcast_to(y * np.array([0.6, 0.8, 1.0]), (16, 32, 3)))
