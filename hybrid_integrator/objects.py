"""Objects and shapes: the heuristic's objects inside a scene batched by material (paper §4, §7).

The paper selects *objects* (§4.1: the pre-production candidates, §4: one relevance and cost per
object and frame). In a Mitsuba scene file an object is a ``<shape>``. But every Mitsuba shape is
an instance that Dr.Jit must visit each time a kernel makes a virtual call on shapes (and a frozen
function walks every registered instance on each replay): the per-frame cost of tracing grows with
the number of shapes alive in the process, not with what a frame traces. Rasterizers batch draws
by material for the same reason.

:func:`batch_by_material` therefore merges the meshes of a scene that share a material (BSDF,
media, emitter, vertex attributes) into one Mitsuba mesh each, with Mitsuba's own ``merge`` shape
plugin (what ``mi.load_file(..., optimize=True)`` does), keeping analytic shapes, emitters and
sensors as they are. Each merged mesh's id records the objects it holds, in order, with their
triangle counts (``hybrid-merge:[["floor", 2], ["box_0_0", 12], ...]``), so the scene itself says
which object every triangle belongs to. :class:`SceneObjects` reads that back: the objects' names,
the shape that holds each, and the object of every triangle (``triangle_object``), on the device.
A scene loaded any other way has one object per shape.
"""
from __future__ import annotations

import json
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .cache import scene_state

#: how a merged mesh's id starts; the rest is JSON: [[object name, triangles], ...]
MERGE_PREFIX = "hybrid-merge:"


def _merge_key(shape: mi.Shape):
    """What meshes must share to be merged (as Mitsuba's ``merge`` plugin groups them), or None
    for a shape that stays on its own (analytic shapes, emitters, sensors, mesh attributes,
    flipped normals, which ``Mesh.merge`` does not carry over)."""
    if not shape.is_mesh() or shape.is_emitter() or shape.is_sensor() or shape.has_mesh_attributes() \
            or shape.has_flipped_normals():
        return None
    return (shape.bsdf(), shape.interior_medium(), shape.exterior_medium(), shape.has_vertex_normals(),
            shape.has_vertex_texcoords(), shape.has_face_normals())


def batch_by_material(scene: mi.Scene) -> mi.Scene:
    """``scene`` with the meshes that share a material merged into one mesh each (module
    docstring); the scene itself when no two meshes share one. Sensors, the integrator and the
    emitters that are not attached to a shape are carried over as they are."""
    groups: dict[tuple, list[mi.Shape]] = {}
    alone: list[mi.Shape] = []
    names = {}  # read now: loading names every object after its dictionary key
    for index, shape in enumerate(scene.shapes()):
        names[id(shape)] = _name(shape, index)
        key = _merge_key(shape)
        if key is None:
            alone.append(shape)
        else:
            groups.setdefault(key, []).append(shape)
    if all(len(group) == 1 for group in groups.values()):
        return scene
    children: dict[str, object] = {}

    def add(obj, key: str) -> None:  # load_dict names each object after its key: keep the names
        children[key if key not in children else f"{key} ({len(children)})"] = obj

    for k, group in enumerate(groups.values()):
        if len(group) == 1:
            alone.append(group[0])
            continue
        record = MERGE_PREFIX + json.dumps([[names[id(shape)], int(shape.face_count())] for shape in group])
        merged = mi.load_dict({"type": "merge", **{f"part_{i:07d}": shape for i, shape in enumerate(group)}})
        _check_concatenated(merged, group)
        merged.set_id(record)
        add(merged, record)
    for k, shape in enumerate(alone):
        add(shape, names[id(shape)])
    for k, emitter in enumerate(scene.emitters()):
        if not mi.has_flag(emitter.flags(), mi.EmitterFlags.Surface):  # area lights come with their shape
            add(emitter, emitter.id() or f"emitter_{k}")
    for k, sensor in enumerate(scene.sensors()):
        add(sensor, sensor.id() or f"sensor_{k}")
    if scene.integrator() is not None:
        add(scene.integrator(), scene.integrator().id() or "integrator")
    return mi.load_dict({"type": "scene", **children}, optimize=False)


def _check_concatenated(merged: mi.Mesh, group: list[mi.Shape]) -> None:
    """The merged mesh must hold the group's triangles in the order given (the object table
    relies on it): Mitsuba's ``merge`` concatenates pairwise, in order."""
    faces = sum(int(shape.face_count()) for shape in group)
    first = np.array(merged.vertex_positions_buffer())[:3]
    expected = np.array(group[0].vertex_positions_buffer())[:3]
    if int(merged.face_count()) != faces or not np.array_equal(first, expected):
        raise RuntimeError("Mitsuba's merge did not concatenate the meshes in order")  # a Mitsuba change


def _name(shape: mi.Shape, index: int) -> str:
    """An object's name: its shape's id, or its place in the file for a shape without one."""
    return shape.id() or f"shape #{index}"


def _parts(shape: mi.Shape, index: int) -> list[tuple[str, int]]:
    """The objects a shape holds and their triangle counts (one object for an unmerged shape;
    its count is its face count, 0 for an analytic shape)."""
    name = shape.id()
    if name.startswith(MERGE_PREFIX):
        parts = [(str(n), int(f)) for n, f in json.loads(name[len(MERGE_PREFIX):])]
        if sum(f for _, f in parts) == int(shape.face_count()):
            return parts
    return [(_name(shape, index), int(shape.face_count()) if shape.is_mesh() else 0)]


@dataclass(frozen=True)
class SceneObjects:
    """The objects of a scene (module docstring), in ``scene.shapes()`` order and, within a merged
    mesh, in triangle order."""

    names: tuple[str, ...]
    shape: np.ndarray  # (n_objects,) index into scene.shapes() of the shape that holds each object
    first_object: np.ndarray  # (n_shapes,) index of each shape's first object
    faces: np.ndarray  # (n_objects,) triangles of each object (0: an analytic shape)

    def __len__(self) -> int:
        return len(self.names)

    def index(self, name: str) -> int:
        return self.names.index(name)

    def bsdf(self, k: int, scene: mi.Scene) -> mi.BSDF | None:
        return scene.shapes()[int(self.shape[k])].bsdf()


def scene_objects(scene: mi.Scene) -> SceneObjects:
    """The :class:`SceneObjects` of ``scene`` (read once per scene, ``cache.scene_state``)."""
    return scene_state(scene, "objects", lambda: _read_objects(scene))


def _read_objects(scene: mi.Scene) -> SceneObjects:
    names, shape_of, faces, first = [], [], [], []
    for k, shape in enumerate(scene.shapes()):
        first.append(len(names))
        for name, count in _parts(shape, k):
            names.append(name)
            shape_of.append(k)
            faces.append(count)
    return SceneObjects(names=tuple(names), shape=np.array(shape_of, dtype=np.int64),
                        first_object=np.array(first, dtype=np.int64), faces=np.array(faces, dtype=np.int64))


def object_of_triangles(objects: SceneObjects, shape_triangles: np.ndarray) -> np.ndarray:
    """The object of every triangle of the scene's global triangle numbering (shapes in order,
    ``shape_triangles[k]`` triangles each, as the raster draws them): a merged mesh's triangles
    belong to its objects in order; every triangle of any other shape (a proxy's too) to its one
    object."""
    out = []
    for k, count in enumerate(shape_triangles):
        owned = np.nonzero(objects.shape == k)[0]
        if len(owned) == 1:
            out.append(np.full(int(count), owned[0], dtype=np.uint32))
        else:
            out.append(np.repeat(owned.astype(np.uint32), objects.faces[owned]))
    return np.concatenate(out) if out else np.zeros(0, dtype=np.uint32)


def object_indices(table: mi.UInt32, first_triangle: mi.UInt32, shape: mi.UInt32, prim: mi.UInt32,
                   active: mi.Bool) -> mi.UInt32:
    """Object index of a hit on ``shape`` (index into ``scene.shapes()``) and triangle ``prim``
    (0 for analytic shapes), through the global triangle table (``object_of_triangles``)."""
    return dr.gather(mi.UInt32, table, dr.gather(mi.UInt32, first_triangle, shape, active) + prim, active)
