"""Stop 44: where the shared buffer's copy differs from the texture's (first try failed the check).
    python3 diag.py SCENE -D ..."""
import os
import sys

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import drjit as dr  # noqa: E402
import numpy as np  # noqa: E402

import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import RasterCamera  # noqa: E402

args = sys.argv[1:]
defines = dict(a.split("=", 1) for a in args[args.index("-D") + 1::2]) if "-D" in args else {}
scene, name = load_bench_scene([a for a in args if a.endswith(".xml")][0], defines)
raster = hi.rasterizer(scene)
camera = RasterCamera.from_sensor(scene.sensors()[0])
for attempt in range(4):
    fbo = raster.render(camera, (0.5, 0.5), "compute")
    shared = raster._shared
    print("shared:", shared, "unshared:", raster._reader().unshared)
    if shared is None:
        break
    if attempt >= 2:
        raster.ctx.finish()
    copied = np.array(shared.copy(mi.UInt32, camera.width * camera.height))
    texture = raster.read_ids(fbo)
    via_gl = np.zeros_like(texture)  # (OpenGL cannot map the imported buffer)
    diff = copied != texture
    print(f"attempt {attempt} (finish {attempt >= 2}): copy != texture at {diff.sum()} of {diff.size}; copy zero {np.mean(copied == 0):.4f}, "
          f"texture zero {np.mean(texture == 0):.4f}; GL's read of the buffer == texture: {np.array_equal(via_gl, texture)}")
    w = camera.width
    rows = np.flatnonzero(diff.reshape(-1, w).any(axis=1))
    print("  rows differing:", rows[:10], "...", len(rows), "; flipped rows equal:", np.array_equal(copied.reshape(-1, w)[::-1].ravel(), texture))
    if diff.any():
        idx = np.flatnonzero(diff)[:8]
        print("  first:", idx, copied[idx], texture[idx], via_gl[idx])
