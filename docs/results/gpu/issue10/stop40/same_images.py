"""Stop 40: images of four settings on two scenes (160×90, 2 spp, no denoiser) saved to an .npz, to
compare this stop's trace code with 93a4593 bit for bit. Run from each tree:
    .venv/bin/python docs/results/gpu/issue10/stop40/same_images.py /tmp/new.npz
    cd .w40 && PYTHONPATH=$PWD ../.venv/bin/python ../docs/results/gpu/issue10/stop40/same_images.py /tmp/old.npz
then np.array_equal on each key. A second argument names another variant (stop 41: cuda_ad_rgb)."""
import sys, numpy as np, time
import mitsuba as mi, drjit as dr
mi.set_variant(sys.argv[2] if len(sys.argv) > 2 else "llvm_ad_rgb")
import hybrid_integrator as hi
print(hi.__file__)
out = {}
for name in ("scenes/many_objects.xml", "scenes/default.xml"):
    scene = hi.load_scene(name, resx=160, resy=90)
    for props in ({}, {"primary": "raytrace"}, {"effects": "shadow,reflection,refraction,indirect"}, {"budget_ms": 0.5}):
        r = hi.render(scene, spp=2, seed=3, denoise="off", **props)
        out[f"{name}{props}"] = np.array(r.image)
        t = time.perf_counter()
        for _ in range(3): np.array(hi.render(scene, spp=2, seed=3, denoise="off", **props).image)
        print(name, props, "ms", (time.perf_counter()-t)/3*1e3, r.stats.rays, flush=True)
np.savez(sys.argv[1], **out)
