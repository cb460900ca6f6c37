"""Probe: what Dr.Jit's kernel history (per-kernel CUDA events) costs a default frame."""
import contextlib, statistics, sys
import drjit as dr, mitsuba as mi
mi.set_variant("cuda_ad_rgb")
import hybrid_integrator as hi
from hybrid_integrator import pipeline
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.raster.camera import sensor_to_world

real = dr.scoped_set_flag
def no_history(flag, value=True):
    return contextlib.nullcontext() if flag == dr.JitFlag.KernelHistory else real(flag, value)

params = dict(d.split("=", 1) for d in sys.argv[2:])
scene, name = load_bench_scene(sys.argv[1], params)
cam = sensor_to_world(scene.sensors()[0])
for primary in ("raster", "raytrace"):
    for r in range(2):
        for mode in ("history", "none"):
            pipeline.dr.scoped_set_flag = real if mode == "history" else no_history
            fr = hi.render_sequence(scene, [cam] * 33, spp=1, layers=False, primary=primary)[3:]
            pipeline.dr.scoped_set_flag = real
            tot = statistics.median(f.stats.times_ms["total"] for f in fr)
            host = {k: round(statistics.median(f.stats.host_ms[k] for f in fr), 3) for k in ("setup", "raster", "replay", "post", "readback")}
            print(f"{name} {primary} {r} {mode:8s} frame {tot:.3f} ms", host, flush=True)
