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
- Q_k = Σ_kind n_k · g_k · rays_per_pixel(k, kind): the secondary rays it will cost (g_k: how
  its pixels grew over the last two frames, :func:`pixel_growth`, 1 for a still camera), with rays per
  pixel per kind learnt from the rays its paths spawned when k was last traced, at every depth
  (a glass object's paths also cast shadow rays where they reach a diffuse surface); before k is
  first traced, a prior for its own kinds: per kind, the median of what the objects traced so far
  that deserve it spawned per pixel (:func:`typical_rays`; a shadow tier: the tiers traced so
  far), and before any was, shadow 1, reflection 1, refraction 2, indirect 1 (a diffuse
  object's full paths spawn ~4 rays per pixel,
  so the fixed prior alone made a newly seen object cost 2–3× what was planned, and the frame miss
  its budget);
- **C_k = V_k · Q_k** (eq. 2), reported as the paper defines it. The budget is in milliseconds,
  so the selectors compare it with ``cost_ms``, the time the cost model (``budget.py``) predicts
  for Q_k rays;
- **R_k = S_k · I + V_k** (eq. 3), S_k = 1 if k was selected in the previous frame, I the
  integrator's ``importance``: hysteresis against flicker.

**Relevance by the error tracing removes** (``relevance="error"``, the default). Eq. 1 ranks
objects by how much of the screen they cover, not by how wrong their raster layer is: a large
diffuse floor outranks a small glass object whose raster pixels are far from the truth. So each
frame also measures, per traced object, E_k: how far its exact estimate lies from its cheap one,
in tone-mapped luminance (τ(x) = Y/(1+Y), so that a bright highlight does not outweigh a whole
shadow). The difference d = τ(traced) − τ(raster) of one pixel at 1 spp is that *bias* b plus the
trace's noise, and the noise (which the denoiser or the history removes, not the choice to
trace) would dominate a mean of |d|: on the Armadillo's floor it is five times the bias. Two
neighbouring pixels trace independent random numbers, so the product of their d has expectation
b_i·b_j ≈ b² wherever the bias varies slowly across a pixel: E_k is the root of the mean of
d_i·d_{i+1} over the object's horizontally adjacent pairs of traced pixels (a mean square bias,
unbiased by the noise). The mean square is learnt across frames (``FrameState.error_squared``,
an average that halves the weight of the past each frame). Then **R_k = S_k · I + V_k · E_k / Ē**, Ē the
mean of the learnt E over the scene's objects, an object never traced yet taking Ē (so that it
is tried). With ``relevance="area"``, R is the paper's eq. 3.

**Shadow tiers** (with a budget and ``relevance="error"``). Tracing an object is all or nothing
per effect set, and a diffuse object's full paths cost several rays per pixel, while the raster
layer's largest error on it is often only its missing shadows. So such an object has a second,
cheaper row: its shadow tier, which traces the object's shadow rays alone (direct light from
every emitter, with visibility) and adds the indirect light from a learnt term, per object
``albedo × E_ind``, E_ind fitted from the paths of the frames that traced it whole (traced light
minus its first vertex's, per albedo: ``lighting.learn_ambient`` on those sums). What the tier
removes is not what it changes: its indirect term is a model. So its E is measured where the
object is traced whole, against the tier's own estimate there (the first vertex's light + the
learnt term): E_tier² = E² − (mean of t_i·t_{i+1}, t = τ(traced) − τ(tier estimate)), the
error the tier leaves subtracted from the error the raster layer leaves; a tier never measured
so is worth nothing, and one that leaves as much error as the raster layer is never picked. The
products' mean is an estimate and comes out below zero where the tier leaves almost no error, but
a tier never removes more than tracing its object whole: its E is capped at the object's (so a
frame's relevance captured stays at most 1; it read 1.037 on the CPU along the 226 objects' path
with parts, docs/results/gpu/issue10/stop74).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .cache import scene_state
from .errors import HybridError
from .objects import scene_objects
from .selection import EFFECTS as KINDS  # the ray kinds an object may deserve are the effects
RELEVANCE = ("error", "area")
#: per-object sums of coverage_sums: pixels, rows, columns, depths, the error products
#: (:func:`add_error`), then over pixels traced with every effect the traced − raster residual
#: (R, G, B) and the albedo (R, G, B) (lighting.py), the pixel pairs of the error products, over
#: the same pixels the indirect light (R, G, B: traced − its first vertex's direct light), and the
#: products of the shadow tier's error
BLOCKS = 16
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
    column centres and of their depths, and over its adjacent pairs of traced pixels the sum of
    the products that estimate the error tracing removed (module docstring; zero where it was
    not traced), with the number of those pairs."""

    width: int
    height: int
    pixels: np.ndarray
    row_sum: np.ndarray
    col_sum: np.ndarray
    depth_sum: np.ndarray
    mean_depth: float  # over every hit pixel
    error_sum: np.ndarray  # Σ d_i·d_{i+1} over the pairs
    residual_sum: np.ndarray  # (3, n): Σ traced − raster over traced pixels
    albedo_sum: np.ndarray  # (3, n): Σ albedo over the same pixels
    pairs: np.ndarray  # adjacent pairs of traced pixels, both of the object
    indirect_sum: np.ndarray  # (3, n): Σ indirect light over the pixels of ``albedo_sum``
    tier_error_sum: np.ndarray  # Σ t_i·t_{i+1} over the pairs: the shadow tier's error (add_error)

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
                   float(total_depth / n_hits) if n_hits else 0.0, error_sum, sums[5:8], sums[8:11], sums[11], sums[12:15], sums[15])


#: copies of the device sums on the GPU (:class:`DeviceSums`), a power of two
SPREAD = 64


class DeviceSums:
    """A few sums (per object, say) added up on the device by atomic adds (``dr.scatter_reduce``)
    from every lane of a kernel, for the host to read after the frame.

    With few objects, every warp of a frame adds into the same few addresses, and the GPU performs
    those atomics one after another (contention: 0.16 ms of the Armadillo's 0.70 ms of DR kernels
    on the H100). On the GPU the sums are therefore kept in ``SPREAD`` copies: each warp (32 lanes,
    whose adds Dr.Jit first combines within the warp, ``JitFlag.ScatterReduceLocal``) adds into
    the copy of its warp number modulo ``SPREAD``, and :meth:`total` adds the copies up. The LLVM
    backend needs no copies: it gives each thread its own for small targets (``ReduceMode.Expand``)."""

    def __init__(self, dtype, size: int, copies: int | None = None):
        """``size`` sums of ``dtype`` (mi.Float, mi.UInt32), all zero; ``copies``: a power of two
        (default: ``SPREAD`` on the GPU, 1 on the CPU)."""
        if copies is None:
            copies = SPREAD if dr.backend_v(dtype) == dr.JitBackend.CUDA else 1
        if copies < 1 or copies & (copies - 1):
            raise HybridError(f"DeviceSums(copies={copies}): give a power of two")
        self.copies = copies
        self.values = dr.zeros(dtype, size * copies)

    def add(self, value, index, active=True) -> None:
        """``sums[index] += value`` where ``active``, per lane."""
        if self.copies > 1:
            lanes = max(dr.width(value), dr.width(index), dr.width(active))
            index = index * self.copies + ((dr.arange(mi.UInt32, lanes) >> 5) & (self.copies - 1))
        dr.scatter_reduce(dr.ReduceOp.Add, self.values, value, index, active)

    def total(self):
        """The sums (the copies added up), still on the device."""
        return dr.block_sum(self.values, self.copies) if self.copies > 1 else self.values


def coverage_sums(obj: mi.UInt32, valid: mi.Bool, depth: mi.Float, width: int, height: int, n_objects: int,
                  extra: int = 0) -> DeviceSums:
    """Per-object sums over a visibility buffer (pixels in row-major order), reduced on the device
    (:class:`DeviceSums`, in the kernel that computes them): pixels, row and column centres,
    depths, one block of ``n_objects`` each, a block for the error (:func:`add_error`, after the
    trace), then ``extra`` zeros for the caller's own counts. Only these few numbers per object
    reach the host, after the frame (:meth:`Coverage.of` of :meth:`DeviceSums.total`)."""
    index = dr.arange(mi.UInt32, width * height)
    row, col = mi.Float(index // width) + 0.5, mi.Float(index % width) + 0.5
    n = max(n_objects, 1)
    sums = DeviceSums(mi.Float, BLOCKS * n + extra)
    for k, value in enumerate((mi.Float(1.0), row, col, depth)):
        sums.add(value, k * n + obj, valid)
    return sums


def add_error(sums: DeviceSums, obj: mi.UInt32, traced: mi.Bool, exact: mi.Color3f, cheap: mi.Color3f,
              base: mi.Color3f, albedo: mi.Color3f, n_objects: int, width: int, full: mi.Bool | None = None,
              direct: mi.Color3f | None = None, tier: mi.Color3f | None = None,
              skipped: mi.Bool | None = None) -> None:
    """Add to each object's sums in ``sums`` (:func:`coverage_sums`) the products
    ``d_i·d_{i+1}`` of horizontally adjacent traced pixels of that object, ``d = τ(exact) −
    τ(cheap)`` (module docstring; ``cheap``: the raster layer as composed; pixels in row-major
    order, ``width`` per row) and the number of those pairs. Over the pixels traced with every
    effect (``full``; default: every traced pixel), per channel, the residual ``exact − base``
    (``base``: the raster layer without its learnt ambient term) and the albedo, the sums that
    term is fitted from (``lighting.learn_ambient``), and with ``direct`` (the light of each path's
    first vertex) the indirect light ``exact − direct``, from which the shadow tier's cheap
    indirect term is fitted. With ``tier`` (what the shadow tier would show there: ``direct`` + the
    learnt indirect term), the products ``t_i·t_{i+1}``, ``t = τ(exact) − τ(tier)``: the mean square
    error the tier leaves (module docstring). ``skipped`` marks the pixels an object traced in part
    leaves out (``selection.QUAD_KEPT``): a traced pixel whose right neighbour is one pairs with
    the pixel after it, so that a part of 1 or 2 quarters (no two traced pixels side by side) is
    measured too."""
    def tone(c):
        y = mi.luminance(c)
        return y / (1.0 + y)

    n = max(n_objects, 1)
    full = traced if full is None else full
    d = dr.select(traced, tone(exact) - tone(cheap), 0.0)
    pixel = dr.arange(mi.UInt32, dr.width(traced))
    right = pixel + 1
    if skipped is not None:  # two apart across a left-out pixel
        right += dr.select(dr.gather(mi.Bool, skipped, right, pixel % width < width - 2), 1, 0)
    pair = traced & (pixel % width < width - (right - pixel))
    pair &= dr.gather(mi.Bool, traced, right, pair) & (dr.gather(mi.UInt32, obj, right, pair) == obj)
    sums.add(d * dr.gather(mi.Float, d, right, pair), 4 * n + obj, pair)
    sums.add(1.0, 11 * n + obj, pair)
    if tier is not None:
        t = dr.select(full, tone(exact) - tone(tier), 0.0)
        sums.add(t * dr.gather(mi.Float, t, right, pair), 15 * n + obj, pair)
    for c in range(3):
        sums.add(exact[c] - base[c], (5 + c) * n + obj, full)
        sums.add(albedo[c], (8 + c) * n + obj, full)
        if direct is not None:
            sums.add(exact[c] - direct[c], (12 + c) * n + obj, full)


def coverage(obj: mi.UInt32, valid: mi.Bool, depth: mi.Float, width: int, height: int, n_objects: int) -> Coverage:
    """:func:`coverage_sums` read back at once."""
    return Coverage.of(coverage_sums(obj, valid, depth, width, height, n_objects).total(), width, height, n_objects)


@dataclass(frozen=True)
class VisibilityTerms:
    """Eq. 1 and 3 for every object at once (numpy arrays indexed by object; see
    :func:`visibility_terms`)."""

    area: np.ndarray
    centrality: np.ndarray
    distance: np.ndarray
    visibility: np.ndarray
    bonus: np.ndarray  # S_k · I of eq. 3
    relevance: np.ndarray
    candidate: np.ndarray  # bool: a visible object that deserves one of the integrator's effects


def rows_of(table: np.ndarray, keys: np.ndarray) -> np.ndarray:
    """The rows ``keys`` of a table learnt per row (``budget.FrameState``), NaN where the table
    has no such row yet (one gather from the table with a NaN row appended, every key past the
    table's end pointed at it)."""
    table = np.asarray(table, dtype=np.float64)
    padded = np.concatenate([table, np.full((1,) + table.shape[1:], np.nan)])
    return padded[np.minimum(keys, len(table))]


def by_kind(table: np.ndarray) -> np.ndarray:
    """The sum over the rows of a (rows × kinds) table, per kind, as a matrix product: the plan
    makes a few such sums over thousands of rows each frame, and numpy's ``sum(axis=0)`` (and
    ``any(axis=1)``) over a table four columns wide costs ~20 µs at 2 000 rows, a product ~3."""
    return np.ones(len(table)) @ table


def any_kind(mask: np.ndarray) -> np.ndarray:
    """Per row of a (rows × KINDS) bool table, whether any kind is set, as its columns or-ed
    (~4 µs at 2 000 rows against ``any(axis=1)``'s ~20: :func:`by_kind`)."""
    return functools.reduce(np.logical_or, mask.T, np.zeros(len(mask), dtype=bool))


def _bonus(n_objects: int, selected_last: set[int], importance: float) -> np.ndarray:
    """S_k · I of eq. 3 per object."""
    bonus = np.zeros(n_objects)
    last = np.fromiter(selected_last, dtype=np.int64, count=len(selected_last))
    bonus[last[last < n_objects]] = importance
    return bonus


def error_weights(keys: np.ndarray, errors: np.ndarray | None, unlearnt=1.0) -> np.ndarray:
    """E_k / Ē for the rows ``keys`` of the learnt errors per pixel (NaN: never traced; module
    docstring), Ē the mean of every learnt row (ones while it is not positive); ``unlearnt``
    (a number, or one per key) where a row is not learnt yet; ones with ``relevance="area"``
    (``errors`` None)."""
    if errors is None:
        return np.ones(len(keys))
    known = np.asarray(errors, dtype=np.float64)
    seen = np.isfinite(known)
    mean = float(known[seen].mean()) if seen.any() else 0.0
    value = rows_of(known, keys)
    return np.where(np.isfinite(value), value / mean if mean > 0 else 1.0, unlearnt)


def active_kinds(kinds: list[tuple[str, ...]], effects: tuple[str, ...]) -> np.ndarray:
    """Per object and kind (``KINDS`` order), whether the object deserves that kind and the
    integrator traces it: an (objects × kinds) bool array."""
    return np.array([[kind in ks and kind in effects for kind in KINDS] for ks in kinds], dtype=bool).reshape(-1, len(KINDS))


def visibility_terms(cov: Coverage, active: np.ndarray, selected_last: set[int], importance: float,
                     errors: np.ndarray | None = None) -> VisibilityTerms:
    """A, P, D, V (eq. 1) and R (eq. 3, V weighted by :func:`error_weights`) of every object of a
    coverage, vectorized; ``active`` is :func:`active_kinds`."""
    w, h = cov.width, cov.height
    n = cov.pixels.astype(np.float64)
    seen = np.maximum(n, 1.0)
    area = n / (w * h)
    offset = np.hypot(cov.col_sum / seen - w / 2, cov.row_sum / seen - h / 2)
    centrality = np.maximum(0.0, 1.0 - offset / (0.5 * np.hypot(w, h)))
    distance = np.maximum((cov.depth_sum / seen) / max(cov.mean_depth, 1e-30), 1e-6)
    visibility = area * centrality / distance
    bonus = _bonus(len(n), selected_last, importance)
    relevance = bonus + (visibility if errors is None else visibility * error_weights(np.arange(len(n)), errors))
    return VisibilityTerms(area, centrality, distance, visibility, bonus, relevance, any_kind(active) & (n > 0))


@dataclass(frozen=True)
class Candidates:
    """The visible candidates of one frame, eq. 1–3 as arrays (a row each): what the selection
    reads, without a Python object per candidate (2 000 objects: 0.25 ms on a CPU of the CI
    machine, 0.5 in a frame, where the LLVM backend's threads run beside it;
    docs/results/gpu/issue10/stop64/plan_time.py, outputs in stop65/outputs). An
    object with a *shadow tier* (:func:`candidates`) has a second row."""

    index: np.ndarray  # object indices
    pixels: np.ndarray
    visibility: np.ndarray  # V, eq. 1
    relevance: np.ndarray  # R, eq. 3
    rays: np.ndarray  # Q per kind (KINDS order): the secondary rays each is expected to spawn per pass
    terms: VisibilityTerms | None  # A, P, D of every object
    tier: np.ndarray | None = None  # per row: the object's shadow tier (None: no such row)

    def __post_init__(self):
        if self.tier is None:
            object.__setattr__(self, "tier", np.zeros(len(self.index), dtype=bool))

    def __len__(self) -> int:
        return len(self.index)

    def keys(self, n_objects: int) -> np.ndarray:
        """Each row's index in the tables learnt per row (``FrameState``): the object's own, or
        ``n_objects`` + the object's for its shadow tier."""
        return self.index + n_objects * self.tier

    def rays_of(self, rows) -> dict[str, float]:
        """The expected rays of the candidates ``rows`` (an index or mask), summed, by kind."""
        total = by_kind(self.rays[rows].reshape(-1, len(KINDS)))
        return {kind: float(v) for kind, v in zip(KINDS, total) if v > 0}


#: the kinds of a shadow tier's row (KINDS order)
SHADOW_KIND = np.array([k == "shadow" for k in KINDS])


def typical_rays(rays_table: np.ndarray, active: np.ndarray, tier: bool = False) -> np.ndarray:
    """Per kind (KINDS order), the prior rays per pixel of a row never traced: the median over
    the learnt objects' rows (``rays_table``, rows × kinds: the objects', then their shadow
    tiers') whose object deserves that kind (``active``, objects × kinds), or
    ``PRIOR_RAYS_PER_PIXEL`` while no such row is learnt. With ``tier``, the prior of a shadow
    tier: the median over the learnt tiers' rows (shadow only). The two apart: an object's full
    paths cast a shadow ray at every vertex that is not a mirror's, a tier one per pixel; with the
    objects' median an untried tier was planned at four times its rays (2 337 888 predicted,
    601 934 traced on the H100), and a 25 % budget took the dining room's large tiers only at its
    18th frame (docs/results/gpu/issue10/stop71). Every kind's median from one sort of the table,
    the rows not chosen sorted last as +inf (this runs once a frame, on the host: at 2 000 objects
    0.045 ms, docs/results/gpu/issue10/stop64/plan_time.py; one statistics-module median per kind
    before))."""
    deserves = np.vstack([active & (not tier), np.broadcast_to(SHADOW_KIND & tier, active.shape)])[:len(rays_table)]
    chosen = np.isfinite(rays_table[:, :1]) & deserves  # a row is learnt whole (budget.blend_rows)
    fixed = np.array([PRIOR_RAYS_PER_PIXEL[k] for k in KINDS])
    if not len(rays_table):
        return fixed
    count = by_kind(chosen).astype(np.int64)
    ranked = np.sort(np.where(chosen, rays_table, np.inf), axis=0)
    cols = np.arange(len(KINDS))
    middle = 0.5 * (ranked[np.maximum(count - 1, 0) // 2, cols] + ranked[count // 2, cols])
    return np.where(count > 0, middle, fixed)


#: the most an object's pixels are expected to grow from one frame to the next (pixel_growth)
MAX_GROWTH = 2.0


def pixel_growth(before: Coverage | None, last: Coverage) -> np.ndarray | None:
    """Per object, the factor by which the next frame is expected to show more of it than ``last``:
    its pixels' growth from ``before`` to ``last`` (the camera moving on as it moved), at least 1
    (an object that shrank is planned at its last pixels: a plan errs on the side of the budget)
    and at most :data:`MAX_GROWTH`; 1 for an object not seen in both. None where ``before`` is no
    coverage of the same objects and film size (a sequence's first frame, a new film)."""
    if not (isinstance(before, Coverage) and len(before.pixels) == len(last.pixels)
            and (before.width, before.height) == (last.width, last.height)):
        return None
    old, new = before.pixels.astype(np.float64), last.pixels.astype(np.float64)
    return np.clip(np.divide(new, old, out=np.ones_like(new), where=(old > 0) & (new > 0)), 1.0, MAX_GROWTH)


def candidates(cov: Coverage, active: np.ndarray, selected_last: set[int], importance: float,
               rays_table: np.ndarray, errors: np.ndarray | None = None, tiers: np.ndarray | None = None,
               growth: np.ndarray | None = None) -> Candidates:
    """Eq. 1–3 for every candidate visible in a visibility buffer (its :func:`coverage`).
    ``rays_table`` holds the learnt rays per pixel (rows × kinds, NaN rows: never traced, which
    take the prior of their own kinds) and ``errors`` the learnt error per row (``relevance="error"``).

    ``tiers`` (per object) marks the objects that also have a **shadow tier**: a second row that
    traces only their shadow rays and takes their indirect light from the cheap model (the learnt
    indirect term, ``lighting.py``), at a fraction of the full row's cost. Its terms are learnt in
    the rows after the objects' (``Candidates.keys``); a larger budget only adds rows (nested
    selection from its first row's cost up: ``selection_graph``), so an object goes from nothing
    to its shadow tier to every effect.

    ``growth`` (per object, :func:`pixel_growth`) scales the pixels its rays are expected from: a
    moving camera's next frame shows more of the objects it approaches or turns towards than the
    last frame did (§4.3's coherence, to first order)."""
    n = len(cov.pixels)
    terms = visibility_terms(cov, active, selected_last, importance)
    index = np.nonzero(terms.candidate)[0]
    tier = np.zeros(len(index), dtype=bool)
    if tiers is not None:
        extra = index[np.asarray(tiers, dtype=bool)[index]]
        index, tier = np.concatenate([index, extra]), np.concatenate([tier, np.ones(len(extra), dtype=bool)])
    keys = index + n * tier
    # a tier is worth nothing until measured, and never more than its object whole (module docstring)
    weights = error_weights(keys, errors, unlearnt=np.where(tier, 0.0, 1.0))
    if tier.any():
        whole = np.zeros(n)
        whole[index[~tier]] = weights[~tier]
        weights[tier] = np.minimum(weights[tier], whole[index[tier]])
    per_pixel = rows_of(rays_table, keys)
    new = np.isnan(per_pixel[:, 0])  # rows never traced (a row is learnt whole): the prior of their own kinds
    for sort in (False, True):  # objects, then shadow tiers: each expects what its own sort traced (typical_rays)
        fresh = new & (tier == sort)
        if fresh.any():
            kinds = SHADOW_KIND if sort else active[index[fresh]]
            per_pixel[fresh] = kinds * typical_rays(rays_table, active, tier=sort)
    pixels = cov.pixels[index]
    relevance = terms.bonus[index] + terms.visibility[index] * weights
    expected = pixels if growth is None else pixels * growth[index]
    return Candidates(index=index, pixels=pixels, visibility=terms.visibility[index], relevance=relevance,
                      rays=expected[:, None] * per_pixel, terms=terms, tier=tier)


def object_relevance(cov: Coverage, kinds: list[tuple[str, ...]], names: list[str],
                     effects: tuple[str, ...], selected_last: set[int], importance: float,
                     rays_per_pixel: dict[int, dict[str, float]],
                     error_per_pixel: dict[int, float] | None = None) -> list[ObjectRelevance]:
    """:func:`candidates` as one :class:`ObjectRelevance` per candidate, from learnt values given
    as mappings (object → rays per pixel by kind; object → error per pixel): for reading the
    terms of a few objects. ``kinds`` are intersected with the integrator's ``effects``."""
    if not cov.any:
        return []
    n = len(kinds)
    table = np.full((n, len(KINDS)), np.nan)
    for k, per_pixel in rays_per_pixel.items():
        table[k] = [per_pixel.get(kind, 0.0) for kind in KINDS]
    errors = None
    if error_per_pixel:
        errors = np.full(n, np.nan)
        errors[list(error_per_pixel)] = list(error_per_pixel.values())
    c = candidates(cov, active_kinds(kinds, effects), selected_last, importance, table, errors)
    t = c.terms
    return [ObjectRelevance(index=int(k), name=names[k], kinds=tuple(kind for kind in kinds[k] if kind in effects),
                            pixels=int(c.pixels[i]), area=float(t.area[k]), centrality=float(t.centrality[k]),
                            distance=float(t.distance[k]), visibility=float(c.visibility[i]), rays=c.rays_of(i),
                            cost=float(c.visibility[i] * c.rays[i].sum()), relevance=float(c.relevance[i]))
            for i, k in enumerate(c.index)]
