"""Stage 2, deferred lighting: the raster layer (paper §3.1, Fig. 1g; §7's lighting stage).

Sabino et al. shade every visible pixel once, in a GLSL pass over the G-buffer, with the direct
light of the scene's lights and no visibility test: that image is what a pixel shows when the ray
tracer does not touch it (§5). Here the same pass is a Dr.Jit kernel over the G-buffer targets
(``gbuffer.aov_values``), which stay on the device where the ray tracer reads them: one loop over
the light table per pixel, compiled once per scene. The lights are read from the Mitsuba scene:

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

**The learnt ambient term** (issue 11: the cheap model of indirect light). The layer above has no
indirect light and no shadows, so where the ray tracer does not touch an object its pixels are
too bright in shadow and too dark everywhere light arrives indirectly. Every traced pixel measures
the difference: its traced radiance minus its raster radiance. Per object, the frame sums that
residual and the albedo over its traced pixels (``heuristic.add_error``), and after the frame
``E_k = Σ residual / Σ albedo`` (per channel) is learnt across frames (:func:`learn_ambient`,
``FrameState.ambient``): the object's mean ambient irradiance, net of its shadows. The raster
layer then adds ``albedo × E_k`` (clamped at zero) on every pixel of object ``k``; an object never
traced takes the median ``E`` of the objects that were, never below zero (:func:`ambient_table`).
It costs one gather per pixel, and it makes an untraced object's pixels as bright on average as
its traced ones (``learn_ambient=false``: off).
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .raster.camera import transform_matrix
from .raster.interop import device_array

AREA_SAMPLES = 16
AMBIENT_DIRECTIONS = 256
KIND = {"point": 0, "spot": 1, "area": 2, "directional": 3}


@dataclass(frozen=True)
class RasterLights:
    """The scene's emitters as the lighting shader sees them."""

    table: np.ndarray  # (3, n, 4) float32: the rows of the light table (:class:`DeferredLighting`)
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


#: the G-buffer targets the lighting pass reads, and their component counts
INPUTS = {"position": 3, "normal": 3, "albedo": 3, "specular": 3, "optical": 4, "emission": 3}


@dataclass(frozen=True)
class LightTable:
    """The light table on the device, as the lighting kernel reads it (:class:`DeferredLighting`)."""

    rows: list  # three mi.Float, 4 floats per light each
    ambient: mi.Color3f
    count: int


class DeferredLighting:
    """The lighting pass of one scene: its lights are read once into a table on the device.

    Light ``k`` is three rows of 4 floats (``RasterLights.table``): position and kind
    (0 isotropic point, 1 spot, 2 area sample, 3 directional); axis (spot axis, area normal,
    directional travel direction) and the cosine of the spot cutoff; intensity (W/sr; area samples:
    radiance × area share; directional: irradiance) and the cosine of the spot beam width."""

    def __init__(self, scene: mi.Scene):
        self.lights = scene_lights(scene)
        # at least one (unused) light: an empty Dr.Jit array cannot be an input of a frozen function.
        # Aligned rows (device_array): mapped where NumPy happened to put them, the LLVM backend
        # read a row in 4 scalar gathers instead of one packet gather in some processes, and the
        # lighting stage took 5.24-5.55 ms instead of 3.37-3.45 (showcase, 320×180;
        # docs/results/gpu/issue10/stop66/README.md, section 4)
        rows = self.lights.table if self.lights.count else np.zeros((3, 1, 4), dtype=np.float32)
        self.table = LightTable(rows=[device_array(mi.Float, rows[r].ravel()) for r in range(3)],
                                ambient=mi.Color3f(*(float(c) for c in self.lights.ambient)), count=self.lights.count)


def shade(gbuffer: dict[str, list[mi.Float]], hit: mi.Bool, view: mi.Vector3f, lights: LightTable) -> mi.Color3f:
    """The raster layer from G-buffer targets (``INPUTS``, per pixel), the hit mask and the unit
    direction towards the viewer (minus the camera ray's: a pinhole's or an orthographic camera's)."""
    p = mi.Point3f(*gbuffer["position"])
    n = dr.normalize(mi.Vector3f(*gbuffer["normal"]))
    albedo, specular, emission = (mi.Color3f(*gbuffer[k]) for k in ("albedo", "specular", "emission"))
    roughness = dr.maximum(gbuffer["optical"][3], 0.05)
    shininess = 2.0 / (roughness * roughness) - 2.0  # Blinn-Phong exponent of a GGX alpha
    v = view
    n = dr.select(dr.dot(n, v) < 0.0, -n, n)  # two-sided shading, as Mitsuba's BSDFs see the front side
    color = emission + lights.ambient * (albedo + specular)
    if lights.count:
        color = _direct(lights.rows, lights.count, p, n, v, albedo, specular, shininess, color)
    return dr.select(hit, color, emission)


def ambient_table(learnt: np.ndarray, n_objects: int) -> np.ndarray:
    """``E`` per object (``n × 3`` float32, row-major) for the device pass, from the learnt rows
    (objects × 3, NaN: never traced): the learnt value; for an object never traced, what the
    learnt ones typically gained, per channel their median, never below zero (zeros when nothing
    is learnt yet).

    An object's own ``E`` is its residual per albedo, so it may be huge where its albedo is small
    (a glossy sphere's: up to 512 on the 226 objects' path) and negative where its pixels lie in
    shadows the raster layer does not have (the floor's). Neither says anything about another
    object: the mean of the learnt rows, taken before for the objects never traced, made those
    many times too bright, or darkened lit objects with the floor's shadows. On the CPU
    (``llvm_ad_rgb``, 320×180, eight poses of that path, ten objects traced, the rest not) the
    frames' FLIP against ``path`` was 0.343 with the mean, 0.283 with the median, 0.256 without
    the learnt term, and 0.252 with the median clamped at zero
    (``docs/results/gpu/issue10/stop60/ambient_fallback.py``)."""
    table = np.zeros((max(n_objects, 1), 3), dtype=np.float32)
    known = np.isfinite(learnt[:n_objects]).all(axis=1) if len(learnt) else np.zeros(0, dtype=bool)
    if known.any():
        table[:] = np.maximum(np.median(learnt[:n_objects][known], axis=0), 0.0)
        table[:len(known)][known] = learnt[:n_objects][known]
    return table


def learn_ambient(learnt: np.ndarray, index: np.ndarray, residual: np.ndarray, albedo: np.ndarray,
                  pixels: np.ndarray, smoothing: float = 0.5) -> np.ndarray:
    """The learnt ``E`` (objects × 3, NaN: never) updated from one frame's sums over the traced
    pixels of objects ``index`` (rows of ``residual`` and ``albedo``; module docstring);
    channels whose albedo is (nearly) black keep the old value. Returns the new table."""
    from .budget import blend_rows, grown_table

    table = grown_table(learnt, int(index.max()) + 1 if len(index) else 0).copy()
    seen = albedo > 1e-3 * np.maximum(pixels, 1)[:, None]
    value = np.where(seen, residual / np.where(seen, albedo, 1.0), np.nan_to_num(table[index]))
    rows = seen.any(axis=1)
    return blend_rows(table, index[rows], value[rows], smoothing)


def with_ambient(raster: mi.Color3f, albedo: mi.Color3f, obj: mi.UInt32, hit: mi.Bool, table: mi.Float) -> mi.Color3f:
    """The raster layer plus ``albedo × E[obj]`` (:func:`ambient_table`), clamped at zero."""
    e = mi.Color3f(*(dr.gather(mi.Float, table, obj * 3 + c, hit) for c in range(3)))
    return dr.select(hit, dr.maximum(raster + albedo * e, 0.0), raster)


@dr.syntax
def _direct(rows: list[mi.Float], count: int, p: mi.Point3f, n: mi.Vector3f, v: mi.Vector3f, albedo: mi.Color3f,
            specular: mi.Color3f, shininess: mi.Float, color: mi.Color3f) -> mi.Color3f:
    """Add the unshadowed direct light of every light in the table (a symbolic loop over them):
    Lambert plus normalized Blinn-Phong."""
    k = mi.UInt32(0)
    while k < count:
        r0, r1, r2 = (dr.gather(mi.Vector4f, row, k) for row in rows)
        kind, axis, intensity = r0.w, mi.Vector3f(r1.x, r1.y, r1.z), mi.Color3f(r2.x, r2.y, r2.z)
        d = mi.Vector3f(r0.x, r0.y, r0.z) - p
        dist2 = dr.maximum(dr.squared_norm(d), 1e-8)
        to_light = d * dr.rsqrt(dist2)
        c = dr.clip(dr.dot(-to_light, axis), -1.0, 1.0)
        cutoff = dr.acos(dr.clip(r1.w, -1.0, 1.0))
        spot = dr.select(c < r1.w, 0.0, dr.select(c >= r2.w, 1.0, (cutoff - dr.acos(c)) /
                                                  dr.maximum(cutoff - dr.acos(dr.clip(r2.w, -1.0, 1.0)), 1e-6)))
        falloff = dr.select(dr.abs(kind - 1.0) < 0.5, spot, dr.select(dr.abs(kind - 2.0) < 0.5, dr.maximum(c, 0.0), 1.0))
        directional = kind > 2.5
        l = dr.select(directional, -axis, to_light)
        irradiance = dr.select(directional, intensity, intensity * falloff / dist2)  # at normal incidence
        cos_i = dr.dot(n, l)
        h = dr.normalize(l + v)
        lobe = (shininess + 8.0) / (8.0 * dr.pi) * dr.power(dr.maximum(dr.dot(n, h), 0.0), shininess)
        color += dr.select(cos_i > 0.0, irradiance * cos_i * (albedo / dr.pi + specular * lobe), 0.0)
        k += 1
    return color
