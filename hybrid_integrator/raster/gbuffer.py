"""The G-buffer: the paper's Table 2 render targets, derived from the visibility buffer (§3.1).

Sabino et al. write position, normal, depth, albedo, specular colour and optical properties
(reflectivity, index of refraction, opacity, specular exponent) to multiple render targets in the
geometry pass, and use the optical target to decide which pixels need reflection and refraction
rays (§3.2, Fig. 1f). Here the geometry pass writes only the visibility buffer; each requested
target is then computed from the pixel's exact Mitsuba surface interaction and *its own Mitsuba
BSDF*, so textures, two-sided wrappers and every material plugin are honoured without a second
material system. Only the targets asked for are computed ("model no more than a scene needs").

The targets are evaluated at the pixel's *refined* primary hit (:mod:`hybrid_integrator.primary`:
analytic-shape proxies and silhouette pixels are re-traced), the hit the ray tracer starts from.

Definitions (world space, per pixel; background pixels are 0):

- ``position``  (3): the hit point ``si.p``.
- ``normal``    (3): the shading normal ``si.sh_frame.n``.
- ``albedo``    (3): ``bsdf.eval_diffuse_reflectance`` (Mitsuba's diffuse albedo) where the BSDF
  has a diffuse lobe, clipped to [0, 1]; 0 for BSDFs without one (conductors and dielectrics,
  smooth or rough). Mitsuba's default for a BSDF that does not define its diffuse albedo is
  π·f(wi, n), the lobe towards the normal: a rough conductor's is 5.9 when seen head-on (Cu,
  α = 0.2), which the lighting stage shaded as a Lambertian surface that bright.
- ``specular``  (3): the weight of the BSDF's delta/glossy *reflection* lobes for the actual view
  direction, as sampled by Mitsuba (Fresnel included): the colour a mirror bounce carries.
- ``optical``   (4): reflectivity (luminance of ``specular``), index of refraction (the BSDF's
  relative ``eta`` where it has a transmissive interface, else 1), opacity (1 − luminance of the
  transmission lobes' weight, importance transport), roughness (the BSDF's GGX/Beckmann
  ``alpha`` or principled ``roughness``; 0 for smooth lobes, 1 for purely diffuse ones): the
  paper's specular exponent as a microfacet roughness.
- ``emission``  (3): radiance emitted towards the camera (Mitsuba's ``emitter.eval``): area
  lights seen directly and, on background pixels, the environment (not in Table 2; the lighting
  stage needs it).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import drjit as dr
import mitsuba as mi
import numpy as np

from ..cache import scene_state
from ..errors import HybridError
from ..primary import PrimaryHits
from .visibility import VisibilityBuffer

#: the paper's Table 2 targets this package can add, with their channel names
AOV_CHANNELS: dict[str, tuple[str, ...]] = {
    "position": ("X", "Y", "Z"),
    "normal": ("X", "Y", "Z"),
    "albedo": ("R", "G", "B"),
    "specular": ("R", "G", "B"),
    "optical": ("reflectivity", "ior", "opacity", "roughness"),
    "emission": ("R", "G", "B"),
}


@dataclass(frozen=True)
class GBuffer(VisibilityBuffer):
    """A visibility buffer plus the G-buffer targets asked for (``None`` where not asked)."""

    position: np.ndarray | None = None  # (H, W, 3) float32
    normal: np.ndarray | None = None  # (H, W, 3) float32
    albedo: np.ndarray | None = None  # (H, W, 3) float32
    specular: np.ndarray | None = None  # (H, W, 3) float32
    optical: np.ndarray | None = None  # (H, W, 4) float32
    emission: np.ndarray | None = None  # (H, W, 3) float32
    #: ``shape.id()`` of every shape, in ``shape_index`` order
    shape_ids: tuple[str, ...] = field(default=())

    @property
    def aovs(self) -> dict[str, np.ndarray]:
        """The G-buffer targets present, by name."""
        return {name: getattr(self, name) for name in AOV_CHANNELS if getattr(self, name) is not None}


def check_aovs(aovs) -> tuple[str, ...]:
    """Validate a list of AOV names (``"all"`` stands for every one)."""
    names = tuple(aovs)
    if "all" in names:
        return tuple(AOV_CHANNELS)
    unknown = [a for a in names if a not in AOV_CHANNELS]
    if unknown:
        raise HybridError(f"unknown G-buffer AOV(s) {unknown}: choose from {list(AOV_CHANNELS)} or 'all'")
    return names


@dataclass(frozen=True)
class ShapeConstants:
    """Per ``scene.shapes()`` entry: the index of refraction and roughness of its BSDF."""

    ior: mi.Float
    roughness: mi.Float


def shape_constants(scene: mi.Scene) -> ShapeConstants:
    """The :class:`ShapeConstants` of ``scene`` (read once per scene)."""
    return scene_state(scene, "shape_constants", lambda: ShapeConstants(*_per_shape_constants(scene)))


def aov_values(scene: mi.Scene, hits: PrimaryHits, aovs: tuple[str, ...], constants: ShapeConstants) -> dict[str, list[mi.Float]]:
    """The requested targets at the primary hits, per pixel, as Dr.Jit arrays (one per channel),
    left on the device for the lighting stage."""
    ray, si, valid = hits.ray, hits.si, hits.valid
    bsdf = si.bsdf(ray)

    def surface(value):  # zero on background pixels
        return [dr.select(valid, value[k], 0.0) for k in range(len(value))]

    out: dict[str, list] = {}
    if "position" in aovs:
        out["position"] = surface(si.p)
    if "normal" in aovs:
        out["normal"] = surface(si.sh_frame.n)
    if "albedo" in aovs:
        # not where the BSDF has no diffuse lobe: there Mitsuba gives π·f(wi, n) (module docstring)
        diffuse = mi.has_flag(bsdf.flags(), mi.BSDFFlags.DiffuseReflection)
        out["albedo"] = surface(dr.select(diffuse, dr.clip(bsdf.eval_diffuse_reflectance(si, valid), 0.0, 1.0), 0.0))
    if "specular" in aovs or "optical" in aovs:
        specular = _lobe_weight(bsdf, si, valid, mi.BSDFFlags.DeltaReflection | mi.BSDFFlags.GlossyReflection)
        if "specular" in aovs:
            out["specular"] = surface(specular)
    if "optical" in aovs:
        transmitted = _lobe_weight(bsdf, si, valid, mi.BSDFFlags.Transmission)
        ior, roughness = constants.ior, constants.roughness
        out["optical"] = surface([mi.luminance(specular), dr.gather(mi.Float, ior, hits.shape, valid),
                                  1.0 - mi.luminance(transmitted), dr.gather(mi.Float, roughness, hits.shape, valid)])
    if "emission" in aovs:  # background pixels keep the environment's radiance
        emitted = si.emitter(scene).eval(si)
        out["emission"] = [dr.select(dr.isfinite(emitted[k]), emitted[k], 0.0) for k in range(3)]
    return out


def to_numpy(values: dict[str, list[mi.Float]], shape: tuple[int, int]) -> dict[str, np.ndarray]:
    """Targets from :func:`aov_values` as (H, W, C) float32 images."""
    channels = [c for value in values.values() for c in value]
    dr.eval(*channels)
    return {name: np.stack([np.array(c, dtype=np.float32) for c in value], axis=-1).reshape(*shape, -1)
            for name, value in values.items()}


def compute_aovs(scene: mi.Scene, hits: PrimaryHits, shape: tuple[int, int], aovs: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Evaluate the requested targets at the primary hits (one per pixel of an image of ``shape``)."""
    return to_numpy(aov_values(scene, hits, aovs, shape_constants(scene)), shape)


def _lobe_weight(bsdf: mi.BSDFPtr, si: mi.SurfaceInteraction3f, valid: mi.Bool, lobes) -> mi.Color3f:
    """Sampled weight of the BSDF restricted to ``lobes`` (importance transport, so transmission is
    not scaled by η²), at the middle of the sample domain: the lobe's colour for this view."""
    ctx = mi.BSDFContext(mi.TransportMode.Importance)
    ctx.type_mask = int(lobes)
    _, weight = bsdf.sample(ctx, si, 0.5, mi.Point2f(0.5, 0.5), valid)
    return dr.select(valid & dr.isfinite(weight[0]), weight, 0.0)


def _per_shape_constants(scene: mi.Scene) -> tuple[mi.Float, mi.Float]:
    """Index of refraction and roughness of each shape's BSDF, read from its parameters."""
    ior, roughness = [], []
    for shape in scene.shapes():
        bsdf = shape.bsdf()
        params = mi.traverse(bsdf) if bsdf is not None else {}
        flags = int(bsdf.flags()) if bsdf is not None else 0
        etas = [_scalar(params[k]) for k in params.keys() if k == "eta" or k.endswith(".eta")]
        transmissive = flags & int(mi.BSDFFlags.Transmission)
        ior.append(etas[0] if transmissive and etas and etas[0] is not None else 1.0)
        alphas = [_scalar(params[k]) for k in params.keys()
                  if k.split(".")[-2 if k.endswith(".value") else -1] in ("alpha", "alpha_u", "alpha_v", "roughness")]
        alphas = [a for a in alphas if a is not None]
        if alphas:
            roughness.append(float(np.mean(alphas)))
        elif flags & int(mi.BSDFFlags.Delta):
            roughness.append(0.0)
        else:
            roughness.append(1.0)
    return mi.Float(np.array(ior, dtype=np.float32)), mi.Float(np.array(roughness, dtype=np.float32))


def _scalar(value) -> float | None:
    """A one-value parameter as a float (None for textures and spectra)."""
    try:
        arr = np.array(value, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        return None
    return float(arr[0]) if arr.size == 1 else None
