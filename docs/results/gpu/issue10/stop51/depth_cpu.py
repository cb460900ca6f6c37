"""Stop 51, CPU: what a depth-capped trace of the glass Armadillo would buy (a "shallow tier" for
refractive objects, as the shadow tier is for diffuse ones): the floor's shadow tier and the
Armadillo traced at max_depth 2-8, 320x180, 1 spp, denoised, trace ms (median of frames 2-5) and
FLIP (mean) against path at 256 spp (max_depth 8).

    .venv/bin/python docs/results/gpu/issue10/stop51/depth_cpu.py
"""
import sys, statistics, numpy as np, mitsuba as mi
mi.set_variant('llvm_ad_rgb')
import hybrid_integrator as hi
from hybrid_integrator.metrics import flip_map
S='../shared/scenes'
scene = mi.load_file('scenes/armadillo_glass.xml', resx=320, resy=180, models_dir=f'{S}/models', spp=1)
gt_scene = mi.load_file('scenes/armadillo_glass.xml', resx=320, resy=180, models_dir=f'{S}/models', spp=256)
ref = np.array(mi.render(gt_scene, integrator=mi.load_dict({'type':'path','max_depth':8})))[..., :3]
for cand in ["", "floor:shadow", "floor:shadow, armadillo"]:
  for depth in ([8] if 'armadillo' not in cand else [2, 3, 4, 5, 6, 8]):
    times, flips = [], []
    for s in range(6):
        r = hi.render(scene, spp=1, seed=s, candidates=cand, max_depth=depth)
        if s >= 2:
            times.append(r.stats.times_ms['trace']); flips.append(flip_map(np.array(r.image)[..., :3], ref)[1])
    print(f"{cand!r:28} depth {depth}: trace {statistics.median(times):6.2f} ms  rays {r.stats.secondary_rays:8d}  FLIP {np.mean(flips):.4f}", flush=True)
