"""Stop 67: a BSDF registered outside the scene (``mi.load_dict`` of a lone BSDF) makes Dr.Jit 1.5
refuse to record the frozen device pass; the pass then runs unfrozen (``frozen_inputs`` is
``unfrozen``). This prints, for one process with (``lone``) or without (``none``) such a BSDF: what
the pass took, whether the frozen-asked frame equals ``freeze=False``'s, and the median wall time
of 20 frames after 3 (one synchronisation per frame: the image read back).
    python3 docs/results/gpu/issue10/stop67/lone_bsdf.py lone|none VARIANT SCENE [NAME=VALUE ...]
"""
import statistics
import sys
import time

import mitsuba as mi
import numpy as np

mi.set_variant(sys.argv[2])
import hybrid_integrator as hi
from hybrid_integrator.bench import load_bench_scene

lone = mi.load_dict({"type": "diffuse"}) if sys.argv[1] == "lone" else None
scene, _ = load_bench_scene(sys.argv[3], dict(kv.split("=", 1) for kv in sys.argv[4:]))
kw = dict(spp=1, seed=2, denoise=False)
walls = []
for k in range(23):
    start = time.perf_counter()
    frame = hi.render(scene, **kw)
    image = np.array(frame.image)
    walls.append((time.perf_counter() - start) * 1e3)
plain = np.array(hi.render(scene, freeze=False, **kw).image)
print(f"{sys.argv[1]}: frozen_inputs {frame.stats.frozen_inputs!r}, equals freeze=False "
      f"{np.allclose(image, plain, rtol=1e-4, atol=1e-5)}, median wall {statistics.median(walls[3:]):.2f} ms")
