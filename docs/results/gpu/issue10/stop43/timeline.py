"""Stop 43: where a frame in flight leaves the GPU waiting (hybrid and RT baseline, all candidates).

Wraps ``HybridRenderer._device`` (a sample pass's frozen replay, issued after the frame's set-up,
selection and interop copy) and ``FrameSpan.stop`` (after the frame's last work) so that each
records a CUDA event on Dr.Jit's stream and the host's clock. Host and GPU clocks are tied by an
event recorded on an idle stream. Per frame N of a 30-frame sequence with ``frames_in_flight=2``:
``gap`` = when the GPU reached N's replay − when it reached N − 1's end (the GL pass of the
hybrid, its interop copy, and time the GPU waited for the host), ``late`` = when the GPU reached
N's replay − when the host issued it (≈ 0: the GPU waited for the host), and the period. With
``COPIED=1`` also an event after each pass's visibility buffer is copied (``_visibility``: the
interop map and copy), which splits ``gap`` there.

    python3 timeline.py SCENE... -D resx=1280 -D resy=720 ...
"""
import ctypes
import os
import statistics
import sys
import time

import drjit as dr
import mitsuba as mi

mi.set_variant(os.environ.get("VARIANT", "cuda_ad_rgb"))
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator import inflight, pipeline  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402
from hybrid_integrator.raster.interop import _Driver  # noqa: E402

driver = _Driver()
marks = []  # (label, event, host time)


def mark(label):
    event = ctypes.c_void_p()
    driver.call("cuEventCreate", ctypes.byref(event), ctypes.c_uint(0))
    driver.call("cuEventRecord", event, driver.stream)
    marks.append((label, event, time.perf_counter()))


device, stop, visibility = pipeline.HybridRenderer._device, inflight.FrameSpan.stop, pipeline.HybridRenderer._visibility


def wrapped_visibility(self, *a, **k):
    out = visibility(self, *a, **k)
    mark("copied")  # behind the interop map and copy of the pass's visibility buffer
    return out


def wrapped_device(self, *a, **k):
    mark("replay")
    return device(self, *a, **k)


def wrapped_stop(self):
    stop(self)
    mark("end")


pipeline.HybridRenderer._device, inflight.FrameSpan.stop = wrapped_device, wrapped_stop
if os.environ.get("COPIED"):  # also split the gap at the interop copy's end
    pipeline.HybridRenderer._visibility = wrapped_visibility
args = sys.argv[1:]
defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
for spec in [a for a in args if a.endswith(".xml")]:
    scene, name = load_bench_scene(spec, defines)
    camera = sensor_to_world(scene.sensors()[0])
    for primary in ("raster", "raytrace"):
        props = dict(primary=primary, frames_in_flight=2, layers=False)
        hi.render_sequence(scene, [camera] * 5, **props)
        dr.sync_thread()
        marks.clear()
        mark("ref")
        dr.sync_thread()
        frames = hi.render_sequence(scene, [camera] * 30, seed=50, **props)
        dr.sync_thread()
        label0, ref, host0 = marks[0]

        def gpu(event):
            ms = ctypes.c_float()
            driver.call("cuEventElapsedTime", ctypes.byref(ms), ref, event)
            return ms.value

        rows = [(label, gpu(event), (host - host0) * 1e3) for label, event, host in marks[1:]]
        ends = [r for r in rows if r[0] == "end"]
        replays = [r for r in rows if r[0] == "replay"]
        gaps = [rp[1] - e[1] for rp, e in zip(replays[1:], ends[:-1])]
        late = [rp[1] - rp[2] for rp in replays[1:]]
        periods = [b[1] - a[1] for a, b in zip(ends[:-1], ends[1:])]
        copied = [r for r in rows if r[0] == "copied"]
        if copied:
            to_copied = [c[1] - e[1] for c, e in zip(copied[1:], ends[:-1])]
            print(f"{name:16s} {primary:8s} GPU from frame N - 1's end to N's copy done {statistics.median(to_copied):.3f} ms, "
                  f"then to its replay {statistics.median([rp[1] - c[1] for rp, c in zip(replays[1:], copied[1:])]):.3f} ms")
        print(f"{name:16s} {primary:8s} gap {statistics.median(gaps):.3f} ms  GPU behind host at replay "
              f"{statistics.median(late):.3f} ms (min {min(late):.3f})  period {statistics.median(periods):.3f} ms  "
              f"frame total {statistics.median(f.stats.times_ms['total'] for f in frames[1:]):.3f} ms", flush=True)
        for _, event, _ in marks:
            driver.call("cuEventDestroy_v2", event)
