"""Experiment: does the order of the trace's lanes change its device time? (long paths first)"""
import statistics, sys, time, json
import drjit as dr, mitsuba as mi
mi.set_variant(sys.argv[1])
import hybrid_integrator as hi
from hybrid_integrator import trace as T
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.api import rasterizer
from hybrid_integrator.primary import camera_rays, traced_hits
from hybrid_integrator.selection import compact as plain_compact

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

def ordered(first):
    def compact(mask):
        a, b = mask & first, mask & ~first
        fa, fb = mi.UInt32(a), mi.UInt32(b)
        sa, sb = dr.prefix_sum(fa), dr.prefix_sum(fb)
        last = mi.UInt32(dr.width(mask) - 1)
        na = dr.gather(mi.UInt32, sa, last) + dr.gather(mi.UInt32, fa, last)
        nb = dr.gather(mi.UInt32, sb, last) + dr.gather(mi.UInt32, fb, last)
        slot = dr.select(a, sa, na + sb)
        lane = dr.arange(mi.UInt32, dr.width(mask))
        index = dr.zeros(mi.UInt32, dr.width(mask))
        dr.scatter(index, lane, slot, mask)
        return index, lane < na + nb, slot
    return compact

variants = {"pixel order": plain_compact, "long first": ordered(long), "short first": ordered(~long)}
effects = hi.selection.EFFECTS
seed = dr.opaque(mi.UInt64, 1)
results = {}
for rnd in range(2):
    for label, comp in variants.items():
        T.compact = comp
        def run(k):
            s = dr.opaque(mi.UInt64, k)
            rt, _, counts = T.trace_effects(scene, hits.ray, hits.si, hits.valid, effects, 8 if "armadillo" in name else -1, 5, False,
                                            seed=s, obj=hits.object, n_objects=n_objects)
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
