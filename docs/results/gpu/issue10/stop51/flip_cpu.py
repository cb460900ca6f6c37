"""Stop 51, CPU: the default frame's FLIP (mean of 6 seeds, 1 spp, denoised) against path at 1024 spp,
320x180, labelled; run once on the tree and once with the denoiser's albedo guide made the diffuse
albedo alone (``sed -i 's/dr.clip(a + s, 0.0, 1.0)/dr.clip(a, 0.0, 1.0)/' hybrid_integrator/pipeline.py``,
then restored) to compare the two guides on the same frames.

    .venv/bin/python docs/results/gpu/issue10/stop51/flip_cpu.py current scenes/sponza_mirror.xml scenes/showcase.xml scenes/armadillo_glass.xml scenes/dining_room.xml
"""
import sys, os, numpy as np, mitsuba as mi
mi.set_variant('llvm_ad_rgb')
import hybrid_integrator as hi
from hybrid_integrator.metrics import flip_map
from hybrid_integrator.bench import load_bench_scene
S='../shared/scenes'
params = dict(resx='320', resy='180', models_dir=f'{S}/models', sponza_dir=f'{S}/sponza-dabrovic', showcase_dir=f'{S}/cbox', dining_dir=f'{S}/dining-room')
label = sys.argv[1]
for spec in sys.argv[2:]:
    scene, name = load_bench_scene(spec, params)
    f = f'/tmp/gt_{name}.npy'
    if not os.path.exists(f):
        np.save(f, np.array(mi.render(scene, integrator=mi.load_dict({'type': 'path', 'max_depth': -1}), spp=1024, seed=5))[..., :3])
    ref = np.load(f)
    fl = [flip_map(np.array(hi.render(scene, spp=1, seed=s, layers=False).image)[..., :3], ref)[1] for s in range(6)]
    print(label, name, round(float(np.mean(fl)), 4), flush=True)
