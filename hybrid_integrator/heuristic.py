"""The relevance/cost heuristic of Sabino et al. §4.1 (pre-production candidates) and §4 eq. 1–3
(per-frame visibility, cost and relevance), computed from the frame's own visibility buffer.

**Candidates** (§4.1). Every object (a ``<shape>`` of the scene file, ``objects.py``) has a candidate flag and the kinds of secondary
ray it deserves. Defaults come from its material: every surface deserves ``shadow``; a BSDF with
delta or glossy reflection lobes (conductors, smooth or glossy coatings) also ``reflection``; a
BSDF with transmission (dielectrics) ``refraction`` and ``reflection``; a BSDF with diffuse lobes
``indirect`` (used only when the integrator's ``effects`` include it). The integrator's
``candidates`` property overrides them per object id: ``"armadillo:refraction|shadow, floor:reflection"``;
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

**Relevance by the error tracing removes** (``relevance="error"``, the default). Eq. 1 ranks
objects by how much of the screen they cover, not by how wrong their raster layer is: a large
diffuse floor outranks a small glass object whose raster pixels are far from the truth. So each
frame also measures, per traced object, E_k: the mean over its traced pixels of
``|τ(traced) − τ(raster)|``, the difference between its exact and its cheap estimate in
tone-mapped luminance (τ(x) = Y/(1+Y), so that a bright highlight does not outweigh a whole
shadow); it is learnt across frames (``FrameState.error_per_pixel``, an average that halves the
weight of the past each frame). Then **R_k = S_k · I + V_k · E_k / Ē**, Ē the mean of the learnt
E over the scene's objects, an object never traced yet taking Ē (so that it is tried). With
``relevance="area"``, R is the paper's eq. 3.
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .cache import scene_state
from .errors import HybridError
from .objects import scene_objects
from .selection import EFFECTS as KINDS  # the ray kinds an object may deserve are the effects
RELEVANCE = ("error", "area")
#: per-object sums of coverage_sums: pixels, rows, columns, depths, errors, then over traced
#: pixels the traced − raster residual (R, G, B) and the albedo (R, G, B) (lighting.py)
BLOCKS = 11
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
    """Ray kinds per object of the scene (``objects.SceneObjects``; empty: not a candidate) from
    the ``candidates`` property: ``None`` (every object, material defaults), a string
    ``"id[:kind|kind], ..."``, or a mapping ``{id: kinds or None}``."""
    ids = scene_objects(scene).names
    defaults = default_kinds(scene)
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
        raise HybridError(f"unknown candidate object id(s) {unknown}: the scene's objects are {list(ids)}")
    return [(_kinds(entries[i], i) if entries[i] is not None else defaults[k]) if i in entries else ()
            for k, i in enumerate(ids)]


def default_kinds(scene: mi.Scene) -> list[tuple[str, ...]]:
    """Each object's kinds from its material (read once per scene)."""
    def read():
        kinds = [material_kinds(shape.bsdf()) for shape in scene.shapes()]
        return [kinds[int(k)] for k in scene_objects(scene).shape]

    return scene_state(scene, "material_kinds", read)


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
    relevance: float  # R = S·I + V (eq. 3), V weighted by the learnt error (relevance="error")


@dataclass(frozen=True)
class Coverage:
    """What one visibility buffer says about each object: its pixels, the sums of their row and
    column centres and of their depths, and over its traced pixels the sum of the error tracing
    removed (module docstring; zero where it was not traced)."""

    width: int
    height: int
    pixels: np.ndarray
    row_sum: np.ndarray
    col_sum: np.ndarray
    depth_sum: np.ndarray
    mean_depth: float  # over every hit pixel
    error_sum: np.ndarray
    residual_sum: np.ndarray  # (3, n): Σ traced − raster over traced pixels
    albedo_sum: np.ndarray  # (3, n): Σ albedo over the same pixels

    @property
    def any(self) -> bool:
        return bool(self.pixels.sum() > 0)

    @classmethod
    def of(cls, sums, width: int, height: int, n_objects: int) -> "Coverage":
        """From the sums of :func:`coverage_sums` (read back here, after the frame)."""
        n = max(n_objects, 1)
        sums = np.array(sums, dtype=np.float64)[:BLOCKS * n].reshape(BLOCKS, n)[:, :n_objects]
        pixels, row_sum, col_sum, depth_sum, error_sum = sums[:5]
        n_hits, total_depth = pixels.sum(), depth_sum.sum()
        return cls(width, height, np.rint(pixels).astype(np.int64), row_sum, col_sum, depth_sum,
                   float(total_depth / n_hits) if n_hits else 0.0, error_sum, sums[5:8], sums[8:11])


def coverage_sums(obj: mi.UInt32, valid: mi.Bool, depth: mi.Float, width: int, height: int, n_objects: int,
                  extra: int = 0) -> mi.Float:
    """Per-object sums over a visibility buffer (pixels in row-major order), reduced on the device
    (``dr.scatter_reduce``, in the kernel that computes them): pixels, row and column centres,
    depths, one block of ``n_objects`` each, a block for the error (:func:`add_error`, after the
    trace), then ``extra`` zeros for the caller's own counts. Only these few numbers per object
    reach the host, after the frame (:meth:`Coverage.of`)."""
    index = dr.arange(mi.UInt32, width * height)
    row, col = mi.Float(index // width) + 0.5, mi.Float(index % width) + 0.5
    n = max(n_objects, 1)
    sums = dr.zeros(mi.Float, BLOCKS * n + extra)
    for k, value in enumerate((mi.Float(1.0), row, col, depth)):
        dr.scatter_reduce(dr.ReduceOp.Add, sums, value, k * n + obj, valid)
    return sums


def add_error(sums: mi.Float, obj: mi.UInt32, traced: mi.Bool, exact: mi.Color3f, cheap: mi.Color3f,
              base: mi.Color3f, albedo: mi.Color3f, n_objects: int) -> None:
    """Add each traced pixel's ``|τ(exact) − τ(cheap)|`` (module docstring; ``cheap``: the raster
    layer as composed) to its object's error sum in ``sums`` (:func:`coverage_sums`), and its
    residual ``exact − base`` (``base``: the raster layer without its learnt ambient term) and
    albedo, per channel, to the sums that term is fitted from (``lighting.learn_ambient``)."""
    def tone(c):
        y = mi.luminance(c)
        return y / (1.0 + y)

    n = max(n_objects, 1)
    dr.scatter_reduce(dr.ReduceOp.Add, sums, dr.abs(tone(exact) - tone(cheap)), 4 * n + obj, traced)
    for c in range(3):
        dr.scatter_reduce(dr.ReduceOp.Add, sums, exact[c] - base[c], (5 + c) * n + obj, traced)
        dr.scatter_reduce(dr.ReduceOp.Add, sums, albedo[c], (8 + c) * n + obj, traced)


def coverage(obj: mi.UInt32, valid: mi.Bool, depth: mi.Float, width: int, height: int, n_objects: int) -> Coverage:
    """:func:`coverage_sums` read back at once."""
    return Coverage.of(coverage_sums(obj, valid, depth, width, height, n_objects), width, height, n_objects)


@dataclass(frozen=True)
class VisibilityTerms:
    """Eq. 1 and 3 for every object at once (numpy arrays indexed by object; see
    :func:`visibility_terms`)."""

    area: np.ndarray
    centrality: np.ndarray
    distance: np.ndarray
    visibility: np.ndarray
    relevance: np.ndarray
    candidate: np.ndarray  # bool: a visible object that deserves one of the integrator's effects


def error_weights(n_objects: int, error_per_pixel: dict[int, float] | None) -> np.ndarray:
    """E_k / Ē per object (module docstring); all ones without learnt errors (``relevance="area"``)."""
    weights = np.ones(n_objects)
    if error_per_pixel:
        known = {k: v for k, v in error_per_pixel.items() if k < n_objects}
        mean = float(np.mean(list(known.values()))) if known else 0.0
        if mean > 0:
            for k, v in known.items():
                weights[k] = v / mean
    return weights


def visibility_terms(cov: Coverage, kinds: list[tuple[str, ...]], effects: tuple[str, ...], selected_last: set[int],
                     importance: float, error_per_pixel: dict[int, float] | None = None) -> VisibilityTerms:
    """A, P, D, V (eq. 1) and R (eq. 3, V weighted by :func:`error_weights`) of every object of a
    coverage, vectorized."""
    w, h = cov.width, cov.height
    n = cov.pixels.astype(np.float64)
    seen = np.maximum(n, 1.0)
    area = n / (w * h)
    offset = np.hypot(cov.col_sum / seen - w / 2, cov.row_sum / seen - h / 2)
    centrality = np.maximum(0.0, 1.0 - offset / (0.5 * np.hypot(w, h)))
    distance = np.maximum((cov.depth_sum / seen) / max(cov.mean_depth, 1e-30), 1e-6)
    visibility = area * centrality / distance
    bonus = np.zeros(len(n))
    bonus[[k for k in selected_last if k < len(n)]] = importance
    deserving = np.array([any(kind in effects for kind in ks) for ks in kinds], dtype=bool)
    relevance = bonus + visibility * error_weights(len(n), error_per_pixel)
    return VisibilityTerms(area, centrality, distance, visibility, relevance, deserving & (n > 0))


def object_relevance(cov: Coverage, kinds: list[tuple[str, ...]], names: list[str],
                     effects: tuple[str, ...], selected_last: set[int], importance: float,
                     rays_per_pixel: dict[int, dict[str, float]],
                     error_per_pixel: dict[int, float] | None = None) -> list[ObjectRelevance]:
    """Eq. 1–3 for every candidate visible in a visibility buffer (its :func:`coverage`), with
    the learnt errors where given. ``kinds`` are intersected with the integrator's ``effects``."""
    if not cov.any:
        return []
    terms = visibility_terms(cov, kinds, effects, selected_last, importance, error_per_pixel)
    out = []
    for k in np.nonzero(terms.candidate)[0]:
        active = tuple(kind for kind in kinds[k] if kind in effects)
        n = int(cov.pixels[k])
        per_pixel = rays_per_pixel.get(k) or {kind: PRIOR_RAYS_PER_PIXEL[kind] for kind in active}
        rays = {kind: float(n) * v for kind, v in per_pixel.items() if v > 0}
        out.append(ObjectRelevance(index=int(k), name=names[k], kinds=active, pixels=n, area=float(terms.area[k]),
                                   centrality=float(terms.centrality[k]), distance=float(terms.distance[k]),
                                   visibility=float(terms.visibility[k]), rays=rays,
                                   cost=float(terms.visibility[k]) * sum(rays.values()),
                                   relevance=float(terms.relevance[k])))
    return out
