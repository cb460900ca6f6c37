"""Stop 43: frames in flight against one frame at a time, on the host's clock and the frames' own.

For each scene given, the hybrid and its RT baseline (all candidates, denoised, 1 spp), each with
``frames_in_flight`` 1 and 2, in turn, three blocks of 20 frames each after a warm-up
(``hi.render_sequence`` with a still camera; a block's wall time runs from its first call to the
synchronization after its last frame's times are read). Prints per side and mode the median wall
ms per frame of the blocks, the median ``times_ms["total"]`` of the frames, and the largest
difference between a block's images with one frame and with two in flight (the same seeds).

    python3 wall.py SCENE... -D resx=1280 -D resy=720 -D models_dir=...
"""
import os
import sys
import statistics
import time

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant(os.environ.get("VARIANT", "cuda_ad_rgb"))
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

args = sys.argv[1:]
defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
scenes = [a for a in args if a.endswith(".xml")]
for spec in scenes:
    scene, name = load_bench_scene(spec, defines)
    camera = sensor_to_world(scene.sensors()[0])
    sides = {(p, n): dict(primary=p, frames_in_flight=n) for p in ("raster", "raytrace") for n in (1, 2)}
    for props in sides.values():
        hi.render_sequence(scene, [camera] * 5, seed=0, layers=False, **props)  # warm-up
    wall = {k: [] for k in sides}
    totals = {k: [] for k in sides}
    last = {}
    for block in range(3):
        for key, props in sides.items():
            dr.sync_thread()
            start = time.perf_counter()
            frames = hi.render_sequence(scene, [camera] * 20, seed=100 * block, layers=False, **props)
            dr.sync_thread()
            wall[key].append((time.perf_counter() - start) * 1e3 / 20)
            totals[key] += [f.stats.times_ms["total"] for f in frames]
            last[key] = np.array(frames[-1].image)
    for p in ("raster", "raytrace"):
        diff = float(np.abs(last[(p, 1)] - last[(p, 2)]).max())
        print(f"{name:16s} {p:8s} wall ms/frame 1 / 2 in flight: "
              f"{statistics.median(wall[(p, 1)]):.3f} / {statistics.median(wall[(p, 2)]):.3f}   "
              f"frame total: {statistics.median(totals[(p, 1)]):.3f} / {statistics.median(totals[(p, 2)]):.3f}   "
              f"image max diff {diff:.2e}", flush=True)
    for n in (1, 2):
        print(f"{name:16s} RT / hybrid, {n} in flight: wall {statistics.median(wall[('raytrace', n)]) / statistics.median(wall[('raster', n)]):.3f}"
              f"  totals {statistics.median(totals[('raytrace', n)]) / statistics.median(totals[('raster', n)]):.3f}", flush=True)
