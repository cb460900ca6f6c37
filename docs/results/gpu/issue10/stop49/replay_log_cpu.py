"""What one replay of the frozen device pass does (issue 10, stop 49), on this project's CPU: Sponza
at 64×36, no denoiser, five frames of warm-up, then one frame whose frozen call runs with Dr.Jit's
log at the ``Trace`` level; prints the counts of the replay's steps from that log (its inputs'
traversals, kernel launches, reductions, output allocations) and the frozen call's median host
time over 60 frames (the backend synchronized before each call).

    .venv/bin/python docs/results/gpu/issue10/stop49/replay_log_cpu.py > docs/results/gpu/issue10/stop49/outputs/replay_log_cpu.txt
"""
import collections
import os
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path

import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")
ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT))
import hybrid_integrator as hi  # noqa: E402 - after the variant
from hybrid_integrator import frozen  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

STEPS = {"input traversals": r"^FlatVariables::traverse\(\): drjit\.", "kernel launches": r"^replay\(\): launching kernel",
         "reduce": r"^replay\(\): reduce", "expand": r"^replay\(\): expand", "aggregate": r"^replay\(\): aggregate",
         "output allocations": r"allocating output of size"}


def main() -> None:
    scene, _ = load_bench_scene(str(ROOT / "scenes/sponza_mirror.xml"),
                                {"resx": "64", "resy": "36", "sponza_dir": str(ROOT.parent / "shared/scenes/sponza-dabrovic")})
    cam = sensor_to_world(scene.sensors()[0])
    props = dict(spp=1, layers=False, denoise=False)
    call, times, logged = frozen.FrozenFunction.__call__, [], {"on": False}

    def timed(self, *args):
        dr.sync_thread()
        if logged["on"]:
            dr.set_log_level(dr.LogLevel.Trace)
        start = time.perf_counter()
        out = call(self, *args)
        times.append((time.perf_counter() - start) * 1e3)
        dr.set_log_level(dr.LogLevel.Warn)
        return out

    frozen.FrozenFunction.__call__ = timed
    hi.render_sequence(scene, [cam] * 5, **props)
    with tempfile.TemporaryFile("w+") as log:  # Dr.Jit's log goes to the process's stdout
        sys.stdout.flush()
        saved = os.dup(1)
        os.dup2(log.fileno(), 1)
        logged["on"] = True
        hi.render_sequence(scene, [cam], **props)
        logged["on"] = False
        os.dup2(saved, 1)
        log.seek(0)
        lines = log.read().splitlines()
    counts = collections.Counter(step for line in lines for step, pattern in STEPS.items() if re.search(pattern, line))
    print("one replay of the device pass (sponza_mirror, 64x36, llvm_ad_rgb):", dict(counts))
    print("input variables assigned per replay:", sum("uses output" in line for line in lines))
    times.clear()
    hi.render_sequence(scene, [cam] * 60, **props)
    print(f"frozen call, median of 60 frames: {statistics.median(times):.3f} ms")


if __name__ == "__main__":
    main()
