"""Stage 2, deferred lighting: the raster layer (paper §3.1, Fig. 1g; §7's lighting stage).

Sabino et al. shade every visible pixel once, in a GLSL pass over the G-buffer, with the direct
light of the scene's lights and no visibility test: that image is what a pixel shows when the ray
tracer does not touch it (§5). Here the lights are read from the Mitsuba scene:

- ``point`` and ``spot`` (with Mitsuba's cutoff/beam-width fall-off), ``directional``: exact,
  unshadowed;
- area emitters: 16 stratified samples of the emitting shape (``shape.sample_position``), each a
  cosine-weighted point source carrying its share of radiance × area;
- infinite emitters (``constant``, ``envmap``, ``sunsky``, ...): an ambient term, the radiance
  averaged over the sphere (Mitsuba's own ``emitter.eval`` in 256 directions), times albedo and
  specular colour;
- any other emitter type is left out of the raster layer; its name is listed in
  :attr:`RasterLights.approximated` and counted in the frame statistics.

The BRDF is Lambert (albedo) plus a normalized Blinn-Phong lobe (specular colour, exponent from
the G-buffer's roughness), the classic deferred-shading model; emission comes from Mitsuba.
"""
from __future__ import annotations

import importlib.resources
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import moderngl
import numpy as np

from .camera import transform_matrix
from .context import gl_context

AREA_SAMPLES = 16
AMBIENT_DIRECTIONS = 256
KIND = {"point": 0, "spot": 1, "area": 2, "directional": 3}


@dataclass(frozen=True)
class RasterLights:
    """The scene's emitters as the lighting shader sees them."""

    table: np.ndarray  # (3, n, 4) float32: rows of the light texture (see lighting.frag)
    ambient: np.ndarray  # (3,) average radiance of the infinite emitters
    approximated: tuple[str, ...]  # emitters the raster layer leaves out

    @property
    def count(self) -> int:
        return self.table.shape[1]


def _rgb(value) -> np.ndarray:
    """An emitter's spectrum parameter as RGB (a scalar spectrum becomes grey)."""
    arr = np.array(value, dtype=np.float64).ravel()
    return np.repeat(arr[:1], 3) if arr.size == 1 else arr[:3]


def _columns(value, n: int) -> np.ndarray:
    """A 3-vector Dr.Jit array as an (n, 3) numpy array (constant lanes are broadcast)."""
    return np.stack([np.broadcast_to(np.array(value[k], dtype=np.float64), (n,)) for k in range(3)], axis=-1)


def scene_lights(scene: mi.Scene) -> RasterLights:
    """Read the lights of ``scene`` (see the module docstring for what each emitter becomes)."""
    rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    ambient = np.zeros(3)
    approximated = []

    def add(kind, position, axis, intensity, cos_cutoff=-1.0, cos_beam=-1.0):
        rows.append((np.r_[position, KIND[kind]], np.r_[axis, cos_cutoff], np.r_[intensity, cos_beam]))

    for shape in scene.shapes():
        if shape.is_emitter():
            emitter = shape.emitter()
            u, v = np.meshgrid((np.arange(4) + 0.5) / 4, (np.arange(4) + 0.5) / 4)
            ps = shape.sample_position(0.0, mi.Point2f(mi.Float(u.ravel()), mi.Float(v.ravel())))
            si = mi.SurfaceInteraction3f(ps, dr.zeros(mi.Color0f))
            si.wi = mi.Vector3f(0, 0, 1)
            radiance = emitter.eval(si)
            p, n, radiance = (_columns(v, AREA_SAMPLES) for v in (ps.p, ps.n, radiance))
            share = radiance / np.broadcast_to(np.array(ps.pdf), (AREA_SAMPLES,))[:, None] / AREA_SAMPLES
            for k in range(AREA_SAMPLES):
                add("area", p[k], n[k], share[k])
    for emitter in scene.emitters():
        name, kind = emitter.id() or emitter.class_name(), emitter.class_name()
        params = mi.traverse(emitter)
        flags = int(emitter.flags())
        if kind == "AreaLight":
            continue  # sampled above, from its shape
        if kind == "PointLight":
            add("point", np.array(params["position"], dtype=np.float64).ravel(), np.zeros(3), _rgb(params["intensity.value"]))
        elif kind == "SpotLight" and "intensity.value" in params:
            m = transform_matrix(params["to_world"])
            axis = m[:3, 2] / np.linalg.norm(m[:3, 2])
            add("spot", m[:3, 3], axis, _rgb(params["intensity.value"]),
                np.cos(np.radians(float(np.array(params["cutoff_angle"]).ravel()[0]))),
                np.cos(np.radians(float(np.array(params["beam_width"]).ravel()[0]))))
        elif kind == "DirectionalEmitter":
            m = transform_matrix(params["to_world"])
            add("directional", np.zeros(3), m[:3, 2] / np.linalg.norm(m[:3, 2]), _rgb(params["irradiance.value"]))
        elif flags & int(mi.EmitterFlags.Infinite) and not flags & int(mi.EmitterFlags.Delta):
            ambient += _average_radiance(emitter)
        else:
            approximated.append(name)
    table = (np.stack([np.stack(r) for r in rows], axis=1) if rows else np.zeros((3, 0, 4))).astype(np.float32)
    return RasterLights(table=table, ambient=ambient.astype(np.float32), approximated=tuple(approximated))


def _average_radiance(emitter: mi.Emitter) -> np.ndarray:
    """Radiance of an infinite emitter averaged over the sphere of directions (Fibonacci lattice)."""
    k = np.arange(AMBIENT_DIRECTIONS) + 0.5
    z = 1.0 - 2.0 * k / AMBIENT_DIRECTIONS
    phi = np.pi * (1.0 + 5 ** 0.5) * k
    r = np.sqrt(1.0 - z * z)
    si = dr.zeros(mi.SurfaceInteraction3f, AMBIENT_DIRECTIONS)
    si.wi = mi.Vector3f(mi.Float(r * np.cos(phi)), mi.Float(r * np.sin(phi)), mi.Float(z))
    return np.array(emitter.eval(si)).reshape(3, -1).mean(axis=1) if dr.width(si.wi) else np.zeros(3)


def _shader(name: str) -> str:
    return importlib.resources.files(__package__).joinpath("shaders", name).read_text()


#: the G-buffer targets the lighting pass reads, and their component counts
INPUTS = {"position": 3, "normal": 3, "albedo": 3, "specular": 3, "optical": 4, "emission": 3}


class DeferredLighting:
    """The GLSL lighting pass of one scene: its lights are read and uploaded once."""

    def __init__(self, scene: mi.Scene):
        self.ctx = gl_context()
        self.lights = scene_lights(scene)
        self.program = self.ctx.program(vertex_shader=_shader("fullscreen.vert"), fragment_shader=_shader("lighting.frag"))
        count = max(self.lights.count, 1)
        table = np.zeros((3, count, 4), np.float32)
        table[:, :self.lights.count] = self.lights.table
        self._light_texture = self.ctx.texture((count, 3), 4, table.tobytes(), dtype="f4")
        self._light_texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self._vao = self.ctx.vertex_array(self.program, [])
        self._targets: dict[tuple[int, int], tuple[dict[str, moderngl.Texture], moderngl.Framebuffer]] = {}

    def _resources(self, width: int, height: int):
        key = (width, height)
        if key not in self._targets:
            textures = {name: self.ctx.texture(key, 4 if n == 4 else 3, dtype="f4") for name, n in INPUTS.items()}
            textures["hit"] = self.ctx.texture(key, 1, dtype="f4")
            for tex in textures.values():
                tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
            self._targets[key] = (textures, self.ctx.framebuffer([self.ctx.texture(key, 4, dtype="f4")]))
        return self._targets[key]

    def shade(self, gbuffer: dict[str, np.ndarray], hit: np.ndarray, eye: np.ndarray) -> np.ndarray:
        """The raster layer (H, W, 3) from G-buffer targets (``INPUTS``) and the hit mask."""
        h, w = hit.shape
        textures, fbo = self._resources(w, h)
        for name in INPUTS:
            textures[name].write(np.ascontiguousarray(gbuffer[name], dtype=np.float32).tobytes())
        textures["hit"].write(hit.astype(np.float32).tobytes())
        for unit, name in enumerate(["position", "normal", "albedo", "specular", "optical", "emission", "hit"]):
            textures[name].use(unit)
            self.program[f"g_{name}"].value = unit
        self._light_texture.use(7)
        self.program["lights"].value = 7
        self.program["light_count"].value = self.lights.count
        self.program["ambient"].value = tuple(float(c) for c in self.lights.ambient)
        self.program["eye"].value = tuple(float(c) for c in eye)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        self.ctx.disable(moderngl.DEPTH_TEST)
        self._vao.render(moderngl.TRIANGLES, vertices=3)
        return np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32).reshape(h, w, 4)[..., :3].copy()
