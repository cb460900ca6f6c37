"""Primary hits: from a visibility buffer to exact Mitsuba surface interactions (paper §3.2).

The hybrid's ray tracer starts where the rasterizer stopped. For every pixel the visibility buffer
names the frontmost triangle (a global number, ``raster.visibility``); tables made once per scene
say which shape and object it belongs to, and the pixel's own camera ray is intersected with that
one triangle (Möller–Trumbore, Mitsuba's ``prim_uv`` convention p = (1 − u − v) p0 + u p1 + v p2),
which gives the barycentrics and the distance the ray tracer would find. A Mitsuba
``PreliminaryIntersection3f`` built from them and completed with ``compute_surface_interaction``
against the same camera ray is the *same* interaction Mitsuba's own ray tracer produces (shading
frame, UVs, ``wi``), so the secondary rays and the BSDFs that follow are Mitsuba's, unchanged.

Some pixels are *refined*: their primary hit is re-found by tracing their camera ray
(``ray_intersect_preliminary``, only on those lanes: :func:`primary_hits`; or, with
``refine="trace"``, the default on CUDA, inside the trace stage's launch, which keeps what their
rays found for :func:`resolved`: :func:`raster_hits` leaves them without a hit), and they are
counted in the frame statistics:

- pixels of tessellated analytic shapes (``proxy``): the proxy only says that the exact shape may
  be there;
- *outline* pixels, whose 4-neighbourhood shows another object or the background, where the
  raster's answer may differ from the ray's (:data:`OUTLINES`). The draw snaps vertices to a
  fixed-point sub-pixel grid (1/256 pixel), so a sample lying that close to an object's outline
  can land on the wrong side of it (on a straight outline aligned with the pixel grid this flips
  a whole column at once), and both rasterizers resolve depth in floats, so where two objects
  meet or overlap at the same depth either may win. With ``ties`` (the default with the compute
  raster pass, :func:`resolve_outline`) only those pixels are re-traced: the sample lies within :data:`EDGE_TOLERANCE` pixels of its own triangle's edge, or
  a neighbour's triangle covers it that closely and lies in front of the raster's hit or within
  :data:`DEPTH_TIE` of its depth (:func:`outline_ties`). ``silhouettes`` (the draw's) re-traces
  every outline pixel (:func:`silhouettes`): at 320×180, 3–17 % of a frame's pixels against
  0.2–1.3 % (``docs/results/cpu/refine_need.md``);
- pixels whose camera ray misses the raster's triangle by more than the snapping can explain
  (``MISS_TOLERANCE`` in barycentric units);
- with ``hide_emitters``, pixels that show an area emitter: Mitsuba's ``path`` hides area emitters
  from camera rays altogether (its camera rays pass through them, ``skip_area_emitters``), so
  such a pixel shows what lies behind the emitter, which only its ray can find
  (:func:`first_hits`).

Within one object a sample on a shared edge may name either triangle: the intersection with the
named one, clamped into it, is the same point.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .cache import scene_state
from .errors import HybridError
from .objects import object_indices
from .raster.visibility import TriangleTables

#: how far outside its raster triangle (in barycentric units) a camera ray may pass before the
#: pixel is re-traced
MISS_TOLERANCE = 1e-3
#: which outline pixels are re-traced (module docstring): ``ties`` (:func:`outline_ties`);
#: ``silhouettes``, every pixel whose 4-neighbourhood shows another object (:func:`silhouettes`);
#: ``auto``, the one the raster pass needs (:func:`resolve_outline`)
OUTLINES = ("auto", "ties", "silhouettes")
#: how close (in pixels) to a triangle's edge a sample must lie for the raster's coverage of it to
#: be doubted: four times the draw's vertex snapping (1/256 pixel), far above the compute pass's
#: float rounding
EDGE_TOLERANCE = 1.0 / 64.0
#: relative difference of two surfaces' distances along a camera ray below which the raster's depth
#: test may pick either of them (both rasterizers resolve depth in 32-bit floats)
DEPTH_TIE = 1e-4


@dataclass
class PrimaryHits:
    """Camera rays and first-hit interactions of every pixel (row-major, row 0 at the top)."""

    ray: mi.Ray3f
    si: mi.SurfaceInteraction3f
    #: index into ``scene.shapes()`` of each pixel's hit
    shape: mi.UInt32
    #: index of each pixel's object (``objects.SceneObjects``)
    object: mi.UInt32
    #: the pixel's first hit is a surface (background pixels and proxy misses are False)
    valid: mi.Bool
    #: per pixel, why its hit came from a ray: 0 it did not, 1 an analytic shape's proxy,
    #: 2 a silhouette or a raster miss, 3 a hidden area emitter (module docstring)
    refined: mi.UInt32


def resolve_outline(outline: str, method: str) -> str:
    """``outline`` (:data:`OUTLINES`) with ``auto`` resolved for the raster pass's ``method``
    (``draw`` or ``compute``, ``raster.visibility.resolve_method``); another value is a
    :class:`HybridError` naming it. The compute pass decides coverage with float edge functions at
    the sample itself, so its answer can differ from the ray's only where :func:`outline_ties`
    looks: ``ties``. The draw snaps vertices to 1/256 pixel, which can move the outline of a dense
    mesh across a sample next to it by a triangle that no sample shows and ``ties`` cannot test
    (the showcase's bunny at 320×180, one pixel; ``scripts/refine_need.py``): ``silhouettes``."""
    if outline not in OUTLINES:
        raise HybridError(f"outline='{outline}' is not one of {list(OUTLINES)}")
    if outline == "auto":
        return "ties" if method == "compute" else "silhouettes"
    return outline


def camera_rays(sensor: mi.Sensor, width: int, height: int, offset, differentials: bool = False) -> mi.Ray3f:
    """Mitsuba's camera rays through every pixel of a ``width`` × ``height`` film at sub-pixel
    ``offset`` (the rays the raster stands in for, and the primary rays of the pure ray-tracing
    baseline). ``offset`` is a pair of floats or a ``mi.Point2f`` (as the device pass passes it).
    ``differentials``: ``mi.RayDifferential3f``, with the rays one pixel to the right and one
    below (the same main rays: Mitsuba's ``sample_ray_differential``), which the ``ties`` outline
    test measures pixels with."""
    index = dr.arange(mi.UInt32, width * height)
    if not isinstance(offset, mi.Point2f):
        # opaque: the offset changes every pass, and a literal would recompile the kernel each time
        offset = mi.Point2f(*(dr.opaque(mi.Float, float(o)) for o in offset))
    position = mi.Point2f((mi.Float(index % width) + offset.x) / width, (mi.Float(index // width) + offset.y) / height)
    sample = sensor.sample_ray_differential if differentials else sensor.sample_ray
    ray, _ = sample(0.0, 0.5, position, mi.Point2f(0.5, 0.5))
    return ray


def first_hits(scene: mi.Scene, ray: mi.Ray3f, active: mi.Bool, hide_emitters: bool) -> mi.PreliminaryIntersection3f:
    """The first hits of camera rays ``ray`` on the lanes of ``active``; with ``hide_emitters``,
    the first hit that is not an area emitter, as Mitsuba's ``path`` finds it for its camera rays
    (a ray spawned past each emitter it meets, ``SamplingIntegrator.skip_area_emitters``), with its
    distance measured along the camera ray itself: Mitsuba's helper returns it from the last
    emitter passed, and a surface interaction made against the camera ray from that distance
    would misplace an analytic shape behind the emitter."""
    pi = scene.ray_intersect_preliminary(ray, False, active)
    if not hide_emitters:
        return pi

    def past(pi):
        beyond = pi.compute_surface_interaction(ray, mi.RayFlags.Minimal).spawn_ray(ray.d)
        found = scene.ray_intersect_preliminary(beyond, False)
        found.t += dr.dot(beyond.o - ray.o, ray.d)
        return (found,)

    return dr.while_loop((pi,), lambda pi: pi.is_valid() & (pi.shape.emitter() != None), past,  # noqa: E711
                         label="hidden emitters")[0]


def shape_indices(table: mi.UInt32, shape: mi.ShapePtr, valid: mi.Bool) -> mi.UInt32:
    """Index into ``scene.shapes()`` of each lane's ``shape`` pointer (``table``: :func:`shape_table`).

    ``PreliminaryIntersection3f.shape_index`` is filled by the LLVM backend's ray tracer but not by
    OptiX, so indices are recovered from the pointers themselves: a shape pointer is an id in
    Dr.Jit's registry, mapped back through a small lookup table."""
    return dr.gather(mi.UInt32, table, dr.reinterpret_array(mi.UInt32, shape), valid)


def shape_table(scene: mi.Scene) -> mi.UInt32:
    """Registry id of each shape → its index in ``scene.shapes()`` (read once per scene)."""
    return scene_state(scene, "shape_table", lambda: _shape_table(scene))


def _shape_table(scene: mi.Scene) -> mi.UInt32:
    ids = np.array(dr.reinterpret_array(mi.UInt32, scene.shapes_dr()), dtype=np.int64)
    table = np.zeros(ids.max() + 1 if ids.size else 1, dtype=np.uint32)
    table[ids] = np.arange(len(ids), dtype=np.uint32)
    return mi.UInt32(table)


def silhouettes(label_at: Callable[[mi.UInt32, mi.Bool], mi.UInt32], width: int, height: int) -> mi.Bool:
    """Pixels with a 4-neighbour inside the image whose label differs; ``label_at(index, active)``
    gives the label (an object number, 0 for the background) of the pixels ``index`` (row-major):
    a function, not an array, so that the labels are read where they are needed, in the kernel
    that tests them (a gather from an array computed in the same kernel would make it a kernel of
    its own)."""
    i, neighbours = _neighbours(width, height)
    label = label_at(i, mi.Bool(True))
    edge = mi.Bool(False)
    for inside, j in neighbours:
        edge |= inside & (label_at(j, inside) != label)
    return edge


def _neighbours(width: int, height: int) -> tuple[mi.UInt32, list[tuple[mi.Bool, mi.UInt32]]]:
    """Every pixel of a ``width`` × ``height`` frame (row-major) and its 4-neighbours: per
    neighbour, whether it lies inside the image and its pixel index."""
    i = dr.arange(mi.UInt32, width * height)
    x, y = i % width, i // width
    return i, [(x + 1 < width, i + 1), (x > 0, i - 1), (y + 1 < height, i + width), (y > 0, i - width)]


def ray_triangle(ray: mi.Ray3f, p0: mi.Point3f, p1: mi.Point3f, p2: mi.Point3f) -> tuple[mi.Float, mi.Point2f]:
    """Distance along ``ray`` to the plane of triangle (p0, p1, p2) and the barycentrics (u, v) of
    that point, Mitsuba's ``prim_uv`` (Möller–Trumbore, as ``Mesh::ray_intersect_triangle``)."""
    e1, e2 = p1 - p0, p2 - p0
    pvec = dr.cross(ray.d, e2)
    inv_det = dr.rcp(dr.dot(e1, pvec))
    tvec = ray.o - p0
    qvec = dr.cross(tvec, e1)
    return dr.dot(e2, qvec) * inv_det, mi.Point2f(dr.dot(tvec, pvec) * inv_det, dr.dot(ray.d, qvec) * inv_det)


def edge_margin(ray: mi.RayDifferential3f, p0: mi.Point3f, p1: mi.Point3f, p2: mi.Point3f) -> tuple[mi.Float, mi.Float]:
    """:func:`ray_triangle`'s distance, and the *margin*: the signed distance in
    pixels from the ray's sample to the triangle's nearest edge, negative outside it (NaN where the
    ray runs in the triangle's plane). A barycentric coordinate is, to first order, affine on the
    film, so its change to the rays one pixel across and one down (the ray's differentials) is its
    gradient in pixels, and the coordinate over that gradient's length is the distance to the edge
    where it is 0. The gradient includes the surface's foreshortening: the margin is measured on
    the film, where the rasterizer decides coverage (to a few per cent: a difference over one
    pixel, where perspective bends the coordinate; far finer than :data:`EDGE_TOLERANCE` needs)."""
    t, uv = ray_triangle(ray, p0, p1, p2)
    _, uv_x = ray_triangle(mi.Ray3f(ray.o_x, ray.d_x), p0, p1, p2)
    _, uv_y = ray_triangle(mi.Ray3f(ray.o_y, ray.d_y), p0, p1, p2)
    margin, unknown = mi.Float(dr.inf), mi.Bool(False)
    for b, b_x, b_y in ((uv.x, uv_x.x, uv_y.x), (uv.y, uv_x.y, uv_y.y),
                        (1.0 - uv.x - uv.y, 1.0 - uv_x.x - uv_x.y, 1.0 - uv_y.x - uv_y.y)):
        distance = b * dr.rsqrt(dr.maximum(dr.square(b_x - b) + dr.square(b_y - b), 1e-30))
        unknown |= dr.isnan(distance)
        margin = dr.minimum(margin, distance)
    return t, dr.select(unknown, dr.nan, margin)


def _corners(tables: TriangleTables, triangle: mi.UInt32, active: mi.Bool) -> tuple[mi.Point3f, mi.Point3f, mi.Point3f]:
    """The vertices of the tables' triangles ``triangle`` (global numbers) on the lanes of ``active``."""
    corners = dr.gather(mi.Vector3u, tables.faces, triangle, active)
    return tuple(dr.gather(mi.Point3f, tables.vertices, corners[k], active) for k in range(3))


@dataclass
class RasterRecord:
    """A visibility buffer resolved on the device, before any refinement: the raster's own answer."""

    hit: mi.Bool  # the raster drew a triangle here (and it is within the sensor's far clip)
    shape: mi.UInt32
    object: mi.UInt32
    prim: mi.UInt32  # triangle index within the shape (0 on a proxy)
    t: mi.Float  # distance along the camera ray
    uv: mi.Point2f  # barycentrics, clamped into the triangle
    inside: mi.Bool  # the camera ray passes through the triangle (up to MISS_TOLERANCE)
    proxy: mi.Bool  # the triangle belongs to an analytic shape's proxy


def resolve(triangle_id: mi.UInt32, ray: mi.Ray3f, tables: TriangleTables) -> RasterRecord:
    """The raster's answer per pixel from its triangle numbers (``Rasterizer.read_ids``)."""
    hit = triangle_id > 0
    triangle = dr.select(hit, triangle_id - 1, 0)
    shape = dr.gather(mi.UInt32, tables.shape, triangle, hit)
    t, uv = ray_triangle(ray, *_corners(tables, triangle, hit))
    inside = (uv.x >= -MISS_TOLERANCE) & (uv.y >= -MISS_TOLERANCE) & (uv.x + uv.y <= 1.0 + MISS_TOLERANCE) & (t > 0)
    hit &= ~(inside & (t > ray.maxt))  # beyond the far clip: background, as for the camera ray
    uv = dr.maximum(uv, 0.0)
    uv /= dr.maximum(uv.x + uv.y, 1.0)  # clamped into the triangle: raster samples sit on its edges too
    proxy = hit & dr.gather(mi.Bool, tables.proxy, shape, hit)
    return RasterRecord(hit=hit, shape=shape, object=dr.gather(mi.UInt32, tables.object, triangle, hit),
                        prim=dr.select(proxy, 0, triangle - dr.gather(mi.UInt32, tables.first_triangle, shape, hit)),
                        t=t, uv=uv, inside=inside, proxy=proxy)


def _label(drawn: mi.UInt32, active: mi.Bool, tables: TriangleTables) -> mi.UInt32:
    """The object (+ 1, 0: none) of the visibility buffer's triangle numbers (+ 1) ``drawn``. A
    pixel beyond the far clip keeps its triangle's object: its own ray decides it exactly."""
    return dr.select(drawn > 0, dr.gather(mi.UInt32, tables.object, drawn - 1, active & (drawn > 0)) + 1, 0)


def outline_ties(ray: mi.RayDifferential3f, record: RasterRecord, triangle_id: mi.UInt32, tables: TriangleTables,
                 width: int, height: int) -> mi.Bool:
    """The outline pixels whose raster hit may not be their camera ray's (``outline="ties"``,
    module docstring). A pixel one of whose 4-neighbours shows another object or the background
    (the neighbour's triangle from the visibility buffer ``triangle_id``, read in this kernel) is
    doubted where

    - its sample lies within :data:`EDGE_TOLERANCE` pixels of its own triangle's edges, or outside
      them (:func:`edge_margin`): the object beyond that edge may be the ray's;
    - a neighbour's triangle covers the sample to within :data:`EDGE_TOLERANCE` pixels and its
      plane lies in front of the raster's hit (or the pixel shows the background): the
      rasterizer's coverage may have left it out;
    - the plane of a neighbour's triangle lies within :data:`DEPTH_TIE` of the hit's distance along
      the ray: where two objects meet, or overlap at one depth, the depth test may pick either.

    Anywhere else the rasterizer's coverage and depth test decide exactly as the ray does. Only the
    triangles seen at the pixel and its neighbours are tested: one that no sample shows (smaller
    than a pixel, between the samples) goes untested, as it does for :func:`silhouettes`. Unknown
    margins (NaN) count as doubted."""
    _, neighbours = _neighbours(width, height)
    own = _label(triangle_id, mi.Bool(True), tables)
    outline, drawn, other = mi.Bool(False), [], []
    for inside, j in neighbours:
        drawn.append(dr.gather(mi.UInt32, triangle_id, j, inside))
        other.append(inside & (_label(drawn[-1], inside, tables) != own))
        outline |= other[-1]

    def doubt(drawn, other) -> mi.Bool:
        """the tests, on the outline pixels' lanes alone (a branch: the GPU's warps and the CPU's
        packets without an outline pixel skip them)"""
        hit, t = record.hit, dr.select(record.hit, record.t, dr.inf)
        _, margin = edge_margin(ray, *_corners(tables, triangle_id - 1, hit))
        doubted = hit & ~(margin >= EDGE_TOLERANCE)
        for number, differs in zip(drawn, other):
            tested = differs & (number > 0)
            t_other, margin = edge_margin(ray, *_corners(tables, number - 1, tested))
            covers = ~(margin < -EDGE_TOLERANCE) & ~(t_other <= 0.0) & ~(t_other >= t * (1.0 + DEPTH_TIE))
            tie = hit & ~(dr.abs(t_other - t) > DEPTH_TIE * t)
            doubted |= tested & (covers | tie)
        return doubted

    return dr.if_stmt((tuple(drawn), tuple(other)), outline, doubt, lambda drawn, other: mi.Bool(False),
                      label="outline ties")


def _indices(hit, valid: mi.Bool, tables: TriangleTables) -> tuple[mi.UInt32, mi.UInt32]:
    """The tables' shape and object of Mitsuba's hits ``hit`` (a preliminary or a surface
    interaction: its shape pointer and triangle) on the lanes of ``valid``."""
    shape = shape_indices(tables.pointer_shape, hit.shape, valid)
    return shape, object_indices(tables.object, tables.first_triangle, shape, hit.prim_index, valid)


@dataclass
class Intersections:
    """Per pixel, what a hit's surface interaction is made from (Mitsuba's preliminary
    intersection, 6 values, against some 40 for the interaction) and what the hit is."""

    pi: mi.PreliminaryIntersection3f
    shape: mi.UInt32
    object: mi.UInt32
    valid: mi.Bool

    @classmethod
    def of(cls, pi: mi.PreliminaryIntersection3f, active: mi.Bool, tables: TriangleTables) -> "Intersections":
        """The camera rays' preliminary intersections ``pi`` on the lanes of ``active``, Mitsuba's
        shape pointers turned into the tables' shape and object."""
        valid = pi.is_valid() & active
        return cls(pi, *_indices(pi, valid, tables), valid)

    def hits(self, ray: mi.Ray3f, refined: mi.UInt32) -> PrimaryHits:
        """The surface interactions of ``ray`` (one ``compute_surface_interaction``), kept with
        the ray, without its differentials (which the stages after this one do not read)."""
        ray = mi.Ray3f(ray)
        si = self.pi.compute_surface_interaction(ray, mi.RayFlags.All, self.valid)
        return PrimaryHits(ray=ray, si=si, shape=self.shape, object=self.object, valid=self.valid, refined=refined)


def raster_intersections(scene: mi.Scene, ray: mi.Ray3f, triangle_id: mi.UInt32, width: int, height: int,
                         tables: TriangleTables, outline: str = "silhouettes",
                         hide_emitters: bool = False) -> tuple[Intersections, mi.UInt32]:
    """The raster's intersections for the camera rays ``ray`` of a ``width`` × ``height`` frame,
    with no ray traced, and per pixel why it is refined (``PrimaryHits.refined``): those pixels
    are left without a hit (``valid`` False), to be found by their camera rays. ``outline``
    (``ties`` or ``silhouettes``, :func:`resolve_outline`): which outline pixels are refined;
    ``ties`` needs ``ray`` with its differentials (``camera_rays(..., differentials=True)``).
    ``hide_emitters``: the pixels showing an area emitter are refined too (module docstring)."""
    if outline not in OUTLINES[1:]:
        raise ValueError(f"outline='{outline}' is not one of {list(OUTLINES[1:])}: resolve 'auto' first")
    if outline == "ties" and not isinstance(ray, mi.RayDifferential3f):
        raise ValueError("outline='ties' measures pixels with the rays' differentials: "
                         "pass camera_rays(..., differentials=True)")
    record = resolve(triangle_id, ray, tables)
    proxy = record.proxy
    if outline == "ties":
        doubted = outline_ties(ray, record, triangle_id, tables, width, height)
    else:  # the labels read from the visibility buffer itself: silhouettes need no kernel before this one
        doubted = silhouettes(lambda index, active: _label(dr.gather(mi.UInt32, triangle_id, index, active), active, tables),
                              width, height)
    edge = (doubted | (record.hit & ~record.inside)) & ~proxy
    hidden = record.hit & dr.gather(mi.Bool, tables.emitter, record.shape, record.hit) if hide_emitters else mi.Bool(False)
    raster_hit = record.hit & ~(proxy | edge | hidden)

    pi = dr.zeros(mi.PreliminaryIntersection3f, dr.width(ray))
    pi.t = dr.select(raster_hit, record.t, dr.inf)
    pi.prim_uv = record.uv
    pi.prim_index = record.prim
    pi.shape_index = record.shape
    pi.shape = dr.gather(mi.ShapePtr, scene.shapes_dr(), record.shape, raster_hit)
    pi.valid = raster_hit
    refined = mi.UInt32(dr.select(hidden, 3, dr.select(proxy, 1, dr.select(edge, 2, 0))))
    return Intersections(pi=pi, shape=record.shape, object=record.object, valid=raster_hit), refined


def raster_hits(scene: mi.Scene, ray: mi.Ray3f, triangle_id: mi.UInt32, width: int, height: int,
                tables: TriangleTables, outline: str = "silhouettes", hide_emitters: bool = False) -> PrimaryHits:
    """The raster's hits as Mitsuba surface interactions (:func:`raster_intersections`), the
    refined pixels without a hit, for :func:`resolved`. A kernel that traces rays costs the GPU
    its traversal's latency however few rays it traces (an H200 without RT cores: 0.21–0.60 ms
    for the 1–5 % refined pixels against 0.05–0.07 without them,
    ``docs/results/gpu/issue10/stop31``), so the device pass re-traces them inside its trace
    stage's launch, which traces anyway (``pipeline.device_pass``)."""
    found, refined = raster_intersections(scene, ray, triangle_id, width, height, tables, outline, hide_emitters)
    return found.hits(ray, refined)


def resolved(hits: PrimaryHits, pi: mi.PreliminaryIntersection3f, again: mi.Bool, tables: TriangleTables) -> PrimaryHits:
    """``hits`` with the lanes of ``again`` taken from the preliminary intersections ``pi`` of
    their camera rays, found in another kernel and kept (``refine="trace"``)."""
    return dr.select(again, Intersections.of(pi, again, tables).hits(hits.ray, hits.refined), hits)


def primary_hits(scene: mi.Scene, ray: mi.Ray3f, triangle_id: mi.UInt32, width: int, height: int,
                 tables: TriangleTables, outline: str = "silhouettes", hide_emitters: bool = False) -> PrimaryHits:
    """Mitsuba's surface interactions at the raster's hits (module docstring) for the camera rays
    ``ray`` of a ``width`` × ``height`` frame, the refined pixels traced in the same kernel
    (:func:`first_hits` on their lanes alone), every pixel's interaction made from the
    merged preliminary intersections: one ``compute_surface_interaction``, whose virtual call over
    the shapes is the kernel's largest part."""
    raster, refined = raster_intersections(scene, ray, triangle_id, width, height, tables, outline, hide_emitters)
    again = refined > 0
    traced = Intersections.of(first_hits(scene, ray, again, hide_emitters), again, tables)
    return dr.select(again, traced, raster).hits(ray, refined)


def traced_hits(scene: mi.Scene, ray: mi.Ray3f, tables: TriangleTables, hide_emitters: bool = False) -> PrimaryHits:
    """The pure ray-tracing baseline's primary hits (paper §8): Mitsuba's camera rays traced
    (past the area emitters with ``hide_emitters``, :func:`first_hits`)."""
    if hide_emitters:
        return Intersections.of(first_hits(scene, ray, mi.Bool(True), True), mi.Bool(True), tables).hits(ray, mi.UInt32(0))
    si = scene.ray_intersect(ray)
    valid = si.is_valid()
    shape, obj = _indices(si, valid, tables)
    return PrimaryHits(ray=ray, si=si, shape=shape, valid=valid, refined=mi.UInt32(0), object=obj)


def visibility_buffer(ray: mi.Ray3f, triangle_id: mi.UInt32, tables: TriangleTables, eye, size: tuple[int, int],
                      offset: tuple[float, float]):
    """The raster's own answer (:func:`resolve`, no refinement) as a host ``VisibilityBuffer``:
    object index, triangle, barycentrics and distance from the eye per pixel."""
    from .raster.visibility import VisibilityBuffer

    w, h = size
    record = resolve(triangle_id, ray, tables)
    depth = record.t + dr.norm(ray.o - mi.Point3f(*(float(c) for c in eye)))  # camera rays start on the near plane
    hit = np.array(record.hit).reshape(h, w)
    return VisibilityBuffer(
        shape_index=np.where(hit, np.array(record.object, dtype=np.int64).reshape(h, w), -1).astype(np.int32),
        prim_index=np.where(hit, np.array(record.prim).reshape(h, w), 0).astype(np.uint32),
        bary=np.where(hit[..., None], np.stack([np.array(record.uv.x), np.array(record.uv.y)], -1).reshape(h, w, 2), 0.0).astype(np.float32),
        depth=np.where(hit, np.array(depth).reshape(h, w), np.inf).astype(np.float32),
        proxy=np.array(record.proxy).reshape(h, w), offset=(float(offset[0]), float(offset[1])))
