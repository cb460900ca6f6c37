"""The Mitsuba sensor as an OpenGL projection, pixel-exact (paper §7: the geometry stage's
perspective camera; Mitsuba's ``orthographic`` sensor too).

Mitsuba maps a film sample ``s`` in [0,1]² (row 0 at the top) to a camera-space point with
``sample_to_camera(s + principal_point_offset)``; its inverse, ``camera_to_sample``, comes from
Mitsuba's own :func:`mitsuba.perspective_projection`. The raster camera is that transform followed
by the affine map from sample space to OpenGL's normalized device coordinates::

    x_ndc = 2 (x_s - ppx) - 1 + (1 - 2 ox) / W        y_ndc = 2 (y_s - ppy) - 1 + (1 - 2 oy) / H

where ``(ox, oy)`` is the sub-pixel sample position: OpenGL rasterizes at pixel centres, so the
shift moves the point Mitsuba would sample at ``(i + ox) / W`` onto the centre of pixel ``i``.
Image row 0 lands on OpenGL's row 0, so a read-back needs no flip; the mirror flips the winding, so
face culling stays off. ``fov_axis`` needs no special case: Mitsuba has already converted every
axis convention to ``x_fov`` when it built the sensor.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field, replace

import drjit as dr
import mitsuba as mi
import numpy as np

from ..errors import HybridError, UnsupportedSceneError

SUPPORTED_SENSORS = ("PerspectiveCamera", "OrthographicCamera")

@dataclass
class _Kept:
    """What is kept per sensor: its ``mi.traverse``, made once (~0.1 ms a frame otherwise; the
    values it holds are the sensor's own members, which a ``params.update()`` changes in place, so
    they stay current), the last camera built, with the key of the parameters it was built
    from, and apart from it the last projection (``camera_to_sample`` and the principal point),
    made from the intrinsics in that key: a moving camera changes only ``to_world``, so its frames
    read only that back from the device. The sensor is held too, so that its ``id`` is
    not reused while this is kept."""

    sensor: mi.Sensor
    params: mi.SceneParameters
    key: tuple | None = None
    values: list | None = None  # copies of the parameters of ``key``: they keep its indices in use
    #: the ``to_world`` set by :func:`place_sensor`, its variable indices and its matrix on the host:
    #: a camera built while the sensor holds it reads no transform back (the variable held keeps its
    #: indices in use)
    placed: tuple | None = None
    camera: "RasterCamera | None" = None
    projection: tuple | None = None  # (camera_to_sample, ppx, ppy) of ``key``'s intrinsics (its first part)


#: per sensor (by ``id``), the oldest first
_CAMERAS: dict[int, _Kept] = {}
_CAMERAS_KEPT = 16


def _kept(sensor: mi.Sensor) -> _Kept:
    """What is kept for ``sensor`` (:class:`_Kept`), made on first use."""
    kept = _CAMERAS.get(id(sensor))
    if kept is None:
        kept = _CAMERAS[id(sensor)] = _Kept(sensor, mi.traverse(sensor))
        while len(_CAMERAS) > _CAMERAS_KEPT:  # the oldest first (dicts keep insertion order)
            del _CAMERAS[next(iter(_CAMERAS))]
    return kept


def place_sensor(sensor: mi.Sensor, matrix: np.ndarray) -> None:
    """Set ``sensor``'s ``to_world`` to ``matrix`` (a 4×4 pose, :func:`camera_pose`'s) without
    waiting for the device.

    ``mi.traverse`` and ``params.update()`` would: Mitsuba's ``Endpoint::parameters_changed``
    refreshes the sensor's host copy of the transform from the new value (``m_to_world =
    m_to_world.value()``, a read-back), which waits for all the work queued on the device. Between
    the frames of a camera path with two frames in flight that is the whole frame before: the H200
    waited 10.4 ms for a 9.9 ms kernel, and took 0.63-0.64 ms even with nothing queued
    (docs/results/gpu/issue10/stop56, ``pose_wait.py``). A ``perspective`` sensor's other state does
    not depend on ``to_world`` (``update_camera_transforms`` reads the film and the field of view),
    so here the transform is made on the host, moved to the device as an opaque variable (what
    ``parameters_changed`` would make of it: ``dr::make_opaque``) and written into the sensor, and
    ``parameters_changed`` is not called. The camera of the next frame takes ``matrix`` as it is,
    with nothing read back (:meth:`RasterCamera.from_sensor`). Mitsuba's own check is made here:
    scale factors are not allowed in a camera's ``to_world``. Left stale is the sensor's host copy
    of the transform, which only its ``bbox()`` reads; ``api.posed`` restores the sensor's pose
    with ``params.update()``, which refreshes it. Other sensor types take ``params.update()``."""
    kept = _kept(sensor)
    transform = mi.ScalarTransform4f(matrix)
    if sensor.class_name() != "PerspectiveCamera":
        kept.params["to_world"] = transform
        kept.params.update()
        return
    if transform.has_scale():
        raise HybridError(f"camera pose {np.asarray(matrix).tolist()} has scale factors: a camera's to_world must "
                          "not scale (Mitsuba's rule)")
    value = type(kept.params["to_world"])(transform)
    dr.make_opaque(value)
    kept.params["to_world"] = value
    kept.placed = (value, tuple(dr.detail.collect_indices(value)), np.asarray(matrix, dtype=np.float64))


@dataclass(frozen=True)
class RasterCamera:
    """What the raster stage needs of a Mitsuba ``perspective`` sensor."""

    width: int
    height: int
    #: world → clip transform for a sample at the pixel centre (float64, column vectors)
    world_to_clip: np.ndarray
    #: centre of projection in world space
    eye: np.ndarray
    near_clip: float
    far_clip: float
    #: an ``orthographic`` sensor: clip w is 1, so depth comes from the camera-space z row below
    orthographic: bool = False
    depth_row: np.ndarray | None = None  # world → camera-space z (a row of the inverse to_world)
    #: camera → clip (the intrinsics: the sensor's projection, then sample space → NDC), which
    #: :meth:`at` places at another pose
    projection: np.ndarray | None = field(default=None, compare=False, repr=False)

    @classmethod
    def from_sensor(cls, sensor: mi.Sensor) -> "RasterCamera":
        """Build the camera of ``sensor``, or raise :class:`UnsupportedSceneError` for a sensor
        type other than ``perspective`` and ``orthographic``, a film without pixels or a film with
        a crop window. The last camera of each sensor is kept and reused while its parameters are
        the same (a frame reads them once)."""
        kind = sensor.class_name()
        if kind not in SUPPORTED_SENSORS:
            raise UnsupportedSceneError(
                f"sensor type '{kind}' is not supported: the raster stage needs a 'perspective' (pinhole) or "
                "'orthographic' sensor, with one centre (or direction) of projection; a thin lens's depth of "
                "field needs camera rays: render it with primary='raytrace'")
        film = sensor.film()
        size, crop_size, crop_offset = film.size(), film.crop_size(), film.crop_offset()
        if min(size) < 1:  # Mitsuba loads it; Dr.Jit aborts the process on the frame's empty arrays
            raise UnsupportedSceneError(f"film size {size[0]}×{size[1]} has no pixels: give the film a width and "
                                        "height of at least 1")
        if tuple(crop_size) != tuple(size) or tuple(crop_offset) != (0, 0):
            raise UnsupportedSceneError(
                f"film crop window (offset {tuple(crop_offset)}, size {tuple(crop_size)} of "
                f"{tuple(size)}) is not supported: render the full film")
        kept = _kept(sensor)
        params = kept.params
        orthographic = kind == "OrthographicCamera"
        names = ("to_world",) if orthographic else ("x_fov", "principal_point_offset_x", "principal_point_offset_y",
                                                    "to_world")
        # the parameters' Dr.Jit variables: a change makes new ones, and holding the old ones (in
        # the cache) keeps their indices from being reused, so equal indices mean equal values,
        # without reading them back from the device. The objects ``traverse`` returns are the
        # sensor's own and are updated in place (new indices, the old ones freed and reused), so
        # the cache holds copies (made only when the key changes), which keep the variables they
        # were made with
        live = [params[k] for k in names]
        near, far = sensor.near_clip(), sensor.far_clip()
        intrinsics = (tuple(size), near, far, tuple(dr.detail.collect_indices(live[:-1])))
        key = (intrinsics, tuple(dr.detail.collect_indices(live[-1])))
        if kept.key == key:
            return kept.camera
        values = [type(v)(v) for v in live]
        placed = kept.placed is not None and kept.placed[1] == key[1]
        camera_to_world = kept.placed[2] if placed else transform_matrix(values[-1])
        if kept.key is None or kept.key[0] != intrinsics:
            # the projection on the host (the scalar variant's: the JIT one would launch a kernel
            # and wait for it on the GPU), in float32 as Mitsuba's sensor makes it
            if orthographic:  # Mitsuba's orthographic sensor: its to_world scales the view volume
                ppx = ppy = 0.0
                projection = mi.scalar_rgb.orthographic_projection(size, crop_size, crop_offset, near, far)
            else:
                x_fov, ppx, ppy = (float(v[0]) for v in values[:3])
                projection = mi.scalar_rgb.perspective_projection(size, crop_size, crop_offset, x_fov, near, far)
            kept.projection = transform_matrix(projection), ppx, ppy
        camera_to_sample, ppx, ppy = kept.projection
        sample_to_ndc = np.array([[2.0, 0.0, 0.0, -2.0 * ppx - 1.0],
                                  [0.0, 2.0, 0.0, -2.0 * ppy - 1.0],
                                  [0.0, 0.0, 2.0, -1.0],
                                  [0.0, 0.0, 0.0, 1.0]])
        projection = sample_to_ndc @ camera_to_sample
        camera = cls(width=int(size[0]), height=int(size[1]), near_clip=float(near), far_clip=float(far),
                     orthographic=orthographic, projection=projection, **_placed(projection, camera_to_world))
        kept.key, kept.values, kept.camera = key, values, camera
        return camera

    def at(self, camera_to_world: np.ndarray) -> "RasterCamera":
        """The same camera (film, projection, clip planes) placed at ``camera_to_world`` (a 4×4
        matrix as :func:`camera_pose` gives it), e.g. the next pose of a camera path
        (``pipeline.HybridRenderer._draw_ahead``)."""
        return replace(self, **_placed(self.projection, camera_to_world))

    def draws_as(self, other: "RasterCamera") -> bool:
        """Whether this camera's raster pass is ``other``'s at every sub-pixel offset: the same film,
        clip planes, world → clip matrix and eye (no matrix is made: a frame compares the camera a
        pass was drawn ahead for with its own, ``pipeline.HybridRenderer._drawn_ahead``)."""
        if self is other:
            return True
        same = (self.width, self.height, self.near_clip, self.far_clip, self.orthographic) == \
               (other.width, other.height, other.near_clip, other.far_clip, other.orthographic)
        return (same and np.array_equal(self.world_to_clip, other.world_to_clip) and np.array_equal(self.eye, other.eye)
                and np.array_equal(self.depth_row, other.depth_row))

    def clip_matrix(self, offset: tuple[float, float] = (0.5, 0.5)) -> np.ndarray:
        """world → clip for samples at sub-pixel position ``offset`` ∈ [0,1)² in every pixel, with
        *reversed* depth: clip z is the near-clip distance, so that after the division by w (the
        camera-space depth) the depth buffer holds ``near / z`` (``context.DepthPrecision``), 1 on
        the near plane and → 0 at infinity; nothing in front of the near plane is drawn, as
        Mitsuba's camera rays start on it. An orthographic camera has w = 1: its depth is
        ``(far − z) / (far − near)`` of the camera-space z, 1 on the near plane and 0 on the far
        one."""
        sx, sy = self._shift(offset)
        clip, _, _ = self._unshifted
        clip = clip.copy()
        clip[0] += sx * clip[3]
        clip[1] += sy * clip[3]
        return clip

    def relative_clip(self, offset: tuple[float, float] = (0.5, 0.5)) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`clip_matrix` for positions relative to the eye's float32 position ``o``: the
        matrix ``M'`` with ``M' · (p − o, 1) = M · (p, 1)``, its last column ``M · (o, 1)`` made in
        float64, and ``o`` (float32). The vertex shader's ``p − o`` is exact near the eye, so a
        scene 1e6 units from the origin is drawn as precisely as one at it."""
        sx, sy = self._shift(offset)
        _, column, origin = self._unshifted
        relative = self.clip_matrix(offset)
        relative[:, 3] = column
        relative[0, 3] += sx * column[3]
        relative[1, 3] += sy * column[3]
        return relative, origin

    def _shift(self, offset: tuple[float, float]) -> tuple[float, float]:
        """The clip-space x and y shift that moves sub-pixel position ``offset`` onto the pixel
        centres: the sample's shift adds these times clip w (row 3) to rows 0 and 1."""
        return (1.0 - 2.0 * offset[0]) / self.width, (1.0 - 2.0 * offset[1]) / self.height

    @functools.cached_property
    def _unshifted(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """What :meth:`clip_matrix` and :meth:`relative_clip` share across sub-pixel offsets (made
        once per camera; a frame's raster pass then costs a few row operations): the world → clip
        matrix with its depth row, its product with the eye ``(o, 1)`` in float64, and ``o``."""
        clip = self.world_to_clip.copy()
        if self.orthographic:
            clip[2] = (np.array([0.0, 0.0, 0.0, self.far_clip]) - self.depth_row) / (self.far_clip - self.near_clip)
        else:
            clip[2] = (0.0, 0.0, 0.0, self.near_clip)
        origin = self.eye.astype(np.float32)
        return clip, clip @ np.r_[origin.astype(np.float64), 1.0], origin


def _placed(projection: np.ndarray, camera_to_world: np.ndarray) -> dict:
    """The fields of a :class:`RasterCamera` that its pose sets, for camera → clip ``projection``."""
    world_to_camera = np.linalg.inv(camera_to_world)
    return dict(world_to_clip=projection @ world_to_camera, eye=camera_to_world[:3, 3].copy(),
                depth_row=world_to_camera[2].copy())


def camera_pose(transform) -> np.ndarray:
    """A sensor's ``to_world`` to be (a Mitsuba transform or a 4×4 matrix) as the sensor will hold
    it: float32 values (Mitsuba's transforms are float32), in float64, so that a camera placed
    there (:meth:`RasterCamera.at`) equals the one the sensor gives once it is moved there. A
    pose that is not a finite, invertible 4×4 transform is a :class:`HybridError` naming it."""
    try:
        matrix = transform_matrix(transform).astype(np.float32).astype(np.float64)
    except (TypeError, ValueError) as exc:
        raise HybridError(f"camera pose {transform!r} is not a 4×4 transform") from exc
    if not np.isfinite(matrix).all() or np.linalg.det(matrix) == 0:
        raise HybridError(f"camera pose {matrix.tolist()} is not a finite, invertible transform")
    return matrix


def transform_matrix(transform) -> np.ndarray:
    """A Mitsuba transform (one-lane JIT or scalar) or a 4×4 array as a float64 numpy matrix."""
    return np.array(getattr(transform, "matrix", transform), dtype=np.float64).reshape(4, 4)


def sensor_to_world(sensor: mi.Sensor) -> mi.ScalarTransform4f:
    """The sensor's camera-to-world transform (its ``to_world`` parameter) as a scalar transform:
    the camera of a still view, or the start of a camera path."""
    return mi.ScalarTransform4f(transform_matrix(mi.traverse(sensor)["to_world"]))


def resolve_sensor(scene: mi.Scene, sensor: int | mi.Sensor) -> mi.Sensor:
    """Mitsuba's convention for ``sensor`` arguments: an index into ``scene.sensors()`` or a sensor."""
    if isinstance(sensor, mi.Sensor):
        return sensor
    sensors = scene.sensors()
    if not 0 <= int(sensor) < len(sensors):
        raise UnsupportedSceneError(f"sensor index {sensor} is out of range: the scene has {len(sensors)} sensor(s)")
    return sensors[int(sensor)]


def sensor_like(sensor: mi.Sensor, width: int, height: int, fov_axis: str = "x",
                principal_point: tuple[float, float] = (0.0, 0.0), rfilter: str = "gaussian") -> mi.Sensor:
    """A ``perspective`` sensor at ``sensor``'s pose with the same horizontal field of view but
    another film size, ``fov_axis`` convention, principal point offset or reconstruction filter,
    built by Mitsuba's own plugin (for resolution sweeps, for checking the camera conventions,
    and for path tracing with a denoiser, which needs a ``box`` filter)."""
    params = mi.traverse(sensor)
    to_world = mi.ScalarTransform4f(transform_matrix(params["to_world"]))
    aspect = width / height
    half_x = np.tan(np.radians(float(params["x_fov"][0])) / 2)
    half = {"x": half_x, "y": half_x / aspect, "diagonal": half_x * np.hypot(1.0, 1.0 / aspect),
            "smaller": half_x / aspect if aspect > 1 else half_x,
            "larger": half_x if aspect > 1 else half_x / aspect}[fov_axis]
    return mi.load_dict({
        "type": "perspective", "to_world": to_world, "fov": float(np.degrees(2 * np.arctan(half))),
        "fov_axis": fov_axis, "near_clip": sensor.near_clip(), "far_clip": sensor.far_clip(),
        "principal_point_offset_x": float(principal_point[0]), "principal_point_offset_y": float(principal_point[1]),
        "film": {"type": "hdrfilm", "width": int(width), "height": int(height), "rfilter": {"type": rfilter}}})
