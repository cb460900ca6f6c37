"""Probe (stop 28): a scene's frozen replay while other scenes are kept alive by the scene cache (cache.py).

    python docs/results/cpu/cached_scenes/probe.py  (from the repository root, .venv, 160x90)
"""
import statistics, gc, mitsuba as mi
mi.set_variant('llvm_ad_rgb')
import hybrid_integrator as hi
from hybrid_integrator.bench import load_bench_scene
from hybrid_integrator.raster.camera import sensor_to_world
S='../shared/scenes'
P=dict(resx=160, resy=90, models_dir=f'{S}/models', sponza_dir=f'{S}/sponza-dabrovic', showcase_dir=f'{S}/cbox', dining_dir=f'{S}/dining-room')
def frames(scene, n=12):
    cam = sensor_to_world(scene.sensors()[0])
    fr = hi.render_sequence(scene, [cam]*n, spp=1, layers=False, candidates="", denoise=False)[3:]
    return statistics.median(f.stats.host_ms['replay'] for f in fr), statistics.median(f.stats.times_ms['total'] for f in fr)
sc, _ = load_bench_scene('scenes/showcase.xml', P)
print('showcase alone: replay %.3f total %.3f' % frames(sc))
others = [load_bench_scene(f'scenes/{n}.xml', P)[0] for n in ('sponza_mirror', 'dining_room', 'many_objects')]
for o in others: frames(o, 4)
print('showcase, 3 more scenes cached: replay %.3f total %.3f' % frames(sc))
for o in others: hi.forget(o)
del others; gc.collect()
print('showcase, others forgotten: replay %.3f total %.3f' % frames(sc))
