"""The relevance/cost heuristic of Sabino et al. §4.1 (pre-production candidates) and §4 eq. 1–3
(per-frame visibility, cost and relevance), computed from the frame's own visibility buffer.

**Candidates** (§4.1). Every object (Mitsuba shape) has a candidate flag and the kinds of secondary
ray it deserves. Defaults come from its material: every surface deserves ``shadow``; a BSDF with
delta or glossy reflection lobes (conductors, smooth or glossy coatings) also ``reflection``; a
BSDF with transmission (dielectrics) ``refraction`` and ``reflection``; a BSDF with diffuse lobes
``indirect`` (used only when the integrator's ``effects`` include it). The integrator's
``candidates`` property overrides them per shape id: ``"armadillo:refraction|shadow, floor:reflection"``;
an id without ``:`` keeps its material's kinds; a listed property makes the unlisted shapes
non-candidates; ``""`` means none.

**Per frame** (eq. 1–3), for each candidate k seen in the visibility buffer of W×H pixels:

- A_k = n_k / (W·H): the fraction of the image it covers (n_k: its pixels);
- P_k = max(0, 1 − |c_k − c| / (diagonal/2)): projected centrality of its pixels' centroid c_k
  (1 at the image centre c, 0 at the corners; 0 when it is not in view);
- D_k = its mean depth / the mean depth of all visible pixels (dimensionless, 1 = typical);
- **V_k = A_k · P_k / D_k** (eq. 1), in [0, 1] for an object at typical depth;
- Q_k = Σ_kind n_k · rays_per_pixel(k, kind): the secondary rays it will cost, with rays per
  pixel per kind learnt from the rays its paths spawned when k was last traced, at every depth
  (a glass object's paths also cast shadow rays where they reach a diffuse surface); before k is
  first traced, a prior for its own kinds: shadow 1, reflection 1, refraction 2, indirect 1;
- **C_k = V_k · Q_k** (eq. 2), reported as the paper defines it. The budget is in milliseconds,
  so the selectors compare it with ``cost_ms``, the time the cost model (``budget.py``) predicts
  for Q_k rays;
- **R_k = S_k · I + V_k** (eq. 3), S_k = 1 if k was selected in the previous frame, I the
  integrator's ``importance``: hysteresis against flicker.
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .errors import HybridError
from .selection import EFFECTS as KINDS  # the ray kinds an object may deserve are the effects
PRIOR_RAYS_PER_PIXEL = {"shadow": 1.0, "reflection": 1.0, "refraction": 2.0, "indirect": 1.0}


def material_kinds(bsdf: mi.BSDF | None) -> tuple[str, ...]:
    """The ray kinds a material deserves by default (§4.1)."""
    if bsdf is None:
        return ("shadow",)
    flags = int(bsdf.flags())
    F = mi.BSDFFlags
    kinds = ["shadow"]
    if flags & (int(F.DeltaReflection) | int(F.GlossyReflection)) or flags & int(F.Transmission):
        kinds.append("reflection")
    if flags & int(F.Transmission):
        kinds.append("refraction")
    if flags & int(F.Diffuse):
        kinds.append("indirect")
    return tuple(kinds)


def _kinds(text, shape_id: str) -> tuple[str, ...]:
    names = [k.strip() for k in (text.split("|") if isinstance(text, str) else text) if k.strip()]
    unknown = [k for k in names if k not in KINDS]
    if unknown:
        raise HybridError(f"unknown ray kind(s) {unknown} for candidate '{shape_id}': choose from {list(KINDS)}")
    return tuple(k for k in KINDS if k in names)


def candidate_kinds(value, scene: mi.Scene) -> list[tuple[str, ...]]:
    """Ray kinds per ``scene.shapes()`` entry (empty: not a candidate) from the ``candidates``
    property: ``None`` (every shape, material defaults), a string ``"id[:kind|kind], ..."``, or a
    mapping ``{id: kinds or None}``."""
    shapes = scene.shapes()
    ids = [s.id() for s in shapes]
    defaults = [material_kinds(s.bsdf()) for s in shapes]
    if value is None:
        return defaults
    if isinstance(value, str):
        entries = {}
        for item in (v.strip() for v in value.split(",")):
            if item:
                name, _, kinds = item.partition(":")
                entries[name.strip()] = kinds if kinds else None
    else:
        entries = dict(value)
    unknown = [n for n in entries if n not in ids]
    if unknown:
        raise HybridError(f"unknown candidate shape id(s) {unknown}: the scene's shapes are {ids}")
    return [(_kinds(entries[i], i) if entries[i] is not None else defaults[k]) if i in entries else ()
            for k, i in enumerate(ids)]


@dataclass(frozen=True)
class ObjectRelevance:
    """One candidate's terms of eq. 1–3 in one frame."""

    index: int
    name: str
    kinds: tuple[str, ...]
    pixels: int
    area: float  # A
    centrality: float  # P
    distance: float  # D
    visibility: float  # V, eq. 1
    rays: dict[str, float]  # Q per kind
    cost: float  # C = V·Q, eq. 2
    relevance: float  # R = S·I + V, eq. 3


@dataclass(frozen=True)
class Coverage:
    """What one visibility buffer says about each shape (indexed like ``scene.shapes()``): its
    pixels, the sums of their row and column centres and of their depths."""

    width: int
    height: int
    pixels: np.ndarray
    row_sum: np.ndarray
    col_sum: np.ndarray
    depth_sum: np.ndarray
    mean_depth: float  # over every hit pixel

    @property
    def any(self) -> bool:
        return bool(self.pixels.sum() > 0)


def coverage(shape_index: mi.UInt32, valid: mi.Bool, depth: mi.Float, width: int, height: int, n_shapes: int) -> Coverage:
    """Per-shape sums over a visibility buffer (pixels in row-major order), reduced on the device
    (``dr.scatter_reduce``), so only a few numbers per shape reach the host."""
    index = dr.arange(mi.UInt32, width * height)
    row, col = mi.Float(index // width) + 0.5, mi.Float(index % width) + 0.5
    sums = [dr.zeros(mi.Float, max(n_shapes, 1)) for _ in range(4)]
    for target, value in zip(sums, (mi.Float(1.0), row, col, depth)):
        dr.scatter_reduce(dr.ReduceOp.Add, target, value, shape_index, valid)
    hits, total_depth = dr.count(valid), dr.sum(dr.select(valid, depth, 0.0))
    dr.eval(*sums, hits, total_depth)
    pixels, row_sum, col_sum, depth_sum = (np.array(v, dtype=np.float64)[:n_shapes] for v in sums)
    n_hits = int(dr.ravel(hits)[0])
    mean_depth = float(dr.ravel(total_depth)[0]) / n_hits if n_hits else 0.0
    return Coverage(width, height, np.rint(pixels).astype(np.int64), row_sum, col_sum, depth_sum, mean_depth)


def object_relevance(cov: Coverage, kinds: list[tuple[str, ...]], names: list[str],
                     effects: tuple[str, ...], selected_last: set[int], importance: float,
                     rays_per_pixel: dict[int, dict[str, float]]) -> list[ObjectRelevance]:
    """Eq. 1–3 for every candidate visible in a visibility buffer (its :func:`coverage`).
    ``kinds`` are intersected with the integrator's ``effects``."""
    if not cov.any:
        return []
    w, h = cov.width, cov.height
    counts, sum_r, sum_c, sum_d, mean_depth = cov.pixels, cov.row_sum, cov.col_sum, cov.depth_sum, cov.mean_depth
    half_diagonal = 0.5 * np.hypot(w, h)
    out = []
    for k, n in enumerate(counts):
        active = tuple(kind for kind in kinds[k] if kind in effects)
        if n == 0 or not active:
            continue
        area = n / (w * h)
        offset = np.hypot(sum_c[k] / n - w / 2, sum_r[k] / n - h / 2)
        centrality = max(0.0, 1.0 - offset / half_diagonal)
        distance = max((sum_d[k] / n) / mean_depth, 1e-6)
        visibility = area * centrality / distance
        per_pixel = rays_per_pixel.get(k) or {kind: PRIOR_RAYS_PER_PIXEL[kind] for kind in active}
        rays = {kind: float(n) * v for kind, v in per_pixel.items() if v > 0}
        relevance = (importance if k in selected_last else 0.0) + visibility
        out.append(ObjectRelevance(index=k, name=names[k], kinds=active, pixels=int(n), area=area, centrality=centrality,
                                   distance=distance, visibility=visibility, rays=rays,
                                   cost=visibility * sum(rays.values()), relevance=relevance))
    return out
