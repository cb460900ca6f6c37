"""The package's Python API: rasterize a G-buffer, render a hybrid frame."""
from __future__ import annotations

import contextlib

import mitsuba as mi
import numpy as np

from .cache import forget, scene_state
from .environment import require_jit_rgb_variant
from .errors import HybridError
from .objects import scene_objects
from .pipeline import HybridSettings
from .primary import camera_rays, primary_hits, resolve_outline, visibility_buffer
from .raster.camera import RasterCamera, camera_pose, place_sensor, resolve_sensor, transform_matrix
from .raster.gbuffer import GBuffer, check_aovs, compute_aovs
from .raster.geometry import geometry_key
from .raster.visibility import Rasterizer, resolve_method

def rasterizer(scene: mi.Scene) -> Rasterizer:
    """The :class:`Rasterizer` of ``scene``, made (and its geometry uploaded) on first use.

    The few most recent scenes keep theirs. Geometry is read when the rasterizer is made; where
    the scene's geometry has changed since (an edit through ``mi.traverse``: a mesh's vertices, a
    shape's ``to_world``, ``raster.geometry.geometry_key``), everything kept for the scene is
    dropped and made again (:func:`forget`: the geometry, the lights, the frozen device pass's
    snapshot of its variables, what the frames learnt), counted in ``FrameStats.geometry_reloads``.
    Until stop 65 the stale geometry was drawn: a sphere moved by its radius, 14 % mean error
    against ``path`` (docs/results/gpu/issue10/stop65/traverse_edits.py)."""
    raster = scene_state(scene, "rasterizer", lambda: Rasterizer(scene))
    if raster.geometry_key != geometry_key(scene):
        reloads = raster.reloads + 1
        forget(scene)
        raster = scene_state(scene, "rasterizer", lambda: Rasterizer(scene, reloads))
    return raster


def renderer(scene: mi.Scene):
    """The hybrid renderer of ``scene`` (its rasterizer plus its lights), made on first use (and
    again after an edit of its geometry: :func:`rasterizer`)."""
    from .pipeline import HybridRenderer

    raster = rasterizer(scene)
    return scene_state(scene, "renderer", lambda: HybridRenderer(scene, raster))


def rasterize(scene: mi.Scene, sensor: int | mi.Sensor = 0, offset: tuple[float, float] = (0.5, 0.5),
              aovs=(), method: str = "auto") -> GBuffer:
    """Rasterize the visibility buffer of ``scene`` as seen by ``sensor`` (paper §3.1).

    ``offset`` is the sub-pixel sample position in [0,1)² (the pixel centre by default); ``aovs``
    names any of the G-buffer targets (``position``, ``normal``, ``albedo``, ``specular``,
    ``optical``, ``emission``, or ``"all"``) to derive from Mitsuba's BSDFs and emitters;
    ``method`` how to rasterize (``raster.visibility.RASTER_METHODS``, as the integrator's ``raster``;
    another value is a :class:`HybridError`). Arrays
    are numpy, indexed ``[row, column]`` with row 0 at the top of the image; ``shape_index``
    indexes the scene's objects (``shape_ids``: its ``<shape>`` ids, ``objects.py``)."""
    require_jit_rgb_variant()
    aovs = check_aovs(aovs)
    if not all(0.0 <= float(o) < 1.0 for o in offset):
        raise HybridError(f"sub-pixel offset {tuple(offset)} must lie in [0, 1)²")
    sensor = resolve_sensor(scene, sensor)
    camera = RasterCamera.from_sensor(sensor)
    raster = rasterizer(scene)
    ids = mi.UInt32(raster.read_ids(raster.render(camera, offset, method)))
    outline = resolve_outline("auto", resolve_method(method))
    ray = camera_rays(sensor, camera.width, camera.height, offset, differentials=outline == "ties")
    vis = visibility_buffer(ray, ids, raster.tables, camera.eye, (camera.width, camera.height), offset)
    targets = {}
    if aovs:
        hits = primary_hits(scene, ray, ids, camera.width, camera.height, raster.tables, outline)
        targets = compute_aovs(scene, hits, vis.depth.shape, aovs)
    return GBuffer(**vars(vis), **targets, shape_ids=scene_objects(scene).names)


def _integrator(properties: dict):
    from .plugins.hybrid import HybridIntegrator, register

    require_jit_rgb_variant()
    register()  # for the active variant, whichever it is now
    if isinstance(properties.get("candidates"), dict):  # a mapping is not a Mitsuba property
        candidates = properties.pop("candidates")
        properties["candidates"] = ", ".join(name if kinds is None else f"{name}:{kinds if isinstance(kinds, str) else '|'.join(kinds)}"
                                             for name, kinds in candidates.items())
    # the settings checked here first: raised inside Mitsuba's plugin loader, the clear HybridError
    # would reach the user wrapped in a RuntimeError with Mitsuba's traceback text
    HybridSettings.from_properties(properties)
    # an optional property given as None is unset: its default (Mitsuba's loader cannot take None)
    integrator = mi.load_dict({"type": "hybrid", **{k: v for k, v in properties.items() if v is not None}})
    assert isinstance(integrator, HybridIntegrator)
    return integrator


def render(scene: mi.Scene, spp: int = 0, seed: int = 0, sensor: int | mi.Sensor = 0, aovs=(), layers: bool = True,
           **properties):
    """Render one hybrid frame; ``properties`` are the ``hybrid`` integrator's (``primary``,
    ``effects``, ``candidates`` (a string or a mapping ``{id: kinds}``), ``blend``, ``budget_ms``,
    ...). Returns a ``HybridResult`` with ``image`` (as ``mi.render`` returns it), ``layers``
    (unless ``layers=False``, which saves their splatting) and ``stats``."""
    result = _integrator(dict(properties)).render_result(scene, sensor=sensor, seed=seed, spp=spp, aovs=aovs,
                                                         layers=layers)
    finish(scene)  # one frame: its times now, also with frames_in_flight=2
    return result


def finish(scene: mi.Scene) -> None:
    """Wait for the scene's frame in flight, if any (``frames_in_flight=2``), and fill in its
    times (``HybridRenderer.finish``)."""
    if scene.shapes():
        renderer(scene).finish()


def _look_at(what: str, key) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A look-at pose ``[origin, target]`` or ``[origin, target, up]`` (default up: +y) as three
    arrays, or a :class:`HybridError` naming ``what`` and what is wrong with it."""
    form = "[origin, target] or [origin, target, up], each three finite numbers"
    try:
        points = [np.asarray(p, dtype=float) for p in key]
    except (TypeError, ValueError) as exc:
        raise HybridError(f"{what} {key!r} is not {form}: {exc}") from exc
    if len(points) not in (2, 3) or any(p.shape != (3,) or not np.isfinite(p).all() for p in points):
        raise HybridError(f"{what} {key!r} is not {form}")
    origin, target, up = (*points, np.array([0.0, 1.0, 0.0]))[:3]
    view = target - origin
    if not np.linalg.norm(view) > 0:
        raise HybridError(f"{what}: origin and target are the same point {origin.tolist()}")
    if not np.linalg.norm(np.cross(view, up)) > 1e-9 * np.linalg.norm(view) * np.linalg.norm(up):
        raise HybridError(f"{what}: up {up.tolist()} is zero or along the view direction {view.tolist()}")
    return origin, target, up


def camera_path(keyframes, frames: int) -> list[mi.ScalarTransform4f]:
    """``frames`` camera transforms along the piecewise-linear path through look-at ``keyframes``
    ``[(origin, target), ...]`` or ``[(origin, target, up), ...]`` (default up: +y). A key frame,
    or a frame between two, that looks nowhere (its origin on its target, or up along its view)
    is an error naming it."""
    if isinstance(keyframes, (str, bytes)) or not hasattr(keyframes, "__iter__"):
        raise HybridError(f"a camera path is a list of key frames [[origin, target], ...], not {keyframes!r}")
    keys = [_look_at(f"camera key frame {k}", key) for k, key in enumerate(keyframes)]
    if len(keys) < 2 or frames < 1:
        raise HybridError("a camera path needs at least two key frames and one frame")
    out = []
    for n, t in enumerate(np.linspace(0.0, len(keys) - 1, frames)):
        i = min(int(t), len(keys) - 2)
        u = t - i
        pose = [(1 - u) * a + u * b for a, b in zip(keys[i], keys[i + 1])]
        origin, target, up = _look_at(f"frame {n} of the camera path (between key frames {i} and {i + 1})", pose)
        out.append(mi.ScalarTransform4f().look_at(origin=origin.tolist(), target=target.tolist(), up=up.tolist()))
    return out


def render_sequence(scene: mi.Scene, cameras, spp: int = 1, seed: int = 0, sensor: int | mi.Sensor = 0,
                    layers: bool = True, workers: int = 1, **properties) -> list:
    """Render a camera path: one frame per camera transform (``mi.ScalarTransform4f`` or 4×4
    matrix, e.g. from :func:`camera_path`), carrying the previous frame's selection (S of eq. 3)
    and the calibrated cost model from frame to frame (paper §4.3). Returns one ``HybridResult``
    per frame; each ``stats`` holds the selected objects, predicted and measured trace time,
    ``budget_met`` and ``selection_changes``. The sensor's own transform is restored afterwards.

    The frames stay in this process's memory; frames on several GPUs or CPU workers (Ray) are
    written to disk by :func:`hybrid_integrator.render_frames` (``workers=N``), whose workers each
    load the scene file themselves: ``workers`` > 1 here says so."""
    if workers != 1:
        raise HybridError(f"render_sequence(workers={workers}) renders in this process; for Ray workers, which load "
                          "the scene file themselves and write the frames to disk, call "
                          "hi.render_frames(scene_file, cameras, out_dir, workers=N) or `hybrid sequence --workers N`")
    integrator = _integrator(dict(properties))
    sensor = resolve_sensor(scene, sensor)
    results = []
    matrices = [camera_pose(camera) for camera in cameras]  # each a finite, invertible 4×4 transform, before any frame
    with posed(sensor) as place:
        for frame, matrix in enumerate(matrices):
            place(matrix)
            # the next pose: this frame draws the next one's raster pass ahead (``raster_ahead``)
            upcoming = matrices[frame + 1] if frame + 1 < len(matrices) else None
            results.append(integrator.render_result(scene, sensor=sensor, seed=seed + frame, spp=spp, layers=layers,
                                                    next_camera=upcoming))
        finish(scene)  # the last frame's times, with frames_in_flight=2
    return results


@contextlib.contextmanager
def posed(sensor: mi.Sensor):
    """A camera path's poses for ``sensor``: yields ``place(matrix)``, which sets the sensor's
    ``to_world`` to a 4×4 pose (``raster.camera.camera_pose``'s) unless it already stands there (a
    still camera needs no update: its Dr.Jit variables, and the frame's camera, stay the same),
    without waiting for the frame before (``raster.camera.place_sensor``: with two frames in
    flight, Mitsuba's ``params.update()`` waited for all of it); the sensor's own pose is restored
    on leaving, through ``params.update()``."""
    params = mi.traverse(sensor)
    original = mi.ScalarTransform4f(transform_matrix(params["to_world"]))
    current = None

    def place(matrix: np.ndarray) -> None:
        nonlocal current
        if current is None or not np.array_equal(matrix, current):
            place_sensor(sensor, matrix)
            current = matrix
    try:
        yield place
    finally:
        params["to_world"] = original
        params.update()
