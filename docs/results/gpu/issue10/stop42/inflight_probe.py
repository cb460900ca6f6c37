"""Stop 42 on the GPU: what frames in flight would buy, measured without building them. A frame
(`HybridRenderer.render`) ends with the backend's synchronization, so the host issues the next
frame only once the GPU is done, and the GPU then waits for the host's ~1 ms of issue before the
next trace (stop 41's "rest"). Here, in *pipelined* blocks, that synchronization is skipped and
the stage times are not read (Dr.Jit's kernel history, whose read synchronizes, off; the frame's
counts are still waited for, so each frame still learns from the one before): the host issues
frame N+1 while the GPU runs frame N's tail. The denoiser is off (its CUDA events are read after
the synchronization). Per side (all-candidates hybrid, RT baseline) and mode, blocks of 20 frames
(after 3 unmeasured) timed on the host's clock from the first frame's call to the synchronization
after the last: the wall ms per frame, median of 3 blocks per side and mode, modes in turn. The
images are not checked: a probe of the time only.

    python3 inflight_probe.py SCENE [NAME=VALUE ...]   (1280×720, 1 spp)
"""
import os
import statistics
import sys
import time

import drjit
import mitsuba as mi

mi.set_variant(os.environ.get("VARIANT", "cuda_ad_rgb"))  # VARIANT=llvm_ad_rgb: a smoke test on the CPU
from hybrid_integrator import pipeline  # noqa: E402
from hybrid_integrator.api import _integrator  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402

defines = dict(a.split("=", 1) for a in sys.argv[2:] if "=" in a)
scene, name = load_bench_scene(sys.argv[1], {"resx": 1280, "resy": 720, **defines})
pipelined = False


class _Backend:
    """``drjit`` as ``pipeline.py`` sees it: no synchronization and no kernel history when pipelined."""

    def __getattr__(self, attribute):
        return getattr(drjit, attribute)

    @staticmethod
    def sync_thread():
        if not pipelined:
            drjit.sync_thread()

    @staticmethod
    def scoped_set_flag(flag, value=True):
        return drjit.scoped_set_flag(flag, False if (flag == drjit.JitFlag.KernelHistory and pipelined) else value)


frame_times = pipeline.StageClock.frame_times


def stage_times(self):
    return dict.fromkeys(pipeline.STAGES[1:], 0.0) if pipelined else frame_times(self)


pipeline.dr = _Backend()
pipeline.StageClock.frame_times = stage_times
sides = {"hybrid": _integrator({"denoise": False}), "rt": _integrator({"denoise": False, "primary": "raytrace"})}
per_frame = {(side, mode): [] for side in sides for mode in (False, True)}
seed = 0
for block in range(6):
    pipelined = block % 2 == 1
    for side, integrator in sides.items():
        for k in range(23):
            if k == 3:
                drjit.sync_thread()
                start = time.perf_counter()
            integrator.render_result(scene, seed=seed + k, spp=1, layers=False)
        drjit.sync_thread()
        per_frame[side, pipelined].append((time.perf_counter() - start) * 1e3 / 20)
    seed += 23
for mode in (False, True):
    h, r = (statistics.median(per_frame[side, mode]) for side in sides)
    print(f"{name} {'pipelined' if mode else 'one frame at a time'}: hybrid {h:.3f} ms/frame, RT {r:.3f}, "
          f"RT / hybrid {r / h:.3f}")
