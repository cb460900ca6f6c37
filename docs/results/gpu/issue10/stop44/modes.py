"""Stop 44: is the showcase's bimodal RT trace time a property of the process's scene (its OptiX
acceleration structure), and is that why the showcase's images differ between processes (same
code, same seeds) where the other bench scenes' do not? One process per call:

    python3 modes.py SCENE -D ...   (prints the trace stage's median ms of 20 RT-baseline and 20
                                      hybrid frames, and a hash of each method's fixed-seed frame)
    SAVE=out.npz python3 modes.py ...   (also saves those frames; python3 modes.py --compare A B
                                      prints how far apart two processes' frames are)
"""
import hashlib
import os
import statistics
import sys

if sys.argv[1] == "--compare":
    import numpy as np
    a, b = np.load(sys.argv[2]), np.load(sys.argv[3])
    for key in a:
        d = np.abs(a[key] - b[key])
        print(f"{key}: max |a - b| {d.max():.3e}, pixels differing {np.mean(d.max(axis=-1) > 0):.5f}, "
              f"over 1e-3 {np.mean(d.max(axis=-1) > 1e-3):.5f}")
    sys.exit()

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import numpy as np  # noqa: E402

import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

args = sys.argv[1:]
defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
scene, name = load_bench_scene([a for a in args if a.endswith(".xml")][0], defines)
camera = sensor_to_world(scene.sensors()[0])
line, saved = [name], {}
for primary in ("raytrace", "raster"):
    frames = hi.render_sequence(scene, [camera] * 25, seed=0, layers=False, primary=primary, denoise=False)
    trace = statistics.median(f.stats.times_ms["trace"] for f in frames[5:])
    first = hi.render(scene, spp=1, seed=123, primary=primary, denoise=False, learn_ambient=False)
    digest = hashlib.sha1(np.ascontiguousarray(first.image).tobytes()).hexdigest()[:10]
    line.append(f"{primary}: trace {trace:.3f} ms, image {digest}")
    saved[primary] = np.array(first.image)
print("   ".join(line), flush=True)
if os.environ.get("SAVE"):
    np.savez(os.environ["SAVE"], **saved)
