"""Stop 40: CPU frame times (llvm_ad_rgb, 320×180, 12 frames of a still camera, median of the last 8),
hybrid and RT baseline on two scenes; run from each tree in turn, as same_images.py."""
import sys, time, statistics, numpy as np
import mitsuba as mi, drjit as dr
mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi
res = {}
for name in ("scenes/many_objects.xml", "scenes/default.xml"):
    scene = hi.load_scene(name, resx=320, resy=180)
    for label, props in (("hybrid", {}), ("rt", {"primary": "raytrace"})):
        cams = [scene.sensors()[0].world_transform()] * 12
        rs = hi.render_sequence(scene, cams, spp=1, layers=False, denoise="off", **props)
        res[f"{name} {label}"] = statistics.median(r.stats.times_ms["total"] for r in rs[4:])
print(sys.argv[1], {k: round(v, 2) for k, v in res.items()})
