"""Stage 4, ray tracing: the secondary rays of the selected pixels (paper §3.2, Fig. 4b-c).

Starting from each selected pixel's primary hit (raster or camera ray, the same code after it),
the paths are those of Mitsuba's ``path`` integrator, restricted to the enabled effects:

- at every vertex, direct light by emitter sampling (``scene.sample_emitter_direction``): with a
  shadow ray when ``shadow`` is enabled, unshadowed otherwise;
- the path continues only by BSDF sampling of the lobes the enabled effects follow
  (``selection.lobes``: reflection, refraction, indirect), up to ``max_depth`` vertices, with
  Russian roulette from ``rr_depth`` on, exactly as ``path``;
- multiple importance sampling joins the two estimators where both can reach a light: lobes that
  are followed are MIS-weighted against emitter sampling, lobes that are not are left entirely to
  emitter sampling. With all four effects every lobe is followed and the estimator is ``path``'s.

Every bounce is its own wavefront: the live paths are compacted (``dr.compress``) before each
intersection, so the cost follows the number of rays actually traced, and the rays are counted
by kind. Random numbers come from a PCG32 stream per pixel and pass (seeded by the pixel's index),
so a pixel's paths do not depend on which other pixels are traced, nor on where its primary hit
came from.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import drjit as dr
import mitsuba as mi

from .selection import count, lobes as followed_lobes

RAY_KINDS = ("shadow", "reflection", "refraction", "indirect")


@dataclass
class TraceCounts:
    """Secondary rays traced, by kind."""

    rays: dict[str, int] = field(default_factory=lambda: dict.fromkeys(RAY_KINDS, 0))

    def add(self, other: "TraceCounts") -> None:
        for k, v in other.rays.items():
            self.rays[k] += v


def _mis(a, b):
    """Power heuristic a²/(a² + b²), as Mitsuba's ``mis_weight``, written as 1/(1 + (b/a)²) so
    that a huge ``a`` (an emitter sampled from a point on itself) gives 1, not inf/inf; 0 where
    ``a`` is 0 (an occluded or failed sample)."""
    r = b / a
    return dr.detach(dr.select(a > 0, dr.rcp(dr.fma(r, r, 1.0)), 0.0))


def _kind_of(sampled_type: mi.UInt32) -> dict[str, mi.Bool]:
    F = mi.BSDFFlags
    return {"reflection": mi.has_flag(sampled_type, F.DeltaReflection) | mi.has_flag(sampled_type, F.GlossyReflection),
            "refraction": mi.has_flag(sampled_type, F.DeltaTransmission) | mi.has_flag(sampled_type, F.GlossyTransmission)
                          | mi.has_flag(sampled_type, F.Null),
            "indirect": mi.has_flag(sampled_type, F.Diffuse)}


def trace_effects(scene: mi.Scene, ray: mi.Ray3f, si: mi.SurfaceInteraction3f, traced: mi.Bool,
                  effects: tuple[str, ...], max_depth: int, rr_depth: int, hide_emitters: bool,
                  seed: int) -> tuple[mi.Color3f, TraceCounts]:
    """Radiance of the traced pixels (zero elsewhere) for one pass; ``ray``/``si`` are the
    primary rays and hits of every pixel, ``seed`` distinguishes passes."""
    radiance = dr.zeros(mi.Color3f, dr.width(traced))
    pixel = dr.compress(traced)  # only the selected pixels are traced: cost follows the selection
    if dr.width(pixel) == 0:
        return radiance, TraceCounts()
    ray = dr.gather(mi.Ray3f, ray, pixel)
    si = dr.gather(mi.SurfaceInteraction3f, si, pixel)
    # one stream per pixel, whatever else is traced: seed() (unlike the constructor) adds no lane
    # offset; the pass seed is opaque so that the kernel is not recompiled every pass
    rng = mi.PCG32(dr.width(pixel))
    rng.seed(dr.opaque(mi.UInt64, seed), mi.UInt64(pixel))
    L, rays = _paths(scene, ray, si, rng, effects, max_depth, rr_depth, hide_emitters)
    dr.scatter(radiance, L, pixel)
    totals = [dr.sum(r) for r in rays]
    dr.eval(radiance, *totals)
    return radiance, TraceCounts(dict(zip(RAY_KINDS, (int(dr.ravel(t)[0]) for t in totals))))


@dr.syntax
def _paths(scene: mi.Scene, ray: mi.Ray3f, si: mi.SurfaceInteraction3f, rng: mi.PCG32, effects: tuple[str, ...],
           max_depth: int, rr_depth: int, hide_emitters: bool):
    """The path loop (one symbolic Dr.Jit loop, as Mitsuba's ``path``) from the primary hits ``si``.
    Returns the radiance and, per ray kind, the rays each lane traced."""
    shadow_rays = "shadow" in effects
    follow = followed_lobes(effects)
    following = follow != 0  # a Python bool: @dr.syntax keeps such conditions out of the kernel
    ctx_follow = mi.BSDFContext()
    ctx_follow.type_mask = follow
    ctx_rest = mi.BSDFContext()
    ctx_rest.type_mask = int(mi.BSDFFlags.All) & ~follow
    has_emitters = len(scene.emitters()) > 0
    depth_limit = max_depth if max_depth >= 0 else 2**31 - 1

    n = dr.width(rng.state)
    L = dr.zeros(mi.Color3f, n)
    if not hide_emitters:
        L = mi.Color3f(si.emitter(scene).eval(si))
    beta = dr.full(mi.Color3f, 1.0, n)
    eta = dr.full(mi.Float, 1.0, n)
    depth = dr.zeros(mi.UInt32, n)
    n_shadow, n_reflection, n_refraction, n_indirect = (dr.zeros(mi.UInt32, n) for _ in range(4))
    active = dr.full(mi.Bool, True, n)

    while active:
        bsdf = si.bsdf(ray)
        active_next = active & si.is_valid() & (depth + 1 < depth_limit)

        # direct light by emitter sampling: through a shadow ray, or unshadowed
        if has_emitters:
            nee = active_next & mi.has_flag(bsdf.flags(), mi.BSDFFlags.Smooth)
            ds, em_weight = scene.sample_emitter_direction(si, mi.Point2f(rng.next_float32(), rng.next_float32()),
                                                           shadow_rays, nee)
            wo = si.to_local(ds.d)
            value = bsdf.eval(ctx_rest, si, wo, nee)
            if following:
                value_follow, pdf_follow = bsdf.eval_pdf(ctx_follow, si, wo, nee)
                value += value_follow * dr.select(ds.delta, 1.0, _mis(ds.pdf, pdf_follow))
            L += dr.select(nee, beta * em_weight * value, 0.0)
            if shadow_rays:
                n_shadow += dr.select(nee & (ds.pdf > 0), 1, 0)

        # continue along the followed lobes only
        if following:
            bs, weight = bsdf.sample(ctx_follow, si, rng.next_float32(),
                                     mi.Point2f(rng.next_float32(), rng.next_float32()), active_next)
            beta *= weight
            eta *= bs.eta
            rr_prob = dr.minimum(dr.max(beta) * eta * eta, 0.95)
            rr_active = depth + 1 >= rr_depth
            beta[rr_active] *= dr.rcp(rr_prob)
            active_next &= (bs.pdf > 0) & (dr.max(beta) > 0) & (~rr_active | (rng.next_float32() < rr_prob))
            kind = _kind_of(bs.sampled_type)
            n_reflection += dr.select(active_next & kind["reflection"], 1, 0)
            n_refraction += dr.select(active_next & kind["refraction"], 1, 0)
            n_indirect += dr.select(active_next & kind["indirect"], 1, 0)

            prev_si = si
            prev_pdf = bs.pdf
            prev_delta = mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)
            ray = si.spawn_ray(si.to_world(bs.wo))
            si = scene.ray_intersect(ray, mi.RayFlags.All, False, active_next)

            # light reached by BSDF sampling, MIS-weighted against emitter sampling
            ds = mi.DirectionSample3f(scene, si, prev_si)
            em_pdf = dr.select(prev_delta, 0.0, scene.pdf_emitter_direction(prev_si, ds, ~prev_delta & active_next))
            L += dr.select(active_next, beta * _mis(prev_pdf, em_pdf) * si.emitter(scene).eval(si, active_next), 0.0)
        else:
            active_next = mi.Bool(False)
        depth += 1
        active = active_next
    return L, (n_shadow, n_reflection, n_refraction, n_indirect)
