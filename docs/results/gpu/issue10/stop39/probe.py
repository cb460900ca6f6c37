"""Stop 39's probe (issue 10, item 3): where the trace call's fixed wall time still goes, before any
change is built. (1) The compaction of ``selection.compact`` (one prefix sum over the frame's
921,600 lanes: a decoupled look-back across 900 blocks of 1024) against a two-level one (a prefix
sum within each block of 1024, the 900 block totals' prefix sum, one gather), with one and with
three parts. (2) The frozen trace call of ``scripts/trace_overhead.py`` timed with Dr.Jit's kernel
history on (two CUDA events per launch) and off, in turn. (3) What walking each group of its
inputs costs a replay: a frozen function that takes them and computes ``x + 1``. (4) The trace call
with its glass pixels launched first (``trace_effects(long=...)``, as the device pass does on CUDA
where a candidate is glass) against without. Medians; the variants called in turn.

    python3 docs/results/gpu/issue10/stop39/probe.py --variant cuda_ad_rgb --resx 1280 --resy 720
"""
import argparse, statistics, sys, time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))
from trace_overhead import timed_in_turn, launches  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--variant", default="llvm_ad_rgb")
parser.add_argument("--resx", type=int, default=320)
parser.add_argument("--resy", type=int, default=180)
parser.add_argument("--repeats", type=int, default=41)
args = parser.parse_args()

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant(args.variant)
import hybrid_integrator as hi
from hybrid_integrator.api import rasterizer
from hybrid_integrator.frozen import FrozenScene
from hybrid_integrator.primary import camera_rays, traced_hits
from hybrid_integrator.selection import compact, long_paths
from hybrid_integrator.trace import trace_effects

scene = hi.load_scene(ROOT / "scenes/many_objects.xml", resx=args.resx, resy=args.resy)
n_objects = len(hi.scene_objects(scene))
hits = traced_hits(scene, camera_rays(scene.sensors()[0], args.resx, args.resy, (0.5, 0.5)), rasterizer(scene).tables)
dr.eval(hits.ray, hits.si, hits.valid, hits.object)
order = np.nonzero(np.array(hits.valid))[0]
width = dr.width(hits.valid)
long = long_paths(hits.si.bsdf(hits.ray).flags()) & hits.valid
dr.eval(long)
print(f"{len(order)} hit pixels, {int(dr.count(long)[0])} with a long lobe", flush=True)
masks = {}
for n in (1, 10000, 100000, len(order)):
    chosen = np.zeros(width, dtype=bool)
    chosen[order[:n]] = True
    masks[n] = mi.Bool(chosen)
    dr.eval(masks[n])


def two_level(mask, *first, block=1024):
    """selection.compact's result by a prefix sum within blocks of ``block`` lanes and one over the
    block totals (no look-back across the whole width)."""
    parts, rest = [], mask
    for group in (g for g in first if g is not None):
        parts.append(rest & group)
        rest = rest & ~group
    parts.append(rest)
    bits = max(width.bit_length(), 1)
    dtype = mi.UInt64 if bits * len(parts) > 32 else mi.UInt32
    flags = dtype(0)
    for k, part in enumerate(parts):
        flags |= dtype(part) << (bits * k)
    dr.eval(flags)
    within = dr.block_prefix_sum(flags, block)
    totals = dr.block_sum(flags, block)
    base = dr.prefix_sum(totals)
    blocks = dr.width(totals)
    total = dr.gather(dtype, base, blocks - 1) + dr.gather(dtype, totals, blocks - 1)
    lane = dr.arange(mi.UInt32, width)
    within = within + dr.gather(dtype, base, lane // block)
    slot, n = mi.UInt32(0), mi.UInt32(0)
    for k, part in enumerate(parts):
        shift, ones = bits * k, (1 << bits) - 1
        slot = dr.select(part, n + mi.UInt32((within >> shift) & ones), slot)
        n = n + mi.UInt32((total >> shift) & ones)
    index = dr.empty(mi.UInt32, width)
    dr.scatter(index, lane, slot, mask)
    return index, lane < n, slot


print("== (1) compaction: prefix sum over the width vs two levels", flush=True)
for n in (1, len(order)):
    for label, first in (("1 part", ()), ("3 parts", (masks[1], long))):
        m = masks[n]
        a, b = compact(m, *first), two_level(m, *first)
        dr.eval(a, b)
        same = all(np.array_equal(np.array(x)[:n] if i == 0 else np.array(x), np.array(y)[:n] if i == 0 else np.array(y))
                   for i, (x, y) in enumerate(zip(a, b)))
        (pw, pd), (tw, td) = timed_in_turn([lambda: compact(m, *first), lambda: two_level(m, *first)], args.repeats)
        print(f"{n} set, {label}: prefix {pw:.3f} wall / {pd:.4f} device ms, two-level {tw:.3f} / {td:.4f}; same {same}", flush=True)
        print("   prefix", [(e["type"], e["lanes"], round(e["ms"], 4)) for e in launches(lambda: compact(m, *first), 11)])
        print("   two-level", [(e["type"], e["lanes"], round(e["ms"], 4)) for e in launches(lambda: two_level(m, *first), 11)], flush=True)

pointers = ("shape", "instance")
fields = {k: getattr(hits.si, k) for k in mi.SurfaceInteraction3f.DRJIT_STRUCT if k not in pointers}
ids = [dr.reinterpret_array(mi.UInt32, getattr(hits.si, k)) for k in pointers]


def call(scene, ray, fields, ids, traced, obj, seed, long=None):
    si = mi.SurfaceInteraction3f()
    for k, v in [*fields.items(), *((k, dr.reinterpret_array(mi.ShapePtr, i)) for k, i in zip(pointers, ids))]:
        setattr(si, k, v)
    rt, _, counts = trace_effects(scene, ray, si, traced, ("shadow", "reflection", "refraction"), -1, 5, False,
                                  seed=seed, obj=obj, n_objects=n_objects, long=long)
    return rt, counts.per_object


owner = FrozenScene(scene)
frozen, frozen_long = owner.freeze(call), owner.freeze(call)
seed = dr.opaque(mi.UInt64, 1)


def wall_history_off_on(fn, repeats):
    """Median wall ms of ``fn()`` (one sync per call) with the kernel history off and on, in turn."""
    for _ in range(3):
        dr.eval(fn())
    off, on = [], []
    for _ in range(repeats):
        for flag, out in ((False, off), (True, on)):
            with dr.scoped_set_flag(dr.JitFlag.KernelHistory, flag):
                dr.sync_thread()
                start = time.perf_counter()
                dr.eval(fn())
                dr.sync_thread()
                out.append((time.perf_counter() - start) * 1e3)
                dr.kernel_history_clear()
    return statistics.median(off), statistics.median(on)


print("== (2) the trace call's wall time with the kernel history off / on", flush=True)
for n in (1, 10000):
    args_n = (hits.ray, fields, ids, masks[n], hits.object, seed)
    off, on = wall_history_off_on(lambda: frozen(*args_n), args.repeats)
    print(f"{n} px: history off {off:.3f} ms, on {on:.3f} ms (inputs: {frozen.inputs}, {len(frozen.read or ())} scene variables)", flush=True)

print("== (3) the walk of each group of inputs (a frozen x + 1 given them)", flush=True)
x1 = dr.arange(mi.Float, 10)
harness = (hits.ray, fields, ids, masks[1], hits.object, seed)
groups = {"nothing": (), "read set": (frozen.read,), "harness inputs": harness, "read set + harness": (frozen.read, *harness),
          "snapshot": (owner.variables.handles,)}
fns = {k: dr.freeze(lambda *a: a[-1] + 1) for k in groups}
res = timed_in_turn([lambda k=k: fns[k](*groups[k], x1) for k in groups], args.repeats)
n_vars = {k: len(dr.detail.collect_indices(v)) if v else 0 for k, v in groups.items()}
for k, (w, d) in zip(groups, res):
    print(f"{k}: {n_vars[k]} variables, {w:.3f} ms wall", flush=True)

print("== (4) glass pixels launched first (as the device pass on CUDA) vs not", flush=True)
for n in (10000, 100000, len(order)):
    a = (hits.ray, fields, ids, masks[n], hits.object, seed)
    (pw, pd), (lw, ld) = timed_in_turn([lambda: frozen(*a), lambda: frozen_long(*a, long)], args.repeats)
    print(f"{n} px: in pixel order {pw:.3f} wall / {pd:.3f} device ms, glass first {lw:.3f} / {ld:.3f}", flush=True)
