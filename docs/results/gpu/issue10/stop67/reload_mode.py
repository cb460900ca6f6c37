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
import sys

import drjit as dr
import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
from trace_probe import load, trace_stage_ms

loads, path = int(sys.argv[1]), sys.argv[2]
pad_mib = int(os.environ.get("PAD", "0"))
for k in range(loads):
    pad = dr.zeros(mi.Float, max(1, k * pad_mib) << 18)
    dr.eval(pad)
    scene, camera = load(path, sys.argv[3:])
    print(f"load {k}: trace stage {trace_stage_ms(scene, camera):.3f} ms", flush=True)
    del scene, camera, pad
    gc.collect()
    dr.flush_malloc_cache()
