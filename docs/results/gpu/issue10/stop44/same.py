"""Stop 44: the hybrid's frames with the raster pass's numbers read from shared memory are the
frames read through the mapped texture (main's way). Run in each tree on the same machine:

    python3 same.py OUT.npz SCENE... -D resx=1280 -D resy=720 -D models_dir=...

For each scene: a still camera's sequence of 8 frames (seeds 0-7, all candidates, denoised), one
at a time and then two in flight; prints how the raster reached Dr.Jit (``FrameStats.readback``)
and the frames' median ``total``; saves the last three images of each. ``python3 same.py --compare
A.npz B.npz`` prints the largest difference per scene and mode.
"""
import os
import statistics
import sys

import numpy as np

if sys.argv[1] == "--compare":
    a, b = np.load(sys.argv[2]), np.load(sys.argv[3])
    for key in sorted(a):
        print(f"{key:32s} max |a - b| = {float(np.abs(a[key] - b[key]).max()):.3e}")
    sys.exit()

import mitsuba as mi  # noqa: E402

mi.set_variant(os.environ.get("VARIANT", "cuda_ad_rgb"))
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

out, args = sys.argv[1], sys.argv[2:]
defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
images = {}
for spec in [a for a in args if a.endswith(".xml")]:
    scene, name = load_bench_scene(spec, defines)
    camera = sensor_to_world(scene.sensors()[0])
    for n in (1, 2):
        frames = hi.render_sequence(scene, [camera] * 8, seed=0, layers=False, frames_in_flight=n)
        modes = sorted({f.stats.readback for f in frames})
        total = statistics.median(f.stats.times_ms["total"] for f in frames[2:])
        print(f"{name:16s} {n} in flight: readback {modes}, drawn ahead {sum(f.stats.raster_ahead for f in frames)}, "
              f"median total {total:.2f} ms", flush=True)
        for k, f in enumerate(frames[-3:]):
            images[f"{name}_{n}_{k}"] = np.array(f.image)
np.savez(out, **images)
