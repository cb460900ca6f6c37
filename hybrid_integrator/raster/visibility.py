"""The visibility buffer: primary visibility resolved by the rasterizer (paper §3.1, §8).

The paper's geometry pass writes a G-buffer whose first job is to replace the primary rays of a
ray tracer (§3.1, Fig. 4a). Its minimal form is a *visibility buffer*: per pixel, which shape and
which triangle is seen, where on the triangle (barycentrics), and how far along the camera ray.
That is exactly what Mitsuba needs to rebuild its own surface interaction
(:mod:`hybrid_integrator.primary`), so everything else (the paper's position, normal, albedo,
specular and optical targets) is derived from it on demand (:mod:`hybrid_integrator.raster.gbuffer`).

The :class:`Rasterizer` uploads a scene's triangles to the GPU once and draws any number of frames
from them: one draw call per shape, at any sub-pixel offset.
"""
from __future__ import annotations

import importlib.resources
from dataclasses import dataclass

import mitsuba as mi
import moderngl
import numpy as np

from .camera import RasterCamera
from .context import gl_context
from .interop import Readback
from .geometry import ShapeGeometry, scene_geometry


@dataclass(frozen=True)
class VisibilityBuffer:
    """Primary hits of one raster pass; arrays are indexed ``[row, column]``, row 0 at the top."""

    shape_index: np.ndarray  # (H, W) int32: index into scene.shapes(), -1 for background
    prim_index: np.ndarray  # (H, W) uint32: triangle index within the shape
    bary: np.ndarray  # (H, W, 2) float32: Mitsuba's prim_uv, clamped into the triangle
    depth: np.ndarray  # (H, W) float32: distance from the eye along the ray, inf for background
    proxy: np.ndarray  # (H, W) bool: the pixel shows a tessellated analytic shape
    offset: tuple[float, float]  # the sub-pixel sample position of the pass

    @property
    def hit(self) -> np.ndarray:
        return self.shape_index >= 0


def _shader(name: str) -> str:
    return importlib.resources.files(__package__).joinpath("shaders", name).read_text()


class Rasterizer:
    """Draws one Mitsuba scene's visibility buffer with OpenGL.

    The scene's geometry is uploaded once, when the rasterizer is made; every :meth:`draw` reuses
    it. Render targets are made per film size and kept."""

    def __init__(self, scene: mi.Scene):
        self.ctx = gl_context()
        self.shapes: list[ShapeGeometry] = scene_geometry(scene)
        self.is_proxy = np.array([s.proxy for s in self.shapes], dtype=bool)
        self.program = self.ctx.program(vertex_shader=_shader("visibility.vert"),
                                        geometry_shader=_shader("visibility.geom"),
                                        fragment_shader=_shader("visibility.frag"))
        self._vaos = [self._upload(shape) for shape in self.shapes]
        corners = np.concatenate([s.positions for s in self.shapes]) if self.shapes else np.zeros((1, 3))
        self._bbox = (corners.min(axis=0).astype(np.float64), corners.max(axis=0).astype(np.float64))
        self._targets: dict[tuple[int, int], moderngl.Framebuffer] = {}
        self._readback: Readback | None = None

    def _upload(self, shape: ShapeGeometry) -> moderngl.VertexArray:
        vbo = self.ctx.buffer(np.ascontiguousarray(shape.positions, dtype="f4").tobytes())
        ibo = self.ctx.buffer(np.ascontiguousarray(shape.faces, dtype="u4").tobytes())
        return self.ctx.vertex_array(self.program, [(vbo, "3f", "in_position")], index_buffer=ibo, index_element_size=4)

    def _framebuffer(self, width: int, height: int) -> moderngl.Framebuffer:
        key = (width, height)
        if key not in self._targets:
            self._targets[key] = self.ctx.framebuffer(
                color_attachments=[self.ctx.texture(key, 4, dtype="u4"), self.ctx.texture(key, 1, dtype="f4")],
                depth_attachment=self.ctx.depth_texture(key))
        return self._targets[key]

    def _max_distance(self, eye: np.ndarray) -> float:
        """Distance from the eye to the farthest corner of the scene's bounding box: the depth
        range, so a 24-bit linear depth resolves ~1e-7 of the scene's extent."""
        lo, hi = self._bbox
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        return float(np.linalg.norm(corners - eye, axis=1).max()) * 1.001 + 1e-6

    def draw(self, camera: RasterCamera, offset: tuple[float, float] = (0.5, 0.5)) -> VisibilityBuffer:
        """Rasterize the visibility buffer of ``camera`` with samples at sub-pixel ``offset``."""
        return self.read(self.render(camera, offset), offset)

    def render(self, camera: RasterCamera, offset: tuple[float, float] = (0.5, 0.5)) -> moderngl.Framebuffer:
        """The raster pass alone: draw every shape into the camera's targets (left on the GPU)."""
        w, h = camera.width, camera.height
        fbo = self._framebuffer(w, h)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        # the all-zero clear is 0 in the integer target (= background) and 0.0 in the float one
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.ctx.enable(moderngl.DEPTH_TEST)
        self.ctx.disable(moderngl.CULL_FACE)
        self.program["world_to_clip"].write(camera.clip_matrix(offset).T.astype("f4").tobytes())
        self.program["eye"].value = tuple(float(v) for v in camera.eye)
        self.program["inv_max_distance"].value = 1.0 / self._max_distance(camera.eye)
        for index, vao in enumerate(self._vaos):
            self.program["shape_id"].value = index
            vao.render(moderngl.TRIANGLES)
        return fbo

    def read_targets(self, fbo: moderngl.Framebuffer) -> tuple[np.ndarray, np.ndarray]:
        """The targets of :meth:`render` as they are: per pixel (row-major, row 0 at the top) four
        words (shape index + 1, 0 for background; triangle index; the two barycentrics' float
        bits) and the distance from the eye. ``primary.primary_hits`` decodes them on the device."""
        return (np.frombuffer(fbo.read(attachment=0, components=4, dtype="u4"), dtype=np.uint32),
                np.frombuffer(fbo.read(attachment=1, components=1, dtype="f4"), dtype=np.float32))

    def device_targets(self, fbo: moderngl.Framebuffer) -> tuple[mi.UInt32, mi.Float]:
        """The targets of :meth:`render` as Dr.Jit arrays (as :meth:`read_targets` lays them out),
        without crossing the host where CUDA–OpenGL interop works (``interop.Readback``)."""
        if self._readback is None:
            self._readback = Readback(self.ctx)
        return self._readback.targets(fbo, self.read_targets)

    @property
    def readback(self) -> str:
        """How :meth:`device_targets` reads: ``cuda-gl-interop``, or ``host (reason)``."""
        return self._readback.mode if self._readback is not None else "not used yet"

    def read(self, fbo: moderngl.Framebuffer, offset: tuple[float, float]) -> VisibilityBuffer:
        """Read the targets of :meth:`render` back to the host as a :class:`VisibilityBuffer`."""
        return self.decode(*self.read_targets(fbo), fbo.size, offset)

    def decode(self, words: np.ndarray, distance: np.ndarray, size: tuple[int, int],
               offset: tuple[float, float]) -> VisibilityBuffer:
        """The :class:`VisibilityBuffer` of targets read by :meth:`read_targets` (film ``size``)."""
        w, h = size
        hit, dist = words.reshape(h, w, 4), distance.reshape(h, w)
        shape_index = hit[..., 0].astype(np.int32) - 1
        valid = shape_index >= 0
        return VisibilityBuffer(
            shape_index=shape_index,
            prim_index=np.where(valid, hit[..., 1], 0).astype(np.uint32),
            bary=np.where(valid[..., None], hit[..., 2:4].view(np.float32), 0.0).astype(np.float32),
            depth=np.where(valid, dist, np.inf).astype(np.float32),
            proxy=valid & self.is_proxy[np.maximum(shape_index, 0)] if len(self.shapes) else valid,
            offset=(float(offset[0]), float(offset[1])))
