"""Stop 42 on the GPU: is the RT baseline's bimodal showcase trace (5.5-5.7 or 6.1-6.3 ms, decided
per process; stops 40-42) the work of OpenGL in the same process? One process per call renders
30 RT-baseline frames of argv[1] (1280×720, 1 spp, all candidates, no denoiser) after nothing
(``alone``: the renderer's rasterizer makes its GL context and uploads the geometry, but nothing
is drawn and interop is never used) or after 10 hybrid frames (``hybrid``: the raster pass drawn
ahead through interop, as in the bench); with ``denoise``, every frame denoised (Open Image
Denoise on CUDA, as the bench's frames are). Prints the median trace stage and frame of the RT
frames.

    python3 rt_mode.py SCENE MODE [denoise] [NAME=VALUE ...]
"""
import statistics
import sys

import mitsuba as mi

mi.set_variant("cuda_ad_rgb")
import hybrid_integrator as hi  # noqa: E402
from hybrid_integrator.bench import load_bench_scene  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

scene_file, mode = sys.argv[1], sys.argv[2]
defines = dict(a.split("=", 1) for a in sys.argv[3:] if "=" in a)
denoise = "denoise" in sys.argv[3:]
scene, name = load_bench_scene(scene_file, {"resx": 1280, "resy": 720, **defines})
cameras = [sensor_to_world(scene.sensors()[0])]
if mode == "hybrid":
    hi.render_sequence(scene, cameras * 10, spp=1, layers=False, denoise=denoise)
elif mode != "alone":
    raise SystemExit(f"unknown mode {mode}")
frames = hi.render_sequence(scene, cameras * 33, spp=1, layers=False, denoise=denoise, primary="raytrace")[3:]
trace = statistics.median(f.stats.times_ms["trace"] for f in frames)
total = statistics.median(f.stats.times_ms["total"] for f in frames)
print(f"{name} {mode:8s}{' denoised' if denoise else ''} RT trace {trace:.3f} ms, frame {total:.3f} ms")
