"""Stop 62's probe: does the `path` + OIDN rival suffer from Mitsuba's albedo guide?

Mitsuba's `aov` integrator gives `albedo` as `eval_diffuse_reflectance`, which is π·f(wi, n) for a
BSDF that does not define it: up to 68 on the dining room's rough conductors (stop 61). OIDN asks
for an albedo in [0, 1]. The bench's rival (`compare.path_denoised_renders`) passes Mitsuba's value
as is. This probe denoises the same 1-spp `path` frames (8 seeds, 320×180, CPU) with that guide as
is and clipped to [0, 1], at OIDN 'fast' and 'high', and scores both against `path` at 1024 spp
(FLIP, relative MSE; means over the seeds):

    .venv/bin/python docs/results/gpu/issue10/stop62/rival_guide.py
"""
import drjit as dr
import mitsuba as mi
import numpy as np
mi.set_variant("llvm_ad_rgb")
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.compare import ground_truth, path_renders
from hybrid_integrator.denoise import Denoiser, Guides
from hybrid_integrator.raster.camera import sensor_like
from hybrid_integrator.metrics import relative_mse, flip_map
for spec, kv in [("scenes/dining_room.xml", ("dining_dir", "../shared/scenes/dining-room")),
                 ("scenes/sponza_mirror.xml", ("sponza_dir", "../shared/scenes/sponza-dabrovic")),
                 ("scenes/showcase.xml", ("showcase_dir", "../shared/scenes/cbox"))]:
    params = {"resx": "320", "resy": "180", kv[0]: kv[1]}
    scene, name = load_bench_scene(spec, params)
    gt, _, cached = ground_truth(spec, scene, params, 1024, -1)
    size = scene.sensors()[0].film().size()
    sensor = sensor_like(scene.sensors()[0], int(size[0]), int(size[1]), rfilter="box")
    renders = path_renders(scene, sensor, [mi.load_dict({"type": "path", "max_depth": -1}),
                                           mi.load_dict({"type": "aov", "aovs": "albedo:albedo,nn:sh_normal"})], 1, True)
    for quality in ("fast", "high"):
        den = Denoiser(quality)
        res = {"as is": [], "clipped": []}
        amax = 0
        for seed in range(8):
            colour, first = renders(seed)
            alb = first[..., 0:3]
            amax = max(amax, float(np.array(alb).max()))
            for k, a in (("as is", alb), ("clipped", dr.clip(alb, 0.0, 1.0))):
                out = np.array(den(colour[..., 0:3], Guides(albedo=a, normal=first[..., 3:6])))[..., :3]
                res[k].append((flip_map(out, gt)[1], relative_mse(out, gt)))
        print(name, quality, f"albedo max {amax:.2f}", {k: (round(float(np.mean([f for f, _ in v])), 4), round(float(np.mean([r for _, r in v])), 4)) for k, v in res.items()}, "gt cached" if cached else "gt rendered", flush=True)
