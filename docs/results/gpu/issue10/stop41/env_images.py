"""Stop 41: images of a scene with what many_objects and default.xml lack (a constant environment
that escaped paths reach, a point light, an area light seen directly, glass, a mirror, a rough
conductor), four settings, 96×64, 4 spp, saved to an .npz to compare two trees' trace code:
    .venv/bin/python docs/results/gpu/issue10/stop41/env_images.py /tmp/env_new.npz [VARIANT]
    cd .w41 && PYTHONPATH=$PWD ../.venv/bin/python ../docs/results/gpu/issue10/stop41/env_images.py /tmp/env_old.npz
then compare.py on the two files."""
import sys, numpy as np
import mitsuba as mi
mi.set_variant(sys.argv[2] if len(sys.argv) > 2 else "llvm_ad_rgb")
import hybrid_integrator as hi
print(hi.__file__)
scene = mi.load_dict({
    "type": "scene",
    "sensor": {"type": "perspective", "fov": 45, "to_world": mi.ScalarTransform4f().look_at(origin=[0, 1, 5], target=[0, 0, 0], up=[0, 1, 0]),
               "film": {"type": "hdrfilm", "width": 96, "height": 64}},
    "env": {"type": "constant", "radiance": {"type": "rgb", "value": [0.4, 0.5, 0.6]}},
    "point": {"type": "point", "position": [2, 3, 2], "intensity": {"type": "rgb", "value": [20, 20, 20]}},
    "floor": {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, -1, 0]).rotate([1, 0, 0], -90).scale(4),
              "bsdf": {"type": "diffuse"}},
    "glass": {"type": "sphere", "center": [-0.8, 0, 0], "radius": 0.7, "bsdf": {"type": "dielectric"}},
    "mirror": {"type": "cube", "to_world": mi.ScalarTransform4f().translate([0.9, -0.3, 0]).scale(0.5), "bsdf": {"type": "conductor"}},
    "rough": {"type": "sphere", "center": [0, -0.6, 1.2], "radius": 0.4, "bsdf": {"type": "roughconductor", "alpha": 0.2}},
    "lamp": {"type": "rectangle", "to_world": mi.ScalarTransform4f().translate([0, 2.5, 0]).rotate([1, 0, 0], 90).scale(0.5),
             "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [5, 5, 5]}}},
})
out = {}
for props in ({}, {"primary": "raytrace"}, {"effects": "shadow,reflection,refraction,indirect"}, {"hide_emitters": True}):
    r = hi.render(scene, spp=4, seed=3, denoise="off", **props)
    out[str(props)] = np.array(r.image)
    print(props, r.stats.rays)
np.savez(sys.argv[1], **out)
