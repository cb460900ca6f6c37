"""Stop 67: Mitsuba loads a scene's shapes on several threads (``mi.load_file(parallel=True)``, the
default), so the registry ids its shapes and BSDFs get come in an order that varies from process
to process; with ``parallel=False`` they come in the file's order. Does that order set the trace
stage's time (reload_mode.py: it is fixed at the scene's load)? One process, one load (``serial``:
``mi.load_file`` given ``parallel=False`` for this probe); prints the shapes' and BSDFs' ids and
the median trace stage of 20 frames after 3.
    python3 docs/results/gpu/issue10/stop67/load_order.py parallel|serial SCENE [NAME=VALUE ...]
(on the device, after stop31/env.sh: the NAME=VALUE pairs are those of $D)
"""
import functools
import sys

import drjit as dr
import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
if sys.argv[1] == "serial":
    mi.load_file = functools.partial(mi.load_file, parallel=False)
from trace_probe import load, trace_stage_ms

scene, camera = load(sys.argv[2], sys.argv[3:])
shapes = dr.reinterpret_array(mi.UInt32, mi.ShapePtr(scene.shapes())).numpy().tolist()
bsdfs = dr.reinterpret_array(mi.UInt32, mi.BSDFPtr([s.bsdf() for s in scene.shapes()])).numpy().tolist()
print(f"{sys.argv[1]}: trace stage {trace_stage_ms(scene, camera):.3f} ms; shape ids {shapes}; bsdf ids {bsdfs}", flush=True)
