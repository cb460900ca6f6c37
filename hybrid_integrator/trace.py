"""Stage 4, ray tracing: the secondary rays of the selected pixels (paper §3.2, Fig. 4b-c).

Starting from each selected pixel's primary hit (raster or camera ray, the same code after it),
the paths are those of Mitsuba's ``path`` integrator, restricted to the enabled effects:

- at every vertex, direct light by emitter sampling (``scene.sample_emitter_direction``): with a
  shadow ray when ``shadow`` is enabled, unshadowed otherwise;
- the path continues only by BSDF sampling of the lobes the enabled effects follow
  (``selection.lobes``: reflection, refraction, indirect), up to ``max_depth`` vertices, with
  Russian roulette from ``rr_depth`` on, as ``path``, but for a lower cap on the probability
  of going on from depth ``rr_tail_depth`` (:class:`RouletteCap`: the GPU's tail of long glass
  paths);
- multiple importance sampling joins the two estimators where both can reach a light: lobes that
  are followed are MIS-weighted against emitter sampling, lobes that are not are left entirely to
  emitter sampling. With all four effects every lobe is followed and the estimator is ``path``'s
  (with ``rr_tail_depth=-1``, vertex for vertex; else the same expectation).

Only the selected pixels are traced: they are compacted on the device (``selection.compact``)
before the path loop, so the cost follows the selection, and the rays are counted by kind and
object. The loop is one symbolic Dr.Jit loop, part of the frame's frozen device pass
(``pipeline.py``). Random numbers come from a PCG32 stream per pixel and pass (seeded by the
pixel's index), so a pixel's paths do not depend on which other pixels are traced, nor on where
its primary hit came from.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import drjit as dr
import mitsuba as mi
from .heuristic import DeviceSums
from .selection import EFFECTS as RAY_KINDS  # one kind of secondary ray per effect
from .selection import compact
from .selection import lobes as followed_lobes


class RouletteCap(NamedTuple):
    """The largest probability with which Russian roulette continues a path: ``path``'s 0.95, and
    ``tail_prob`` from path depth ``tail_depth`` on (-1: never). The defaults are the integrator's
    in a denoised frame (its ``rr_tail_depth`` and ``rr_tail_prob``).

    Past ``rr_depth`` a path continues with probability min(max throughput · η², cap). Through
    glass the throughput stays near 1, so with ``path``'s cap of 0.95 a path's length past
    ``rr_depth`` is geometric with mean 20, and the longest of N paths grows with 20 · ln N. On a
    GPU a launch lasts until its slowest lanes are done: a frame's trace ended in a tail of a few
    lanes bouncing on through glass, hundreds of vertices deep, while the rest of the GPU idled.
    From depth 16 (deeper than any bench scene's own ``max_depth``) a cap of 0.5 ends that tail
    within a few more vertices. The estimator stays unbiased (a surviving path is weighted by
    1 / probability); only the paths that deep gain variance. H200, 1280×720, the default frame
    against the cap 0.95 everywhere, in turn: the showcase 1.11× faster (FLIP 0.0970 → 0.0971),
    the Armadillo 1.04× (0.0310 → 0.0314, rel. MSE 0.0042 both), the 226 objects 1.03×, Sponza
    1.00× (docs/results/gpu/issue10/stop57: ``rr_cap.py``).

    The price is rare fireflies: the weight doubles at each vertex past ``tail_depth``, so the few
    paths that survive long through glass carry 2^k their light. The denoiser removes them, but an
    undenoised frame keeps them. On the CPU (320×180, 24 seeds) the undenoised frame's relative MSE
    against ``path``, without / with the cap: the Armadillo's mean 0.137 / 0.197 (max 0.263 /
    0.726); the showcase's 0.511 / 9.85 in one run (one frame at 224) and 0.509 / 0.539 in another.
    Denoised, the same either way (0.010, 0.012; docs/results/gpu/issue10/stop61 and stop62:
    ``tail_variance.py``). So since stop 62 a frame without the denoiser has no cap unless
    ``rr_tail_depth`` is given (``HybridSettings.roulette``); ``rr_tail_depth=-1`` turns it off
    everywhere, as for an average of frames that should converge like ``path``'s. That undenoised
    frame is 1.04× (Armadillo) and 1.08× (showcase) slower than with the cap, for 22–26 % less
    relative MSE (H100, in turn: docs/results/gpu/issue10/stop63)."""

    tail_depth: int = 16
    tail_prob: float = 0.5

    #: ``path``'s cap
    PROB = 0.95

    def at(self, depth: mi.UInt32):
        """The cap at a vertex of ``depth`` (counted as ``rr_depth`` is)."""
        if self.tail_depth < 0 or self.tail_prob >= self.PROB:
            return self.PROB
        return dr.select(depth >= self.tail_depth, mi.Float(self.tail_prob), mi.Float(self.PROB))


@dataclass
class TraceCounts:
    """Secondary rays of one pass, per object and kind, left on the device: ``per_object[k·n + i]``
    counts the rays of kind ``RAY_KINDS[k]`` spawned from object ``i``'s pixels, at every depth
    (n: the scene's object count); the last entry counts the traced pixels."""

    per_object: mi.UInt32


@dataclass
class LaneHits:
    """The primary hits that the trace's lanes (one per path) start from."""

    ray: mi.Ray3f
    si: mi.SurfaceInteraction3f
    object: mi.UInt32
    config: mi.UInt32 | None  # index into the primary vertex's effect sets (None: one set)
    #: the lane's paths are traced (a lane may be there for its primary hit alone: ``primary``)
    traced: mi.Bool


#: the primary hits of a trace's lanes from (each lane's pixel: UInt32, the lane is busy: Bool, it is
#: its pixel's first path: Bool): ``trace_effects``' ``primary``
LanePrimary = Callable[..., LaneHits]


def gathered(ray: mi.Ray3f, si: mi.SurfaceInteraction3f, obj: mi.UInt32, config: mi.UInt32 | None) -> LanePrimary:
    """The lanes' primary hits read from per-pixel arrays, every busy lane traced."""
    def lanes(pixel: mi.UInt32, busy: mi.Bool, first: mi.Bool) -> LaneHits:
        return LaneHits(ray=dr.gather(mi.Ray3f, ray, pixel, busy), si=dr.gather(mi.SurfaceInteraction3f, si, pixel, busy),
                        object=dr.gather(mi.UInt32, obj, pixel, busy),
                        config=None if config is None else dr.gather(mi.UInt32, config, pixel, busy), traced=busy)
    return lanes


def _mis(a, b):
    """Power heuristic a²/(a² + b²), as Mitsuba's ``mis_weight``, written as 1/(1 + (b/a)²) so
    that a huge ``a`` (an emitter sampled from a point on itself) gives 1, not inf/inf; 0 where
    ``a`` is 0 (an occluded or failed sample)."""
    r = b / a
    return dr.detach(dr.select(a > 0, dr.rcp(dr.fma(r, r, 1.0)), 0.0))


def _kind_of(sampled_type: mi.UInt32) -> dict[str, mi.Bool]:
    """Which kind of ray a sampled lobe continues the path with (the lobes of ``selection.lobes``)."""
    return {kind: (sampled_type & followed_lobes((kind,))) != 0 for kind in RAY_KINDS[1:]}


class Lobes:
    """What a path vertex does: a shadow ray (or unshadowed light) and the BSDF lobes followed.
    (A plain class, not a dataclass: Dr.Jit's loops would take a dataclass for loop state.)"""

    __slots__ = ("shadow", "follow")

    def __init__(self, shadow: bool, follow: int):
        self.shadow = shadow
        self.follow = follow  # BSDFFlags bits

    @classmethod
    def of(cls, effects: tuple[str, ...]) -> "Lobes":
        return cls(shadow="shadow" in effects, follow=followed_lobes(effects))

    def key(self) -> tuple[bool, int]:
        return self.shadow, self.follow


def trace_effects(scene: mi.Scene, ray: mi.Ray3f, si: mi.SurfaceInteraction3f, traced: mi.Bool,
                  effects: tuple[str, ...], max_depth: int, rr_depth: int, hide_emitters: bool, *,
                  seed: mi.UInt64, obj: mi.UInt32, n_objects: int,
                  first_effects: tuple[tuple[str, ...], ...] | None = None,
                  first_config: mi.UInt32 | None = None,
                  keep_direct: bool = False, paths: int = 1,
                  long: mi.Bool | None = None, primary: LanePrimary | None = None,
                  primary_first: mi.Bool | None = None,
                  roulette: RouletteCap = RouletteCap()) -> tuple[mi.Color3f, mi.Color3f | None, TraceCounts]:
    """Radiance of the traced pixels (zero elsewhere) for one pass; ``ray``/``si`` are the
    primary rays and hits of every pixel, ``seed`` (a 1-element array) distinguishes passes.
    With ``keep_direct``, also returns the light of each path's first vertex alone (its emission
    and direct light, both MIS strategies), where the primary vertex is not the loop's first
    iteration (otherwise, and without ``keep_direct``, ``None``): radiance − that is the pixel's
    indirect light.

    The rays spawned at the primary hit are the kinds its object deserves (§4.1): pixel ``i``
    uses ``first_effects[first_config[i]]`` (default: ``effects`` everywhere), so objects with
    different kinds are traced in one call; deeper vertices use ``effects``. The traced pixels are
    compacted first (``selection.compact``), so the paths run on the first lanes only. The rays
    are counted per object (``obj`` per pixel, of ``n_objects``): what the cost model learns from.

    ``paths`` > 1 traces that many independent paths from each traced pixel's one primary hit, in
    the same kernel launch, and returns their mean: the raster draws each hit once, and one launch
    of ``paths``× the lanes costs the GPU less per path than as many launches (a launch of one
    path per pixel ends in a tail of few long paths; docs/results/README.md has the measured cost
    per path). The sub-pixel position, hence antialiasing, still varies only from pass to pass
    (and frame to frame).

    ``long`` marks the pixels whose paths are expected to be the longest (``selection.long_paths``:
    glass); their lanes are launched first. A GPU schedules a launch's blocks roughly in lane
    order, and the launch lasts until its slowest block is done: long paths started last leave
    most of the GPU idle behind them, started first they overlap the many short ones
    (longest-first scheduling). The lane order changes no result: each pixel's random stream is
    its own. The device pass asks for it on the CUDA backend where a candidate is glass
    (``pipeline.PassStatic.long_first``).

    ``primary`` (default: :func:`gathered` from ``ray``, ``si``, ``obj`` and ``first_config``)
    gives the lanes' primary hits, inside the launch: the device pass re-traces the raster's
    refined pixels there (``primary.raster_hits``), which are in ``traced`` for that alone where
    their object is not traced (``LaneHits.traced``); only the traced lanes are counted. The
    pixels of ``primary_first`` (those it re-traces) are launched before all others, together: a
    launch runs its lanes in groups (a GPU's warps, the LLVM backend's packets) that take a branch
    if one of their lanes does, so the re-traced lanes, scattered among the others, would delay
    almost every group by a ray's traversal; launched first, their extra ray is behind them before
    the longest paths end."""
    n = dr.width(traced)
    width = max(n_objects, 1)
    if first_effects == () and primary is None:  # no object deserves any effect: nothing can be traced
        return dr.zeros(mi.Color3f, n), None, TraceCounts(per_object=dr.zeros(mi.UInt32, len(RAY_KINDS) * width + 1))
    pixel, active, slot = compact(traced, primary_first, long)  # only the selected pixels are traced: cost follows the selection
    # the lanes of the paths: ``paths`` consecutive lanes per traced pixel, so the busy lanes stay in front
    path_pixel, path_active, stream = (pixel, active, pixel) if paths == 1 else _lanes_of(pixel, active, paths)
    first = tuple(Lobes.of(e) for e in (first_effects if first_effects is not None else (effects,)))
    lanes = (primary or gathered(ray, si, obj, first_config if len(first) > 1 else None))(
        path_pixel, path_active, path_active & (stream % paths == 0))
    if first:
        # one stream per pixel (and path), whatever else is traced: seed() (unlike the constructor)
        # adds no lane offset. The initial state is hashed from (stream, pass seed) with TEA, as
        # Mitsuba's samplers do: PCG32 states that differ by a small constant (pass 0, 1, 2, ...) give
        # correlated sequences, whose noise then does not average out over passes or frames
        rng = mi.PCG32(n * paths)
        s = dr.gather(mi.UInt64, seed, 0)
        key = mi.sample_tea_32(mi.UInt32(s), mi.UInt32(s >> 32))[0]
        rng.seed(mi.sample_tea_64(stream, key), mi.UInt64(stream))
        L, first_light, rays = _paths(scene, lanes.ray, lanes.si, rng, lanes.config if len(first) > 1 else None,
                                      lanes.traced, first, Lobes.of(effects), max_depth, rr_depth, hide_emitters,
                                      roulette)
    else:  # no object deserves any effect: the lanes are there for their primary hits alone
        L, first_light, rays = dr.zeros(mi.Color3f, n * paths), None, [dr.zeros(mi.UInt32, n * paths) for _ in RAY_KINDS]
    first_light = first_light if keep_direct else None  # not written by the kernel where no one reads it
    # one kernel: the loop runs once for all (with ``primary``, also what its lanes found)
    dr.eval(L, first_light, rays, *(() if primary is None else (lanes.object, lanes.traced)))
    if primary is None:  # every busy lane is traced: each pixel's object as given
        objects, busy = dr.gather(mi.UInt32, obj, pixel, active), active
    else:  # each pixel's object and whether it was traced, from its first path's lane
        own = dr.arange(mi.UInt32, n) * paths
        objects, busy = dr.gather(mi.UInt32, lanes.object, own), dr.gather(mi.Bool, lanes.traced, own)
    if paths > 1:  # each pixel's mean; its rays, all of them
        L, first_light = (None if c is None else dr.block_sum(c, paths) / paths for c in (L, first_light))
        rays = [dr.block_sum(r, paths) for r in rays]
    radiance = dr.select(traced, dr.gather(mi.Color3f, L, slot, traced), 0.0)  # back to each pixel's lane
    direct = None if first_light is None else dr.select(traced, dr.gather(mi.Color3f, first_light, slot, traced), 0.0)
    per_object = DeviceSums(mi.UInt32, len(RAY_KINDS) * width + 1)
    for k, r in enumerate(rays):
        per_object.add(r, k * width + objects, busy)
    per_object.add(mi.UInt32(1), mi.UInt32(len(RAY_KINDS) * width), busy)
    return radiance, direct, TraceCounts(per_object=per_object.total())


def _lanes_of(pixel: mi.UInt32, active: mi.Bool, paths: int) -> tuple[mi.UInt32, mi.Bool, mi.UInt32]:
    """``paths`` lanes per compacted lane: lane ``j·paths + k`` is path ``k`` of the ``j``-th
    traced pixel. Returns each lane's pixel, whether it is busy, and its random stream
    (``pixel·paths + k``: with one path, the pixel itself)."""
    lane = dr.arange(mi.UInt32, dr.width(pixel) * paths)
    j = lane // paths
    path_pixel = dr.gather(mi.UInt32, pixel, j)
    return path_pixel, dr.gather(mi.Bool, active, j), path_pixel * paths + lane % paths


@dataclass
class _Path:
    """The state of a batch of paths between two vertices (the symbolic loop's variables)."""

    ray: mi.Ray3f
    si: mi.SurfaceInteraction3f
    rng: mi.PCG32
    L: mi.Color3f
    beta: mi.Color3f
    eta: mi.Float
    depth: mi.UInt32
    active: mi.Bool
    rays: list  # per ray kind (RAY_KINDS order), per lane


def _lanes(pairs: list) -> mi.Bool | bool:
    """The lanes of the (lane mask, condition) pairs whose condition holds: a Python bool when
    that is all or none of them."""
    chosen = [m for m, holds in pairs if holds]
    if len(chosen) == len(pairs):
        return True
    out = mi.Bool(False)
    for m in chosen:
        out |= m
    return out if chosen else False


def _vertex(scene: mi.Scene, p: _Path, lobes: tuple[Lobes, ...], config: mi.UInt32 | None, depth_limit: int,
            rr_depth: int, roulette: RouletteCap) -> None:
    """One path vertex, as Mitsuba's ``path``: emitter sampling (a shadow ray or unshadowed light),
    then BSDF sampling of the followed lobes, the next intersection and the light it reaches,
    MIS-weighted. Lane ``i`` does what ``lobes[config[i]]`` says (``config`` None: ``lobes[0]``
    everywhere). Updates ``p`` in place."""
    si = p.si
    bsdf = si.bsdf(p.ray)
    active_next = p.active & si.is_valid() & (p.depth + 1 < depth_limit)
    masks = [None] if config is None else [config == k for k in range(len(lobes))]

    if len(scene.emitters()) > 0:
        flags = bsdf.flags()
        nee = active_next & mi.has_flag(flags, mi.BSDFFlags.Smooth)
        sample = mi.Point2f(p.rng.next_float32(), p.rng.next_float32())  # drawn by every lane, as before
        # a branch (Dr.Jit's symbolic if), not masked code: a warp none of whose lanes samples an
        # emitter (lanes on delta BSDFs: glass, mirrors; finished paths; lanes that are there for
        # their primary hit alone) jumps over the emitter sampling instead of stepping through it
        # with its lanes masked off. The same paths and random numbers (images bit-identical); on
        # the H200 the 226 objects' full trace loop is 3-5 % shorter, and the RT baseline's trace
        # stage on the showcase, whose launch holds every pixel's primary lane, 0.4 ms on average
        # (docs/results/gpu/issue10/stop40)
        light, shadow_rays = dr.if_stmt((p.beta, sample), nee,
                                        lambda beta, sample: _direct(scene, si, bsdf, flags, beta, sample, nee, masks, lobes),
                                        lambda beta, sample: (dr.zeros(mi.Color3f), mi.UInt32(0)), label="direct light")
        p.L += light
        p.rays[0] += shadow_rays

    followed = _lanes([(m, l.follow != 0) for m, l in zip(masks, lobes)])
    if followed is False:
        p.active = mi.Bool(False)
        return
    sample1, sample2 = p.rng.next_float32(), mi.Point2f(p.rng.next_float32(), p.rng.next_float32())
    bs, weight = None, None
    for mask, lobe in zip(masks, lobes):
        if not lobe.follow:
            continue
        ctx_follow = mi.BSDFContext()
        ctx_follow.type_mask = lobe.follow
        bs_k, weight_k = bsdf.sample(ctx_follow, si, sample1, sample2, _within(mask, active_next))
        bs = bs_k if bs is None else dr.select(mask, bs_k, bs)
        weight = weight_k if weight is None else dr.select(mask, weight_k, weight)
    if followed is not True:
        active_next &= followed
    p.beta *= weight
    p.eta *= bs.eta
    rr_prob = dr.minimum(dr.max(p.beta) * p.eta * p.eta, roulette.at(p.depth + 1))
    rr_active = p.depth + 1 >= rr_depth
    p.beta[rr_active] *= dr.rcp(rr_prob)
    active_next &= (bs.pdf > 0) & (dr.max(p.beta) > 0) & (~rr_active | (p.rng.next_float32() < rr_prob))
    for k, mask in enumerate(_kind_of(bs.sampled_type).values(), start=1):
        p.rays[k] += dr.select(active_next & mask, 1, 0)

    prev_delta = mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)
    p.ray = si.spawn_ray(si.to_world(bs.wo))
    p.si = scene.ray_intersect(p.ray, mi.RayFlags.All, False, active_next)
    # light reached by BSDF sampling, MIS-weighted against emitter sampling (a branch too: most
    # vertices hit no emitter)
    emitter = p.si.emitter(scene)
    p.L += dr.if_stmt((p.beta, bs.pdf), active_next & (emitter != None),  # noqa: E711 (an array of pointers)
                      lambda beta, pdf: _emitted(scene, si, p.si, emitter, beta, pdf, prev_delta),
                      lambda beta, pdf: dr.zeros(mi.Color3f), label="emitter hit")
    p.depth += 1
    p.active = active_next


def _within(mask: mi.Bool | None, active):
    """``active`` restricted to the lanes of ``mask`` (None: every lane)."""
    return active if mask is None else active & mask


def _direct(scene: mi.Scene, si: mi.SurfaceInteraction3f, bsdf: mi.BSDFPtr, flags: mi.UInt32, beta: mi.Color3f,
            sample: mi.Point2f, nee: mi.Bool, masks: list, lobes: tuple[Lobes, ...]) -> tuple[mi.Color3f, mi.UInt32]:
    """Direct light at a vertex by emitter sampling (``nee``: the lanes whose BSDF, of ``flags``,
    has a smooth lobe), as ``path``: a shadow ray where the lane's ``lobes`` cast one (unshadowed light
    otherwise), the BSDF's smooth lobes that are not followed evaluated alone, those followed
    MIS-weighted against BSDF sampling. Returns the light (times the path's throughput ``beta``)
    and the shadow rays cast (0 or 1 per lane)."""
    ds, em_weight = scene.sample_emitter_direction(si, sample, False, nee)
    shadow_rays = mi.UInt32(0)
    shadowed = _lanes([(m, l.shadow) for m, l in zip(masks, lobes)])
    if shadowed is not False:  # the shadow ray, as sample_emitter_direction(test_visibility=True) casts it
        test = nee & (ds.pdf > 0) & shadowed
        em_weight[scene.ray_test(si.spawn_ray_to(ds.p), test)] = 0.0
        shadow_rays = dr.select(test, mi.UInt32(1), 0)
    wo = si.to_local(ds.d)
    value = dr.zeros(mi.Color3f, dr.width(nee))
    # only lanes whose BSDF has a smooth lobe of a kind call its evaluation (delta lobes add nothing)
    smooth = flags & int(mi.BSDFFlags.Smooth)
    for mask, lobe in zip(masks, lobes):
        active = _within(mask, nee)
        v = dr.zeros(mi.Color3f, dr.width(nee))
        rest = int(mi.BSDFFlags.Smooth) & ~lobe.follow  # smooth lobes left to emitter sampling alone
        if rest:
            ctx_rest = mi.BSDFContext()
            ctx_rest.type_mask = rest
            v = bsdf.eval(ctx_rest, si, wo, active & ((smooth & rest) != 0))
        if lobe.follow:
            ctx_follow = mi.BSDFContext()
            ctx_follow.type_mask = lobe.follow
            value_follow, pdf_follow = bsdf.eval_pdf(ctx_follow, si, wo, active & ((smooth & lobe.follow) != 0))
            v += value_follow * dr.select(ds.delta, 1.0, _mis(ds.pdf, pdf_follow))
        value = v if mask is None else dr.select(mask, v, value)
    return dr.select(nee, beta * em_weight * value, 0.0), shadow_rays


def _emitted(scene: mi.Scene, prev: mi.SurfaceInteraction3f, si: mi.SurfaceInteraction3f, emitter: mi.EmitterPtr,
             beta: mi.Color3f, bsdf_pdf: mi.Float, prev_delta: mi.Bool) -> mi.Color3f:
    """The light of the emitter that BSDF sampling (density ``bsdf_pdf`` at ``prev``) reached at
    ``si``, MIS-weighted against emitter sampling (none after a delta lobe), times the path's
    throughput ``beta``."""
    ds = mi.DirectionSample3f(scene, si, prev)
    em_pdf = dr.select(prev_delta, 0.0, scene.pdf_emitter_direction(prev, ds, ~prev_delta))
    return beta * _mis(bsdf_pdf, em_pdf) * emitter.eval(si)


@dr.syntax
def _paths(scene: mi.Scene, ray: mi.Ray3f, si: mi.SurfaceInteraction3f, rng: mi.PCG32, config: mi.UInt32 | None,
           active: mi.Bool, first: tuple[Lobes, ...], rest: Lobes, max_depth: int, rr_depth: int, hide_emitters: bool,
           roulette: RouletteCap):
    """The paths from the primary hits ``si`` of the ``active`` lanes: the primary vertex with its
    object's own lobes (``first[config]``), then one symbolic Dr.Jit loop (as Mitsuba's ``path``)
    with the integrator's; when the primary vertex's lobes are the loop's (every candidate with
    the full effect set: the default), it is the loop's first iteration. Returns the radiance, the
    light of the primary vertex alone (``None`` when it is the loop's first iteration) and, per ray
    kind, the rays each lane traced."""
    n = dr.width(rng.state)
    depth_limit = max_depth if max_depth >= 0 else 2**31 - 1
    emitted = dr.zeros(mi.Color3f, n) if hide_emitters else mi.Color3f(si.emitter(scene).eval(si, active))
    p = _Path(ray=ray, si=si, rng=rng, L=emitted, beta=dr.full(mi.Color3f, 1.0, n), eta=dr.full(mi.Float, 1.0, n),
              depth=dr.zeros(mi.UInt32, n), active=mi.Bool(active),
              rays=[dr.zeros(mi.UInt32, n) for _ in RAY_KINDS])
    # a primary vertex with the loop's lobes is the loop's first iteration: one copy of the vertex
    # code in the kernel (the same paths, the same random numbers; showcase trace 6.7 -> 6.0 ms)
    first_light = None
    if len(first) > 1 or first[0].key() != rest.key():
        _vertex(scene, p, first, config, depth_limit, rr_depth, roulette)
        first_light = mi.Color3f(p.L)
    # the loop's state variables, one by one, as dr.while_loop tracks them
    ray, si, rng, L, beta, eta, depth, active, rays = p.ray, p.si, p.rng, p.L, p.beta, p.eta, p.depth, p.active, p.rays
    while active:
        q = _Path(ray=ray, si=si, rng=rng, L=L, beta=beta, eta=eta, depth=depth, active=active, rays=list(rays))
        _vertex(scene, q, (rest,), None, depth_limit, rr_depth, roulette)
        ray, si, rng, L, beta, eta, depth, active, rays = q.ray, q.si, q.rng, q.L, q.beta, q.eta, q.depth, q.active, q.rays
    return L, first_light, rays
