"""The visibility pass rasterized in OpenGL compute shaders (paper §3.1).

The paper's G-buffer pass is the GPU's fixed-function rasterizer, and so is ``Rasterizer``'s draw.
On the H100 and H200, whose graphics units are few, that path is slow where a game GPU is fast:
the draw is bound by geometry (0.9 ms for the Armadillo's 400k triangles at 1280×720, 8.4 ms for
5M; face culling saves nothing, ``scripts/raster_cull_probe.py``), while the same GPU casts a
camera ray per pixel in 0.3–0.8 ms. Real-time renderers that meet geometry-bound rasterization (Nanite's visibility
buffer; Kenzel et al. 2018) rasterize small triangles in compute shaders, one invocation per
triangle, resolving visibility with atomics. This module does all of it in moderngl compute
shaders (``shaders/visibility.comp`` explains the method: small triangles one per invocation,
medium ones by 64 invocations each, large ones by screen tiles): the result is the draw's visibility buffer (the global triangle
number + 1 per pixel, 0 for the background, at the camera's sub-pixel offset) in the draw's own
target texture, so interop (``interop.Readback``) and everything after stage 1 are unchanged.

Per frame: five dispatches, no host wait and no graphics work: clear; the small triangles'
depth and number, and the lists of the others; the medium triangles' dispatch size, then their
depth and number; the tiles of the large ones. Depth and number go into one 64-bit word per pixel,
resolved by one 64-bit ``atomicMax`` (``GL_NV_shader_atomic_int64``, the ``one_pass`` pass). A GL
without 64-bit atomics (Mesa 22's llvmpipe, which CI runs) rasterizes the small and the medium
triangles twice, the depths, then the numbers where the depth won: seven dispatches, the same
visibility buffer bit for bit (``scripts/raster_compute_probe.py`` compares the two on the GPU).
The geometry is the draw's, uploaded once.
"""
from __future__ import annotations

import weakref

import moderngl
import numpy as np

from .camera import RasterCamera
from .context import shader_source

#: invocations per work group (``local_size_x`` of the shader)
GROUP = 256
#: pixels per side of the tiles of the last stage (``TILE`` in the shader)
TILE = 32
#: bytes per listed triangle (``Listed`` in the shader)
LISTED_BYTES = 64
#: the most work groups OpenGL guarantees per dispatch dimension
MAX_GROUPS = 65535
#: the shader's stages (``visibility.comp``), numbered in the order they run
CLEAR, SMALL_DEPTH, MEDIUM_GROUPS, MEDIUM_DEPTH, SMALL_NUMBERS, MEDIUM_NUMBERS, TILES = range(7)
#: the extension whose 64-bit atomics resolve depth and number in one pass
ATOMIC64 = "GL_NV_shader_atomic_int64"
_MEDIUM_GROUPS_OFFSET = 8  # bytes into the counts buffer: the indirect dispatch of the medium triangles
#: per GL context, the :class:`ComputeVisibility` whose buffers and target are bound to its
#: storage-buffer and image units (nothing else in the package binds them)
_BOUND: dict[int, "weakref.ref[ComputeVisibility]"] = {}


def _grid(invocations: int) -> tuple[int, int, int]:
    """Work groups for ``invocations`` (the shader numbers them across a 2D grid)."""
    groups = max(-(-invocations // GROUP), 1)
    return min(groups, MAX_GROUPS), -(-groups // MAX_GROUPS), 1


class ComputeVisibility:
    """A ``Rasterizer``'s visibility pass in compute shaders."""

    def __init__(self, ctx: moderngl.Context, vertices: moderngl.Buffer, faces: moderngl.Buffer, triangles: int,
                 one_pass: bool | None = None):
        """``vertices`` (3 float32 each) and ``faces`` (3 uint32 each, ``triangles`` of them): the
        draw's own buffers. ``one_pass``: depth and number in one 64-bit atomic (module
        docstring); None: where the context has :data:`ATOMIC64`. (No reference to the
        :class:`Rasterizer`: a cycle would leave its Dr.Jit tables to the garbage collector, which
        may free them inside a frozen function.)"""
        self.ctx, self.triangles = ctx, triangles
        supported = ATOMIC64 in ctx.extensions and "GL_ARB_gpu_shader_int64" in ctx.extensions
        self.one_pass = supported if one_pass is None else bool(one_pass)
        if self.one_pass and not supported:
            raise RuntimeError(f"one_pass=True needs 64-bit atomics ({ATOMIC64}), which "
                               f"{ctx.info['GL_RENDERER']} does not have")
        source = shader_source("visibility.comp")
        if self.one_pass:  # the define after the #version line, which must come first
            version, rest = source.split("\n", 1)
            source = f"{version}\n#define ONE_PASS\n{rest}"
        self.program = ctx.compute_shader(source)
        #: the stages a pass runs (the two NUMBERS stages only without 64-bit atomics)
        self.stages = ((CLEAR, SMALL_DEPTH, MEDIUM_GROUPS, MEDIUM_DEPTH, TILES) if self.one_pass else
                       (CLEAR, SMALL_DEPTH, MEDIUM_GROUPS, MEDIUM_DEPTH, SMALL_NUMBERS, MEDIUM_NUMBERS, TILES))
        self._storage = [
            vertices, faces,
            None, None,  # per pixel: depth and number (one_pass: one 64-bit word, binding 2), per film size
            ctx.buffer(reserve=20),  # the lists' lengths, then the medium triangles' work groups
            ctx.buffer(reserve=LISTED_BYTES * max(self.triangles, 1)),  # the large triangles
            ctx.buffer(reserve=4 * max(self.triangles, 1)),  # the medium triangles' numbers
        ]
        self._targets: dict[tuple[int, int], tuple[moderngl.Buffer, moderngl.Buffer | None]] = {}
        self._size = None  # the film size the program's uniforms and the context's bindings are set for

    def _target(self, width: int, height: int) -> tuple[moderngl.Buffer, moderngl.Buffer | None]:
        key = (width, height)
        if key not in self._targets:
            pixels = width * height
            self._targets[key] = ((self.ctx.buffer(reserve=8 * pixels), None) if self.one_pass else
                                  (self.ctx.buffer(reserve=4 * pixels), self.ctx.buffer(reserve=4 * pixels)))
        return self._targets[key]

    def _run(self, stage: int, grid: tuple[int, int, int] | None) -> None:
        """Dispatch one stage (``grid`` None: the medium triangles' indirect dispatch), then the
        barrier that makes its writes visible to the next (all of them after the last)."""
        self.program["stage"].value = stage
        if grid is None:
            self.program.run_indirect(self._storage[4], _MEDIUM_GROUPS_OFFSET)
        else:
            self.program.run(*grid)
        barrier = moderngl.SHADER_STORAGE_BARRIER_BIT
        if stage == MEDIUM_GROUPS:
            barrier |= moderngl.COMMAND_BARRIER_BIT
        self.ctx.memory_barrier(moderngl.ALL_BARRIER_BITS if stage == TILES else barrier)

    def tiers(self) -> tuple[int, int]:
        """The last pass's large and medium triangle counts (a host read: for tests and probes)."""
        large, medium = np.frombuffer(self._storage[4].read(8), np.uint32)
        return int(large), int(medium)

    def render(self, camera: RasterCamera, offset: tuple[float, float], fbo: moderngl.Framebuffer) -> moderngl.Framebuffer:
        """The visibility pass at ``offset`` into ``fbo``, the draw's target of the camera's size."""
        w, h = camera.width, camera.height
        program = self.program
        clip, origin = camera.relative_clip(offset)
        program["world_to_clip"].write(clip.T.astype("f4").tobytes())
        program["origin"].write(origin.tobytes())
        # the size, the buffers and the target change with the film's size alone: set again only
        # then, or after another pass bound its own (the bindings are the context's state)
        bound = _BOUND.get(id(self.ctx))
        if self._size != (w, h) or bound is None or bound() is not self:
            self._storage[2:4] = self._target(w, h)
            program["size"].value = (w, h)
            program["triangles"].value = self.triangles
            for binding, buffer in enumerate(self._storage):
                if buffer is not None:
                    buffer.bind_to_storage_buffer(binding)
            fbo.color_attachments[0].bind_to_image(0, read=False, write=True)
            self._size, _BOUND[id(self.ctx)] = (w, h), weakref.ref(self)
        triangles, medium = _grid(self.triangles), None  # None: the indirect dispatch
        grids = {CLEAR: _grid(w * h), SMALL_DEPTH: triangles, MEDIUM_GROUPS: (1, 1, 1), MEDIUM_DEPTH: medium,
                 SMALL_NUMBERS: triangles, MEDIUM_NUMBERS: medium, TILES: (-(-w // TILE), -(-h // TILE), 1)}
        for stage in self.stages:
            self._run(stage, grids[stage])
        return fbo
