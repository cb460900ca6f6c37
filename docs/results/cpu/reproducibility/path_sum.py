"""Probe (stop 28): Mitsuba's own path on llvm_ad_rgb, the same seed in fresh processes: its image sum, and hashes of the primary hits.

    for i in 1 2 3 4 5 6; do python docs/results/cpu/reproducibility/path_sum.py; done
"""
import numpy as np, mitsuba as mi
mi.set_variant('llvm_ad_rgb')
import hybrid_integrator as hi
sc = hi.load_scene('../shared/scenes/cbox/showcase_coloured_glass.xml', resx=320, resy=180)
img = np.array(mi.render(sc, integrator=mi.load_dict({"type": "path", "max_depth": 12}), spp=2, seed=7))
pi = sc.ray_intersect_preliminary(hi.primary.camera_rays(sc.sensors()[0], 320, 180, (0.3, 0.7)) if hasattr(hi, 'primary') else None)
import hashlib
print(float(img.sum()), hashlib.md5(np.array(pi.prim_index).tobytes()).hexdigest()[:8], hashlib.md5(np.array(pi.t).tobytes()).hexdigest()[:8])
