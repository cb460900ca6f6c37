"""Geometry of the raster stage, read from the loaded Mitsuba scene (paper §3.1, §7).

There is one scene model, Mitsuba's: every mesh shape is drawn from its own world-space vertex
and face buffers (``vertex_positions_buffer``, ``faces_buffer``). All shapes are concatenated into
one vertex and one index buffer (:class:`SceneGeometry`) and drawn in a single call, so a raster
triangle index is a *global* triangle number: shape ``k`` owns the triangles
``first_triangle[k] … first_triangle[k + 1] − 1``, in the order of its own ``prim_index``. Analytic ``sphere``, ``disk`` and ``cylinder`` shapes have no triangles:
they are drawn as tessellated *proxies* that enclose the exact surface (the polygon is scaled out
by ``1/cos(π/n)`` so that no pixel of the true shape is missed), and their pixels are flagged so
that the ray tracer refines them with a real ray. Any other shape type is refused by name.
"""
from __future__ import annotations

from dataclasses import dataclass

import mitsuba as mi
import numpy as np

from ..errors import UnsupportedSceneError
from .camera import transform_matrix

#: segments around the circumference of a proxy
PROXY_SEGMENTS = 64
PROXY_TYPES = ("Sphere", "Disk", "Cylinder")


@dataclass(frozen=True)
class ShapeGeometry:
    """Triangles of one shape, in world space, as the GPU draws them."""

    name: str
    positions: np.ndarray  # (n_vertices, 3) float32, world space
    faces: np.ndarray  # (n_faces, 3) uint32
    proxy: bool  # True for a tessellated analytic shape


@dataclass(frozen=True)
class SceneGeometry:
    """Every shape's triangles in one buffer, as the single draw call sees them."""

    positions: np.ndarray  # (n_vertices, 3) float32, world space
    faces: np.ndarray  # (n_triangles, 3) uint32, indices into ``positions``
    first_triangle: np.ndarray  # (n_shapes + 1,) int64: shape k owns triangles [first[k], first[k + 1])
    proxy: np.ndarray  # (n_shapes,) bool: the shape is an analytic shape drawn as a proxy

    @property
    def triangles_per_shape(self) -> np.ndarray:
        return np.diff(self.first_triangle)

    def renumbered(self) -> "SceneGeometry":
        """The same triangles with the vertices numbered in the order the triangles first use
        them (unused vertices left out). No triangle changes its number or its corners, but
        consecutive triangles then fetch nearby vertices: the geometry-bound draw on the H100
        takes 0.98 -> 0.87 ms on the Armadillo, whose subdivided mesh numbers its vertices far from
        where they are used, and changes nothing on the other scenes (``scripts/raster_order_probe.py``,
        docs/results/gpu/issue10/order)."""
        flat = self.faces.ravel()
        if not len(flat):
            return self
        _, first = np.unique(flat, return_index=True)
        used = flat[np.sort(first)]
        new = np.empty(int(flat.max()) + 1, dtype=np.uint32)
        new[used] = np.arange(len(used), dtype=np.uint32)
        return SceneGeometry(positions=self.positions[used], faces=new[self.faces], first_triangle=self.first_triangle,
                             proxy=self.proxy)

    def shape_of_triangles(self) -> np.ndarray:
        """(n_triangles,) uint32: the shape of every triangle."""
        return np.repeat(np.arange(len(self.proxy), dtype=np.uint32), self.triangles_per_shape)


def geometry_key(scene: mi.Scene) -> tuple:
    """What the raster's geometry is read from, per shape of ``scene.shapes()``: a mesh's
    vertex-buffer variable and vertex count (an edit through ``mi.traverse`` gives the buffer a new
    variable), another shape's bounding box (which moving, scaling or resizing it changes; its
    proxy is placed from it or from its ``to_world``). Cheap enough to compare at every frame
    (~3 µs for the dining room's 18 shapes on a CPU of the CI machine,
    docs/results/gpu/issue10/stop65/traverse_edits.py): ``api.rasterizer`` re-reads the scene when
    it changes."""
    return tuple((shape.vertex_positions_buffer().index, shape.vertex_count()) if shape.is_mesh()
                 else (tuple(shape.bbox().min), tuple(shape.bbox().max)) for shape in scene.shapes())


def scene_geometry(scene: mi.Scene) -> SceneGeometry:
    """The :class:`SceneGeometry` of ``scene.shapes()``, in that order. Raises
    :class:`UnsupportedSceneError` for shape types that have neither triangles nor a proxy, and for
    non-finite vertex positions."""
    shapes = [shape_geometry(shape, index) for index, shape in enumerate(scene.shapes())]
    counts = [len(s.faces) for s in shapes]
    offsets = np.cumsum([0] + [len(s.positions) for s in shapes])
    return SceneGeometry(
        positions=np.concatenate([s.positions for s in shapes]).astype(np.float32) if shapes else np.zeros((0, 3), np.float32),
        faces=(np.concatenate([s.faces.astype(np.int64) + o for s, o in zip(shapes, offsets)]).astype(np.uint32)
               if shapes else np.zeros((0, 3), np.uint32)),
        first_triangle=np.cumsum([0] + counts).astype(np.int64),
        proxy=np.array([s.proxy for s in shapes], dtype=bool))


def shape_geometry(shape: mi.Shape, index: int) -> ShapeGeometry:
    name = shape.id() or f"shape #{index}"
    kind = shape.class_name()
    if shape.is_mesh():
        positions = np.array(shape.vertex_positions_buffer(), dtype=np.float32).reshape(-1, 3)
        faces = np.array(shape.faces_buffer(), dtype=np.uint32).reshape(-1, 3)
        proxy = False
    elif kind in PROXY_TYPES:
        positions, faces = _PROXIES[kind]()
        to_world = _proxy_to_world(shape, kind)
        positions = (positions @ to_world[:3, :3].T + to_world[:3, 3]).astype(np.float32)
        proxy = True
    else:
        raise UnsupportedSceneError(
            f"shape '{name}' has type '{kind}', which the raster stage cannot draw: use a mesh "
            f"(obj, ply, serialized, rectangle, cube) or one of sphere, disk, cylinder")
    if not np.isfinite(positions).all():
        bad = int((~np.isfinite(positions)).any(axis=1).sum())
        raise UnsupportedSceneError(f"shape '{name}' has {bad} vertices with NaN or infinite positions")
    return ShapeGeometry(name=name, positions=positions, faces=faces, proxy=proxy)


def _proxy_to_world(shape: mi.Shape, kind: str) -> np.ndarray:
    """The 4×4 matrix that places a proxy on the surface Mitsuba intersects: the shape's
    ``to_world``, except for a sphere, which Mitsuba keeps round whatever the scale of its
    ``to_world`` (its radius from the x axis; it warns of a non-uniform scale): that sphere is
    placed by its bounding box (a non-uniformly scaled sphere's ellipsoid proxy missed rows of it)."""
    if kind != "Sphere":
        return transform_matrix(mi.traverse(shape)["to_world"])
    box = shape.bbox()
    low, high = np.array(box.min, dtype=np.float64), np.array(box.max, dtype=np.float64)
    to_world = np.diag(np.r_[np.full(3, (high - low).max() / 2), 1.0])
    to_world[:3, 3] = (low + high) / 2
    return to_world


def _ring(n: int) -> tuple[np.ndarray, np.ndarray]:
    """cos/sin of ``n`` angles round the circle, scaled so the n-gon encloses the unit circle."""
    phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    scale = 1.0 / np.cos(np.pi / n)
    return scale * np.cos(phi), scale * np.sin(phi)


def _sphere_proxy(n: int = PROXY_SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """Unit sphere (Mitsuba's local frame), a latitude/longitude mesh that encloses it."""
    rings = n // 2
    theta = np.linspace(0.0, np.pi, rings + 1)
    scale = 1.0 / np.cos(np.pi / (2 * rings))  # the latitude polygon encloses the meridian circle
    cx, sy = _ring(n)
    r = scale * np.sin(theta)[:, None]
    z = scale * np.cos(theta)[:, None]
    pos = np.stack([r * cx, r * sy, np.broadcast_to(z, (rings + 1, n))], axis=-1).reshape(-1, 3)
    a = np.arange(rings)[:, None] * n + np.arange(n)[None, :]
    b = np.arange(rings)[:, None] * n + (np.arange(n)[None, :] + 1) % n
    faces = np.concatenate([np.stack([a, b, a + n], -1).reshape(-1, 3),
                            np.stack([b, b + n, a + n], -1).reshape(-1, 3)])
    return pos, faces.astype(np.uint32)


def _disk_proxy(n: int = PROXY_SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """Unit disk in the z = 0 plane, a triangle fan that encloses it."""
    cx, sy = _ring(n)
    pos = np.concatenate([[[0.0, 0.0, 0.0]], np.stack([cx, sy, np.zeros(n)], -1)])
    k = np.arange(n)
    return pos, np.stack([np.zeros(n, int), 1 + k, 1 + (k + 1) % n], -1).astype(np.uint32)


def _cylinder_proxy(n: int = PROXY_SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """Open unit cylinder along z ∈ [0, 1], a tube that encloses it."""
    cx, sy = _ring(n)
    pos = np.concatenate([np.stack([cx, sy, np.zeros(n)], -1), np.stack([cx, sy, np.ones(n)], -1)])
    k = np.arange(n)
    faces = np.concatenate([np.stack([k, (k + 1) % n, k + n], -1), np.stack([(k + 1) % n, (k + 1) % n + n, k + n], -1)])
    return pos, faces.astype(np.uint32)


_PROXIES = {"Sphere": _sphere_proxy, "Disk": _disk_proxy, "Cylinder": _cylinder_proxy}
