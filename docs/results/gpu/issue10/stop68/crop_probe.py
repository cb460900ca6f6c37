"""Stop 68 probe: what Open Image Denoise costs on a crop of the frame.

The 'fast' filter of ``denoise.Denoiser`` (an OIDN CUDA device on Dr.Jit's stream, CUDA events
around the filter) on crops of a 1280×720 frame: its device time per crop size, median of 30
calls after 3. Could a budgeted frame denoise only the box around what it traces?

    python3 docs/results/gpu/issue10/stop68/crop_probe.py --variant cuda_ad_rgb -D resx=1280 -D resy=720
"""
import argparse
import statistics

import mitsuba as mi
import numpy as np

parser = argparse.ArgumentParser()
parser.add_argument("--variant", default="llvm_ad_rgb")
parser.add_argument("-D", action="append", default=[])
args = parser.parse_args()
mi.set_variant(args.variant)
import drjit as dr  # noqa: E402

from hybrid_integrator.denoise import Denoiser, Guides  # noqa: E402

defines = dict(d.split("=", 1) for d in args.D)
width, height = int(defines.get("resx", 1280)), int(defines.get("resy", 720))

denoiser = Denoiser("fast")
rng = np.random.default_rng(1)
for w, h in [(width, height), (width * 3 // 4, height), (width // 2, height), (width // 2, height // 2),
             (width // 4, height // 2), (width // 4, height // 4)]:
    color, albedo, normal = (mi.TensorXf(rng.random((h, w, 3), dtype=np.float32)) for _ in range(3))
    times = []
    for _ in range(33):
        out = denoiser(color, Guides(albedo, normal))
        dr.eval(out)
        dr.sync_thread()
        times.append(denoiser.elapsed_ms())
    print(f"denoise {w}x{h} ({w * h / (width * height):.3f} of the frame): {statistics.median(times[3:]):.3f} ms", flush=True)
