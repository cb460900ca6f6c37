"""Experiment: does the order of the trace's lanes change its device time? (long paths first)

Stand-alone trace_effects on camera-ray primaries, with the compaction in pixel order, with the
pixels of delta or glossy BSDFs first, and with them last (``trace_effects``' ``long``; the runs
of ab.txt patched in an inline copy of that partition before it was folded into the trace). Usage, from the
repository root (GPU: on the device with $S from scripts/gpu_scenes.sh):

    python .../lane_order.py llvm_ad_rgb scenes/armadillo_glass.xml resx=320 resy=180 models_dir=../shared/scenes/models
    python3 .../lane_order.py cuda_ad_rgb scenes/SCENE.xml resx=1280 resy=720 models_dir=$S/models showcase_dir=$S/cbox sponza_dir=$S/sponza-dabrovic
"""
import statistics, sys, time, json
import drjit as dr, mitsuba as mi
mi.set_variant(sys.argv[1])
import hybrid_integrator as hi
from hybrid_integrator import trace as T
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.api import rasterizer
from hybrid_integrator.primary import camera_rays, traced_hits

defines = dict(d.split("=", 1) for d in sys.argv[3:])
scene, name = load_bench_scene(sys.argv[2], defines)
sensor = scene.sensors()[0]
w, h = sensor.film().size()
n_objects = len(hi.scene_objects(scene))
hits = traced_hits(scene, camera_rays(sensor, w, h, (0.5, 0.5)), rasterizer(scene).tables)
flags = hits.si.bsdf(hits.ray).flags()
long = hits.valid & ((flags & int(mi.BSDFFlags.Delta | mi.BSDFFlags.Glossy)) != 0)
dr.eval(hits.ray, hits.si, hits.valid, hits.object, long)
print(name, "pixels", dr.count(hits.valid)[0], "long", dr.count(long)[0], flush=True)

variants = {"pixel order": None, "long first": long, "short first": ~long}  # trace_effects' ``long``
effects = hi.selection.EFFECTS
seed = dr.opaque(mi.UInt64, 1)
results = {}
for rnd in range(2):
    for label, first in variants.items():
        def run(k):
            s = dr.opaque(mi.UInt64, k)
            rt, _, counts = T.trace_effects(scene, hits.ray, hits.si, hits.valid, effects, 8 if "armadillo" in name else -1, 5, False,
                                            seed=s, obj=hits.object, n_objects=n_objects, long=first)
            return rt, counts.per_object
        dr.eval(run(0)); dr.sync_thread()
        dev, wall = [], []
        with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
            for k in range(15):
                dr.kernel_history_clear(); dr.sync_thread()
                t = time.perf_counter()
                out = run(k + 1); dr.eval(out); dr.sync_thread()
                wall.append((time.perf_counter() - t) * 1e3)
                hist = dr.kernel_history()
                dev.append(max(float(e.get("execution_time", 0.0)) for e in hist))
        results[label] = (statistics.median(dev), statistics.median(wall))
        print(rnd, label, "longest kernel ms %.3f  wall %.3f" % results[label], flush=True)
