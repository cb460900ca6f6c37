"""Stop 67: is the showcase's trace-stage mode (4.95 or 5.19 ms on the H100) decided per process or per
scene load? One process loads the scene LOADS times (a new scene, a new ray-tracing acceleration
structure, a new renderer each time, the old one dropped) and prints the median trace stage of 20
frames for each load. With PAD=k (environment), load i first allocates i * k MiB that it keeps
alive, which moves where the scene's and the frame's device arrays land.
    python3 docs/results/gpu/issue10/stop67/reload_mode.py LOADS SCENE [NAME=VALUE ...]
(on the device, after stop31/env.sh: the NAME=VALUE pairs are those of $D, e.g. resx=1280 resy=720)
"""
import gc
import os
import statistics
import sys

import drjit as dr
import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import hybrid_integrator as hi
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.raster.camera import sensor_to_world

loads, path = int(sys.argv[1]), sys.argv[2]
defines = dict(kv.split("=", 1) for kv in sys.argv[3:])
pad_mib = int(os.environ.get("PAD", "0"))
for load in range(loads):
    pad = dr.zeros(mi.Float, max(1, load * pad_mib) << 18)
    dr.eval(pad)
    scene, _ = load_bench_scene(path, defines)
    camera = sensor_to_world(scene.sensors()[0])
    hi.render_sequence(scene, [camera] * 3, layers=False)
    frames = hi.render_sequence(scene, [camera] * 20, layers=False)
    trace = statistics.median(f.stats.times_ms["trace"] for f in frames)
    print(f"load {load}: trace stage {trace:.3f} ms", flush=True)
    del frames, scene, camera, pad
    gc.collect()
    dr.flush_malloc_cache()
