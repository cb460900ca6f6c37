"""Stop 38's probe (issue 10, item 3): what two changes to a trace call would save, before either
is built. (1) Compaction by an atomic counter (``dr.scatter_inc``: one kernel) against the prefix
sum of ``selection.compact`` (three launches, one of them a block prefix reduction). (2) The
frozen trace call given only the scene variables its recording reads (learned from Dr.Jit's trace
log of one recording) against the whole snapshot (``frozen.FrozenScene``). Wall (one sync per call)
and device ms (kernel history), medians, the variants called in turn.

    python3 docs/results/gpu/issue10/stop38/probe.py --variant cuda_ad_rgb --resx 1280 --resy 720
"""
import argparse, os, re, sys, tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))
from trace_overhead import timed_in_turn, launches  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--variant", default="llvm_ad_rgb")
parser.add_argument("--resx", type=int, default=320)
parser.add_argument("--resy", type=int, default=180)
parser.add_argument("--repeats", type=int, default=41)
parser.add_argument("--max-depth", type=int, default=-1)
parser.add_argument("--log", type=Path, help="write the recording's trace log here")
parser.add_argument("--skip-compaction", action="store_true")
args = parser.parse_args()

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant(args.variant)
import hybrid_integrator as hi
from hybrid_integrator.api import rasterizer
from hybrid_integrator.frozen import FrozenScene
from hybrid_integrator.primary import camera_rays, traced_hits
from hybrid_integrator.selection import compact
from hybrid_integrator.trace import trace_effects

scene = hi.load_scene(ROOT / "scenes/many_objects.xml", resx=args.resx, resy=args.resy)
n_objects = len(hi.scene_objects(scene))
hits = traced_hits(scene, camera_rays(scene.sensors()[0], args.resx, args.resy, (0.5, 0.5)), rasterizer(scene).tables)
dr.eval(hits.ray, hits.si, hits.valid, hits.object)
order = np.nonzero(np.array(hits.valid))[0]
width = dr.width(hits.valid)
masks = {}
for n in (1, 1000, len(order)):
    chosen = np.zeros(width, dtype=bool)
    chosen[order[:n]] = True
    masks[n] = mi.Bool(chosen)
    dr.eval(masks[n])


def atomic(mask):
    counter = dr.zeros(mi.UInt32, 1)
    slot = dr.scatter_inc(counter, mi.UInt32(0), mask)
    lane = dr.arange(mi.UInt32, dr.width(mask))
    index, slots = dr.empty(mi.UInt32, dr.width(mask)), dr.empty(mi.UInt32, dr.width(mask))
    dr.scatter(index, lane, slot, mask)  # the atomic's result, used twice in its one kernel
    dr.scatter(slots, slot, lane, mask)
    return index, lane < dr.gather(mi.UInt32, counter, 0), slots


print("== compaction (unfrozen eval): prefix sum vs scatter_inc", flush=True)
for n, m in ({} if args.skip_compaction else masks).items():
    a, b = compact(m), atomic(m)
    ok = np.array_equal(np.sort(np.array(b[0])[:n]), np.array(a[0])[:n]) and np.array_equal(np.array(a[1]), np.array(b[1]))
    (pw, pd), (aw, ad) = timed_in_turn([lambda: compact(m), lambda: atomic(m)], args.repeats)
    print(f"{n} lanes set: prefix {pw:.3f} wall / {pd:.3f} device ms, atomic {aw:.3f} / {ad:.3f}; same set {ok}", flush=True)
    print("   prefix launches", [(e["type"], round(e["ms"], 4)) for e in launches(lambda: compact(m), 11)])
    print("   atomic launches", [(e["type"], round(e["ms"], 4)) for e in launches(lambda: atomic(m), 11)], flush=True)

pointers = ("shape", "instance")
fields = {k: getattr(hits.si, k) for k in mi.SurfaceInteraction3f.DRJIT_STRUCT if k not in pointers}
ids = [dr.reinterpret_array(mi.UInt32, getattr(hits.si, k)) for k in pointers]


def call(ray, fields, ids, traced, obj, seed):
    si = mi.SurfaceInteraction3f()
    for k, v in [*fields.items(), *((k, dr.reinterpret_array(mi.ShapePtr, i)) for k, i in zip(pointers, ids))]:
        setattr(si, k, v)
    rt, _, counts = trace_effects(scene, ray, si, traced, ("shadow", "reflection", "refraction"), args.max_depth, 5,
                                  False, seed=seed, obj=obj, n_objects=n_objects)
    return rt, counts.per_object


handles = FrozenScene(scene).snapshot().handles
seed = dr.opaque(mi.UInt64, 1)
full = dr.freeze(lambda variables, *a: call(*a))
inputs = (hits.ray, fields, ids, masks[1], hits.object, seed)
sys.stdout.flush()
saved, log = os.dup(1), tempfile.TemporaryFile()
os.dup2(log.fileno(), 1)
dr.set_log_level(dr.LogLevel.Trace)
try:
    dr.eval(full(handles, *inputs))
finally:
    dr.set_log_level(dr.LogLevel.Warn)
    sys.stdout.flush()
    os.dup2(saved, 1)
log.seek(0)
text = log.read().decode(errors="replace")
if args.log:
    args.log.write_text(text)
slots = {int(v): int(s) for v, s in re.findall(r"Adding variable (\d+) <[^>]*> input \d+ to slot s(\d+)", text)}
read_slots = {int(s) for s in re.findall(r"(?:->|<-) param s(\d+)", text)}
trimmed = tuple(h for h in handles if slots.get(h.index) in read_slots)
print(f"== snapshot: {len(handles)} handles, {len(trimmed)} read by the recording ({text.count(chr(10))} log lines)", flush=True)
part = dr.freeze(lambda variables, *a: call(*a))
for n, m in masks.items():
    inputs = (hits.ray, fields, ids, m, hits.object, seed)
    (fw, fd), (tw, td) = timed_in_turn([lambda: full(handles, *inputs), lambda: part(trimmed, *inputs)], args.repeats)
    print(f"{n} px: whole snapshot {fw:.3f} wall / {fd:.3f} device ms, read set {tw:.3f} / {td:.3f}", flush=True)
print("recordings", full.n_recordings, part.n_recordings)
