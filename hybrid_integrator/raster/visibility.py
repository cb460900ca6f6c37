"""The visibility buffer: primary visibility resolved by the rasterizer (paper §3.1, §8).

The paper's geometry pass writes a G-buffer whose first job is to replace the primary rays of a
ray tracer (§3.1, Fig. 4a). Its minimal form is a *visibility buffer*: per pixel, the one number of
the frontmost triangle. Everything else follows from it on the device (:mod:`hybrid_integrator.primary`):
which shape and object the triangle belongs to (tables made once per scene), and where the pixel's
camera ray meets it and how far away (a ray–triangle intersection, so the barycentrics and the
distance are the ray tracer's own, not the rasterizer's interpolation); the paper's position, normal,
albedo, specular and optical targets then come from Mitsuba's own surface interaction and BSDFs
(:mod:`hybrid_integrator.raster.gbuffer`).

The :class:`Rasterizer` uploads a scene's triangles to the GPU once, in one vertex and one index
buffer, and draws every frame with a single draw call at any sub-pixel offset: the fragment shader
only writes ``gl_PrimitiveID``, there is no geometry shader, and the depth test runs early on a
reversed-Z float depth buffer (``context.DepthPrecision``). Or it computes the same buffer with
compute shaders from the same two buffers (:mod:`.compute`): the default on a CUDA variant, where
the GPU's fixed-function rasterizer is the slow part (``RASTER_METHODS``).
"""
from __future__ import annotations

from dataclasses import dataclass

import mitsuba as mi
import moderngl
import numpy as np

from ..errors import HybridError, UnsupportedSceneError
from ..objects import object_of_triangles, scene_objects
from .camera import RasterCamera
from .compute import ComputeVisibility
from .context import depth_precision, gl_context, max_target_side, shader_source
from .geometry import SceneGeometry, geometry_key, scene_geometry
from .interop import Readback


#: how the visibility pass rasterizes (:meth:`Rasterizer.render`): ``draw`` (OpenGL's rasterizer),
#: ``compute`` (compute shaders, :mod:`.compute`), or ``auto``: ``compute`` on a CUDA variant (the
#: H100's and H200's fixed-function rasterizer is slow, and their compute units are not) and
#: ``draw`` otherwise (Mesa's llvmpipe draws faster than it runs the compute shaders)
RASTER_METHODS = ("auto", "draw", "compute")


def resolve_method(method: str) -> str:
    """``method`` (:data:`RASTER_METHODS`) with ``auto`` resolved for the current variant; any
    other value is a :class:`HybridError` naming it (as the integrator's ``raster`` property)."""
    if method not in RASTER_METHODS:
        raise HybridError(f"raster='{method}' is not one of {list(RASTER_METHODS)}")
    if method == "auto":
        return "compute" if (mi.variant() or "").startswith("cuda") else "draw"
    return method


@dataclass(frozen=True)
class VisibilityBuffer:
    """Primary hits of one raster pass; arrays are indexed ``[row, column]``, row 0 at the top."""

    shape_index: np.ndarray  # (H, W) int32: index of the object seen (``objects.SceneObjects``), -1 for background
    prim_index: np.ndarray  # (H, W) uint32: triangle index within the object's Mitsuba shape
    bary: np.ndarray  # (H, W, 2) float32: Mitsuba's prim_uv of the camera ray's hit, clamped into the triangle
    depth: np.ndarray  # (H, W) float32: distance from the eye along the ray, inf for background
    proxy: np.ndarray  # (H, W) bool: the pixel shows a tessellated analytic shape
    offset: tuple[float, float]  # the sub-pixel sample position of the pass

    @property
    def hit(self) -> np.ndarray:
        return self.shape_index >= 0


@dataclass(frozen=True)
class TriangleTables:
    """What a global triangle number (``SceneGeometry``) stands for, on the device."""

    vertices: mi.Float  # 3 per vertex, world space (as drawn)
    faces: mi.UInt32  # 3 per triangle, into ``vertices``
    shape: mi.UInt32  # per triangle: index into scene.shapes()
    object: mi.UInt32  # per triangle: index into the scene's objects
    first_triangle: mi.UInt32  # per shape
    proxy: mi.Bool  # per shape: an analytic shape drawn as a proxy
    emitter: mi.Bool  # per shape: an area emitter (which ``hide_emitters`` hides from camera rays)
    pointer_shape: mi.UInt32  # shape pointer (registry id) → index into scene.shapes() (primary.shape_table)

    @classmethod
    def of(cls, scene: mi.Scene, geometry: SceneGeometry) -> "TriangleTables":
        from ..primary import shape_table

        objects = object_of_triangles(scene_objects(scene), geometry.triangles_per_shape)
        return cls(pointer_shape=shape_table(scene), vertices=mi.Float(geometry.positions.ravel()), faces=mi.UInt32(geometry.faces.ravel()),
                   shape=mi.UInt32(geometry.shape_of_triangles()), object=mi.UInt32(objects),
                   first_triangle=mi.UInt32(geometry.first_triangle[:-1].astype(np.uint32)),
                   proxy=mi.Bool(geometry.proxy) if len(geometry.proxy) else mi.Bool(False),
                   emitter=mi.Bool([shape.is_emitter() for shape in scene.shapes()] or [False]))


class Rasterizer:
    """Draws one Mitsuba scene's visibility buffer with OpenGL.

    The scene's geometry is uploaded once, when the rasterizer is made; every :meth:`render` reuses
    it. Render targets are made per film size and kept."""

    def __init__(self, scene: mi.Scene, reloads: int = 0):
        self.ctx = gl_context()
        #: what the geometry was read from (``geometry.geometry_key``), and how many times before
        #: the scene's state was re-made for an edit of it (``api.rasterizer``)
        self.geometry_key, self.reloads = geometry_key(scene), reloads
        self.geometry = scene_geometry(scene).renumbered()  # vertices in the order the draw fetches them
        self.tables = TriangleTables.of(scene, self.geometry)
        self.program = self.ctx.program(vertex_shader=shader_source("visibility.vert"),
                                        fragment_shader=shader_source("visibility.frag"))
        #: the scene's vertices (3 float32 each) and triangles (3 uint32 each), uploaded once; the
        #: compute pass (``compute.py``) reads them as storage buffers
        self.vertices = self.ctx.buffer(np.ascontiguousarray(self.geometry.positions, dtype="f4").tobytes() or bytes(12))
        self.faces = self.ctx.buffer(np.ascontiguousarray(self.geometry.faces, dtype="u4").tobytes() or bytes(12))
        self._vao = None
        if len(self.geometry.faces):
            self._vao = self.ctx.vertex_array(self.program, [(self.vertices, "3f", "in_position")],
                                              index_buffer=self.faces, index_element_size=4)
        self._compute: ComputeVisibility | None = None
        self._depth = depth_precision()
        self._targets: dict[tuple[int, int], moderngl.Framebuffer] = {}
        self._readback: Readback | None = None
        #: passes drawn so far: a buffer drawn ahead for the next frame (``pipeline.py``) is that
        #: frame's only while no other pass has drawn into the target since
        self.draws = 0
        #: faces left out of the draw (``method="draw"`` only): None (every face, the default:
        #: meshes may be open), or moderngl's "front" / "back" (``scripts/raster_cull_probe.py``
        #: measures what that saves)
        self.cull: str | None = None

    def target(self, width: int, height: int) -> moderngl.Framebuffer:
        """The target of one film size: the triangle numbers (R32UI) on a 32-bit float depth buffer;
        an :class:`UnsupportedSceneError` where a side exceeds what the OpenGL context can draw."""
        key = (width, height)
        if key not in self._targets:
            limit = max_target_side(self.ctx)
            if max(key) > limit:
                raise UnsupportedSceneError(
                    f"film size {width}×{height} is too large to rasterize: this OpenGL context ({self.ctx.info['GL_RENDERER']}) "
                    f"draws at most {limit} pixels per side; render it with primary='raytrace'")
            fbo = self.ctx.framebuffer(color_attachments=[self.ctx.texture(key, 1, dtype="u4")],
                                       depth_attachment=self.ctx.depth_texture(key))
            self._depth.attach_float_depth(fbo, key)
            self._targets[key] = fbo
        return self._targets[key]

    def render(self, camera: RasterCamera, offset: tuple[float, float] = (0.5, 0.5),
               method: str = "auto") -> moderngl.Framebuffer:
        """The raster pass alone: the scene's visibility buffer in the camera's target (left on the
        GPU), by ``method`` (:data:`RASTER_METHODS`)."""
        self.release()
        self.draws += 1
        if resolve_method(method) == "compute":
            if self._compute is None:
                self._compute = ComputeVisibility(self.ctx, self.vertices, self.faces, len(self.geometry.faces))
            return self._compute.render(camera, offset, self.target(camera.width, camera.height))
        w, h = camera.width, camera.height
        fbo = self.target(w, h)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        # 0 is the background in the integer target; depth 0 is infinitely far (reversed Z)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=0.0)
        if self._vao is not None:
            self.ctx.enable(moderngl.DEPTH_TEST)
            if self.cull is None:
                self.ctx.disable(moderngl.CULL_FACE)
            else:  # the mirrored projection flips the winding: "front" leaves out the hidden faces
                self.ctx.enable(moderngl.CULL_FACE)
                self.ctx.cull_face = self.cull
            self.ctx.depth_func = ">"
            self._depth.zero_to_one(True)
            clip, origin = camera.relative_clip(offset)
            self.program["world_to_clip"].write(clip.T.astype("f4").tobytes())
            self.program["origin"].write(origin.tobytes())
            self._vao.render(moderngl.TRIANGLES)
            self._depth.zero_to_one(False)
        return fbo

    def compute_tiers(self) -> tuple[int, int]:
        """How many triangles the last compute pass rasterized by tiles (large, or crossing the
        eye's plane) and by 64 invocations each (medium); the rest were small (read from the GPU)."""
        return self._compute.tiers() if self._compute is not None else (0, 0)

    def read_ids(self, fbo: moderngl.Framebuffer) -> np.ndarray:
        """The target of :meth:`render` on the host: per pixel (row-major, row 0 at the top) the
        global triangle number + 1, 0 for the background."""
        self.release()
        return np.frombuffer(fbo.read(attachment=0, components=1, dtype="u4"), dtype=np.uint32)

    def device_ids(self, fbo: moderngl.Framebuffer) -> mi.UInt32:
        """The target of :meth:`render` as a Dr.Jit array (as :meth:`read_ids` lays it out), without
        crossing the host where CUDA–OpenGL interop works (``interop.Readback``)."""
        if self._readback is None:
            self._readback = Readback()
        return self._readback.ids(fbo, self.read_ids)

    def release(self) -> None:
        """The targets back from CUDA (``interop.Readback.release``): before OpenGL touches them,
        and at the end of a frame (``pipeline.HybridRenderer.render``)."""
        if self._readback is not None:
            self._readback.release()

    @property
    def readback(self) -> str:
        """How :meth:`device_ids` reads: ``cuda-gl-interop``, or ``host (reason)``."""
        return self._readback.mode if self._readback is not None else "not used yet"
