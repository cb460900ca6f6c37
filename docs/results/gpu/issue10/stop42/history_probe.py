"""Stop 42 on the GPU: what Dr.Jit's kernel history (``JitFlag.KernelHistory``, on in every
frame for its stage times: two CUDA events per launch) costs a frame. One hybrid (all
candidates) and one RT-baseline integrator render a still camera in turn, in blocks of 12 frames
(2 warm-up), the history on and off by turns over 8 blocks (off: the flag is left unset, so the
stage times read zero and the frame's total, the host's clock to its synchronization, is all
that is measured). Median frame ms per side and mode, and the paired Gain per mode.

    python3 history_probe.py SCENE [NAME=VALUE ...]   (1280×720, 1 spp, the denoiser off)
"""
import statistics
import sys

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant("cuda_ad_rgb")
from hybrid_integrator.api import _integrator  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402

defines = dict(a.split("=", 1) for a in sys.argv[2:] if "=" in a)
scene, name = load_bench_scene(sys.argv[1], {"resx": 1280, "resy": 720, **defines})
history_off = False
scoped = dr.scoped_set_flag


def scoped_set_flag(flag, value=True):
    return scoped(flag, False if (flag == dr.JitFlag.KernelHistory and history_off) else value)


dr.scoped_set_flag = scoped_set_flag
sides = {"hybrid": _integrator({"denoise": False}), "rt": _integrator({"denoise": False, "primary": "raytrace"})}
totals = {(side, off): [] for side in sides for off in (False, True)}
seed = 0
for block in range(8):
    history_off = block % 2 == 1
    for k in range(12):
        order = list(sides) if (block + k) % 2 == 0 else list(sides)[::-1]
        for side in order:
            result = sides[side].render_result(scene, seed=seed, spp=1, layers=False)
            if k >= 2:
                totals[side, history_off].append(result.stats.times_ms["total"])
        seed += 1
for off in (False, True):
    h, r = np.array(totals["hybrid", off]), np.array(totals["rt", off])
    print(f"{name} history {'off' if off else 'on '}: hybrid {statistics.median(h):.3f} ms, RT {statistics.median(r):.3f} ms, "
          f"paired Gain {np.median(r / h):.3f} ({len(h)} pairs)")
