"""Stop 68: does where the scene's own data lies set the showcase's trace-stage time? (Stop 67 found it fixed
at load: not the emitter table, the renderer, the BVH build or the registry ids.)

One process, one load. Each round copies every Dr.Jit array that ``mi.traverse`` exposes (mesh
vertices, normals, texture coordinates, faces, BSDF and emitter parameters, textures) into a fresh
allocation, a pad of a different size kept alive between the rounds so that the copies land
elsewhere, then ``params.update()`` (Mitsuba rebuilds what depends on them, the acceleration
structure included) and drops the hybrid's state (``hi.api.forget``). The trace stage's median over
20 frames is printed after each round: if the placement of the scene's data sets it, the fast and the
slow time both show up across the rounds.
    python3 docs/results/gpu/issue10/stop68/placement_probe.py SCENE [NAME=VALUE ...]
(on the device, after stop31/env.sh, from docs/results/gpu/issue10/stop67 on the path)
"""
import os
import sys

import drjit as dr
import mitsuba as mi

mi.set_variant(os.environ.get("VARIANT", "cuda_ad_rgb"))  # VARIANT=llvm_ad_rgb: a CPU check of the probe
import hybrid_integrator as hi  # noqa: E402
from trace_probe import load, trace_stage_ms  # noqa: E402

scene, camera = load(sys.argv[1], sys.argv[2:])
params = mi.traverse(scene)
keys = [k for k in params.keys() if isinstance(params[k], (mi.Float, mi.UInt32, mi.TensorXf, mi.Color3f, mi.Point3f,
                                                             mi.Vector3f, mi.Normal3f, mi.Point2f))]
print(f"{len(keys)} arrays copied each round; first: {trace_stage_ms(scene, camera):.3f} ms", flush=True)
pads = []
for round_ in range(8):
    pads.append(dr.zeros(mi.Float, 1 + 37_000 * (round_ + 1)))  # shifts where the copies land
    dr.eval(pads[-1])
    for k in keys:
        value = params[k]
        params[k] = type(value)(value) if not isinstance(value, mi.TensorXf) else mi.TensorXf(mi.Float(value.array), value.shape)
    params.update()
    hi.api.forget(scene)
    print(f"round {round_}: {trace_stage_ms(scene, camera):.3f} ms", flush=True)
