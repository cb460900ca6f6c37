"""Stop 67: what sets the showcase's trace-stage time within one load of the scene (reload_mode.py:
it changes from one load to the next)? One process, one load; the median trace stage of 20 frames
after each step, 3 times each:
  renderer: the hybrid's state dropped (``hi.api.forget``: a new renderer, a new frozen pass, new
            frame arrays), the scene kept (its shapes, registry ids, acceleration structure);
  accel:    the scene's acceleration structure rebuilt (one mesh's vertices written back unchanged
            through ``mi.traverse``, ``params.update()``), then the renderer dropped as above.
    python3 docs/results/gpu/issue10/stop67/rebuild_mode.py SCENE [NAME=VALUE ...]
(on the device, after stop31/env.sh: the NAME=VALUE pairs are those of $D)
"""
import sys

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import hybrid_integrator as hi
from trace_probe import load, trace_stage_ms

scene, camera = load(sys.argv[1], sys.argv[2:])
params = mi.traverse(scene)
mesh_key = next(k for k in params.keys() if k.endswith("vertex_positions"))

print(f"first: {trace_stage_ms(scene, camera):.3f} ms", flush=True)
for step in ("renderer", "accel") * 3:
    if step == "accel":
        params[mesh_key] = mi.Float(params[mesh_key])
        params.update()
    hi.api.forget(scene)
    print(f"{step} ({mesh_key}): {trace_stage_ms(scene, camera):.3f} ms", flush=True)
