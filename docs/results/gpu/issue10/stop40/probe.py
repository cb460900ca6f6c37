"""Stop 40's probe (issue 10, item 3): what makes a small trace call grow with its pixels. At
max_depth 6 (many_objects' own) the line's intercept stays 0.47-0.52 ms wall (depth.sh), so the
growth below 10k pixels is not only Russian roulette's longest glass path. Here the trace call of
scripts/trace_overhead.py (its ``TraceCall``) traces sets of pixels chosen in different ways: none
(the launch's floor), the first N hit pixels (the script's sets), N pixels of one diffuse object,
of one glass object, and N random hit pixels. Per set: how many distinct BSDFs and objects its
pixels hold, the fraction of glass, and the median device ms of the path loop's launch and of the
whole call (kernel history), and the call's wall ms.

    python3 docs/results/gpu/issue10/stop40/probe.py --variant cuda_ad_rgb --resx 1280 --resy 720 --max-depth 6
"""
import argparse, sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))
from trace_overhead import TraceCall, add_arguments, launches, timed  # noqa: E402

parser = argparse.ArgumentParser()
add_arguments(parser, repeats=21)
args = parser.parse_args()

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant(args.variant)
import hybrid_integrator as hi

scene = hi.load_scene(ROOT / "scenes/many_objects.xml", resx=args.resx, resy=args.resy)
trace = TraceCall(scene, args.resx, args.resy, args.max_depth)
order, width = trace.order, dr.width(trace.hits.valid)
obj = np.array(trace.hits.object)
bsdf = np.array(dr.reinterpret_array(mi.UInt32, trace.hits.si.bsdf(trace.hits.ray)))
glass = np.array(trace.hits.si.bsdf(trace.hits.ray).flags() & int(mi.BSDFFlags.DeltaTransmission)) != 0
valid = np.zeros(width, bool)
valid[order] = True
counts = np.bincount(obj[order], minlength=obj.max() + 1)
diffuse_obj = max((o for o in range(len(counts)) if counts[o] and not glass[order][obj[order] == o].any()), key=lambda o: counts[o])
glass_obj = max((o for o in range(len(counts)) if counts[o] and glass[order][obj[order] == o].all()), key=lambda o: counts[o])
rng = np.random.default_rng(1)
sets = {"none": np.array([], int)}
for n in (1, 10, 100, 1000):
    sets[f"first {n}"] = order[:n]
for n in (10, 100, 1000):
    sets[f"one diffuse object {n}"] = np.nonzero(valid & (obj == diffuse_obj))[0][:n]
    sets[f"one glass object {n}"] = np.nonzero(valid & (obj == glass_obj))[0][:n]
    sets[f"random {n}"] = np.sort(rng.choice(order, n, replace=False))
print(f"max_depth {args.max_depth}; diffuse object {diffuse_obj} ({counts[diffuse_obj]} px), glass object {glass_obj} ({counts[glass_obj]} px)")
print(f"{'set':26s} {'px':>5s} {'bsdfs':>5s} {'objs':>5s} {'glass':>5s} {'loop ms':>8s} {'device':>7s} {'wall':>7s}")
for name, pixels in sets.items():
    mask = trace.mask(pixels)
    wall, device = timed(lambda: trace(mask), args.repeats)
    loop = max(e["ms"] for e in launches(lambda: trace(mask), args.repeats))
    print(f"{name:26s} {len(pixels):5d} {len(set(bsdf[pixels])):5d} {len(set(obj[pixels])):5d} "
          f"{glass[pixels].mean() if len(pixels) else 0:5.2f} {loop:8.3f} {device:7.3f} {wall:7.3f}", flush=True)
