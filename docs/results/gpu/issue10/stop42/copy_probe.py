"""Stop 42 on the GPU: the host's time in the visibility buffer's interop copy
(``interop._SharedImage.copy``, ~0.1 ms per frame in `host.sh`), call by call: each CUDA driver
call by name, the DLPack export of the destination (``interop.device_pointer``), and the rest
of ``copy`` (``dr.empty`` + ``dr.eval`` of the destination, Python). 40 frames of a still camera
on argv[1] (1280×720, 1 spp, no denoiser), after 5 warm-up frames; each call's median host time
over the measured frames, in µs, and ``_SharedImage.release`` (the unmap) the same way.

    python3 copy_probe.py scenes/many_objects.xml [NAME=VALUE ...]
"""
import collections
import statistics
import sys
import time

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster import interop  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

defines = dict(a.split("=", 1) for a in sys.argv[2:] if "=" in a)
scene, _ = load_bench_scene(sys.argv[1], {"resx": 1280, "resy": 720, **defines})
calls = collections.defaultdict(list)
inside = []  # the labels of the calls made inside the copy being timed


def timed(owner, name, label=None):
    function = getattr(owner, name)

    def wrapper(*a, **k):
        start = time.perf_counter()
        try:
            return function(*a, **k)
        finally:
            key = label or (a[1] if name == "call_current" else name)
            calls[key].append((time.perf_counter() - start) * 1e6)
            inside.append(key)
    setattr(owner, name, wrapper)


timed(interop._Driver, "call_current")
timed(interop, "device_pointer")
timed(interop._SharedImage, "copy", "copy (all)")
timed(interop._SharedImage, "release", "release (all)")
camera = sensor_to_world(scene.sensors()[0])
renderer = hi.render_sequence  # one renderer per call: warm-up and measured frames in one sequence
frames = renderer(scene, [camera] * 45, spp=1, layers=False, denoise=False)[5:]
print(f"{sys.argv[1]}: host µs per call, median over the last 40 of 45 frames")
for key, values in calls.items():
    tail = values[len(values) * 5 // 45:]  # the measured frames' calls
    print(f"  {key:40s} n={len(values):4d} median {statistics.median(tail):8.1f}")
print("frame ms median", round(statistics.median(f.stats.times_ms["total"] for f in frames), 3), "host ms",
      {k: round(statistics.median(f.stats.host_ms[k] for f in frames), 3) for k in frames[0].stats.host_ms})
